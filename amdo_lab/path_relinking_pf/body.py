"""The 2-D geometrical body model of Sec. 5.1 (Table 1): limbs in their father's frame, drawn as polygons.

Conventions (ours; the paper fixes only the hierarchy): image coordinates ``(x, y)`` in pixels with y
pointing down; a limb's direction is the absolute angle ``phi`` (radians from +x towards +y), the sum of
the relative angles ``theta`` along its chain, as in :func:`amdo_lab.common.planar_chain`; a point of a
limb is written ``(along, across)`` in its own frame, ``along`` pointing from its joint to its far end.
A pose is ``[x1, y1, theta_1, ..., theta_n]``: the root joint of the trunk and one relative angle per limb
(the first half of eq. (4)'s state; the velocities are the second half).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from amdo_lab.common import as_finite_array, check_choice, check_image_shape, check_instance, check_positive_int

__all__ = ["ELLIPSE_VERTICES", "MAX_POSE", "BodyModel", "Limb", "check_limb", "edge_map", "joint_errors_px"]

#: Vertices of the polygon that stands for an ellipse (head, hands).
ELLIPSE_VERTICES = 16
#: Largest |coordinate| or |angle| a pose may hold: far outside any image, still exact in float64.
MAX_POSE = 1e5
#: Sub-pixel bits of OpenCV's polygon filler (vertices are rounded to 1/16 px).
_SHIFT = 4


@dataclass(frozen=True)
class Limb:
    """One row of Table 1: a trapezium (``"T"``) or an ellipse (``"E"``) jointed to its father.

    Parameters
    ----------
    name : str
        The limb's name ("trunk", "R. arm", ...).
    shape : str
        ``"T"`` (trapezium: ``size = (length, width at the joint, width at the far end)``) or ``"E"``
        (ellipse: ``size = (half-length along, half-width across)``, sitting on its joint).
    father : int
        Index of the father limb in the model's list, -1 for the root (the trunk).
    size : tuple of float
        As described for ``shape``, pixels.
    position : tuple of float
        ``(along, across)`` of the joint in the father's frame, pixels (Table 1's *Pos.*).
    grey : int
        Grey level of the limb in the synthetic frames (0-255).

    References
    ----------
    Pantrigo, Sánchez, Gianikellis & Montemayor, AMDO 2004, Sec. 5.1 and Table 1.
    """

    name: str
    shape: str
    father: int
    size: tuple[float, ...]
    position: tuple[float, float] = (0.0, 0.0)
    grey: int = 200

    def outline(self) -> np.ndarray:
        """Vertices of the limb's polygon in its own frame.

        Returns
        -------
        numpy.ndarray
            ``(m, 2)`` rows of ``(along, across)``, pixels: 4 for a trapezium, 16 for an ellipse.
        """
        if self.shape == "T":
            length, near, far = self.size
            return np.array([[0.0, -near / 2], [0.0, near / 2], [length, far / 2], [length, -far / 2]])
        half_along, half_across = self.size
        t = 2 * np.pi * np.arange(ELLIPSE_VERTICES) / ELLIPSE_VERTICES
        return np.stack([half_along * (1 + np.cos(t)), half_across * np.sin(t)], axis=1)


def check_limb(limb: object, name: str = "limb") -> Limb:
    """Return ``limb`` after checking each field of a :class:`Limb` against its documented rule, or raise.

    ``name`` is a non-empty str, ``shape`` ``"T"`` with 3 sizes or ``"E"`` with 2, ``father`` an int
    (at least -1), ``size`` and ``position`` finite numbers within ``MAX_POSE`` (``position`` a pair),
    ``grey`` an int in 0-255. :class:`BodyModel` checks every limb through it (the order of the
    fathers is the model's rule).

    Parameters
    ----------
    limb : Limb
        The limb, e.g. one edited with ``dataclasses.replace``.
    name : str
        The caller's argument, for the messages (``"limbs[2]"``).

    Returns
    -------
    Limb
        ``limb``.
    """
    check_instance(limb, name, Limb)
    if not isinstance(limb.name, str) or not limb.name:
        raise TypeError(f"{name}.name must be a non-empty str, got {limb.name!r}")
    check_choice(limb.shape, f"{name}.shape", ("T", "E"))
    check_positive_int(limb.father, f"{name}.father", minimum=-1)
    size = as_finite_array(limb.size, f"{name}.size", ndim=1, max_abs=MAX_POSE)
    if size.size != (3 if limb.shape == "T" else 2):
        raise ValueError(f"{name}.size must hold 3 sizes for shape 'T' or 2 for 'E', got {size.size} for "
                         f"{limb.shape!r}")
    as_finite_array(limb.position, f"{name}.position", shape=(2,), max_abs=MAX_POSE)
    check_positive_int(limb.grey, f"{name}.grey", minimum=0, maximum=255)
    return limb


class BodyModel:
    """A hierarchical set of articulated limbs (Sec. 5.1): kinematics, polygons and rendering.

    Parameters
    ----------
    limbs : sequence of Limb
        Table 1's rows; each father must come before its children (no cycle), the first is the root.

    Attributes
    ----------
    limbs : tuple of Limb
    n_pose : int
        Length of a pose, ``2 + len(limbs)``.
    draw_order : numpy.ndarray
        Limbs sorted by level (distance from the trunk): children are drawn over their fathers.

    References
    ----------
    Pantrigo et al., AMDO 2004, Sec. 5.1, Table 1 and eq. (4).

    Examples
    --------
    >>> model = BodyModel.upper_body()
    >>> model.n_pose
    10
    """

    def __init__(self, limbs) -> None:
        limbs = tuple(limbs) if isinstance(limbs, (list, tuple)) else ()
        if not limbs or not all(isinstance(limb, Limb) for limb in limbs):
            raise TypeError("limbs must be a non-empty sequence of Limb")
        for k, limb in enumerate(limbs):
            check_limb(limb, f"limbs[{k}]")
            if (k == 0) != (limb.father == -1) or limb.father >= k:
                raise ValueError(f"limbs: limb {k} ({limb.name}) has father {limb.father}; the first limb is the "
                                 "only root and every father comes before its children (no cycle)")
        self.limbs = limbs
        self.n_pose = 2 + len(limbs)
        levels = np.zeros(len(limbs), int)
        for k, limb in enumerate(limbs[1:], start=1):
            levels[k] = levels[limb.father] + 1
        self.draw_order = np.argsort(levels, kind="stable")
        self._fill_order = tuple(int(k) for k in self.draw_order)
        self._outlines = [limb.outline() for limb in limbs]

    @classmethod
    def upper_body(cls) -> BodyModel:
        """The eight-limb upper body of Table 1, seen from the front (sizes in pixels, ours).

        Returns
        -------
        BodyModel
            Limbs trunk, head, R. arm, L. arm, R. forearm, L. forearm, R. hand, L. hand (ids 1-8 of the
            paper; the subject's right side is on the image's left).

        References
        ----------
        Pantrigo et al., AMDO 2004, Table 1 (ids 4, 6, 8 are the left limbs the table leaves out).
        """
        h1, shoulder, delta = 50.0, 17.0, 2.0
        return cls([
            Limb("trunk", "T", -1, (h1, 26.0, 34.0), grey=170),
            Limb("head", "E", 0, (11.0, 9.0), (h1 + delta, 0.0), grey=170),
            Limb("R. arm", "T", 0, (24.0, 11.0, 9.0), (h1 - 5.5, -shoulder), grey=220),
            Limb("L. arm", "T", 0, (24.0, 11.0, 9.0), (h1 - 5.5, shoulder), grey=220),
            Limb("R. forearm", "T", 2, (22.0, 9.0, 7.0), (24.0, 0.0), grey=120),
            Limb("L. forearm", "T", 3, (22.0, 9.0, 7.0), (24.0, 0.0), grey=120),
            Limb("R. hand", "E", 4, (5.0, 4.0), (22.0, 0.0), grey=120),
            Limb("L. hand", "E", 5, (5.0, 4.0), (22.0, 0.0), grey=120),
        ])

    @classmethod
    def jumper(cls) -> BodyModel:
        """The five-limb side view of the jump sequence (Fig. 8): trunk, head, thigh, shank, foot.

        Returns
        -------
        BodyModel
            The root joint is the hip; the jumper faces +x.

        References
        ----------
        Pantrigo et al., AMDO 2004, Sec. 6 and Fig. 8.
        """
        return cls([
            Limb("trunk", "T", -1, (38.0, 20.0, 24.0), grey=170),
            Limb("head", "E", 0, (8.0, 7.0), (40.0, 2.0), grey=170),
            Limb("thigh", "T", 0, (30.0, 14.0, 11.0), (0.0, 0.0), grey=220),
            Limb("shank", "T", 2, (28.0, 11.0, 8.0), (30.0, 0.0), grey=120),
            Limb("foot", "T", 3, (14.0, 7.0, 5.0), (28.0, 0.0), grey=220),
        ])

    def check_poses(self, poses: object, name: str = "poses") -> np.ndarray:
        """Return ``poses`` as a finite float array of shape ``(n_pose,)`` or ``(N, n_pose)``, or raise.

        Parameters
        ----------
        poses : array_like
            One pose or a stack of poses, |values| at most ``MAX_POSE``.
        name : str
            The caller's argument name, for the message.

        Returns
        -------
        numpy.ndarray
            The poses as floats.
        """
        poses = as_finite_array(poses, name, max_abs=MAX_POSE)
        if poses.ndim not in (1, 2) or poses.shape[-1] != self.n_pose:
            raise ValueError(f"{name} must have shape ({self.n_pose},) or (N, {self.n_pose}), got {poses.shape}")
        return poses

    def forward(self, poses: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Joint positions and absolute angles of every limb, vectorised over poses.

        Parameters
        ----------
        poses : numpy.ndarray
            ``(n_pose,)`` or ``(N, n_pose)`` poses ``[x1, y1, theta_1, ..., theta_n]`` (px, rad).

        Returns
        -------
        joints : numpy.ndarray
            ``(..., n_limbs, 2)`` the joint (origin) of each limb, pixels.
        angles : numpy.ndarray
            ``(..., n_limbs)`` absolute angles ``phi`` of the limbs, radians.

        References
        ----------
        Pantrigo et al., AMDO 2004, Sec. 5.1: each limb's position and orientation in its father's frame.
        """
        return self._forward(self.check_poses(poses))

    def _forward(self, poses: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        n = len(self.limbs)
        joints = np.empty(poses.shape[:-1] + (n, 2))
        angles = np.empty(poses.shape[:-1] + (n,))
        for k, limb in enumerate(self.limbs):
            if limb.father < 0:
                joints[..., k, :], angles[..., k] = poses[..., :2], poses[..., 2]
                continue
            phi = angles[..., limb.father]
            along, across = limb.position  # the joint in the father's frame (Table 1, Pos.)
            direction = np.stack([np.cos(phi), np.sin(phi)], axis=-1)
            normal = np.stack([-np.sin(phi), np.cos(phi)], axis=-1)
            joints[..., k, :] = joints[..., limb.father, :] + along * direction + across * normal
            angles[..., k] = phi + poses[..., 2 + k]
        return joints, angles

    def _polygons(self, poses: np.ndarray) -> list[np.ndarray]:
        """World vertices of each limb, ``[(..., m_k, 2)]``, from the check-free kinematics."""
        joints, angles = self._forward(poses)
        polygons = []
        for k, outline in enumerate(self._outlines):
            cos, sin = np.cos(angles[..., k])[..., None], np.sin(angles[..., k])[..., None]
            x = joints[..., k, None, 0] + outline[:, 0] * cos - outline[:, 1] * sin
            y = joints[..., k, None, 1] + outline[:, 0] * sin + outline[:, 1] * cos
            polygons.append(np.stack([x, y], axis=-1))
        return polygons

    def render_labels(self, pose: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
        """The label image of one pose: 0 for the background, ``k + 1`` where limb k is seen.

        Limbs are filled as convex polygons (pixel centres at integer coordinates) in ``draw_order``,
        so a child hides its father where they overlap and a crossing arm hides the trunk.

        Parameters
        ----------
        pose : numpy.ndarray
            ``(n_pose,)`` one pose (px, rad).
        shape : tuple of int
            ``(rows, cols)`` of the image, each at most 4,096.

        Returns
        -------
        numpy.ndarray
            ``(rows, cols)`` uint8 labels.

        References
        ----------
        Pantrigo et al., AMDO 2004, Sec. 5.1 and Fig. 3 (the blob model).
        """
        pose = as_finite_array(pose, "pose", shape=(self.n_pose,), max_abs=MAX_POSE)
        shape = check_image_shape(shape, "shape")
        labels = np.zeros(shape, np.uint8)
        self._render_into(labels, [polygon for polygon in self._polygons(pose)])
        return labels

    def _render_into(self, labels: np.ndarray, polygons: list[np.ndarray]) -> None:
        """Fill one pose's limb polygons ``[(m_k, 2)]`` into ``labels`` (check-free)."""
        self._fill(labels, _fixed_point(polygons))

    def _fill(self, labels: np.ndarray, fixed: list[np.ndarray]) -> None:
        """Fill one pose's fixed-point polygons (from :func:`_fixed_point`) into ``labels``, in draw order."""
        for k in self._fill_order:
            cv2.fillConvexPoly(labels, fixed[k], k + 1, lineType=cv2.LINE_8, shift=_SHIFT)

    def joint_positions(self, poses: np.ndarray) -> np.ndarray:
        """The joints of every limb (its origin), ``(..., n_limbs, 2)`` pixels: what joint errors compare.

        Parameters
        ----------
        poses : numpy.ndarray
            ``(n_pose,)`` or ``(N, n_pose)`` poses.

        Returns
        -------
        numpy.ndarray
            Joint positions, pixels.

        References
        ----------
        Pantrigo et al., AMDO 2004, Sec. 5.1.
        """
        return self._forward(self.check_poses(poses))[0]


def _fixed_point(polygons: list[np.ndarray]) -> list[np.ndarray]:
    """Polygon vertices ``[(..., m_k, 2)]`` as OpenCV's int32 fixed point (``_SHIFT`` fractional bits)."""
    return [np.round(polygon * (1 << _SHIFT)).astype(np.int32) for polygon in polygons]


def edge_map(labels: np.ndarray) -> np.ndarray:
    """E^P: the pixels whose label differs from one of their 4-neighbours (model edges, occlusion kept).

    Parameters
    ----------
    labels : numpy.ndarray
        ``(rows, cols)`` integer label image (see :meth:`BodyModel.render_labels`).

    Returns
    -------
    numpy.ndarray
        ``(rows, cols)`` bool edge map: both sides of every boundary between two labels.

    References
    ----------
    Pantrigo et al., AMDO 2004, Sec. 5.2 and Fig. 3 (the edge model).
    """
    labels = as_finite_array(labels, "labels", ndim=2, dtype=int, max_abs=MAX_POSE)
    return _edge_map(labels)


def _edge_map(labels: np.ndarray) -> np.ndarray:
    edges = np.zeros(labels.shape, bool)
    across = labels[:, 1:] != labels[:, :-1]
    down = labels[1:, :] != labels[:-1, :]
    edges[:, 1:] |= across
    edges[:, :-1] |= across
    edges[1:, :] |= down
    edges[:-1, :] |= down
    return edges


def joint_errors_px(model: BodyModel, poses: np.ndarray, truth: np.ndarray) -> np.ndarray:
    """Distance of each limb's joint from its true position, pixels.

    Parameters
    ----------
    model : BodyModel
        The body model of the poses.
    poses, truth : numpy.ndarray
        ``(T, n_pose)`` estimated and true poses.

    Returns
    -------
    numpy.ndarray
        ``(T, n_limbs)`` joint errors, pixels.

    References
    ----------
    Pantrigo et al., AMDO 2004, Sec. 6 (the estimates are compared with manual digitising).

    Examples
    --------
    >>> model = BodyModel.upper_body()
    >>> pose = np.r_[80.0, 130.0, -np.pi / 2, 0.0, np.pi, np.pi, 0.0, 0.0, 0.0, 0.0]
    >>> float(joint_errors_px(model, pose[None], pose[None]).max())
    0.0
    """
    if not isinstance(model, BodyModel):
        raise TypeError(f"model must be a BodyModel, got {type(model).__name__}")
    poses = model.check_poses(poses, "poses")
    if poses.ndim != 2:  # documented (T, n_pose): a single pose would make truth's message misleading
        raise ValueError(f"poses must have shape (T, {model.n_pose}), got {poses.shape}")
    truth = as_finite_array(truth, "truth", shape=poses.shape, max_abs=MAX_POSE)
    return np.linalg.norm(model._forward(poses)[0] - model._forward(truth)[0], axis=-1)
