"""Contour detection (eqs. 1-5), coordinate normalisation (eq. 6) and the two feature vectors
V (eq. 7) and F (eq. 9) of Choraś (AMDO 2004)."""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from scipy import ndimage
from skimage.morphology import skeletonize

from amdo_lab.common import check_choice, check_positive, check_positive_int

EIGHT = np.ones((3, 3), dtype=bool)


def as_grey_image(image: object, name: str = "image") -> np.ndarray:
    """Validate a 2-D grey-level image (uint8 or float) and return it as float64.

    Colour (3-D) images are rejected: convert them with ``cv2.cvtColor`` first (the folder loader
    does this for you). Booleans, NaN/inf and non-numeric arrays raise.
    """
    array = np.asarray(image)
    if array.dtype == bool or array.dtype == object or not np.issubdtype(array.dtype, np.number) \
            or np.issubdtype(array.dtype, np.complexfloating):
        raise TypeError(f"{name} must be a real numeric (uint8 or float) array, got dtype {array.dtype}")
    if array.ndim != 2:
        raise ValueError(f"{name} must be a 2-D grey-level image, got shape {array.shape}"
                         + (" (convert colour images to grey first)" if array.ndim == 3 else ""))
    if min(array.shape) < 8:
        raise ValueError(f"{name} must be at least 8x8 pixels, got shape {array.shape}")
    array = array.astype(float)
    if not np.all(np.isfinite(array)):
        raise ValueError(f"{name} must be finite, got NaN or infinite values")
    if array.min() < 0:
        raise ValueError(f"{name} must hold non-negative intensities, got minimum {array.min():.3g}")
    return array


def as_contour_image(contours: object, name: str = "contours") -> np.ndarray:
    """Validate a boolean 2-D contour image with at least one contour pixel."""
    array = np.asarray(contours)
    if array.dtype != bool:
        raise TypeError(f"{name} must be a boolean image (from detect_contours), got dtype {array.dtype}")
    if array.ndim != 2:
        raise ValueError(f"{name} must be 2-D, got shape {array.shape}")
    if not array.any():
        raise ValueError(f"{name} holds no contour pixels (blank or constant image?)")
    return array


def detect_contours(image: object, k: float = 8.0, window: int = 3) -> np.ndarray:
    """Local-statistics contour detector, eqs. (1)-(5).

    For the n x n window around every pixel: mean mu (eq. 1), standard deviation sigma with the
    n^2 - 1 denominator (eq. 2), range S = I_H - I_L (eq. 3), threshold T = mu - k sigma (eq. 4);
    the pixel is a contour pixel when S >= T (eq. 5). Our reading: mu, sigma, I_H and I_L are all
    taken over the same window of raw intensities. Because S is about c*sigma for a window, the rule
    is (c + k) sigma >= mu, a threshold on the local *relative* contrast sigma/mu; larger k = more
    sensitive. We add S > 0 so that a flat window (e.g. pure black, where mu = sigma = 0) is never a
    contour. Borders are handled by reflection.
    """
    grey = as_grey_image(image)
    k = check_positive(k, "k", allow_zero=True)
    window = check_positive_int(window, "window", minimum=3)
    if window % 2 == 0:
        raise ValueError(f"window must be odd, got {window}")
    n2 = window * window
    mean = cv2.blur(grey, (window, window), borderType=cv2.BORDER_REFLECT)
    mean_sq = cv2.blur(grey * grey, (window, window), borderType=cv2.BORDER_REFLECT)
    sigma = np.sqrt(np.maximum(mean_sq - mean * mean, 0.0) * n2 / (n2 - 1))
    kernel = np.ones((window, window), np.uint8)
    spread = cv2.dilate(grey, kernel, borderType=cv2.BORDER_REFLECT) - cv2.erode(grey, kernel, borderType=cv2.BORDER_REFLECT)
    return (spread >= mean - k * sigma) & (spread > 0)


