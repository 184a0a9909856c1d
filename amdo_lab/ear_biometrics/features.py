"""Contour detection (eqs. 1-5), coordinate normalisation (eq. 6) and the two feature vectors
V (eq. 7) and F (eq. 9) of Choraś (AMDO 2004)."""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from skimage.morphology import skeletonize

from amdo_lab.common import (as_bool_mask, as_finite_array, check_choice, check_in_range, check_positive,
                             check_positive_int)


def as_bool_image(value: object, name: str) -> np.ndarray:
    """Check a non-empty 2-D boolean image (contours, a skeleton).

    OpenCV's morphology and component labelling crash the interpreter on an image with zero rows,
    so empty images are refused here.

    Parameters
    ----------
    value : object
        The argument to check.
    name : str
        The argument's name in error messages.

    Returns
    -------
    numpy.ndarray, shape (rows, cols), bool
        The image as an array.
    """
    array = np.asarray(value)
    if array.dtype != bool or array.ndim != 2:
        raise TypeError(f"{name} must be a 2-D boolean image, got dtype {array.dtype}, shape {array.shape}")
    return as_bool_mask(array, name)


MAX_GREY_LEVEL = 1e6
"""Largest grey level of an image: 8- and 16-bit images and float images fit with room to spare;
the squared window sums of eq. (2) and the HOG gradients stay exact and finite far beyond it."""


def as_grey_image(image: object, name: str = "image") -> np.ndarray:
    """Validate a 2-D grey-level image (uint8 or float) and return it as float64.

    Colour (3-D) images are rejected: convert them with ``cv2.cvtColor`` first (the folder loader
    does this for you).

    Parameters
    ----------
    image : array_like, shape (rows, cols)
        Grey levels: real, finite, non-negative and at most :data:`MAX_GREY_LEVEL` (0-255 for 8-bit
        images), at least 8 x 8 pixels; booleans are refused.
    name : str
        The argument's name in error messages.

    Returns
    -------
    numpy.ndarray, shape (rows, cols), float64
        A float copy of ``image``.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 2: the grey-level input of the contour detector.
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
    if array.max() > MAX_GREY_LEVEL:
        raise ValueError(f"{name} must hold intensities of at most {MAX_GREY_LEVEL:g}, got maximum {array.max():.3g}")
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

    Parameters
    ----------
    image : array_like, shape (rows, cols)
        Grey levels, as :func:`as_grey_image` accepts them (an 8-bit image takes a faster path with
        the same result).
    k : float
        The threshold's multiple of sigma in eq. (4), >= 0; larger finds more contour pixels.
    window : int
        Side n of the square window, odd, >= 3.

    Returns
    -------
    numpy.ndarray, shape (rows, cols), bool
        True on contour pixels.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 2, eqs. (1)-(5).

    Examples
    --------
    A vertical step from grey level 100 to 200: the two columns at the step are contour pixels,
    the flat part is not.

    >>> import numpy as np
    >>> from amdo_lab import ear_biometrics as eb
    >>> image = np.full((32, 32), 100, np.uint8)
    >>> image[:, 16:] = 200
    >>> contours = eb.detect_contours(image, k=8.0)
    >>> np.flatnonzero(contours[5]).tolist()
    [15, 16]
    """
    grey = as_grey_image(image)
    k = check_positive(k, "k", allow_zero=True)
    window = check_positive_int(window, "window", minimum=3)
    if window % 2 == 0:
        raise ValueError(f"window must be odd, got {window}")
    n2 = window * window
    kernel = np.ones((window, window), np.uint8)
    raw = np.asarray(image)
    # 8-bit images: window sums of the integer values are exact in float32 (below 2**24), and the
    # max/min filters run on uint8 -- several times faster than the float64 path, same rule.
    values = raw if raw.dtype == np.uint8 else grey
    work = values.astype(np.float32) if raw.dtype == np.uint8 else grey
    box = dict(ddepth=-1, ksize=(window, window), normalize=False, borderType=cv2.BORDER_REFLECT)
    sums = cv2.boxFilter(work, **box).astype(float)
    sums_sq = cv2.boxFilter(work * work, **box).astype(float)
    mean = sums / n2  # eq. 1
    sigma = np.sqrt(np.maximum(sums_sq - sums * mean, 0.0) / (n2 - 1))  # eq. 2
    spread = (cv2.dilate(values, kernel, borderType=cv2.BORDER_REFLECT).astype(float)
              - cv2.erode(values, kernel, borderType=cv2.BORDER_REFLECT))  # eq. 3
    return (spread >= mean - k * sigma) & (spread > 0)  # eqs. 4-5


