"""One figure style for the whole workbook, and figure saving switched by ``AMDO_FIG_DIR``.

The book build sets ``AMDO_FIG_DIR`` to ``build/figures/<chapter>``; in a notebook opened by hand
it is unset and :func:`savefig` does nothing, so notebooks never litter the tree.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import matplotlib.pyplot as plt
from matplotlib.figure import Figure

from amdo_lab.common.validation import check_instance

__all__ = ["FIG_DIR_VARIABLE", "PALETTE", "STYLE_PATH", "savefig", "use_style"]

#: Okabe & Ito's colour-blind-safe palette, in the order of the style's colour cycle.
PALETTE: dict[str, str] = {
    "blue": "#0072B2",
    "orange": "#E69F00",
    "green": "#009E73",
    "vermillion": "#D55E00",
    "purple": "#CC79A7",
    "sky": "#56B4E9",
    "yellow": "#F0E442",
    "black": "#000000",
}

STYLE_PATH = Path(__file__).with_name("amdo.mplstyle")
FIG_DIR_VARIABLE = "AMDO_FIG_DIR"
_NAME_PATTERN = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")


def use_style() -> None:
    """Apply the workbook's matplotlib style (call once at the top of a notebook)."""
    plt.style.use(str(STYLE_PATH))


def savefig(fig: Figure, name: str) -> None:
    """Write ``fig`` as ``<AMDO_FIG_DIR>/<name>.png`` when the variable is set; else do nothing.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure to save.
    name : str
        File stem made of letters, digits, ``_``, ``-`` and ``.`` (e.g. ``"fig2_bending"``);
        a ``.png`` suffix is added when missing.

    Returns
    -------
    None
        Nothing, so a figure cell that ends with this call shows no output value (a returned path
        would print the reader's own machine path in the book).
    """
    check_instance(fig, "fig", Figure, what="a matplotlib Figure")
    if not isinstance(name, str) or not _NAME_PATTERN.match(name):
        raise ValueError(f"name must be a file stem of letters, digits, '_', '-' or '.', got {name!r}")
    directory = os.environ.get(FIG_DIR_VARIABLE)
    if not directory:
        return
    path = Path(directory) / (name if name.endswith(".png") else f"{name}.png")
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