def clean_contours(contours: object, min_size: int = 20, closing: int = 1) -> np.ndarray:
    """Binarisation clean-up (Fig. 3's "binarization" box, not specified in the paper): a binary
    closing with a (2*closing+1)^2 square (bridges the one-pixel gaps between the two flanks of a
    groove, so one groove crosses a circle once), then drop 8-connected fragments with fewer than
    ``min_size`` pixels. ``closing=0`` skips the closing."""
    array = np.asarray(contours)
    if array.dtype != bool or array.ndim != 2:
        raise TypeError(f"contours must be a 2-D boolean image, got dtype {array.dtype}, shape {array.shape}")
    min_size = check_positive_int(min_size, "min_size")
    closing = check_positive_int(closing, "closing", minimum=0)
    if closing:
        kernel = np.ones((2 * closing + 1,) * 2, np.uint8)
        padded = np.pad(array.astype(np.uint8), closing)  # zero border, as binary closing with border 0
        closed = cv2.morphologyEx(padded, cv2.MORPH_CLOSE, kernel, borderType=cv2.BORDER_CONSTANT, borderValue=0)
        array = closed[closing:-closing, closing:-closing].astype(bool)
    labels, n = ndimage.label(array, structure=EIGHT)
    sizes = np.bincount(labels.ravel(), minlength=n + 1)
    keep = sizes >= min_size
    keep[0] = False
    return keep[labels]


def canny_contours(image: object, sigma: float = 1.5, low: float = 20, high: float = 50) -> np.ndarray:
    """Peer method: OpenCV Canny after Gaussian smoothing (thresholds on the 0-255 scale)."""
    grey = as_grey_image(image)
    smooth = cv2.GaussianBlur(grey, (0, 0), check_positive(sigma, "sigma"))
    return cv2.Canny(np.clip(smooth, 0, 255).astype(np.uint8), low, high) > 0


@dataclass(frozen=True)
class Normalisation:
    """Eq. (6): centroid (I, J) in (row, col) pixels and per-axis spreads (sigma_i, sigma_j)."""

    centroid: np.ndarray
    spread: np.ndarray

    def to_normalised(self, rows_cols: np.ndarray) -> np.ndarray:
        """Pixel (row, col) -> normalised (x, y) with x to the right and y up."""
        rc = (np.asarray(rows_cols, float) - self.centroid) / self.spread
        return np.c_[rc[:, 1], -rc[:, 0]]

    def to_pixels(self, xy: np.ndarray) -> np.ndarray:
        """Normalised (x, y) -> pixel (row, col)."""
        xy = np.asarray(xy, float).reshape(-1, 2)
        return np.c_[-xy[:, 1], xy[:, 0]] * self.spread + self.centroid


def normalise_coordinates(contours: object, mode: str = "isotropic") -> Normalisation:
    """Eq. (6): translate the centroid of the contour pixels to the origin and divide by the spread.

    ``mode="axes"`` is the paper's literal matrix: rows divided by sigma_i, columns by sigma_j.
    ``mode="isotropic"`` (our default) divides both by sqrt((sigma_i^2 + sigma_j^2)/2), which keeps
    circles circles under rotation: the paper's rotation-invariance claim holds only for this variant
    (with per-axis spreads an elongated ear rotated by 45 degrees is squashed differently).
    """
    array = as_contour_image(contours)
    check_choice(mode, "mode", ("axes", "isotropic"))
    pixels = np.argwhere(array).astype(float)
    centroid = pixels.mean(axis=0)
    spread = pixels.std(axis=0)
    if np.any(spread == 0):
        raise ValueError("contours must not lie on a single row or column (zero spread)")
    if mode == "isotropic":
        spread = np.full(2, np.sqrt(np.mean(spread**2)))
    return Normalisation(centroid, spread)


@dataclass(frozen=True)
class CircleFeatures:
    """Eq. (7): V = {[r, l_r, sum d_r]} for the N_r circles, plus what was used to compute it."""

    radii: np.ndarray  # (N_r,) normalised radii
    counts: np.ndarray  # (N_r,) l_r, number of intersections
    distance_sums: np.ndarray  # (N_r,) sum of distances between neighbouring intersections
    intersections: tuple[np.ndarray, ...]  # per circle (l_r, 2) normalised (x, y), counter-clockwise
    normalisation: Normalisation

    @property
    def vector(self) -> np.ndarray:
        """V as an (N_r, 3) array of (r, l_r, sum d)."""
        return np.c_[self.radii, self.counts, self.distance_sums]