def detect_contours_reference(image: object, k: float = 8.0, window: int = 3) -> np.ndarray:
    """:func:`detect_contours` written plainly: one window at a time, eqs. (1)-(5) line by line.

    The readable path of the filtered :func:`detect_contours` (tested equal to it); a Python loop
    over the pixels, so for small images only.

    Parameters
    ----------
    image : array_like, shape (rows, cols)
        Grey levels, as :func:`as_grey_image` accepts them.
    k : float
        The threshold's multiple of sigma in eq. (4), >= 0.
    window : int
        Side n of the square window, odd, >= 3.

    Returns
    -------
    numpy.ndarray, shape (rows, cols), bool
        True on contour pixels.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 2, eqs. (1)-(5).
    """
    grey = as_grey_image(image)
    k = check_positive(k, "k", allow_zero=True)
    window = check_positive_int(window, "window", minimum=3)
    if window % 2 == 0:
        raise ValueError(f"window must be odd, got {window}")
    half = window // 2
    padded = np.pad(grey, half, mode="symmetric")  # borders by reflection, as cv2.BORDER_REFLECT
    contours = np.zeros(grey.shape, bool)
    for row in range(grey.shape[0]):
        for col in range(grey.shape[1]):
            values = padded[row:row + window, col:col + window]
            mu = values.mean()  # eq. (1): the window's mean
            sigma = values.std(ddof=1)  # eq. (2): its standard deviation, n² - 1 in the denominator
            spread = values.max() - values.min()  # eq. (3): S = I_H - I_L
            threshold = mu - k * sigma  # eq. (4): T = μ - kσ
            contours[row, col] = spread >= threshold and spread > 0  # eq. (5): S ≥ T (and not a flat window)
    return contours


def clean_contours(contours: object, min_size: int = 20, closing: int = 1) -> np.ndarray:
    """Binarisation clean-up of a contour image (Fig. 3's "binarization" box, not specified in the paper).

    A binary closing with a (2 ``closing`` + 1)^2 square bridges the one-pixel gaps between the two
    flanks of a groove (so one groove crosses a circle once), then 8-connected fragments with fewer
    than ``min_size`` pixels are dropped.

    Parameters
    ----------
    contours : array_like, shape (rows, cols), bool
        Contour image (from :func:`detect_contours`), not empty.
    min_size : int
        Smallest fragment kept, pixels, >= 1.
    closing : int
        Half-width of the closing square, pixels, >= 0 (0 skips the closing).

    Returns
    -------
    numpy.ndarray, shape (rows, cols), bool
        The cleaned contour image.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 1, Fig. 3 (binarisation before the features).
    """
    array = as_bool_image(contours, "contours")
    min_size = check_positive_int(min_size, "min_size")
    closing = check_positive_int(closing, "closing", minimum=0)
    if closing:
        kernel = np.ones((2 * closing + 1,) * 2, np.uint8)
        padded = np.pad(array.astype(np.uint8), closing)  # zero border, as binary closing with border 0
        closed = cv2.morphologyEx(padded, cv2.MORPH_CLOSE, kernel, borderType=cv2.BORDER_CONSTANT, borderValue=0)
        array = closed[closing:-closing, closing:-closing].astype(bool)
    _, labels, stats, _ = cv2.connectedComponentsWithStats(array.astype(np.uint8), connectivity=8)
    keep = stats[:, cv2.CC_STAT_AREA] >= min_size
    keep[0] = False
    return keep[labels]


def canny_contours(image: object, sigma: float = 1.5, low: float = 20, high: float = 50) -> np.ndarray:
    """Peer contour detector: OpenCV's Canny after Gaussian smoothing.

    Parameters
    ----------
    image : array_like, shape (rows, cols)
        Grey levels on the 0-255 scale, as :func:`as_grey_image` accepts them.
    sigma : float
        Standard deviation of the Gaussian smoothing, pixels, > 0 and at most the image's larger
        side (a wider blur leaves a flat image).
    low : float
        Lower hysteresis threshold of the gradient magnitude, >= 0 (grey levels per pixel).
    high : float
        Upper hysteresis threshold, >= 0.

    Returns
    -------
    numpy.ndarray, shape (rows, cols), bool
        True on edge pixels.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 2 (the detector this peer is compared with, eqs. (1)-(5)).
    J. Canny, "A Computational Approach to Edge Detection", IEEE TPAMI 8(6), 1986.
    """
    grey = as_grey_image(image)
    check_positive(low, "low", allow_zero=True)
    check_positive(high, "high", allow_zero=True)
    sigma = check_in_range(check_positive(sigma, "sigma"), "sigma", 0, max(grey.shape), closed="right")
    smooth = cv2.GaussianBlur(grey, (0, 0), sigma)
    return cv2.Canny(np.clip(smooth, 0, 255).astype(np.uint8), low, high) > 0


NORMALISATION_MODES = ("principal", "axes", "isotropic")


@dataclass(frozen=True)
class Normalisation:
    """Eq. (6): the centroid (I, J) of the contour pixels and the linear map to normalised (x, y).

    Parameters
    ----------
    centroid : numpy.ndarray, shape (2,)
        The centroid (row, col), pixels.
    spread : numpy.ndarray, shape (2,)
        Pixel standard deviations along the normalised axes (the sigmas that eq. 6 divides by).
    matrix : numpy.ndarray, shape (2, 2)
        Maps a pixel offset (row - I, col - J) to normalised (x, y); x right, y up.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 3, eq. (6).
    """

    centroid: np.ndarray
    spread: np.ndarray
    matrix: np.ndarray

    def to_normalised(self, rows_cols: np.ndarray) -> np.ndarray:
        """Map pixel positions to normalised coordinates (eq. 6).

        Parameters
        ----------
        rows_cols : array_like, shape (n, 2) or (2,)
            Pixel positions (row, col), finite, within +-1e6 pixels.

        Returns
        -------
        numpy.ndarray, shape (n, 2)
            Normalised (x, y).
        """
        return (_check_points(rows_cols, "rows_cols") - self.centroid) @ self.matrix.T

    def to_pixels(self, xy: np.ndarray) -> np.ndarray:
        """Map normalised coordinates back to pixel positions (the inverse of eq. 6).

        Parameters
        ----------
        xy : array_like, shape (n, 2) or (2,)
            Normalised (x, y), finite, within +-1e6 (a contour lies within a few units of the origin).

        Returns
        -------
        numpy.ndarray, shape (n, 2)
            Pixel positions (row, col), not rounded.
        """
        return _check_points(xy, "xy") @ np.linalg.inv(self.matrix).T + self.centroid


