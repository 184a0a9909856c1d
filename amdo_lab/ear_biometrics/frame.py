"""A canonical frame for ear images: centroid, principal axis and scale from second moments, the
180-degree ambiguity settled by the third moment, applied to the image *before* contour detection.

Choraś (AMDO 2004, Sec. 3, eq. 6) makes the features invariant by moving the origin to the centroid
of the contour pixels and dividing by their spread. That normalises the contour pixels *after* they
were detected, and the detector works on a pixel grid: a rotated, rescaled or shifted copy of the
same ear is resampled, so its detected contours (and hence its features) differ. Here the image
itself is first brought into a frame fixed by the ear: the centroid goes to the image centre, the
principal axis to the image's vertical axis, the spread to a fixed number of pixels. The contour
detector then sees every copy of an ear at the same position, orientation and size.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from amdo_lab.common import MAX_SIDE, as_finite_array, check_choice, check_in_range, make_rng
from amdo_lab.ear_biometrics.images import as_bool_image, as_grey_image, check_record
from amdo_lab.ear_biometrics.normalisation import NORMALISATION_MODES, Normalisation, check_spread

FRAME_SOURCES = ("image", "silhouette", "contours")
"""Where the canonical frame comes from: ``"image"`` (none: the image as given, the paper's
pipeline), ``"silhouette"`` (the ear's silhouette against the background) or ``"contours"`` (the
contour pixels detected in the given image)."""

CANONICAL_SPREAD = 0.18
"""Root of the summed second moments of the silhouette in the canonical image, as a fraction of the
image side (a little below the spread of an ear drawn at scale 1 by the generator, so that the most
elongated ears still fit the image and detection runs at about the resolution of a capture)."""

SILHOUETTE_BLUR_PX = 2.0
"""Standard deviation of the Gaussian blur before the silhouette's threshold, pixels."""

SILHOUETTE_CLOSING_PX = 7
"""Side of the elliptic closing element that seals the silhouette's seams, pixels."""

MAX_SCALE = 10.0
"""Largest scale factor of :func:`similarity_copy`: a copy ten times larger shows another part of the scene."""


@dataclass(frozen=True)
class CanonicalFrame:
    """The similarity that maps an image onto its canonical frame.

    Parameters
    ----------
    centroid : numpy.ndarray, shape (2,)
        Centroid (row, col) of the mask in the given image, pixels.
    axis : numpy.ndarray, shape (2,)
        Unit (row, col) vector of the signed principal axis in the given image.
    spread : float
        sqrt(lambda_1 + lambda_2) of the mask's pixel covariance, pixels.
    elongation : float
        sqrt(lambda_major / lambda_minor), >= 1.
    third_moment : float
        Skewness along ``axis``, >= 0 by construction (it fixes the axis's sign).
    matrix : numpy.ndarray, shape (2, 3)
        Affine map from given (x = col, y = row) to canonical (x, y) coordinates, as
        ``cv2.warpAffine`` takes it.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 3, eq. (6). Beyond the paper: its Sec. 3 moments (eq. 6) taken of the silhouette and applied to the image.
    """

    centroid: np.ndarray
    axis: np.ndarray
    spread: float
    elongation: float  # sqrt(lambda_major / lambda_minor)
    third_moment: float
    matrix: np.ndarray

    @property
    def angle_deg(self) -> float:
        """Angle of ``axis`` from the image's downward vertical, degrees, counter-clockwise as displayed."""
        return float(np.degrees(np.arctan2(self.axis[1], self.axis[0])))


