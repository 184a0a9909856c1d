"""Geometry shared by the chapters: rotations, rigid and similarity transforms, Procrustes.

Conventions: points are rows (``(n, d)`` arrays); rotations act on column vectors, so a point set
is rotated as ``points @ R.T``; angles are in radians; rotations follow the right-hand rule.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common.validation import (
    as_finite_array,
    as_points,
    as_rotation,
    as_weights,
    check_bool,
    check_overflow,
    check_positive,
    check_same_shape,
)

__all__ = [
    "ProcrustesResult",
    "apply_rigid",
    "apply_similarity_2d",
    "planar_chain",
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
    largest = check_positive(float(np.max(np.abs(axis))), "axis (a non-zero 3-vector): its largest entry in magnitude")
    axis = axis / largest  # scale first: the norm of an axis above about 1e154 would overflow
    k = skew(axis / np.linalg.norm(axis))
    angle = as_finite_array(angle, "angle", allow_empty=True)[..., None, None]
    return np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * (k @ k)


def rotation_x(angle: float | np.ndarray) -> np.ndarray:
    """Rotation about the x axis by ``angle`` radians.

    Parameters
    ----------
    angle : float or array_like
        Angle(s) in radians.

    Returns
    -------
    numpy.ndarray
        ``(3, 3)`` for a scalar angle, ``(*angle.shape, 3, 3)`` otherwise.
    """
    return rotation_matrix(np.array([1.0, 0.0, 0.0]), angle)


def rotation_y(angle: float | np.ndarray) -> np.ndarray:
    """Rotation about the y axis by ``angle`` radians.

    Parameters
    ----------
    angle : float or array_like
        Angle(s) in radians.

    Returns
    -------
    numpy.ndarray
        ``(3, 3)`` for a scalar angle, ``(*angle.shape, 3, 3)`` otherwise.
    """
    return rotation_matrix(np.array([0.0, 1.0, 0.0]), angle)


def rotation_z(angle: float | np.ndarray) -> np.ndarray:
    """Rotation about the z axis by ``angle`` radians.

    Parameters
    ----------
    angle : float or array_like
        Angle(s) in radians.

    Returns
    -------
    numpy.ndarray
        ``(3, 3)`` for a scalar angle, ``(*angle.shape, 3, 3)`` otherwise.
    """
    return rotation_matrix(np.array([0.0, 0.0, 1.0]), angle)


def rotation_2d(angle: float | np.ndarray) -> np.ndarray:
    """Counter-clockwise 2-D rotation matrix.

    Parameters
    ----------
    angle : float or array_like
        Angle(s) in radians, counter-clockwise.

    Returns
    -------
    numpy.ndarray
        ``(2, 2)`` for a scalar angle, ``(*angle.shape, 2, 2)`` otherwise.
    """
    return _rotation_2d(as_finite_array(angle, "angle", allow_empty=True))


def _rotation_2d(angle: np.ndarray) -> np.ndarray:
    """:func:`rotation_2d` of an already validated float array of angles."""
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([np.stack([c, -s], axis=-1), np.stack([s, c], axis=-1)], axis=-2)


def rigid_transform(rotation: np.ndarray, translation: np.ndarray) -> np.ndarray:
    """Homogeneous ``(d+1, d+1)`` matrix of the map ``x -> R x + t``; batched over leading axes.

    Parameters
    ----------
    rotation : (..., d, d) array_like
        Rotation matrix, or a stack of them: orthonormal with determinant +1 (to 1e-6).
    translation : (..., d) array_like
        Translation vector(s), broadcastable against the leading axes of ``rotation``.

    Returns
    -------
    numpy.ndarray
        ``(..., d+1, d+1)`` homogeneous matrices with ``[R t; 0 1]``.
    """
    rotation = as_rotation(rotation, "rotation")
    d = rotation.shape[-1]
    translation = as_finite_array(translation, "translation")
    if translation.ndim < 1 or translation.shape[-1] != d or not _broadcasts_to(translation.shape, rotation.shape[:-1]):
        raise ValueError(f"translation must have shape (..., {d}) for rotation {rotation.shape}, got {translation.shape}")
    out = np.zeros(rotation.shape[:-2] + (d + 1, d + 1))
    out[..., :d, :d] = rotation
    out[..., :d, d] = translation
    out[..., d, d] = 1.0
    return out


def _broadcasts_to(shape: tuple[int, ...], target: tuple[int, ...]) -> bool:
    try:
        return np.broadcast_shapes(shape, target) == target
    except ValueError:
        return False


def apply_rigid(transform: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Apply a homogeneous transform ``(d+1, d+1)`` to points ``(n, d)``: ``R p + t`` per row.

    Parameters
    ----------
    transform : (d+1, d+1) array_like
        Homogeneous matrix ``[R t; 0 1]``, e.g. from :func:`rigid_transform`.
    points : (n, d) or (d,) array_like
        Points as rows; an empty ``(0, d)`` set is allowed.

    Returns
    -------
    numpy.ndarray
        The mapped points, of the shape of ``points``.
    """
    transform = as_finite_array(transform, "transform", ndim=2)
    d = transform.shape[-1] - 1
    if d < 1 or transform.shape != (d + 1, d + 1):
        raise ValueError(f"transform must be a homogeneous (d+1, d+1) matrix with d >= 1, got shape {transform.shape}")
    points = as_points(points, "points", dim=d)
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is refused by name just below
        mapped = points @ transform[:d, :d].T + transform[:d, d]
    check_overflow(mapped, "points and transform")
    return mapped


