"""The second feature vector F of Choraś (AMDO 2004), Sec. 4, eq. (9): per traced contour its endings,
bifurcations (by the crossing number of eq. 8) and circle intersections."""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from amdo_lab.common import check_choice
from amdo_lab.ear_biometrics.circles import CircleFeatures, circle_features
from amdo_lab.ear_biometrics.images import as_contour_image
from amdo_lab.ear_biometrics.normalisation import Normalisation
from amdo_lab.ear_biometrics.skeleton import EQ8_READINGS, connectivity_number, crossing_number, thin_contours

@dataclass(frozen=True)
class ContourTopology:
    """One traced contour of eq. (9): its endings, bifurcations and circle intersections (normalised).

    Parameters
    ----------
    endings : numpy.ndarray, shape (N_E, 2)
        Endings e, normalised (x, y).
    bifurcations : numpy.ndarray, shape (N_B, 2)
        Bifurcations b, normalised (x, y).
    intersections : numpy.ndarray, shape (N_I, 2)
        Intersections i with the circles of V, normalised (x, y).
    outer_radius : float
        Largest normalised radius reached by the contour (the tracing order).

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 4, eq. (9) and Fig. 8.
    """

    endings: np.ndarray  # (N_E, 2)
    bifurcations: np.ndarray  # (N_B, 2)
    intersections: np.ndarray  # (N_I, 2)
    outer_radius: float

    @property
    def triple(self) -> tuple[int, int, int]:
        """The triple (N_E, N_B, N_I) of eq. (9)."""
        return len(self.endings), len(self.bifurcations), len(self.intersections)

    @property
    def points(self) -> np.ndarray:
        """All characteristic points: endings, then bifurcations, then intersections, shape (n, 2)."""
        return np.vstack([self.endings, self.bifurcations, self.intersections])


@dataclass(frozen=True)
class TopologyFeatures:
    """Eq. (9): F = one ContourTopology per contour, ordered from the outermost contour inwards.

    Parameters
    ----------
    contours : tuple of ContourTopology
        The traced contours, outermost first.
    skeleton : numpy.ndarray, shape (rows, cols), bool
        The thinned contour image.
    ending_pixels : numpy.ndarray, shape (n, 2)
        All endings, pixel (row, col) (for plotting).
    bifurcation_pixels : numpy.ndarray, shape (n, 2)
        All bifurcations, pixel (row, col).
    circles : CircleFeatures
        V, computed on the same contours (its intersections are the i of eq. 9).

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 4, eqs. (8)-(9) and Figs. 7-8.
    """

    contours: tuple[ContourTopology, ...]
    skeleton: np.ndarray
    ending_pixels: np.ndarray  # (n, 2) row, col (for plotting)
    bifurcation_pixels: np.ndarray  # (n, 2) row, col
    circles: CircleFeatures


def _label(mask: np.ndarray) -> tuple[np.ndarray, int]:
    """8-connected component labels (0 = background) and the number of components."""
    n, labels = cv2.connectedComponents(mask.astype(np.uint8), connectivity=8, ltype=cv2.CV_32S)
    return labels, n - 1


def _cluster_centres(mask: np.ndarray) -> np.ndarray:
    """Centres (row, col) of 8-connected clusters of ``mask`` (adjacent bifurcation pixels are one
    bifurcation)."""
    n, _, _, centroids = cv2.connectedComponentsWithStats(mask.astype(np.uint8), connectivity=8)
    return centroids[1:, ::-1].reshape(-1, 2)  # OpenCV gives (x, y) = (col, row)