def _circle_runs(hits: np.ndarray) -> np.ndarray:
    """Midpoint sample indices (float) of the runs of True on a closed (circular) boolean array."""
    if not hits.any():
        return np.zeros(0)
    if hits.all():
        return np.zeros(1)
    first_false = int(np.argmin(hits))
    rolled = np.roll(hits, -first_false)
    edges = np.diff(rolled.astype(np.int8))
    starts = np.flatnonzero(edges == 1) + 1
    ends = np.flatnonzero(edges == -1)
    if rolled[-1]:
        ends = np.append(ends, len(rolled) - 1)
    return ((starts + ends) / 2 + first_false) % len(hits)


def circle_features(contours: object, n_circles: int = 8, step: float = 0.25, *, mode: str = "isotropic") -> CircleFeatures:
    """First feature vector V, eq. (7).

    Circles of radius r_m = m * step (m = 1..n_circles) in *normalised* units (eq. 6) are centred on
    the centroid; our reading of "alpha pixels apart" uses normalised units so that V is scale
    invariant. Each circle is sampled at about two points per pixel of its circumference; a run of
    consecutive samples on contour pixels is one intersection (l_r counts runs, so a 2-pixel-thick
    contour crossing the circle counts once). sum d is the perimeter of the polygon through the
    intersections taken counter-clockwise, closed so that it does not depend on a start angle.
    """
    array = as_contour_image(contours)
    n_circles = check_positive_int(n_circles, "n_circles")
    step = check_positive(step, "step")
    norm = normalise_coordinates(array, mode)
    radii = step * np.arange(1, n_circles + 1)
    counts, sums, points = [], [], []
    for radius in radii:
        n_samples = int(8 * np.ceil(4 * np.pi * radius * norm.spread.max() / 8)) + 8
        angles = 2 * np.pi * np.arange(n_samples) / n_samples
        xy = radius * np.c_[np.cos(angles), np.sin(angles)]
        rc = np.round(norm.to_pixels(xy)).astype(int)
        inside = (rc[:, 0] >= 0) & (rc[:, 0] < array.shape[0]) & (rc[:, 1] >= 0) & (rc[:, 1] < array.shape[1])
        hits = np.zeros(n_samples, bool)
        hits[inside] = array[rc[inside, 0], rc[inside, 1]]
        mids = 2 * np.pi * _circle_runs(hits) / n_samples
        crossing = radius * np.c_[np.cos(mids), np.sin(mids)]
        counts.append(len(mids))
        closed = np.vstack([crossing, crossing[:1]]) if len(mids) > 1 else crossing
        sums.append(float(np.linalg.norm(np.diff(closed, axis=0), axis=1).sum()))
        points.append(crossing)
    return CircleFeatures(radii, np.array(counts), np.array(sums), tuple(points), norm)


def crossing_number(skeleton: np.ndarray) -> np.ndarray:
    """8-connected crossing number N_c = 1/2 sum_k |p_{k+1} - p_k| over the 8 neighbours in cyclic
    order (Fig. 7), evaluated on every pixel (0 off the skeleton)."""
    padded = np.pad(skeleton.astype(np.int8), 1)
    h, w = skeleton.shape
    ring = [(0, 1), (0, 2), (1, 2), (2, 2), (2, 1), (2, 0), (1, 0), (0, 0)]  # N, NE, E, SE, S, SW, W, NW
    neighbours = np.stack([padded[r:r + h, c:c + w] for r, c in ring])
    transitions = np.abs(np.diff(np.concatenate([neighbours, neighbours[:1]]), axis=0)).sum(axis=0) // 2
    return np.where(skeleton, transitions, 0)


@dataclass(frozen=True)
class ContourTopology:
    """One traced contour of eq. (9): its endings, bifurcations and circle intersections (normalised)."""

    endings: np.ndarray  # (N_E, 2)
    bifurcations: np.ndarray  # (N_B, 2)
    intersections: np.ndarray  # (N_I, 2)
    outer_radius: float

    @property
    def triple(self) -> tuple[int, int, int]:
        """(N_E, N_B, N_I)."""
        return len(self.endings), len(self.bifurcations), len(self.intersections)

    @property
    def points(self) -> np.ndarray:
        return np.vstack([self.endings, self.bifurcations, self.intersections])


