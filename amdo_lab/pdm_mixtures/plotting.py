"""Drawing helper for articulated shapes (one line per limb stroke)."""

from __future__ import annotations

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection

from amdo_lab.common import as_finite_array, check_axes

__all__ = ["draw_shape"]


def draw_shape(ax: Axes, shape: np.ndarray, *, color: str = "black", linewidth: float = 1.5,
               alpha: float = 1.0, label: str | None = None) -> None:
    """Draw a ``(13, m, 2)`` shape as 13 polylines on ``ax`` (equal aspect, no ticks)."""
    check_axes(ax)
    shape = as_finite_array(shape, "shape", shape=(13, None, 2))
    # one collection of 13 polylines: drawing a training set is then one artist per shape
    ax.add_collection(LineCollection(list(shape), colors=color, linewidths=linewidth, alpha=alpha, label=label))
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.axis("off")
