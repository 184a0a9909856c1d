"""Drawing helper for articulated shapes (one line per limb stroke)."""

from __future__ import annotations

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection
from matplotlib.colors import is_color_like

from amdo_lab.common import as_finite_array, check_axes, check_in_range, check_instance, check_positive

__all__ = ["draw_shape"]


def draw_shape(ax: Axes, shape: np.ndarray, *, color: str = "black", linewidth: float = 1.5,
               alpha: float = 1.0, label: str | None = None) -> None:
    """Draw an articulated shape as 13 limb polylines (equal aspect, axes hidden).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes to draw on.
    shape : (13, m, 2) array_like
        Landmark strokes of the 13 limbs.
    color : str
        Matplotlib colour of every stroke.
    linewidth : float
        Stroke width in points (positive).
    alpha : float
        Opacity in [0, 1].
    label : str, optional
        Legend label of the shape (one legend entry for all 13 strokes).

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 3 (a shape as K limbs of landmarks).
    """
    check_axes(ax)
    shape = as_finite_array(shape, "shape", shape=(13, None, 2))
    linewidth = check_positive(linewidth, "linewidth")
    alpha = check_in_range(alpha, "alpha", 0, 1, closed="both")
    check_instance(color, "color", str, what="a matplotlib colour name or hex string")
    if not is_color_like(color):
        raise ValueError(f"color must be a matplotlib colour name or hex string, got {color!r}")
    check_instance(label, "label", (str, type(None)), what="a str or None")
    # one collection of 13 polylines: drawing a training set is then one artist per shape
    ax.add_collection(LineCollection(list(shape), colors=color, linewidths=linewidth, alpha=alpha, label=label))
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.axis("off")