@dataclass(frozen=True)
class TopologyFeatures:
    """Eq. (9): F = one ContourTopology per contour, ordered from the outermost contour inwards."""

    contours: tuple[ContourTopology, ...]
    skeleton: np.ndarray
    ending_pixels: np.ndarray  # (n, 2) row, col (for plotting)
    bifurcation_pixels: np.ndarray  # (n, 2) row, col
    circles: CircleFeatures


def _cluster_centres(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Centres (row, col) of 8-connected clusters of ``mask`` (adjacent bifurcation pixels are one
    bifurcation) and the cluster count."""
    labels, n = ndimage.label(mask, structure=EIGHT)
    if n == 0:
        return np.zeros((0, 2)), labels
    return np.array(ndimage.center_of_mass(mask, labels, np.arange(1, n + 1))).reshape(-1, 2), labels


def topology_features(contours: object, n_circles: int = 8, step: float = 0.25, *, mode: str = "isotropic") -> TopologyFeatures:
    """Second feature vector F, eq. (9).

    The contour image is thinned (``skimage.morphology.skeletonize``); skeleton pixels with
    N_c = 1 are endings and with N_c > 2 bifurcations (clusters of adjacent ones merged). Each
    8-connected skeleton component that reaches inside the outermost circle is one contour; the
    circle intersections of V are assigned to the nearest skeleton component. Contours are listed
    from the outermost (largest normalised radius) inwards, the paper's tracing order.
    """
    array = as_contour_image(contours)
    circles = circle_features(array, n_circles, step, mode=mode)
    norm = circles.normalisation
    skeleton = skeletonize(array)
    n_c = crossing_number(skeleton)
    endings, _ = _cluster_centres(n_c == 1)
    bifurcations, _ = _cluster_centres(n_c > 2)
    # Thinning preserves 8-connectivity, so a skeleton component is the skeleton of exactly one
    # contour component: label the (thick) contours and look points up in a 3x3-dilated label image
    # (a crossing's rounded position can fall one pixel off the contour).
    labels, n_components = ndimage.label(skeleton, structure=EIGHT)
    spread_labels = cv2.dilate(labels.astype(np.float32), np.ones((3, 3), np.uint8)).astype(int)
    contour_labels, _ = ndimage.label(array, structure=EIGHT)
    # skeleton label of each contour component (the paper traces contours; one skeleton per contour)
    to_skeleton = np.zeros(contour_labels.max() + 1, int)
    on = labels > 0
    to_skeleton[contour_labels[on]] = labels[on]

    def component_of(rows_cols: np.ndarray) -> np.ndarray:
        rc = np.clip(np.round(rows_cols).astype(int), 0, np.array(array.shape) - 1).reshape(-1, 2)
        direct = to_skeleton[contour_labels[rc[:, 0], rc[:, 1]]]
        return np.where(direct > 0, direct, spread_labels[rc[:, 0], rc[:, 1]])

    all_crossings = np.vstack(circles.intersections)
    crossing_labels = component_of(norm.to_pixels(all_crossings)) if len(all_crossings) else np.zeros(0, int)
    ending_labels = component_of(endings)
    bifurcation_labels = component_of(bifurcations)
    pixels = np.argwhere(skeleton)
    radius = np.linalg.norm(norm.to_normalised(pixels), axis=1)
    pixel_labels = labels[pixels[:, 0], pixels[:, 1]]
    outer = ndimage.maximum(radius, pixel_labels, np.arange(1, n_components + 1))
    inner = ndimage.minimum(radius, pixel_labels, np.arange(1, n_components + 1))
    result = []
    for label in np.argsort(-np.asarray(outer)) + 1:
        if inner[label - 1] > circles.radii[-1]:
            continue  # entirely outside the outermost circle
        result.append(ContourTopology(
            endings=norm.to_normalised(endings[ending_labels == label]),
            bifurcations=norm.to_normalised(bifurcations[bifurcation_labels == label]),
            intersections=all_crossings[crossing_labels == label],
            outer_radius=float(outer[label - 1]),
        ))
    return TopologyFeatures(tuple(result), skeleton, endings, bifurcations, circles)
