"""Polar limb representation (Sec. 3): limb centres c_k, articulation centre U, angles theta_k.

The public functions validate their input; the recogniser calls the unchecked ``_`` versions on
shapes it has already validated.
"""

from __future__ import annotations

import numpy as np

from amdo_lab.common import as_finite_array

#: Largest accepted magnitude of a coordinate or feature: squares and sums of squares of larger
#: numbers (covariances, distances, centroid sizes) overflow float64 (max about 1.8e308).
MAX_MAGNITUDE = 1e150

__all__ = ["limb_centres", "articulation_centre", "limb_angles", "wrap_angle", "polar_shape_vector"]


def _check_shapes(shapes: object) -> np.ndarray:
    return as_finite_array(shapes, "shapes", shape=(None, None, None, 2), max_abs=MAX_MAGNITUDE)


def _check_centres(centres: object) -> np.ndarray:
    return as_finite_array(centres, "centres", shape=(None, None, 2), max_abs=MAX_MAGNITUDE)


def wrap_angle(angles: np.ndarray) -> np.ndarray:
    """Wrap angles in radians to (-pi, pi] (the paper's (-180, 180] degrees).

    Parameters
    ----------
    angles : array_like of float
        Angles in radians, any shape (empty allowed), finite.

    Returns
    -------
    numpy.ndarray
        The same angles mapped into (-pi, pi], same shape; -pi itself maps to pi.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 3 (limb angles in (-180, 180] degrees).
    """
    angles = as_finite_array(angles, "angles", allow_empty=True)
    wrapped = np.mod(angles + np.pi, 2 * np.pi) - np.pi
    return np.where(wrapped == -np.pi, np.pi, wrapped)


def limb_centres(shapes: np.ndarray) -> np.ndarray:
    """Centre of gravity ``c_k`` of each limb's landmarks.

    Parameters
    ----------
    shapes : (n, K, m, 2) array_like
        ``n`` shapes of ``K`` limbs with ``m`` landmarks each, (x, y) in the shapes' units.

    Returns
    -------
    numpy.ndarray
        Limb centres ``(n, K, 2)``, ``c_k = (1/m) sum_i (x_i^k, y_i^k)``.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 3 (limb centre of gravity).
    """
    return _limb_centres(_check_shapes(shapes))


def _limb_centres(shapes: np.ndarray) -> np.ndarray:
    return shapes.mean(axis=-2)


def articulation_centre(centres: np.ndarray) -> np.ndarray:
    """Centre of articulation ``U``: the mean of the limb centres.

    Parameters
    ----------
    centres : (n, K, 2) array_like
        Limb centres ``c_k`` of ``n`` shapes (as from :func:`limb_centres`).

    Returns
    -------
    numpy.ndarray
        ``U = (1/K) sum_k c_k`` of every shape, ``(n, 2)``.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 3 (centre of articulation).
    """
    return _articulation_centre(_check_centres(centres))


def _articulation_centre(centres: np.ndarray) -> np.ndarray:
    return centres.mean(axis=-2)


def limb_angles(centres: np.ndarray) -> np.ndarray:
    """Polar limb angles ``theta_k = atan2(U_y - c_ky, U_x - c_kx)`` about the centre of articulation.

    The paper writes ``tan^-1`` of the ratio; the quadrant-aware ``atan2`` is needed to cover
    (-180, 180] degrees as the text requires.

    Parameters
    ----------
    centres : (n, K, 2) array_like
        Limb centres ``c_k`` of ``n`` shapes.

    Returns
    -------
    numpy.ndarray
        Angles ``theta_k`` in radians, in (-pi, pi], ``(n, K)``.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 3 (limb angles theta_k).
    """
    return _limb_angles(_check_centres(centres))


def _limb_angles(centres: np.ndarray) -> np.ndarray:
    offsets = _articulation_centre(centres)[..., None, :] - centres
    return wrap_angle(np.arctan2(offsets[..., 1], offsets[..., 0]))


def polar_shape_vector(shapes: np.ndarray) -> np.ndarray:
    """Polar shape vector ``S = (Theta^T, C^T)^T`` of each shape: limb angles, then limb centres.

    Parameters
    ----------
    shapes : (n, K, m, 2) array_like
        ``n`` shapes of ``K`` limbs with ``m`` landmarks each.

    Returns
    -------
    numpy.ndarray
        ``(n, 3K)``: the ``K`` angles ``theta_k`` in radians (in (-pi, pi]), then the ``2K``
        flattened limb centres ``(c_1x, c_1y, ..., c_Kx, c_Ky)`` in the shapes' units.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 3 (the vector S).
    """
    centres = _limb_centres(_check_shapes(shapes))
    return np.concatenate([_limb_angles(centres), centres.reshape(centres.shape[0], -1)], axis=1)


def _centred_limbs(shapes: np.ndarray) -> np.ndarray:
    """Limb long-vectors ``X_k`` with the limb centre removed, what the limb PDMs model: ``(n, K, 2m)``
    from checked shapes ``(n, K, m, 2)``, each limb's ``(x_1 - c_x, y_1 - c_y, ..., x_m - c_x, y_m - c_y)``."""
    centred = shapes - _limb_centres(shapes)[..., None, :]
    return centred.reshape(shapes.shape[0], shapes.shape[1], -1)
