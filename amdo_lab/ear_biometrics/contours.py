"""Contour detection of Choraś (AMDO 2004), Sec. 2, eqs. (1)-(5); the clean-up of Fig. 3; Canny as a peer."""

from __future__ import annotations

import cv2
import numpy as np

from amdo_lab.common import check_in_range, check_odd_int, check_positive_int
from amdo_lab.ear_biometrics.images import as_bool_image, as_grey_image

MAX_K = 1e6
"""Largest multiple k of sigma in eq. (4): far beyond the paper's 6-10, and small enough that k sigma
stays finite for every grey level up to :data:`~amdo_lab.ear_biometrics.images.MAX_GREY_LEVEL`."""

MAX_WINDOW = 99
"""Largest window side n of eqs. (1)-(3), pixels (the paper uses 3)."""

MAX_CLOSING_PX = 64
"""Largest half-width of the closing square of :func:`clean_contours`, pixels: it bridges gaps of a
few pixels; a wider one fills the whole ear."""

CANNY_SIGMA = 1.5
"""Gaussian blur before the Canny peer, pixels: the matcher's own blur."""

CANNY_THRESHOLDS = (20.0, 50.0)
"""Hysteresis thresholds of the Canny peer, grey levels per pixel (OpenCV's gradient magnitude)."""


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
        The threshold's multiple of sigma in eq. (4), in [0, :data:`MAX_K`]; larger finds more contour
        pixels.
    window : int
        Side n of the square window, odd, from 3 to :data:`MAX_WINDOW`.

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
    grey, k, window = _check_detector_input(image, k, window)
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


def _check_detector_input(image: object, k: object, window: object) -> tuple[np.ndarray, float, int]:
    """The grey image, k and window of eqs. (1)-(5), checked once for both detectors."""
    grey = as_grey_image(image)
    k = check_in_range(k, "k", 0, MAX_K, closed="both")
    window = check_odd_int(window, "window", maximum=MAX_WINDOW)
    return grey, k, window


def detect_contours_reference(image: object, k: float = 8.0, window: int = 3) -> np.ndarray:
    """:func:`detect_contours` written plainly: one window at a time, eqs. (1)-(5) line by line.

    The readable path of the filtered :func:`detect_contours` (tested equal to it); a Python loop
    over the pixels, so for small images only.

    Parameters
    ----------
    image : array_like, shape (rows, cols)
        Grey levels, as :func:`as_grey_image` accepts them.
    k : float
        The threshold's multiple of sigma in eq. (4), in [0, :data:`MAX_K`].
    window : int
        Side n of the square window, odd, from 3 to :data:`MAX_WINDOW`.

    Returns
    -------
    numpy.ndarray, shape (rows, cols), bool
        True on contour pixels.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 2, eqs. (1)-(5).
    """
    grey, k, window = _check_detector_input(image, k, window)
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
        Smallest fragment kept, pixels, from 1 to the number of pixels of the image.
    closing : int
        Half-width of the closing square, pixels, from 0 (no closing) to :data:`MAX_CLOSING_PX`.

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
    min_size = check_positive_int(min_size, "min_size", maximum=array.size)
    closing = check_positive_int(closing, "closing", minimum=0, maximum=MAX_CLOSING_PX)
    if closing:
        kernel = np.ones((2 * closing + 1,) * 2, np.uint8)
        padded = np.pad(array.astype(np.uint8), closing)  # zero border, as binary closing with border 0
        closed = cv2.morphologyEx(padded, cv2.MORPH_CLOSE, kernel, borderType=cv2.BORDER_CONSTANT, borderValue=0)
        array = closed[closing:-closing, closing:-closing].astype(bool)
    _, labels, stats, _ = cv2.connectedComponentsWithStats(array.astype(np.uint8), connectivity=8)
    keep = stats[:, cv2.CC_STAT_AREA] >= min_size
    keep[0] = False
    return keep[labels]


def canny_contours(image: object) -> np.ndarray:
    """Peer contour detector: OpenCV's Canny after a Gaussian blur of :data:`CANNY_SIGMA` pixels.

    The hysteresis thresholds are :data:`CANNY_THRESHOLDS`.

    Parameters
    ----------
    image : array_like, shape (rows, cols)
        Grey levels on the 0-255 scale, as :func:`as_grey_image`
        accepts them.

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
    smooth = cv2.GaussianBlur(as_grey_image(image), (0, 0), CANNY_SIGMA)
    return cv2.Canny(np.clip(smooth, 0, 255).astype(np.uint8), *CANNY_THRESHOLDS) > 0
