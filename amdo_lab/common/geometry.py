"""Geometry shared by the chapters: rotations, rigid and similarity transforms, Procrustes.

Conventions: points are rows (``(n, d)`` arrays); rotations act on column vectors, so a point set
is rotated as ``points @ R.T``; angles are in radians; rotations follow the right-hand rule.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common.validation import as_finite_array

__all__ = [
    "ProcrustesResult",
    "apply_rigid",
    "apply_similarity_2d",
    "procrustes_align",
    "rigid_transform",
    "rotation_2d",
    "rotation_matrix",
    "rotation_x",
    "rotation_y",
    "rotation_z",
    "skew",
]


def skew(vector: np.ndarray) -> np.ndarray:
    """Cross-product matrix ``[v]_x`` with ``[v]_x @ w == cross(v, w)``; accepts ``(..., 3)``."""
    v = np.asarray(vector, dtype=float)
    zero = np.zeros(v.shape[:-1])
    return np.stack(
        [
            np.stack([zero, -v[..., 2], v[..., 1]], axis=-1),
            np.stack([v[..., 2], zero, -v[..., 0]], axis=-1),
            np.stack([-v[..., 1], v[..., 0], zero], axis=-1),
        ],
        axis=-2,
    )


def rotation_matrix(axis: np.ndarray, angle: float | np.ndarray) -> np.ndarray:
    """Rotation by ``angle`` about ``axis`` (Rodrigues' formula), vectorised over angles.

    R = I + sin(a) K + (1 - cos(a)) K^2, with K the cross-product matrix of the unit axis.

    Parameters
    ----------
    axis : (3,) array_like
        Rotation axis; it is normalised (a zero axis is an error).
    angle : float or array_like
        Angle(s) in radians.

    Returns
    -------
    numpy.ndarray
        ``(3, 3)`` for a scalar angle, ``(*angle.shape, 3, 3)`` otherwise.
    """
    axis = as_finite_array(axis, "axis", shape=(3,))
    norm = np.linalg.norm(axis)
    if norm == 0:
        raise ValueError("axis must be a non-zero 3-vector")
    k = skew(axis / norm)
    angle = np.asarray(angle, dtype=float)[..., None, None]
    return np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * (k @ k)


def rotation_x(angle: float | np.ndarray) -> np.ndarray:
    """Rotation about the x axis by ``angle`` radians."""
    return rotation_matrix(np.array([1.0, 0.0, 0.0]), angle)


def rotation_y(angle: float | np.ndarray) -> np.ndarray:
    """Rotation about the y axis by ``angle`` radians."""
    return rotation_matrix(np.array([0.0, 1.0, 0.0]), angle)


def rotation_z(angle: float | np.ndarray) -> np.ndarray:
    """Rotation about the z axis by ``angle`` radians."""
    return rotation_matrix(np.array([0.0, 0.0, 1.0]), angle)


def rotation_2d(angle: float | np.ndarray) -> np.ndarray:
    """Counter-clockwise 2-D rotation, ``(2, 2)`` or ``(*angle.shape, 2, 2)``."""
    angle = np.asarray(angle, dtype=float)
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([np.stack([c, -s], axis=-1), np.stack([s, c], axis=-1)], axis=-2)


def rigid_transform(rotation: np.ndarray, translation: np.ndarray) -> np.ndarray:
    """Homogeneous ``(d+1, d+1)`` matrix of the map ``x -> R x + t``; batched over leading axes."""
    rotation = np.asarray(rotation, dtype=float)
    translation = np.asarray(translation, dtype=float)
    d = rotation.shape[-1]
    out = np.zeros(rotation.shape[:-2] + (d + 1, d + 1))
    out[..., :d, :d] = rotation
    out[..., :d, d] = translation
    out[..., d, d] = 1.0
    return out


def apply_rigid(transform: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Apply a homogeneous transform ``(d+1, d+1)`` to points ``(n, d)``: ``R p + t`` per row."""
    transform = np.asarray(transform, dtype=float)
    points = np.asarray(points, dtype=float)
    d = transform.shape[-1] - 1
    return points @ transform[:d, :d].T + transform[:d, d]


def apply_similarity_2d(
    points: np.ndarray, scale: float, angle: float, translation: np.ndarray
) -> np.ndarray:
    """Map 2-D points by ``x -> s R(angle) x + t`` (the similarity group of the plane)."""
    points = np.asarray(points, dtype=float)
    return scale * points @ rotation_2d(angle).T + np.asarray(translation, dtype=float)


@dataclass(frozen=True)
class ProcrustesResult:
    """Outcome of :func:`procrustes_align`: ``aligned = scale * source @ rotation.T + translation``."""

    aligned: np.ndarray
    scale: float
    rotation: np.ndarray
    translation: np.ndarray
    rms_error: float


def procrustes_align(
    source: np.ndarray,
    target: np.ndarray,
    *,
    allow_scale: bool = True,
    allow_reflection: bool = False,
    weights: np.ndarray | None = None,
) -> ProcrustesResult:
    """Least-squares similarity (or rigid) alignment of ``source`` onto ``target`` (Umeyama 1991).

    Minimises sum_i w_i |s R x_i + t - y_i|^2 over rotation R (a proper rotation unless
    ``allow_reflection``), scale s (1 unless ``allow_scale``) and translation t, by the SVD of the
    weighted cross-covariance of the centred point sets.

    Parameters
    ----------
    source, target : (n, d) array_like
        Corresponding points.
    allow_scale : bool
        Estimate an isotropic scale.
    allow_reflection : bool
        Allow an improper orthogonal matrix.
    weights : (n,) array_like, optional
        Non-negative weights per correspondence.
    """
    source = as_finite_array(source, "source", ndim=2)
    target = as_finite_array(target, "target", ndim=2)
    if source.shape != target.shape:
        raise ValueError(f"source and target must have the same shape, got {source.shape} and {target.shape}")
    n, d = source.shape
    if weights is None:
        w = np.full(n, 1.0 / n)
    else:
        w = as_finite_array(weights, "weights", shape=(n,))
        if np.any(w < 0) or w.sum() <= 0:
            raise ValueError("weights must be non-negative with a positive sum")
        w = w / w.sum()
    mu_source = w @ source
    mu_target = w @ target
    centred_source = source - mu_source
    centred_target = target - mu_target
    covariance = (centred_target * w[:, None]).T @ centred_source
    u, singular, vt = np.linalg.svd(covariance)
    correction = np.ones(d)
    if not allow_reflection and np.linalg.det(u) * np.linalg.det(vt) < 0:
        correction[-1] = -1.0
    rotation = (u * correction) @ vt
    if allow_scale:
        source_var = float(w @ np.sum(centred_source**2, axis=1))
        if source_var == 0:
            raise ValueError("source points are all identical: scale is undefined")
        scale = float(singular @ correction) / source_var
    else:
        scale = 1.0
    translation = mu_target - scale * rotation @ mu_source
    aligned = scale * source @ rotation.T + translation
    rms = float(np.sqrt(np.mean(np.sum((aligned - target) ** 2, axis=1))))
    return ProcrustesResult(aligned, scale, rotation, translation, rms)