def apply_similarity_2d(
    points: np.ndarray, scale: float, angle: float, translation: np.ndarray
) -> np.ndarray:
    """Map 2-D points by ``x -> s R(angle) x + t`` (the similarity group of the plane).

    Parameters
    ----------
    points : (n, 2) or (2,) array_like
        Points as rows.
    scale : float
        Positive scale factor s.
    angle : float
        Rotation angle in radians (a single angle).
    translation : (2,) array_like
        Translation t.

    Returns
    -------
    numpy.ndarray
        The mapped points, of the shape of ``points``.
    """
    points = as_points(points, "points", dim=2)
    scale = check_positive(scale, "scale")
    angle = as_finite_array(angle, "angle", ndim=0)
    translation = as_finite_array(translation, "translation", shape=(2,))
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is refused by name just below
        mapped = scale * points @ _rotation_2d(angle).T + translation
    check_overflow(mapped, "points, scale and translation")
    return mapped


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
        Corresponding points, entries within ±1e150 (their squares are summed).
    allow_scale : bool
        Estimate an isotropic scale.
    allow_reflection : bool
        Allow an improper orthogonal matrix.
    weights : (n,) array_like, optional
        Non-negative weights per correspondence.

    Returns
    -------
    ProcrustesResult
        The aligned source, scale, rotation, translation and RMS error.

    References
    ----------
    S. Umeyama. Least-squares estimation of transformation parameters between two point patterns.
    IEEE TPAMI 13(4), 1991, pp. 376-380.
    """
    source = as_finite_array(source, "source", ndim=2, max_abs=1e150)
    target = as_finite_array(target, "target", ndim=2, max_abs=1e150)
    allow_scale = check_bool(allow_scale, "allow_scale")
    allow_reflection = check_bool(allow_reflection, "allow_reflection")
    check_same_shape(source, target, "source", "target")
    n, d = source.shape
    w = np.full(n, 1.0) if weights is None else as_weights(weights, "weights", n=n)
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
        if source_var == 0 or np.all(source == source[0]):  # round-off can leave identical points a tiny variance
            raise ValueError("source points are all identical: scale is undefined")
        scale = float(singular @ correction) / source_var
    else:
        scale = 1.0
    translation = mu_target - scale * rotation @ mu_source
    aligned = scale * source @ rotation.T + translation
    rms = float(np.sqrt(np.mean(np.sum((aligned - target) ** 2, axis=1))))
    check_overflow([*aligned.ravel(), rms], "source and target")
    return ProcrustesResult(aligned, scale, rotation, translation, rms)


#: Lengths and offsets beyond this are refused (pixels or millimetres: far beyond any image or body).
MAX_CHAIN_LENGTH = 1e6


def planar_chain(angles: np.ndarray, lengths: np.ndarray, base: np.ndarray = (0.0, 0.0)) -> np.ndarray:
    """Joint positions of a planar kinematic chain: each link turns by its angle relative to the last.

    Link k points along the absolute angle ``phi_k = angles[0] + ... + angles[k]`` (radians, measured
    from the +x axis towards +y), so joint k+1 is joint k plus ``lengths[k] (cos phi_k, sin phi_k)``.

    Parameters
    ----------
    angles : numpy.ndarray
        (..., n) relative joint angles in radians, |angle| at most 1e6; leading axes are a batch.
    lengths : numpy.ndarray
        (n,) link lengths, at most 1e6 in magnitude.
    base : array_like
        (2,) position of the first joint, at most 1e6 in magnitude.

    Returns
    -------
    numpy.ndarray
        (..., n + 1, 2) the base and the n joints after it.

    References
    ----------
    Pantrigo et al., AMDO 2004, Sec. 5.1 (each limb in its father's frame); the planar arm of
    chapter 1's toy.

    Examples
    --------
    >>> planar_chain(np.array([0.0, np.pi / 2]), np.array([2.0, 1.0])).round(6)
    array([[0., 0.],
           [2., 0.],
           [2., 1.]])
    """
    angles = as_finite_array(angles, "angles", max_abs=MAX_CHAIN_LENGTH)
    lengths = as_finite_array(lengths, "lengths", ndim=1, max_abs=MAX_CHAIN_LENGTH)
    base = as_finite_array(base, "base", shape=(2,), max_abs=MAX_CHAIN_LENGTH)
    if angles.ndim == 0:
        raise ValueError(f"angles must end in one angle per link of lengths ({len(lengths)}), got a scalar")
    if angles.shape[-1] != len(lengths):  # a mismatch: either may be at fault, so both are named with their sizes
        raise ValueError(f"angles and lengths disagree: angles ends in {angles.shape[-1]} angles (shape "
                         f"{angles.shape}), lengths has {len(lengths)} links; give one angle per link")
    absolute = np.cumsum(angles, axis=-1)
    steps = lengths[..., None] * np.stack([np.cos(absolute), np.sin(absolute)], axis=-1)
    joints = np.concatenate([np.zeros(steps.shape[:-2] + (1, 2)), np.cumsum(steps, axis=-2)], axis=-2)
    return joints + base