def topology_features(contours: object, n_circles: int = 8, step: float = 0.25, *, mode: str = "principal",
                      min_gap_px: float = 0.0, crossings: str = "pixels", polyline_smoothing: int = 2,
                      band_px: float = 0.0, spur_length_px: int = 0, eq8: str = "crossing",
                      normalisation: Normalisation | None = None) -> TopologyFeatures:
    """Second feature vector F, eq. (9).

    The contour image is thinned (``skimage.morphology.skeletonize``); skeleton pixels with
    N_c = 1 (eq. 8) are endings and with N_c > 2 bifurcations (clusters of adjacent ones merged).
    Each 8-connected skeleton component that reaches inside the outermost circle is one contour; the
    circle intersections of V are assigned to the nearest skeleton component. Contours are listed
    from the outermost (largest normalised radius) inwards, the paper's tracing order.

    Parameters
    ----------
    contours : array_like, shape (rows, cols), bool
        Contour image with at least one contour pixel.
    n_circles : int
        Number of circles N_r, from 1 to ``MAX_CIRCLES`` (64).
    step : float
        Radius step between circles, normalised units, > 0, as in :func:`circle_features`.
    mode : {"principal", "axes", "isotropic"}
        Reading of eq. (6); unused with ``normalisation``.
    min_gap_px : float
        As in :func:`circle_features`, pixels, >= 0.
    crossings : {"pixels", "polyline"}
        As in :func:`circle_features`.
    polyline_smoothing : int
        As in :func:`circle_features`, from 0 to 100,000.
    band_px : float
        As in :func:`circle_features`, pixels, >= 0.
    spur_length_px : int
        As in :func:`circle_features`, pixels, from 0 to 4,096.
    eq8 : {"crossing", "yokoi"}
        Reading of eq. (8): Rutovitz's crossing number or Yokoi's connectivity number; either way 1
        marks an ending and 3 or more a bifurcation.
    normalisation : Normalisation or None
        A given frame in place of eq. (6) on the contour pixels.

    Returns
    -------
    TopologyFeatures
        F, with the skeleton, the pixel positions of endings and bifurcations, and V.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 4, eqs. (7)-(9) and Figs. 7-8.
    """
    array = as_contour_image(contours)
    check_choice(eq8, "eq8", EQ8_READINGS)
    full_skeleton = thin_contours(array)
    circles = circle_features(array, n_circles, step, mode=mode, min_gap_px=min_gap_px, crossings=crossings,
                              polyline_smoothing=polyline_smoothing, band_px=band_px, spur_length_px=spur_length_px,
                              skeleton=full_skeleton, normalisation=normalisation)
    norm = circles.normalisation
    # Work inside the contours' bounding box (plus a 1-pixel margin): same result, less to scan.
    rows, cols = np.flatnonzero(array.any(axis=1)), np.flatnonzero(array.any(axis=0))
    top, left = max(rows[0] - 1, 0), max(cols[0] - 1, 0)
    crop = array[top:rows[-1] + 2, left:cols[-1] + 2]
    offset = np.array([top, left])
    thin = full_skeleton[top:rows[-1] + 2, left:cols[-1] + 2]
    n_c = (crossing_number if eq8 == "crossing" else connectivity_number)(thin)  # eq. (8): 1 ending, > 2 bifurcation
    endings = _cluster_centres(n_c == 1) + offset
    bifurcations = _cluster_centres(n_c > 2) + offset
    # Thinning preserves 8-connectivity, so a skeleton component is the skeleton of exactly one
    # contour component: label the (thick) contours and look points up in a 3x3-dilated label image
    # (a crossing's rounded position can fall one pixel off the contour).
    labels, n_components = _label(thin)
    spread_labels = cv2.dilate(labels.astype(np.float32), np.ones((3, 3), np.uint8)).astype(int)
    contour_labels, _ = _label(crop)
    # skeleton label of each contour component (the paper traces contours; one skeleton per contour)
    to_skeleton = np.zeros(contour_labels.max() + 1, int)
    on = labels > 0
    to_skeleton[contour_labels[on]] = labels[on]

    def component_of(rows_cols: np.ndarray) -> np.ndarray:
        rc = np.clip(np.round(rows_cols - offset).astype(int), 0, np.array(crop.shape) - 1).reshape(-1, 2)
        direct = to_skeleton[contour_labels[rc[:, 0], rc[:, 1]]]
        return np.where(direct > 0, direct, spread_labels[rc[:, 0], rc[:, 1]])

    all_crossings = np.vstack(circles.intersections)
    crossing_labels = component_of(norm.to_pixels(all_crossings)) if len(all_crossings) else np.zeros(0, int)
    ending_labels = component_of(endings)
    bifurcation_labels = component_of(bifurcations)
    pixels = np.argwhere(thin)
    radius = np.linalg.norm(norm.to_normalised(pixels + offset), axis=1)
    pixel_labels = labels[pixels[:, 0], pixels[:, 1]]
    outer = np.full(n_components, -np.inf)
    inner = np.full(n_components, np.inf)
    np.maximum.at(outer, pixel_labels - 1, radius)
    np.minimum.at(inner, pixel_labels - 1, radius)
    # eq. (9): F, per contour (outermost first) its endings e, bifurcations b and circle intersections i,
    # whose counts are the triple (N_E, N_B, N_I)
    result = []
    for label in np.argsort(-outer, kind="stable") + 1:
        if inner[label - 1] > circles.radii[-1]:
            continue  # entirely outside the outermost circle
        result.append(ContourTopology(
            endings=norm.to_normalised(endings[ending_labels == label]),
            bifurcations=norm.to_normalised(bifurcations[bifurcation_labels == label]),
            intersections=all_crossings[crossing_labels == label],
            outer_radius=float(outer[label - 1]),
        ))
    return TopologyFeatures(tuple(result), full_skeleton, endings, bifurcations, circles)
