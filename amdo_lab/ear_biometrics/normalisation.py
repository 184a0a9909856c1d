"""Eq. (6) of Choraś (AMDO 2004), Sec. 3: the centroid of the contour pixels as origin, each axis divided
by its spread; three readings of the per-axis division."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common import as_finite_array, check_choice
from amdo_lab.ear_biometrics.images import as_contour_image

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
    return as_finite_array(np.atleast_2d(points), name, shape=(None, 2), allow_empty=True, max_abs=MAX_COORDINATE)


def _image_axes_matrix(spread: np.ndarray) -> np.ndarray:
    # x to the right (columns), y up (minus rows), each divided by its sigma
    return np.array([[0.0, 1.0 / spread[1]], [-1.0 / spread[0], 0.0]])


def check_spread(variances: np.ndarray, name: str) -> None:
    """Refuse points that lie on one straight line: the smaller variance is (nearly) zero.

    Parameters
    ----------
    variances : numpy.ndarray, shape (2,)
        The two variances (eigenvalues of the points' covariance, or per-axis variances), ascending.
    name : str
        The argument the points come from, for the error message.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 3, eq. (6) (each axis is divided by its spread).
    """
    if variances[0] <= 1e-12 * variances[1]:
        raise ValueError(f"{name} must not lie on a single straight line (no spread across it)")


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
    check_spread(np.sort(spread**2), "contours")  # a single row or column: no spread to divide by
    if mode == "axes":
        return Normalisation(centroid, spread, _image_axes_matrix(spread))
    if mode == "isotropic":
        spread = np.full(2, np.sqrt(np.mean(spread**2)))
        return Normalisation(centroid, spread, _image_axes_matrix(spread))
    variances, vectors = np.linalg.eigh(np.cov(offsets.T, bias=True))  # ascending: minor, major
    check_spread(variances, "contours")
    projected = offsets @ vectors  # (n, 2): along minor, major axis
    signs = np.where(np.mean(projected**3, axis=0) < 0, -1.0, 1.0)  # positive skewness on both axes
    spread = np.sqrt(variances)
    matrix = (vectors * signs).T / spread[:, None]  # row m: unit axis m (signed) / sigma_m
    return Normalisation(centroid, spread, matrix)