# Largest coordinate accepted by Normalisation's maps, pixels or normalised units: far beyond any
# image, and far enough below overflow that a map through an extreme spread stays finite.
MAX_COORDINATE = 1e6


def _check_points(points: object, name: str) -> np.ndarray:
    """Finite 2-D points as rows; an (n, 3) array is refused rather than silently re-cut into pairs."""
    array = as_finite_array(points, name, allow_empty=True, max_abs=MAX_COORDINATE)
    if array.ndim not in (1, 2) or array.shape[-1] != 2:
        raise ValueError(f"{name} must have shape (n, 2) or (2,), got {array.shape}")
    return array.reshape(-1, 2)


def _image_axes_matrix(spread: np.ndarray) -> np.ndarray:
    # x to the right (columns), y up (minus rows), each divided by its sigma
    return np.array([[0.0, 1.0 / spread[1]], [-1.0 / spread[0], 0.0]])


def check_normalisation_mode(mode: object, name: str = "mode") -> str:
    """One of :data:`NORMALISATION_MODES`."""
    return check_choice(mode, name, NORMALISATION_MODES)


def normalise_coordinates(contours: object, mode: str = "principal") -> Normalisation:
    """Eq. (6): translate the centroid of the contour pixels to the origin and divide by the spread.

    Three readings of the per-axis division:

    ``"axes"``
        The literal matrix: rows divided by sigma_i, columns by sigma_j (the image axes). Not
        rotation invariant: an elongated ear turned by 45 degrees has other per-axis spreads than
        upright, so its normalised shape is squashed differently.
    ``"principal"`` (default)
        The same division along the *principal axes* of the contour pixels (eigenvectors of their
        2x2 covariance): y along the major axis, x along the minor one. For an upright ear (principal
        axes = image axes) this is eq. 6 exactly; for a rotated one it first undoes the rotation, so
        the paper's rotation-invariance claim holds. It also removes any horizontal foreshortening
        of an upright ear (the camera's yaw), as the literal eq. 6 does. Axis signs are fixed by the
        sign of the third moment (skewness) along each axis, so the frame is the same for every
        capture of an ear.
    ``"isotropic"``
        Both image axes divided by sqrt((sigma_i^2 + sigma_j^2) / 2): a similarity normalisation,
        rotation covariant (circles stay circles) but the frame turns with the ear and the aspect
        ratio is kept.

    Parameters
    ----------
    contours : array_like, shape (rows, cols), bool
        Contour image with at least one contour pixel, not on a single row, column or line.
    mode : {"principal", "axes", "isotropic"}
        The reading of eq. (6), as above.

    Returns
    -------
    Normalisation
        Centroid, spreads and the map to normalised coordinates.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 3, eq. (6).
    """
    array = as_contour_image(contours)
    check_choice(mode, "mode", NORMALISATION_MODES)
    pixels = np.argwhere(array).astype(float)
    centroid = pixels.mean(axis=0)
    offsets = pixels - centroid
    spread = offsets.std(axis=0)
    if np.any(spread == 0):
        raise ValueError("contours must not lie on a single row or column (zero spread)")
    if mode == "axes":
        return Normalisation(centroid, spread, _image_axes_matrix(spread))
    if mode == "isotropic":
        spread = np.full(2, np.sqrt(np.mean(spread**2)))
        return Normalisation(centroid, spread, _image_axes_matrix(spread))
    variances, vectors = np.linalg.eigh(np.cov(offsets.T, bias=True))  # ascending: minor, major
    if variances[0] <= 1e-12 * variances[1]:
        raise ValueError("contours must not lie on a single straight line (zero spread across it)")
    projected = offsets @ vectors  # (n, 2): along minor, major axis
    signs = np.where(np.mean(projected**3, axis=0) < 0, -1.0, 1.0)  # positive skewness on both axes
    spread = np.sqrt(variances)
    matrix = (vectors * signs).T / spread[:, None]  # row m: unit axis m (signed) / sigma_m
    return Normalisation(centroid, spread, matrix)


@dataclass(frozen=True)
class CircleFeatures:
    """Eq. (7): V = {[r, l_r, sum d_r]} for the N_r circles, plus what was used to compute it.

    Parameters
    ----------
    radii : numpy.ndarray, shape (N_r,)
        Circle radii r, normalised units.
    counts : numpy.ndarray, shape (N_r,), int
        l_r, the number of intersections of the contours with each circle.
    distance_sums : numpy.ndarray, shape (N_r,)
        sum d_r, the summed distances between neighbouring intersections, normalised units.
    intersections : tuple of numpy.ndarray
        Per circle, the (l_r, 2) intersection points, normalised (x, y), counter-clockwise.
    normalisation : Normalisation
        The frame of eq. (6) the circles are drawn in.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 4, eq. (7) and Figs. 5-6.
    """

    radii: np.ndarray  # (N_r,) normalised radii
    counts: np.ndarray  # (N_r,) l_r, number of intersections
    distance_sums: np.ndarray  # (N_r,) sum of distances between neighbouring intersections
    intersections: tuple[np.ndarray, ...]  # per circle (l_r, 2) normalised (x, y), counter-clockwise
    normalisation: Normalisation

    @property
    def vector(self) -> np.ndarray:
        """V as an (N_r, 3) array of (r, l_r, sum d)."""
        return np.c_[self.radii, self.counts, self.distance_sums]


