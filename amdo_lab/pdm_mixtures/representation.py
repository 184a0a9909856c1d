"""Polar limb representation (Sec. 3): limb centres c_k, articulation centre U, angles theta_k.

The public functions validate their input; the recogniser calls the unchecked ``_`` versions on
shapes it has already validated.
"""

from __future__ import annotations

import numpy as np

from amdo_lab.common import as_finite_array

__all__ = ["limb_centres", "articulation_centre", "limb_angles", "wrap_angle", "polar_shape_vector", "centred_limbs"]


def _check_shapes(shapes: object) -> np.ndarray:
    return as_finite_array(shapes, "shapes", shape=(None, None, None, 2))


def _check_centres(centres: object) -> np.ndarray:
    return as_finite_array(centres, "centres", shape=(None, None, 2))


def wrap_angle(angles: np.ndarray) -> np.ndarray:
    """Wrap radians to (-pi, pi] (the paper's (-180, 180] degrees)."""
    return _wrap_angle(as_finite_array(angles, "angles", allow_empty=True))


def _wrap_angle(angles: np.ndarray) -> np.ndarray:
    wrapped = np.mod(angles + np.pi, 2 * np.pi) - np.pi
    return np.where(wrapped == -np.pi, np.pi, wrapped)


def limb_centres(shapes: np.ndarray) -> np.ndarray:
    """Centre of gravity of each limb's landmarks: ``(n, K, m, 2) -> (n, K, 2)``."""
    return _limb_centres(_check_shapes(shapes))


def _limb_centres(shapes: np.ndarray) -> np.ndarray:
    return shapes.mean(axis=-2)


def articulation_centre(centres: np.ndarray) -> np.ndarray:
    """U: the mean of the limb centres, ``(n, K, 2) -> (n, 2)``."""
    return _articulation_centre(_check_centres(centres))


def _articulation_centre(centres: np.ndarray) -> np.ndarray:
    return centres.mean(axis=-2)


def limb_angles(centres: np.ndarray) -> np.ndarray:
    """Polar limb angles ``theta_k = atan2(U_y - c_ky, U_x - c_kx)`` in (-pi, pi], ``(n, K)``.

    The paper writes ``tan^-1`` of the ratio; the quadrant-aware ``atan2`` is needed to cover
    (-180, 180] degrees as the text requires.
    """
    return _limb_angles(_check_centres(centres))


def _limb_angles(centres: np.ndarray) -> np.ndarray:
    offsets = _articulation_centre(centres)[..., None, :] - centres
    return _wrap_angle(np.arctan2(offsets[..., 1], offsets[..., 0]))


def polar_shape_vector(shapes: np.ndarray) -> np.ndarray:
    """S = (Theta, C): ``(n, K + 2K)`` with angles in radians then the flattened limb centres."""
    return _polar_shape_vector(_check_shapes(shapes))


def _polar_shape_vector(shapes: np.ndarray) -> np.ndarray:
    centres = _limb_centres(shapes)
    return np.concatenate([_limb_angles(centres), centres.reshape(centres.shape[0], -1)], axis=1)


def centred_limbs(shapes: np.ndarray) -> np.ndarray:
    """Limb long-vectors with the limb centre removed, ``(n, K, 2m)``: what the limb PDMs model."""
    return _centred_limbs(_check_shapes(shapes))


def _centred_limbs(shapes: np.ndarray) -> np.ndarray:
    centred = shapes - _limb_centres(shapes)[..., None, :]
    return centred.reshape(shapes.shape[0], shapes.shape[1], -1)