def silhouette(image: np.ndarray) -> np.ndarray:
    """The ear's silhouette: pixels that differ from the background level, largest part, holes filled.

    The background level is the median of the image border. Skin is brighter and grooves darker than
    the background, so the absolute difference (after a Gaussian blur of :data:`SILHOUETTE_BLUR_PX`
    pixels) is thresholded by Otsu's rule; an elliptic closing (:data:`SILHOUETTE_CLOSING_PX`) seals the thin seams
    where a blurred groove passes through the background level; the largest 8-connected part is kept
    and its holes filled. Assumes a cropped ear in front of a roughly even background. An 8-bit
    image is blurred in 8 bits (fast); a float one in float32 (the masks can differ by rounding).

    Parameters
    ----------
    image : array_like, shape (rows, cols)
        Grey levels, as :func:`~amdo_lab.ear_biometrics.images.as_grey_image` accepts them.

    Returns
    -------
    numpy.ndarray, shape (rows, cols), bool
        The silhouette (all False when nothing stands out from the background).

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 3. Beyond the paper: its Sec. 3 moments (eq. 6) taken of the silhouette and applied to the image.
    N. Otsu, "A Threshold Selection Method from Gray-Level Histograms", IEEE SMC 9(1), 1979.
    """
    grey = as_grey_image(image)
    array = np.asarray(image) if np.asarray(image).dtype == np.uint8 else grey.astype(np.float32)
    blurred = cv2.GaussianBlur(array, (0, 0), SILHOUETTE_BLUR_PX)
    border = np.r_[blurred[0], blurred[-1], blurred[:, 0], blurred[:, -1]]
    level = np.median(border)
    if blurred.dtype == np.uint8:  # |I - level| in 8 bits without a float pass
        level = int(round(float(level)))
        difference = cv2.absdiff(blurred, np.full_like(blurred, level))
    else:
        difference = np.clip(np.abs(blurred - level), 0, 255).astype(np.uint8)
    _, mask = cv2.threshold(difference, 0, 1, cv2.THRESH_BINARY + cv2.THRESH_OTSU)
    element = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (SILHOUETTE_CLOSING_PX,) * 2)
    mask = cv2.morphologyEx(mask, cv2.MORPH_CLOSE, element)
    n, labels, stats, _ = cv2.connectedComponentsWithStats(mask, connectivity=8)
    if n < 2:
        return np.zeros(mask.shape, bool)
    largest = (labels == 1 + np.argmax(stats[1:, cv2.CC_STAT_AREA])).astype(np.uint8)
    outside = np.pad(1 - largest, 1, constant_values=1)
    cv2.floodFill(outside, None, (0, 0), 2)  # background reachable from the border
    return outside[1:-1, 1:-1] != 2


def moment_frame(mask: np.ndarray, shape: tuple[int, int]) -> CanonicalFrame:
    """Canonical frame of a binary ``mask`` from its moments (plain-numpy reference).

    The moments of the paper's Sec. 3, applied to the image rather than to the contour pixels.
    Centroid c = mean of the pixel positions p; covariance C = mean (p - c)(p - c)^T with
    eigenvalues lambda_minor <= lambda_major and major eigenvector e; spread s = sqrt(lambda_minor +
    lambda_major) (rotation invariant, scales with the ear). The eigenvector's sign is arbitrary (a
    180-degree ambiguity): we take the sign for which the third moment mean(((p - c) . e)^3) is
    positive, i.e. e points towards the longer tail of the shape. The map sends c to the centre of
    an image of ``shape``, e to the downward vertical, and scales by :data:`CANONICAL_SPREAD` * side / s.

    Parameters
    ----------
    mask : array_like, shape (rows, cols), bool
        The silhouette (or contours): at least 3 pixels, not on one straight line.
    shape : tuple of int
        (rows, cols) of the canonical image, each from 8 to ``MAX_SIDE`` (4,096).

    Returns
    -------
    CanonicalFrame
        Centroid, signed axis, spread, elongation, third moment and the 2 x 3 map.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 3, eq. (6). Beyond the paper: its Sec. 3 moments (eq. 6) taken of the silhouette and applied to the image.
    """
    mask, shape = _check_mask(mask), _check_shape(shape)
    pixels = np.argwhere(mask).astype(float)  # (n, 2) row, col
    centroid = pixels.mean(axis=0)
    offsets = pixels - centroid
    variances, vectors = np.linalg.eigh(offsets.T @ offsets / len(offsets))  # ascending
    check_spread(variances, "mask")
    axis = vectors[:, 1]
    along = offsets @ axis
    third = float(np.mean(along**3) / variances[1] ** 1.5)
    return _frame(centroid, axis, variances, third, shape)


def _check_mask(mask: object) -> np.ndarray:
    """A boolean image with at least 3 pixels set (fewer define no frame)."""
    mask = as_bool_image(mask, "mask")
    if np.count_nonzero(mask) < 3:
        raise ValueError("mask must hold at least 3 pixels to define a frame (no ear found?)")
    return mask


def _check_shape(shape: object) -> tuple[int, int]:
    """(rows, cols) of a canonical image, each from 8 to ``MAX_SIDE`` pixels."""
    return tuple(int(v) for v in as_finite_array(shape, "shape", shape=(2,), dtype=int, bounds=(8, MAX_SIDE)))


