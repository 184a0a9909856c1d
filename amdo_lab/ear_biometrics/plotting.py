"""Figures of chapter 4: contours with the circles of V (Figs. 5-6) and the topology of F (Figs. 7-8)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from amdo_lab.common import PALETTE, check_axes, check_bool
from amdo_lab.ear_biometrics.circles import CircleFeatures
from amdo_lab.ear_biometrics.images import as_bool_image, check_record
from amdo_lab.ear_biometrics.topology import TopologyFeatures

if TYPE_CHECKING:  # matplotlib is imported by the caller's figure
    from matplotlib.axes import Axes


def _circle_pixels(features: CircleFeatures, radius: float, n: int = 200) -> np.ndarray:
    angles = np.linspace(0, 2 * np.pi, n)
    return features.normalisation.to_pixels(radius * np.c_[np.cos(angles), np.sin(angles)])


def draw_circles(ax: Axes, contours: np.ndarray, features: CircleFeatures, *, show_crossings: bool = False) -> None:
    """Draw the contours, the centroid (cross) and the N_r circles of V (Figs. 5-6).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    contours : numpy.ndarray, shape (rows, cols), bool
        The contour image V was computed from.
    features : CircleFeatures
        V, eq. (7).
    show_crossings : bool
        Also draw the crossings and the counter-clockwise polygon whose length is sum d (Fig. 6).

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 4, eq. (7) and Figs. 5-6.
    """
    check_axes(ax)
    check_record(features, "features", CircleFeatures, "circle_features")
    check_bool(show_crossings, "show_crossings")
    contours = as_bool_image(contours, "contours")
    ax.imshow(contours, cmap="gray_r", interpolation="nearest")
    centre = features.normalisation.centroid
    for radius in features.radii:
        rc = _circle_pixels(features, radius)
        ax.plot(rc[:, 1], rc[:, 0], color=PALETTE["sky"], lw=0.8)
    ax.plot(centre[1], centre[0], "+", color=PALETTE["vermillion"], ms=12, mew=2)
    if show_crossings:
        for points in features.intersections:
            if len(points) == 0:
                continue
            rc = features.normalisation.to_pixels(np.vstack([points, points[:1]]))
            ax.plot(rc[:, 1], rc[:, 0], "-o", color=PALETTE["orange"], ms=3, lw=0.8)
    ax.set_xlim(0, contours.shape[1]); ax.set_ylim(contours.shape[0], 0)
    ax.axis("off")


def draw_topology(ax: Axes, features: TopologyFeatures) -> None:
    """Draw the skeleton with endings (squares), bifurcations (diamonds) and circle crossings (dots).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    features : TopologyFeatures
        F, eq. (9).

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 4, eqs. (8)-(9) and Figs. 7-8.
    """
    check_axes(ax)
    check_record(features, "features", TopologyFeatures, "topology_features")
    ax.imshow(features.skeleton, cmap="gray_r", interpolation="nearest")
    circles = features.circles
    for radius in circles.radii:
        rc = _circle_pixels(circles, radius)
        ax.plot(rc[:, 1], rc[:, 0], color=PALETTE["sky"], lw=0.6)
    e, b = features.ending_pixels, features.bifurcation_pixels
    ax.plot(e[:, 1], e[:, 0], "s", mfc="none", color=PALETTE["vermillion"], ms=6, label=f"endings E ({len(e)})")
    ax.plot(b[:, 1], b[:, 0], "D", mfc="none", color=PALETTE["blue"], ms=6, label=f"bifurcations B ({len(b)})")
    crossings = np.vstack(circles.intersections)
    if len(crossings):
        rc = circles.normalisation.to_pixels(crossings)
        ax.plot(rc[:, 1], rc[:, 0], ".", color=PALETTE["orange"], ms=4, label=f"crossings ({len(rc)})")
    ax.legend(fontsize=7, loc="lower right")
    ax.set_xlim(0, features.skeleton.shape[1]); ax.set_ylim(features.skeleton.shape[0], 0)
    ax.axis("off")