def _roll_rows(values: np.ndarray, shifts: np.ndarray) -> np.ndarray:
    """Row r rolled left by shifts[r] (row r starts at its element shifts[r])."""
    n = values.shape[1]
    return values[np.arange(len(values))[:, None], (np.arange(n) + shifts[:, None]) % n]


def _runs(rolled: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(row, start, end exclusive) of every run of True in each row (rows need not be circular)."""
    edges = np.diff(np.pad(rolled.astype(np.int8), ((0, 0), (1, 1))), axis=1)
    rows, starts = np.nonzero(edges == 1)
    _, ends = np.nonzero(edges == -1)  # row-major order pairs each start with its end
    return rows, starts, ends


def _fill_short_gaps(hits: np.ndarray, arc: np.ndarray, min_gap_px: float) -> np.ndarray:
    """Close runs of False on closed rows whose arc length (sum of ``arc``) is below ``min_gap_px``."""
    partial = hits.any(axis=1) & ~hits.all(axis=1)
    if min_gap_px <= 0 or not partial.any():
        return hits
    sub, sub_arc = hits[partial], arc[partial]
    shifts = np.argmax(sub, axis=1)  # start every row on a True, so no gap wraps around
    rolled, rolled_arc = _roll_rows(sub, shifts), _roll_rows(sub_arc, shifts)
    rows, starts, ends = _runs(~rolled)
    cumulative = np.pad(np.cumsum(rolled_arc, axis=1), ((0, 0), (1, 0)))
    short = cumulative[rows, ends] - cumulative[rows, starts] < min_gap_px
    fill = np.zeros(rolled.shape[1] + 1, np.int32)[None].repeat(len(rolled), axis=0)
    np.add.at(fill, (rows[short], starts[short]), 1)
    np.add.at(fill, (rows[short], ends[short]), -1)
    rolled = rolled | (np.cumsum(fill, axis=1)[:, :-1] > 0)
    filled = hits.copy()
    filled[partial] = _roll_rows(rolled, (-shifts) % hits.shape[1])
    return filled


def _circle_crossings(hits: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Row and midpoint sample index (float) of every run of True on closed (circular) rows,
    sorted by row, then counter-clockwise. A fully covered row counts as one crossing at index 0."""
    n = hits.shape[1]
    full = hits.all(axis=1)
    shifts = np.argmin(hits, axis=1)  # start every row on a False, so no run wraps around
    rows, starts, ends = _runs(_roll_rows(hits & ~full[:, None], shifts))
    mids = ((starts + ends - 1) / 2 + shifts[rows]) % n
    rows, mids = np.r_[rows, np.flatnonzero(full)], np.r_[mids, np.zeros(full.sum())]
    order = np.lexsort((mids, rows))
    return rows[order], mids[order]


CROSSING_READINGS = ("pixels", "polyline")


def skeleton_graph(skeleton: object) -> tuple[np.ndarray, np.ndarray]:
    """The contour polylines of a thinned contour image as a graph.

    Nodes are the skeleton pixels (row, col); edges join 4-adjacent pixels, and diagonal pixels only
    when no 4-adjacent pixel of the skeleton already links them (a staircase corner is one path, not
    a triangle, so a circle passing the corner is crossed once).

    Parameters
    ----------
    skeleton : array_like, shape (rows, cols), bool
        A thinned contour image (one pixel wide), not empty.

    Returns
    -------
    nodes : numpy.ndarray, shape (n, 2), float
        Pixel positions (row, col) of the skeleton pixels.
    edges : numpy.ndarray, shape (m, 2), int
        Pairs of node indices joined by the contour.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 4 (the contours traced for eq. (9), read here as polylines).
    """
    thin = as_bool_image(skeleton, "skeleton")
    h, w = thin.shape
    index = np.full((h + 2, w + 2), -1, np.int64)
    nodes = np.argwhere(thin)
    index[nodes[:, 0] + 1, nodes[:, 1] + 1] = np.arange(len(nodes))
    on = index >= 0

    def at(d_row: int, d_col: int, array: np.ndarray) -> np.ndarray:
        return array[1 + d_row:1 + d_row + h, 1 + d_col:1 + d_col + w]

    here = at(0, 0, index)
    pairs = []
    for d_row, d_col, keep in [(0, 1, None), (1, 0, None), (1, 1, (0, 1, 1, 0)), (1, -1, (0, -1, 1, 0))]:
        linked = thin & at(d_row, d_col, on)
        if keep is not None:  # diagonal: only if neither shared 4-neighbour is on the skeleton
            linked &= ~at(keep[0], keep[1], on) & ~at(keep[2], keep[3], on)
        pairs.append(np.c_[here[linked], at(d_row, d_col, index)[linked]])
    return nodes.astype(float), np.vstack(pairs)


def smooth_polylines(nodes: np.ndarray, edges: np.ndarray, n_iter: int) -> np.ndarray:
    """Light smoothing along the contours, endings and bifurcations held fixed.

    Each of ``n_iter`` rounds replaces every node of degree 2 (an interior polyline point) by the
    mean of itself and its two neighbours. Endings and bifurcations stay put, so contours neither
    shrink nor come apart.

    Parameters
    ----------
    nodes : array_like, shape (n, 2)
        Node positions (from :func:`skeleton_graph`), finite, not empty.
    edges : array_like, shape (m, 2), int
        Pairs of node indices, each in 0..n-1.
    n_iter : int
        Number of smoothing rounds, >= 0.

    Returns
    -------
    numpy.ndarray, shape (n, 2)
        The smoothed node positions (a new array).

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 4 (beyond the paper: sub-pixel crossings of the circles of eq. (7)).
    """
    n_iter = check_positive_int(n_iter, "n_iter", minimum=0)
    positions = as_finite_array(nodes, "nodes", shape=(None, 2))
    edges = np.asarray(edges)
    if edges.ndim != 2 or edges.shape[1] != 2 or not np.issubdtype(edges.dtype, np.integer):
        raise ValueError(f"edges must be an (m, 2) integer array of node indices, got dtype {edges.dtype}, "
                         f"shape {edges.shape}")
    if edges.size and (edges.min() < 0 or edges.max() >= len(positions)):
        raise ValueError(f"edges must index nodes 0..{len(positions) - 1}, got indices {edges.min()}..{edges.max()}")
    degree = np.bincount(edges.ravel(), minlength=len(positions))
    interior = degree == 2
    for _ in range(n_iter):
        totals = positions.copy()
        np.add.at(totals, edges[:, 0], positions[edges[:, 1]])
        np.add.at(totals, edges[:, 1], positions[edges[:, 0]])
        positions[interior] = totals[interior] / 3.0
    return positions


def _pixel_crossings(array: np.ndarray, norm: Normalisation, radii: np.ndarray,
                     min_gap_px: float) -> tuple[np.ndarray, np.ndarray]:
    """Literal reading: circle index and angle of every run of contour pixels met along each circle."""
    n_samples = int(8 * np.ceil(4 * np.pi * radii[-1] * norm.spread.max() / 8)) + 8
    angles = 2 * np.pi * np.arange(n_samples) / n_samples
    unit = np.c_[np.cos(angles), np.sin(angles)]
    pixels = norm.to_pixels((radii[:, None, None] * unit).reshape(-1, 2)).reshape(len(radii), n_samples, 2)
    rc = np.round(pixels).astype(int)
    inside = (rc[..., 0] >= 0) & (rc[..., 0] < array.shape[0]) & (rc[..., 1] >= 0) & (rc[..., 1] < array.shape[1])
    hits = np.zeros((len(radii), n_samples), bool)
    hits[inside] = array[rc[inside][:, 0], rc[inside][:, 1]]
    arc = np.linalg.norm(np.roll(pixels, -1, axis=1) - pixels, axis=2)  # pixel length of each sample step
    rows, mids = _circle_crossings(_fill_short_gaps(hits, arc, min_gap_px))
    return rows, 2 * np.pi * mids / n_samples


def _polyline_crossings(skeleton: np.ndarray, norm: Normalisation, radii: np.ndarray, smoothing: int,
                        band_px: float) -> tuple[np.ndarray, np.ndarray]:
    """Sub-pixel reading: circle index and angle of every crossing of the (lightly smoothed) skeleton
    polylines with each circle.

    With ``band_px`` = 0 a crossing is a sign change of r(s) - R along an edge, located by linear
    interpolation. With ``band_px`` = h > 0 (pixels) the sign change must go from below R - h to above
    R + h (a dead band, as in a Schmitt trigger): a stretch of contour inside the band counts once if
    it enters from one side and leaves on the other, and not at all if it touches the circle and turns
    back (a graze), so sub-pixel wobble near a tangent point cannot add or remove crossings.
    """
    nodes, edges = skeleton_graph(skeleton)
    xy = norm.to_normalised(smooth_polylines(nodes, edges, smoothing))
    radius = np.linalg.norm(xy, axis=1)
    n_nodes, n_circles = len(xy), len(radii)
    h = band_px / np.sqrt(np.prod(norm.spread))  # pixels -> normalised units (geometric-mean spread)
    side = np.where(radius[:, None] < radii - h, -1, np.where(radius[:, None] >= radii + h, 1, 0))
    a, b = edges[:, 0], edges[:, 1]
    # direct jumps over the whole band (always the case for h = 0)
    edge_index, rows = np.nonzero(side[a] * side[b] == -1)
    ea, eb = a[edge_index], b[edge_index]
    t = (radii[rows] - radius[ea]) / (radius[eb] - radius[ea])
    points = xy[ea] + t[:, None] * (xy[eb] - xy[ea])
    rows_out, theta_out = [rows], [np.arctan2(points[:, 1], points[:, 0])]
    if h > 0:
        # stretches inside the band: connected components of band nodes, one graph per circle
        in_band = side == 0  # (n_nodes, n_circles)
        key = lambda node, circle: circle * n_nodes + node  # noqa: E731
        e_idx, c_idx = np.nonzero(in_band[a] & in_band[b])
        graph = coo_matrix((np.ones(len(e_idx)), (key(a[e_idx], c_idx), key(b[e_idx], c_idx))),
                           shape=(n_nodes * n_circles,) * 2)
        _, component = connected_components(graph, directed=False)
        # edges leaving a band stretch to the inside (-1) or the outside (+1)
        both = np.r_[a, b], np.r_[b, a]
        e_idx, c_idx = np.nonzero(in_band[both[0]] & (side[both[1]] != 0))
        stretch = component[key(both[0][e_idx], c_idx)]
        exits = side[both[1][e_idx], c_idx]
        n_comp = component.max() + 1
        inward = np.bincount(stretch, exits < 0, minlength=n_comp)
        outward = np.bincount(stretch, exits > 0, minlength=n_comp)
        crossing_stretches = np.flatnonzero(np.minimum(inward, outward) > 0)
        count = np.minimum(inward, outward)[crossing_stretches].astype(int)
        band_nodes, band_circles = np.nonzero(in_band)
        band_component = component[key(band_nodes, band_circles)]
        size = np.bincount(band_component, minlength=n_comp)
        centre = np.c_[np.bincount(band_component, xy[band_nodes, 0], n_comp),
                       np.bincount(band_component, xy[band_nodes, 1], n_comp)] / np.maximum(size, 1)[:, None]
        circle_of = np.zeros(n_comp, int)
        circle_of[band_component] = band_circles
        centre = np.repeat(centre[crossing_stretches], count, axis=0)
        rows_out.append(np.repeat(circle_of[crossing_stretches], count))
        theta_out.append(np.arctan2(centre[:, 1], centre[:, 0]))
    return np.concatenate(rows_out), np.concatenate(theta_out) % (2 * np.pi)


def prune_spurs(skeleton: object, length_px: int) -> np.ndarray:
    """Remove side branches shorter than ``length_px`` pixels from a thinned image.

    Spurs are what a ragged contour border leaves after thinning: ``length_px`` rounds of deleting
    end pixels, then the surviving ends regrow along the original skeleton by up to ``length_px``
    pixels, so genuine open contours keep their full length.

    Parameters
    ----------
    skeleton : array_like, shape (rows, cols), bool
        A thinned contour image, not empty.
    length_px : int
        Longest spur removed, pixels, >= 0 (0 returns the skeleton unchanged).

    Returns
    -------
    numpy.ndarray, shape (rows, cols), bool
        The pruned skeleton.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 4 (beyond the paper: endings of eq. (9) that a ragged contour would add).
    """
    thin = as_bool_image(skeleton, "skeleton")
    length = check_positive_int(length_px, "length_px", minimum=0)
    kernel = np.ones((3, 3), np.uint8)

    def ends(mask: np.ndarray) -> np.ndarray:  # one branch (N_c = 1) or isolated (N_c = 0)
        return mask & (_crossing_number(mask) <= 1)

    pruned = thin.copy()
    for _ in range(length):
        pruned &= ~ends(pruned)
    grown = ends(pruned) & (_crossing_number(pruned) == 1)  # ends of the pruned skeleton
    front = grown
    for _ in range(length):
        front = cv2.dilate(front.astype(np.uint8), kernel).astype(bool) & thin & ~pruned & ~grown
        grown |= front
    return pruned | grown


def _circle_polygons(rows: np.ndarray, theta: np.ndarray, radii: np.ndarray
                     ) -> tuple[np.ndarray, np.ndarray, tuple[np.ndarray, ...]]:
    """Counts l_r, closed counter-clockwise polygon perimeters sum d and crossing points per circle."""
    order = np.lexsort((theta, rows))
    rows, theta = rows[order], theta[order]
    n_circles = len(radii)
    crossings = radii[rows, None] * np.c_[np.cos(theta), np.sin(theta)]
    counts = np.bincount(rows, minlength=n_circles)
    # closed polygon per circle: each crossing joined to the next one of the same circle (cyclically)
    first = np.cumsum(counts) - counts
    position = np.arange(len(rows)) - first[rows]
    following = first[rows] + (position + 1) % np.maximum(counts[rows], 1)
    chords = np.linalg.norm(crossings[following] - crossings, axis=1)
    sums = np.where(counts > 1, np.bincount(rows, chords, minlength=n_circles), 0.0)
    return counts, sums, tuple(np.split(crossings, np.cumsum(counts)[:-1]))


def _skeleton(array: np.ndarray) -> np.ndarray:
    """skeletonize inside the contours' bounding box (plus a 1-pixel margin): same result, less to scan."""
    rows, cols = np.flatnonzero(array.any(axis=1)), np.flatnonzero(array.any(axis=0))
    top, left = max(rows[0] - 1, 0), max(cols[0] - 1, 0)
    thin = np.zeros_like(array)
    thin[top:rows[-1] + 2, left:cols[-1] + 2] = skeletonize(array[top:rows[-1] + 2, left:cols[-1] + 2])
    return thin


def circle_features(contours: object, n_circles: int = 8, step: float = 0.25, *, mode: str = "principal",
                    min_gap_px: float = 0.0, crossings: str = "pixels", polyline_smoothing: int = 2,
                    band_px: float = 0.0, spur_length_px: int = 0, skeleton: np.ndarray | None = None,
                    normalisation: Normalisation | None = None) -> CircleFeatures:
    """First feature vector V, eq. (7).

    Circles of radius r_m = m * step (m = 1..n_circles) in *normalised* units (eq. 6) are centred on
    the centroid; our reading of "alpha pixels apart" uses normalised units so that V is scale
    invariant. Two readings of "the contour crosses the circle":

    ``crossings="pixels"`` (the literal one)
        All circles are sampled at the same angles, at least two samples per pixel of the largest
        one; a run of consecutive samples on contour pixels is one intersection (l_r counts runs, so
        a 2-pixel-thick contour crossing the circle counts once). ``min_gap_px`` > 0 first merges
        runs separated by a shorter gap (a ragged contour grazing the circle).
    ``crossings="polyline"`` (sub-pixel)
        The contours are thinned, the skeleton is read as polylines (:func:`skeleton_graph`),
        smoothed (:func:`smooth_polylines`) and intersected with each circle analytically: one
        crossing per sign change of r(s) - R along a contour, so a contour that crosses a circle once
        counts once however ragged its pixels are.

    sum d is the perimeter of the polygon through the intersections taken counter-clockwise, closed
    so that it does not depend on a start angle (0 for fewer than two intersections).

    Parameters
    ----------
    contours : array_like, shape (rows, cols), bool
        Contour image with at least one contour pixel.
    n_circles : int
        Number of circles N_r, >= 1.
    step : float
        Radius step alpha between circles, normalised units, > 0; the first circle must reach into
        the image (step times the larger normalisation spread at most the image diagonal).
    mode : {"principal", "axes", "isotropic"}
        Reading of eq. (6) (see :func:`normalise_coordinates`); unused with ``normalisation``.
    min_gap_px : float
        ``"pixels"`` only: runs closer than this arc length, pixels, are merged; >= 0 (0 is the
        literal count).
    crossings : {"pixels", "polyline"}
        Reading of "the contour crosses the circle", as above.
    polyline_smoothing : int
        ``"polyline"`` only: rounds of :func:`smooth_polylines`, >= 0.
    band_px : float
        ``"polyline"`` only: half-width of the dead band around each circle, pixels, >= 0; a crossing
        must go from below R - band to above R + band, so a graze is not counted.
    spur_length_px : int
        ``"polyline"`` only: spurs shorter than this, pixels, are pruned first (:func:`prune_spurs`).
    skeleton : numpy.ndarray or None
        ``"polyline"`` only: an already thinned image of the contours' shape (saves the thinning).
    normalisation : Normalisation or None
        A given frame in place of eq. (6) on the contour pixels (for instance the silhouette's,
        :func:`~amdo_lab.ear_biometrics.frame.frame_normalisation`).

    Returns
    -------
    CircleFeatures
        V: radii, counts l_r, distance sums, the intersections and the frame.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 3, eq. (6) and Sec. 4, eq. (7), Figs. 5-6.

    Examples
    --------
    A '+' of two one-pixel lines crosses every circle around its centre four times.

    >>> import numpy as np
    >>> from amdo_lab import ear_biometrics as eb
    >>> plus = np.zeros((64, 64), bool)
    >>> plus[32, 8:56] = True
    >>> plus[8:56, 32] = True
    >>> eb.circle_features(plus, n_circles=2, step=0.5, mode="isotropic").counts.tolist()
    [4, 4]
    """
    array = as_contour_image(contours)
    n_circles = check_positive_int(n_circles, "n_circles")
    step = check_positive(step, "step")
    min_gap_px = check_positive(min_gap_px, "min_gap_px", allow_zero=True)
    check_choice(crossings, "crossings", CROSSING_READINGS)
    polyline_smoothing = check_positive_int(polyline_smoothing, "polyline_smoothing", minimum=0)
    band_px = check_positive(band_px, "band_px", allow_zero=True)
    spur_length_px = check_positive_int(spur_length_px, "spur_length_px", minimum=0)
    if normalisation is None:
        norm = normalise_coordinates(array, mode)
    elif isinstance(normalisation, Normalisation):
        norm = normalisation
    else:
        raise TypeError(f"normalisation must be a Normalisation or None, got {type(normalisation).__name__}")
    # the first circle must reach into the image (beyond it every count is 0 and the sampling grows without bound)
    check_in_range(step, "step", 0, np.hypot(*array.shape) / norm.spread.max(), closed="right")
    radii = step * np.arange(1, n_circles + 1)
    if crossings == "pixels":
        rows, theta = _pixel_crossings(array, norm, radii, min_gap_px)
    else:
        thin = _skeleton(array) if skeleton is None else np.asarray(skeleton)
        if thin.shape != array.shape or thin.dtype != bool:
            raise ValueError(f"skeleton must be a boolean image of the contours' shape {array.shape}, "
                             f"got dtype {thin.dtype}, shape {thin.shape}")
        rows, theta = _polyline_crossings(prune_spurs(thin, spur_length_px), norm, radii, polyline_smoothing, band_px)
    counts, sums, points = _circle_polygons(rows, theta, radii)
    return CircleFeatures(radii, counts, sums, points, norm)


def circle_features_reference(contours: object, n_circles: int = 8, step: float = 0.25) -> CircleFeatures:
    """Eqs. (6)-(7) written out in plain numpy, one circle at a time: the reading to open beside the paper.

    Literal eq. 6 (the image axes, ``mode="axes"``) and the literal count (every run of contour
    pixels met along a sampled circle is one intersection, ``crossings="pixels"``,
    ``min_gap_px=0``); :func:`circle_features` with those settings is the vectorised path and is
    tested equal to this.

    Parameters
    ----------
    contours : array_like, shape (rows, cols), bool
        Contour image with at least one contour pixel.
    n_circles : int
        Number of circles N_r, >= 1.
    step : float
        Radius step alpha between circles, normalised units, > 0; the first circle must reach into
        the image (step times the larger normalisation spread at most the image diagonal).

    Returns
    -------
    CircleFeatures
        V: radii, counts l_r, distance sums, the intersections and the frame of eq. (6).

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 3, eq. (6) and Sec. 4, eq. (7).
    """
    array = as_contour_image(contours)
    n_circles = check_positive_int(n_circles, "n_circles")
    step = check_positive(step, "step")
    rows_cols = np.argwhere(array).astype(float)
    # eq. 6: the centroid (I, J) becomes the origin; each axis is divided by its standard deviation
    centroid = rows_cols.mean(axis=0)  # (I, J)
    sigma = rows_cols.std(axis=0)  # (sigma_i, sigma_j)
    norm = Normalisation(centroid, sigma, _image_axes_matrix(sigma))  # x = (j - J)/sigma_j, y = -(i - I)/sigma_i
    check_in_range(step, "step", 0, np.hypot(*array.shape) / sigma.max(), closed="right")  # as in circle_features
    radii = step * np.arange(1, n_circles + 1)  # r_m = m * alpha, normalised units
    n_samples = int(8 * np.ceil(4 * np.pi * radii[-1] * sigma.max() / 8)) + 8  # >= 2 samples per pixel
    angles = 2 * np.pi * np.arange(n_samples) / n_samples
    counts, sums, points = [], [], []
    for r in radii:
        # the circle of radius r around the centroid, back in pixels (inverse of eq. 6)
        circle_xy = r * np.c_[np.cos(angles), np.sin(angles)]
        pixel = np.round(norm.to_pixels(circle_xy)).astype(int)
        inside = np.all((pixel >= 0) & (pixel < array.shape), axis=1)
        on_contour = np.zeros(n_samples, bool)
        on_contour[inside] = array[pixel[inside, 0], pixel[inside, 1]]
        # l_r (eq. 7): runs of consecutive samples on contour pixels, the circle read as closed
        if on_contour.all():
            middles = np.array([0.0])
        else:
            start = np.argmin(on_contour)  # begin on a sample off the contour: no run wraps around
            rolled = np.roll(on_contour, -start)
            edges = np.diff(np.r_[0, rolled.astype(int), 0])
            first, last = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1
            middles = ((first + last) / 2 + start) % n_samples
        middles = np.sort(middles)
        crossing_xy = r * np.c_[np.cos(2 * np.pi * middles / n_samples), np.sin(2 * np.pi * middles / n_samples)]
        # sum d (eq. 7): distances between neighbouring intersections, counter-clockwise, closed
        if len(crossing_xy) > 1:
            chords = np.linalg.norm(np.roll(crossing_xy, -1, axis=0) - crossing_xy, axis=1)
            sums.append(chords.sum())
        else:
            sums.append(0.0)
        counts.append(len(crossing_xy))
        points.append(crossing_xy)
    return CircleFeatures(radii, np.array(counts), np.array(sums), tuple(points), norm)


def crossing_number(skeleton: np.ndarray) -> np.ndarray:
    """The 8-connected crossing number N_c of every skeleton pixel (eq. 8, Fig. 7).

    N_c = 1/2 sum_k |p_{k+1} - p_k| over the 8 neighbours p_1..p_8 in cyclic order: 1 at an ending,
    2 along a contour, 3 or more at a bifurcation.

    Parameters
    ----------
    skeleton : array_like, shape (rows, cols), bool
        A thinned contour image, not empty.

    Returns
    -------
    numpy.ndarray, shape (rows, cols), int
        N_c on the skeleton, 0 off it.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 4, eq. (8) and Fig. 7.
    """
    thin = as_bool_image(skeleton, "skeleton")
    return _crossing_number(thin)


def _crossing_number(skeleton: np.ndarray) -> np.ndarray:
    """:func:`crossing_number` of a validated skeleton (the spur pruning loop's inner call)."""
    padded = np.pad(skeleton.astype(np.int8), 1)
    h, w = skeleton.shape
    ring = [(0, 1), (0, 2), (1, 2), (2, 2), (2, 1), (2, 0), (1, 0), (0, 0)]  # N, NE, E, SE, S, SW, W, NW
    neighbours = np.stack([padded[r:r + h, c:c + w] for r, c in ring])
    # eq. (8): N_c = 1/2 Σ_k |p_{k+1} - p_k| around the ring, p_9 = p_1
    transitions = np.abs(np.diff(np.concatenate([neighbours, neighbours[:1]]), axis=0)).sum(axis=0) // 2
    return np.where(skeleton, transitions, 0)


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
                      band_px: float = 0.0, spur_length_px: int = 0,
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
        Number of circles N_r, >= 1.
    step : float
        Radius step between circles, normalised units, > 0, as in :func:`circle_features`.
    mode : {"principal", "axes", "isotropic"}
        Reading of eq. (6); unused with ``normalisation``.
    min_gap_px : float
        As in :func:`circle_features`, pixels, >= 0.
    crossings : {"pixels", "polyline"}
        As in :func:`circle_features`.
    polyline_smoothing : int
        As in :func:`circle_features`, >= 0.
    band_px : float
        As in :func:`circle_features`, pixels, >= 0.
    spur_length_px : int
        As in :func:`circle_features`, pixels, >= 0.
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
    full_skeleton = _skeleton(array)
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
    n_c = _crossing_number(thin)  # eq. (8): 1 at an ending, 3 or more at a bifurcation
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