def moment_frame_fast(mask: np.ndarray, shape: tuple[int, int]) -> CanonicalFrame:
    """:func:`moment_frame` from OpenCV's image moments (the fast path the matcher uses).

    The same centroid, covariance and third moment as the plain-numpy reference, from the central
    moments mu_pq (x = col, y = row) without listing the pixels; tested equal to :func:`moment_frame`.

    Parameters
    ----------
    mask : array_like, shape (rows, cols), bool
        The silhouette (or contours): at least 3 pixels, not on one straight line.
    shape : tuple of int
        (rows, cols) of the canonical image, each from 8 to ``MAX_SIDE`` (4,096).

    Returns
    -------
    CanonicalFrame
        Centroid, signed axis, spread, elongation, third moment and the 2 x 3 map.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 3, eq. (6). Beyond the paper: its Sec. 3 moments (eq. 6) taken of the silhouette and applied to the image.
    """
    mask, shape = _check_mask(mask), _check_shape(shape)
    m = cv2.moments(mask.astype(np.uint8), binaryImage=True)
    n = m["m00"]
    centroid = np.array([m["m01"], m["m10"]]) / n  # (row, col)
    covariance = np.array([[m["mu02"], m["mu11"]], [m["mu11"], m["mu20"]]]) / n  # (row, col)
    variances, vectors = np.linalg.eigh(covariance)
    check_spread(variances, "mask")
    axis = vectors[:, 1]
    r, c = axis
    # E[((p - centroid) . axis)^3] expanded in the third-order central moments
    third = (c**3 * m["mu30"] + 3 * c**2 * r * m["mu21"] + 3 * c * r**2 * m["mu12"] + r**3 * m["mu03"]) / n
    third /= variances[1] ** 1.5
    return _frame(centroid, axis, variances, float(third), shape)


def _frame(centroid: np.ndarray, axis: np.ndarray, variances: np.ndarray, third: float,
           shape: tuple[int, int]) -> CanonicalFrame:
    """The similarity sending ``centroid`` to the image centre, ``axis`` to the downward vertical and
    the total spread sqrt(sum of ``variances``) to :data:`CANONICAL_SPREAD` * side; ``axis`` is first
    turned towards the longer tail (``third``, the third moment along it, made positive)."""
    if third < 0:  # the 180-degree ambiguity: point the axis towards the longer tail
        axis, third = -axis, -third
    spread = float(np.sqrt(variances.sum()))
    scale = CANONICAL_SPREAD * min(shape) / spread
    # rotation taking the axis (row, col) = (cos, sin) to (1, 0), written in (x, y) = (col, row)
    cos, sin = axis[0], axis[1]
    rotation = np.array([[cos, -sin], [sin, cos]])
    centre = np.array([shape[1], shape[0]]) / 2.0
    linear = scale * rotation
    matrix = np.c_[linear, centre - linear @ centroid[::-1]]
    return CanonicalFrame(centroid, axis, spread, float(np.sqrt(variances[1] / variances[0])), third, matrix)


def to_canonical(image: np.ndarray, frame: CanonicalFrame) -> np.ndarray:
    """Resample ``image`` into its canonical frame (bilinear, border replicated, same size and dtype).

    When the frame shrinks the image (scale s < 1) it is first blurred with a Gaussian of
    sigma = 0.5 sqrt(1/s^2 - 1) pixels (anti-aliasing), so a copy that was larger to begin with is not
    sampled more coarsely than the original.

    Parameters
    ----------
    image : array_like, shape (rows, cols)
        Grey levels, as :func:`~amdo_lab.ear_biometrics.images.as_grey_image` accepts them.
    frame : CanonicalFrame
        The frame (from :func:`moment_frame`).

    Returns
    -------
    numpy.ndarray, shape (rows, cols)
        The resampled image, of ``image``'s dtype.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 3. Beyond the paper: its Sec. 3 moments (eq. 6) taken of the silhouette and applied to the image.
    """
    as_grey_image(image)
    check_record(frame, "frame", CanonicalFrame, "moment_frame")
    array = np.asarray(image)
    scale = float(np.sqrt(abs(np.linalg.det(frame.matrix[:, :2]))))
    if scale < 1:
        array = cv2.GaussianBlur(array, (0, 0), 0.5 * np.sqrt(1 / scale**2 - 1))
    return cv2.warpAffine(array, frame.matrix, (array.shape[1], array.shape[0]), flags=cv2.INTER_LINEAR,
                          borderMode=cv2.BORDER_REPLICATE)


def frame_normalisation(frame: CanonicalFrame, shape: tuple[int, int], mode: str = "principal") -> Normalisation:
    """Eq. (6) with the silhouette's moments instead of the contour pixels', in the canonical image.

    In the canonical image of ``shape`` the silhouette's centroid is the image centre, its major axis
    the vertical and its total spread S = :data:`CANONICAL_SPREAD` * side. ``mode="principal"`` or
    ``"axes"`` divide the vertical by the spread along the major axis and the horizontal by the one
    along the minor axis (their ratio is the frame's elongation e: sigma_minor = S / sqrt(1 + e^2),
    sigma_major = e sigma_minor), as eq. 6 divides each axis by its own sigma; ``"isotropic"``
    divides both by S / sqrt(2). Normalised y points up the image (away from the longer tail).

    Parameters
    ----------
    frame : CanonicalFrame
        The silhouette's frame (from :func:`moment_frame`).
    shape : tuple of int
        (rows, cols) of the canonical image, each from 8 to ``MAX_SIDE`` (4,096).
    mode : {"principal", "axes", "isotropic"}
        Reading of eq. (6), as above.

    Returns
    -------
    Normalisation
        The frame of eq. (6) in the canonical image.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 3, eq. (6).
    """
    check_record(frame, "frame", CanonicalFrame, "moment_frame")
    check_choice(mode, "mode", NORMALISATION_MODES)
    shape = _check_shape(shape)
    total = CANONICAL_SPREAD * min(shape)
    if mode == "isotropic":
        spread = np.full(2, total / np.sqrt(2))
    else:
        minor = total / np.sqrt(1 + frame.elongation**2)
        spread = np.array([frame.elongation * minor, minor])  # (rows = major axis, cols = minor axis)
    centre = np.array([shape[0], shape[1]]) / 2.0
    matrix = np.array([[0.0, 1.0 / spread[1]], [-1.0 / spread[0], 0.0]])  # x right, y up
    return Normalisation(centre, spread, matrix)


def similarity_copy(image: object, *, rng: int | np.random.Generator, max_rotation_deg: float = 25.0,
                    scale_range: tuple[float, float] = (0.85, 1.15), max_shift_px: float = 8.0,
                    rotation_deg: float | None = None) -> np.ndarray:
    """A copy of ``image`` turned about its centre, rescaled and shifted.

    This is how a user's camera would present the same ear: rotation uniform in
    +-``max_rotation_deg`` (or exactly ``rotation_deg``), scale uniform in ``scale_range``, shift
    uniform in +-``max_shift_px`` pixels per axis; bilinear interpolation (``cv2.warpAffine``),
    border replicated.

    Parameters
    ----------
    image : array_like, shape (rows, cols)
        Grey levels, as :func:`~amdo_lab.ear_biometrics.images.as_grey_image` accepts them.
    rng : int or numpy.random.Generator
        Seed or generator of the rotation, scale and shift; a generator is advanced (the rotation is
        drawn even when ``rotation_deg`` is given, so the stream does not depend on it).
    max_rotation_deg : float
        Largest rotation, degrees, in [0, 180].
    scale_range : tuple of float
        (low, high) of the scale factor, 0 < low <= high <= :data:`MAX_SCALE`.
    max_shift_px : float
        Largest shift per axis, pixels, >= 0 and at most the image's larger side.
    rotation_deg : float or None
        A fixed rotation, degrees, in place of the drawn one.

    Returns
    -------
    numpy.ndarray, shape (rows, cols)
        The transformed copy, of ``image``'s dtype.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 3 (the invariance to rotation, scale and shift that eq. (6) is meant to give).
    """
    as_grey_image(image)
    array = np.asarray(image)
    rng = make_rng(rng, "rng")
    check_in_range(max_rotation_deg, "max_rotation_deg", 0, 180, closed="both")
    low, high = as_finite_array(scale_range, "scale_range", shape=(2,), bounds=(0, MAX_SCALE), closed="right")
    if low > high:
        raise ValueError(f"scale_range must be (low, high) with low <= high, got {tuple(scale_range)}")
    check_in_range(max_shift_px, "max_shift_px", 0, max(array.shape), closed="both")
    angle = rng.uniform(-max_rotation_deg, max_rotation_deg)
    if rotation_deg is not None:
        angle = float(as_finite_array(rotation_deg, "rotation_deg", ndim=0))
    centre = ((array.shape[1] - 1) / 2, (array.shape[0] - 1) / 2)  # the middle of the pixel grid
    matrix = cv2.getRotationMatrix2D(centre, angle, rng.uniform(low, high))
    matrix[:, 2] += rng.uniform(-max_shift_px, max_shift_px, 2)
    return cv2.warpAffine(array, matrix, (array.shape[1], array.shape[0]), flags=cv2.INTER_LINEAR,
                          borderMode=cv2.BORDER_REPLICATE)
