"""Articulated hand: kinematics (Sec. 2), ellipsoid field surface (eqs. 1-2), bending texture (eq. 3).

Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
bending surfaces", ECCV 2006. Lengths in millimetres, angles in radians.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common import MAX_ITERATIONS, MAX_SAMPLES
from amdo_lab.common import as_finite_array, check_bool, check_in_range, check_instance, check_positive_int, make_rng
from amdo_lab.common.geometry import rigid_transform, rotation_matrix, skew

__all__ = ["HandModel", "PART_NAMES"]

FINGERS = ("thumb", "index", "middle", "ring", "little")
PART_NAMES = ("palm",) + tuple(f"{f}_{k}" for f in FINGERS for k in (1, 2, 3))
#: Each digit's DOFs (thumb, index, middle, ring, little) in the layout :class:`HandModel` builds
#: (checked there): the thumb's five, then four per finger.
DIGIT_DOFS: tuple[tuple[int, ...], ...] = tuple(tuple(range(start, stop)) for start, stop in
                                                ((6, 11), (11, 15), (15, 19), (19, 23), (23, 27)))
#: The digit DOFs that swing a digit sideways (rotations about the palm normal): the thumb's two and
#: each finger's knuckle abduction. Every other digit DOF flexes.
SIDEWAYS_DOFS: tuple[int, ...] = (6, 8, 11, 15, 19, 23)

# Phalanx lengths (mm), roughly an adult hand (proximal, middle, distal).
_PHALANX_LENGTHS = {
    "thumb": (45.0, 32.0, 27.0),
    "index": (40.0, 25.0, 20.0),
    "middle": (45.0, 28.0, 22.0),
    "ring": (42.0, 27.0, 21.0),
    "little": (33.0, 20.0, 18.0),
}
_FINGER_BASE_X = {"index": -30.0, "middle": -10.0, "ring": 10.0, "little": 30.0}
_DEG = np.pi / 180.0
# Joint ranges of the Shadow Dexterous Hand (Shadow Robot Company, "Shadow Dexterous Hand
# technical specification", joint table: FFJ4 -20..20, FFJ3 -15..90, FFJ2 0..90, FFJ1 0..90;
# THJ5 -60..60, THJ4 0..70, THJ3 -12..12, THJ2 -30..30, THJ1 -15..90 degrees).
_FINGER_LIMITS = ((-20, 20), (-15, 90), (0, 90), (0, 90))
_THUMB_LIMITS = ((-60, 60), (0, 70), (-12, 12), (-30, 30), (-15, 90))

#: Largest length parameter (ν, σ, noise, offsets) and largest coordinate of a point or pose entry the
#: chapter's functions accept, mm: a kilometre, far beyond any hand and far below where squares and
#: exponentials of it overflow to inf.
MAX_LENGTH_MM = 1e6
#: Largest exponent ``a`` of the bending weights of eq. (3): at 1,000 each point already moves rigidly
#: with its strongest part (the chapter uses 2 to 50); beyond it the powers of the fields overflow.
MAX_BENDING_EXPONENT = 1000.0

_X = np.array([1.0, 0.0, 0.0])
_Y = np.array([0.0, 1.0, 0.0])
_Z = np.array([0.0, 0.0, 1.0])
_FLEX = -_X  # positive flexion curls the finger towards -z (the palm side)


@dataclass(frozen=True)
class _Part:
    """One rigid part of the kinematic tree: its parent, fixed offset, DOFs and their rotation axes."""

    parent: int  # -1 for the palm
    offset: np.ndarray  # 4x4 fixed transform from parent frame to this joint's frame
    dofs: tuple[int, ...]
    axes: tuple[np.ndarray, ...]  # rotation axes in the joint frame, applied in order
    centre: np.ndarray  # ellipsoid centre in the part frame
    radii: np.ndarray  # ellipsoid semi-axes in the part frame


def _axis_levers(axes: np.ndarray, origins: np.ndarray, points: np.ndarray) -> np.ndarray:
    """ω_k × (x_m - o_k) for every point and axis, (M, 3) points -> (M, K, 3).

    Written as one matrix product, x @ [ω_k]ₓᵀ for all k at once, minus the constant ω_k × o_k:
    the cross product is linear in x, and a single GEMM beats K broadcast cross products.
    """
    cross = skew(axes)  # (K, 3, 3): cross[k] @ x = ω_k × x
    levers = (points @ cross.transpose(2, 0, 1).reshape(3, -1)).reshape(len(points), len(axes), 3)
    return levers - (cross @ origins[..., None])[None, ..., 0]  # minus ω_k × o_k


class HandModel:
    """A 16-part, 27-DOF hand of ellipsoids (Sec. 2 of Dewaele et al. 2006).

    DOF layout: 0-2 palm translation (mm), 3-5 palm rotation about z, y, x (rad), 6-10 thumb
    (two 2-DOF joints and a 1-DOF joint), then 4 DOF per finger (abduction + flexion at the
    knuckle, flexion at the two distal joints) for index, middle, ring and little.

    Parameters
    ----------
    nu : float, default 4.0
        Field fall-off ν of eq. (1), mm, in (0, 1e6].

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; Sec. 2, eqs. (1)-(3).
    """

    n_parts = 16
    n_dof = 27

    def __init__(self, nu: float = 4.0) -> None:
        self.nu = check_in_range(nu, "nu", 0.0, MAX_LENGTH_MM, closed="right")
        parts: list[_Part] = []
        limits = [(-np.inf, np.inf)] * 3 + [(-np.pi, np.pi), (-np.pi / 2, np.pi / 2), (-np.pi, np.pi)]
        parts.append(_Part(-1, np.eye(4), (3, 4, 5), (_Z, _Y, _X), np.array([0.0, 0.0, 0.0]),
                           np.array([42.0, 48.0, 13.0])))
        dof = 6
        for finger in FINGERS:
            lengths = _PHALANX_LENGTHS[finger]
            radius = 10.0 if finger == "thumb" else 8.5
            if finger == "thumb":
                # the thumb leaves the palm's radial side pointing outwards (35° from the fingers)
                base = rigid_transform(rotation_matrix(_Z, 35 * _DEG), np.array([-36.0, -14.0, -4.0]))
                joint_axes = ((_Z, _FLEX), (_Z, _FLEX), (_FLEX,))
                limits += [(lo * _DEG, hi * _DEG) for lo, hi in _THUMB_LIMITS]
            else:
                base = rigid_transform(np.eye(3), np.array([_FINGER_BASE_X[finger], 46.0, 0.0]))
                joint_axes = ((_Z, _FLEX), (_FLEX,), (_FLEX,))
                limits += [(lo * _DEG, hi * _DEG) for lo, hi in _FINGER_LIMITS]
            parent = 0
            for k, (length, axes) in enumerate(zip(lengths, joint_axes)):
                offset = base if k == 0 else rigid_transform(np.eye(3), np.array([0.0, lengths[k - 1], 0.0]))
                dofs = tuple(range(dof, dof + len(axes)))
                dof += len(axes)
                shrink = 1.0 - 0.08 * k
                parts.append(_Part(parent, offset, dofs, axes, np.array([0.0, length / 2, 0.0]),
                                   np.array([radius * shrink, length / 2 + 3.0, radius * shrink * 0.9])))
                parent = len(parts) - 1
        assert dof == self.n_dof and len(parts) == self.n_parts
        self._parts = tuple(parts)
        self._limits = np.array(limits)
        # ancestor[k, p]: DOF k moves part p.
        ancestor = np.zeros((self.n_dof, self.n_parts), dtype=bool)
        ancestor[:6, :] = True
        for p, part in enumerate(parts):
            q = p
            while q > 0:
                ancestor[list(parts[q].dofs), p] = True
                q = parts[q].parent
        self._dof_moves_part = ancestor
        # per-DOF unit axes in their joint frames and Rodrigues matrices K, K^2 (vectorised kinematics)
        joint_axes = np.zeros((self.n_dof, 3))
        for part in parts:
            for k, axis in zip(part.dofs, part.axes):
                joint_axes[k] = axis
        assert all(tuple(k for part in parts[1 + 3 * digit:4 + 3 * digit] for k in part.dofs) == DIGIT_DOFS[digit]
                   for digit in range(len(FINGERS)))
        assert tuple(np.flatnonzero(np.all(joint_axes[6:] == _Z, axis=1)) + 6) == SIDEWAYS_DOFS
        skew_axes = skew(joint_axes)
        self._joint_axes, self._skew, self._skew2 = joint_axes, skew_axes, skew_axes @ skew_axes
        self._centres = np.array([part.centre for part in parts])
        self._radii = np.array([part.radii for part in parts])
        # the digits' parts grouped by depth for _forward: (parts, parents, offset R, offset t, DOF slots)
        depth = np.zeros(self.n_parts, int)
        for p, part in enumerate(parts[1:], start=1):
            depth[p] = depth[part.parent] + 1
        width = max(len(part.dofs) for part in parts[1:])
        levels = []
        for level in range(1, depth.max() + 1):
            members = np.flatnonzero(depth == level)
            slots = np.full((len(members), width), self.n_dof)  # n_dof = no DOF in this slot
            for row, p in enumerate(members):
                slots[row, :len(parts[p].dofs)] = parts[p].dofs
            levels.append((members, np.array([parts[p].parent for p in members]),
                           np.array([parts[p].offset[:3, :3] for p in members]),
                           np.array([parts[p].offset[:3, 3] for p in members]), slots))
        self._levels = tuple(levels)
        self._joint_axes_padded = np.concatenate([joint_axes, np.zeros((1, 3))])
        adjacency = np.eye(self.n_parts, dtype=bool)
        for p, part in enumerate(parts):
            if part.parent >= 0:
                adjacency[p, part.parent] = adjacency[part.parent, p] = True
        self.adjacency = adjacency

    # ------------------------------------------------------------------ kinematics
    def rest_pose(self) -> np.ndarray:
        """Open flat hand at the origin, slightly flexed fingers (within limits).

        Returns
        -------
        numpy.ndarray, shape (27,)
            The rest pose.
        """
        theta = np.zeros(self.n_dof)
        theta[6:11] = [0.2, 0.3, 0.0, 0.1, 0.1]
        for f in range(4):
            theta[11 + 4 * f: 15 + 4 * f] = [0.0, 0.1, 0.1, 0.1]
        return theta

    def joint_limits(self) -> np.ndarray:
        """Lower and upper bound of every DOF (a copy).

        Returns
        -------
        numpy.ndarray, shape (27, 2)
            [lower, upper] per DOF: ±inf for the palm translation, radians for the rest (the
            Shadow Dexterous Hand's ranges for the digits).
        """
        return self._limits.copy()

    def check_theta(self, theta: object, name: str = "theta", *, within_limits: bool = False) -> np.ndarray:
        """Validate a pose vector (length 27, finite; optionally inside the joint limits).

        Parameters
        ----------
        theta : array_like, shape (27,)
            The pose to check: every entry within ±1e6 (mm for DOFs 0-2, radians for the others).
        name : str, default "theta"
            Argument name used in error messages.
        within_limits : bool, default False
            Also require every DOF inside :meth:`joint_limits` (to 1e-9).

        Returns
        -------
        numpy.ndarray, shape (27,)
            ``theta`` as a float array.
        """
        theta = as_finite_array(theta, name, ndim=1, shape=(self.n_dof,), max_abs=MAX_LENGTH_MM)
        if check_bool(within_limits, "within_limits"):
            lo, hi = self._limits[:, 0], self._limits[:, 1]
            bad = np.flatnonzero((theta < lo - 1e-9) | (theta > hi + 1e-9))
            if bad.size:
                raise ValueError(f"{name} must lie within joint_limits(); DOF {bad.tolist()} are outside")
        return theta

    def _check_query(self, points: object, theta: object) -> tuple[np.ndarray, np.ndarray]:
        """The query points (M, 3) and the pose (27,) that every distance method takes, checked."""
        points = check_points(points, "points")
        theta = self.check_theta(theta)
        return points, theta

    def _forward(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Part frames (16, 4, 4), and every DOF's world axis and a point on it (27, 3) each.

        The palm first, then the five digits together, one phalanx depth at a time (a DOF slot a
        part lacks points at an identity rotation), so a pose costs a few batched products.
        """
        angles = theta[:, None, None]
        rotations = np.eye(3) + np.sin(angles) * self._skew + (1.0 - np.cos(angles)) * self._skew2
        rotations = np.concatenate([rotations, np.eye(3)[None]])  # index n_dof: the padding slot
        frames = np.zeros((self.n_parts, 4, 4))
        frames[:, 3, 3] = 1.0
        axes_world = np.zeros((self.n_dof + 1, 3))
        origins_world = np.zeros((self.n_dof + 1, 3))
        axes_world[:3] = np.eye(3)
        rotation = np.eye(3)
        for k in self._parts[0].dofs:  # palm: rotations about z, y, x in turn, centred at the translation
            axes_world[k], origins_world[k] = rotation @ self._joint_axes[k], theta[:3]
            rotation = rotation @ rotations[k]
        frames[0, :3, :3], frames[0, :3, 3] = rotation, theta[:3]
        for parts, parents, offset_rotation, offset_origin, slots in self._levels:
            parent_rotation = frames[parents, :3, :3]
            rotation = parent_rotation @ offset_rotation
            origin = (parent_rotation @ offset_origin[..., None])[..., 0] + frames[parents, :3, 3]
            for slot in slots.T:
                axes_world[slot] = (rotation @ self._joint_axes_padded[slot][..., None])[..., 0]
                origins_world[slot] = origin
                rotation = rotation @ rotations[slot]
            frames[parts, :3, :3], frames[parts, :3, 3] = rotation, origin
        return frames, axes_world[:-1], origins_world[:-1]

    def part_transforms(self, theta: object) -> np.ndarray:
        """Rigid motion T_p(Θ) of every part, part frame -> world.

        Parameters
        ----------
        theta : array_like, shape (27,)
            Pose (mm for DOFs 0-2, radians for the others).

        Returns
        -------
        numpy.ndarray, shape (16, 4, 4)
            Homogeneous transforms, translations in mm.
        """
        return self._forward(self.check_theta(theta))[0]

    def digit_clearance(self, theta: object, n_samples: int = 7) -> float:
        """Smallest gap (mm) between the phalanges of two different digits; negative = overlap.

        Each phalanx is reduced to its axis (sampled at ``n_samples`` points) and a radius (its
        larger cross-section semi-axis), which is enough to reject poses where fingers cross.

        Parameters
        ----------
        theta : array_like, shape (27,)
            Pose (mm for DOFs 0-2, radians for the others).
        n_samples : int, default 7
            Points sampled along each phalanx axis (≥ 1).
            At most :data:`amdo_lab.common.MAX_SAMPLES` (1,000,000).

        Returns
        -------
        float
            The smallest gap, mm.
        """
        frames = self._forward(self.check_theta(theta))[0]
        along = np.linspace(-0.5, 0.5, check_positive_int(n_samples, "n_samples", maximum=MAX_SAMPLES))
        axis_points, radius, digit = [], [], []
        for p, part in enumerate(self._parts[1:], start=1):
            half = part.radii[1] - 3.0  # the ellipsoid overshoots the joints by 3 mm
            local = part.centre[None, :] + along[:, None] * 2 * half * _Y[None, :]
            axis_points.append(local @ frames[p, :3, :3].T + frames[p, :3, 3])
            radius.append(np.full(len(along), max(part.radii[0], part.radii[2])))
            digit.append(np.full(len(along), (p - 1) // 3))
        points, radius, digit = np.concatenate(axis_points), np.concatenate(radius), np.concatenate(digit)
        gap = np.linalg.norm(points[:, None] - points[None], axis=2) - radius[:, None] - radius[None]
        return float(np.min(gap[digit[:, None] != digit[None]]))

    # ------------------------------------------------------------------ shape, eqs. (1)-(2)
    def _local_coordinates(self, points: np.ndarray, frames: np.ndarray) -> np.ndarray:
        """R_p^T (x_m - t_p) - c_p for every point and part, shape (M, 16, 3)."""
        rotations = frames[:, :3, :3]
        # (x - t_p) R_p for all parts as one product: x @ [R_0 | R_1 | ...] minus the constant t_p R_p
        rotated = (points @ rotations.transpose(1, 0, 2).reshape(3, -1)).reshape(len(points), self.n_parts, 3)
        return rotated - np.einsum("pi,pij->pj", frames[:, :3, 3], rotations) - self._centres

    def part_distances(self, points: np.ndarray, theta: object) -> np.ndarray:
        """Pseudo-Euclidean distance from each point to each ellipsoid, (M, 16).

        Radial reading: d = ||x - c|| (1 - 1/r) with r = ||(x - c)/radii|| in the part frame,
        exact for spheres, negative inside.

        Parameters
        ----------
        points : array_like, shape (M, 3)
            Query points in world coordinates, mm, within ±1e6.
        theta : array_like, shape (27,)
            Pose (mm for DOFs 0-2, radians for the others).

        Returns
        -------
        numpy.ndarray, shape (M, 16)
            Distances, mm.
        """
        points, theta = self._check_query(points, theta)
        return self._part_distances(points, theta)

    def _part_distances(self, points: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """:meth:`part_distances` on checked input."""
        frames = self._forward(theta)[0]
        # local[m, p] = R_p^T (x_m - t_p) - c_p
        local = self._local_coordinates(points, frames)
        radial = np.linalg.norm(local / self._radii, axis=2)
        return np.linalg.norm(local, axis=2) * (1.0 - 1.0 / np.maximum(radial, 1e-12))

    def part_fields(self, points: np.ndarray, theta: object) -> np.ndarray:
        """Field functions φ_p = exp(-d/ν), eq. (1).

        Parameters
        ----------
        points : array_like, shape (M, 3)
            Query points in world coordinates, mm, within ±1e6.
        theta : array_like, shape (27,)
            Pose (mm for DOFs 0-2, radians for the others).

        Returns
        -------
        numpy.ndarray, shape (M, 16)
            φ_p per point and part (1 on an ellipsoid, > 1 inside, clipped at d = -20ν).
        """
        points, theta = self._check_query(points, theta)
        return self._part_fields(points, theta)

    def _part_fields(self, points: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """:meth:`part_fields` on checked input."""
        # eq. (1): φ_p(X) = exp(-d(X, Q_p)/ν), d clipped deep inside so that exp cannot overflow
        return np.exp(-np.clip(self._part_distances(points, theta), -20 * self.nu, None) / self.nu)

    def fused_field(self, points: np.ndarray, theta: object, *, neighbour_rule: bool = True) -> np.ndarray:
        """φ = Σ φ_p over the strongest part and its kinematic neighbours (Sec. 2).

        Parameters
        ----------
        points : array_like, shape (M, 3)
            Query points in world coordinates, mm, within ±1e6.
        theta : array_like, shape (27,)
            Pose (mm for DOFs 0-2, radians for the others).
        neighbour_rule : bool, default True
            Sum over the strongest part and its neighbours only (the paper's rule); False sums
            over all 16 parts.

        Returns
        -------
        numpy.ndarray, shape (M,)
            The fused field φ (1 on the surface).
        """
        points, theta = self._check_query(points, theta)
        neighbour_rule = check_bool(neighbour_rule, "neighbour_rule")
        return self._fused_field(points, theta, neighbour_rule)

    def _fused_field(self, points: np.ndarray, theta: np.ndarray, neighbour_rule: bool = True) -> np.ndarray:
        """:meth:`fused_field` on checked input."""
        fields = self._part_fields(points, theta)
        if not neighbour_rule:
            return fields.sum(axis=1)
        strongest = np.argmax(fields, axis=1)
        return np.sum(fields * self.adjacency[strongest], axis=1)

    def surface_distance(self, points: object, theta: object, *, neighbour_rule: bool = True) -> np.ndarray:
        """Distance to the fused surface d = -ν log φ, eq. (2) (negative inside).

        Parameters
        ----------
        points : array_like, shape (M, 3)
            Query points in world coordinates, mm, within ±1e6.
        theta : array_like, shape (27,)
            Pose (mm for DOFs 0-2, radians for the others).
        neighbour_rule : bool, default True
            As for :meth:`fused_field`.

        Returns
        -------
        numpy.ndarray, shape (M,)
            Signed distances, mm.
        """
        points, theta = self._check_query(points, theta)
        neighbour_rule = check_bool(neighbour_rule, "neighbour_rule")
        return self._surface_distance(points, theta, neighbour_rule)

    def _surface_distance(self, points: np.ndarray, theta: np.ndarray, neighbour_rule: bool = True) -> np.ndarray:
        """:meth:`surface_distance` on checked input (the loops of :meth:`sample_surface` call it)."""
        # eq. (2): d(X, Θ) = -ν log φ(X), φ = Σ_p φ_p the fused field
        return -self.nu * np.log(self._fused_field(points, theta, neighbour_rule))

    def surface_distance_jacobian(self, points: object, theta: object) -> tuple[np.ndarray, np.ndarray]:
        """Distance to the fused surface (eq. 2) and its analytic derivative in Θ, shapes (M,) and (M, 27).

        With φ = Σ_p φ_p over the strongest part and its neighbours, ∂d/∂Θ = Σ_p (φ_p/φ) ∂d_p/∂Θ.
        A part's distance depends on Θ through the point's local coordinates; for a revolute DOF k
        with world axis ω_k through o_k, ∂d_p/∂θ_k = -n_p · (ω_k × (x - o_k)), with n_p the world
        gradient of d_p in x; for a palm translation it is -n_p. The strongest part is held fixed
        (the rule is piecewise constant), as is the clip of very deep points in :meth:`part_fields`.

        Parameters
        ----------
        points : array_like, shape (M, 3)
            Query points in world coordinates, mm, within ±1e6.
        theta : array_like, shape (27,)
            Pose (mm for DOFs 0-2, radians for the others).

        Returns
        -------
        distance : numpy.ndarray, shape (M,)
            Signed distances d (eq. 2), mm.
        jacobian : numpy.ndarray, shape (M, 27)
            ∂d/∂Θ: mm per mm for the palm translation, mm per radian for the rest.
        """
        points, theta = self._check_query(points, theta)
        frames, axes, origins = self._forward(theta)
        rotations = frames[:, :3, :3]
        local = self._local_coordinates(points, frames)
        length = np.maximum(np.linalg.norm(local, axis=2), 1e-12)
        radial = np.maximum(np.linalg.norm(local / self._radii, axis=2), 1e-12)
        part_distance = length * (1.0 - 1.0 / radial)
        fields = np.exp(-np.clip(part_distance, -20 * self.nu, None) / self.nu)
        fields = fields * self.adjacency[np.argmax(fields, axis=1)]
        fused = fields.sum(axis=1)
        share = fields / fused[:, None]  # φ_p / φ over the strongest part's neighbourhood
        # ∂d_p/∂l in the part frame, then rotated to the world frame
        grad_local = ((1.0 - 1.0 / radial) / length)[..., None] * local + (length / radial**3)[..., None] * local / self._radii**2
        grad_world = (rotations[None] @ grad_local[..., None])[..., 0]
        # N[m, k] = Σ_p (φ_p/φ) [DOF k moves part p] n_p
        # (a sum over parts for every DOF: one tensordot rather than a three-operand einsum)
        blended = np.tensordot(self._dof_moves_part.astype(float), share[..., None] * grad_world, axes=([1], [1]))
        jac = np.empty((len(points), self.n_dof))  # blended is (27, M, 3)
        jac[:, :3] = -blended[:3].transpose(1, 0, 2).diagonal(axis1=1, axis2=2)
        lever = _axis_levers(axes[3:], origins[3:], points)
        jac[:, 3:] = -np.einsum("kmj,mkj->mk", blended[3:], lever)
        return -self.nu * np.log(fused), jac

    def sample_surface(self, theta: object, n: int, *, rng: np.random.Generator | int,
                       newton_steps: int = 4) -> np.ndarray:
        """Draw ``n`` points on the fused surface φ = 1 at pose ``theta``.

        Points are drawn on the ellipsoids (by approximate area) and pushed onto φ = 1 by Newton
        steps along a finite-difference gradient of eq. (2); points left far from it are redrawn.

        Parameters
        ----------
        theta : array_like, shape (27,)
            Pose (mm for DOFs 0-2, radians for the others).
        n : int
            Number of points (≥ 1). At most :data:`amdo_lab.common.MAX_SAMPLES` (1,000,000).
        rng : int or numpy.random.Generator
            Seed (≥ 0) or generator of the points.
        newton_steps : int, default 4
            Newton steps that project each drawn point onto the surface (≥ 1).
            At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).

        Returns
        -------
        numpy.ndarray, shape (n, 3)
            Points within 0.2 mm of the surface, mm.
        """
        theta = self.check_theta(theta)
        n = check_positive_int(n, "n", maximum=MAX_SAMPLES)
        rng = make_rng(rng, "rng")
        newton_steps = check_positive_int(newton_steps, "newton_steps", maximum=MAX_ITERATIONS)
        frames = self._forward(theta)[0]
        radii = np.array([part.radii for part in self._parts])
        area = (radii[:, 0] * radii[:, 1] + radii[:, 1] * radii[:, 2] + radii[:, 0] * radii[:, 2])
        kept: list[np.ndarray] = []
        total = 0
        while total < n:
            draw = 2 * (n - total) + 50
            part_ids = rng.choice(self.n_parts, size=draw, p=area / area.sum())
            direction = rng.normal(size=(draw, 3))
            direction /= np.linalg.norm(direction, axis=1, keepdims=True)
            centres = np.array([part.centre for part in self._parts])[part_ids]
            local = centres + direction * radii[part_ids]
            points = np.einsum("nij,nj->ni", frames[part_ids, :3, :3], local) + frames[part_ids, :3, 3]
            for _ in range(newton_steps):
                dist = self._surface_distance(points, theta)
                grad = self._distance_gradient(points, theta)
                points = points - (dist / np.maximum(np.sum(grad**2, axis=1), 1e-6))[:, None] * grad
            ok = np.abs(self._surface_distance(points, theta)) < 0.2
            kept.append(points[ok])
            total += int(ok.sum())
        return np.concatenate(kept)[:n]

    def _distance_gradient(self, points: np.ndarray, theta: np.ndarray, step: float = 1e-3) -> np.ndarray:
        """∂d/∂Y of eq. (2) at each point by central differences of ``step`` mm (for the surface normals)."""
        grad = np.empty_like(points)
        for axis in range(3):
            shift = np.zeros(3)
            shift[axis] = step
            grad[:, axis] = (self._surface_distance(points + shift, theta)
                             - self._surface_distance(points - shift, theta)) / (2 * step)
        return grad

    def surface_normals(self, points: object, theta: object) -> np.ndarray:
        """Unit outward normals of the fused surface (finite-difference gradient of eq. 2).

        Parameters
        ----------
        points : array_like, shape (M, 3)
            Query points in world coordinates, mm, within ±1e6.
        theta : array_like, shape (27,)
            Pose (mm for DOFs 0-2, radians for the others).

        Returns
        -------
        numpy.ndarray, shape (M, 3)
            Unit vectors (zero where the gradient vanishes).
        """
        points, theta = self._check_query(points, theta)
        return self._surface_normals(points, theta)

    def _surface_normals(self, points: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """:meth:`surface_normals` on checked input (the data generators call it every frame)."""
        grad = self._distance_gradient(points, theta)
        return grad / np.maximum(np.linalg.norm(grad, axis=1, keepdims=True), 1e-12)

    def ellipsoid_mesh(self, theta: object, resolution: int = 16) -> tuple[np.ndarray, np.ndarray]:
        """Triangle mesh of the 16 raw ellipsoids at pose ``theta``: vertices (V, 3) and faces (F, 3).

        Each ellipsoid is a latitude-longitude grid of ``resolution`` x ``resolution`` vertices,
        scaled by its semi-axes and placed by its part's rigid motion T_p(Θ).

        Parameters
        ----------
        theta : array_like, shape (27,)
            Pose (mm for DOFs 0-2, radians for the others).
        resolution : int, default 16
            Vertices per side of each ellipsoid's grid (≥ 4).
            At most 512 (16 parts of 512² vertices each).

        Returns
        -------
        vertices : numpy.ndarray, shape (16·resolution², 3)
            Vertex positions, mm.
        faces : numpy.ndarray of int, shape (F, 3)
            Vertex indices of each triangle.
        """
        frames = self._forward(self.check_theta(theta))[0]
        n = check_positive_int(resolution, "resolution", minimum=4, maximum=512)  # 16 parts of 512² vertices
        polar, azimuth = np.meshgrid(np.linspace(0, np.pi, n), np.linspace(0, 2 * np.pi, n), indexing="ij")
        unit = np.stack([np.sin(polar) * np.cos(azimuth), np.cos(polar), np.sin(polar) * np.sin(azimuth)], axis=-1)
        local = unit.reshape(1, -1, 3) * self._radii[:, None, :] + self._centres[:, None, :]  # (16, n², 3)
        vertices = np.einsum("pij,pvj->pvi", frames[:, :3, :3], local) + frames[:, None, :3, 3]
        cell = np.arange(n - 1)[:, None] * n + np.arange(n - 1)[None, :]
        quads = np.stack([cell, cell + 1, cell + n + 1, cell + n], axis=-1).reshape(-1, 4)
        one = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
        faces = (one[None] + (np.arange(self.n_parts) * n * n)[:, None, None]).reshape(-1, 3)
        return vertices.reshape(-1, 3), faces

    # ------------------------------------------------------------------ bending texture, eq. (3)
    def texture_binding(self, points: object, theta: object, a: float = 2.0) -> "TextureBinding":
        """Attach texture points to their strongest part p and its strongest neighbour r.

        The weights φ_p^a / (φ_p^a + φ_r^a) of eq. (3) are evaluated once, at the pose where the
        texture was observed, and the points are stored in both parts' local frames.

        Parameters
        ----------
        points : array_like, shape (N, 3)
            Texture points X at pose ``theta``, mm, within ±1e6.
        theta : array_like, shape (27,)
            Pose (mm for DOFs 0-2, radians for the others).
        a : float, default 2.0
            Exponent of the weights of eq. (3), in (0, :data:`MAX_BENDING_EXPONENT`]: large ``a``
            moves each point rigidly with
            its strongest part.

        Returns
        -------
        TextureBinding
            Both parts, the weight of the first, and the local coordinates.
        """
        points, theta = self._check_query(points, theta)
        a = check_in_range(a, "a", 0.0, MAX_BENDING_EXPONENT, closed="right")
        fields = self._part_fields(points, theta)
        part_p = np.argmax(fields, axis=1)
        neighbour_fields = np.where(self.adjacency[part_p] & (np.arange(self.n_parts) != part_p[:, None]),
                                    fields, -1.0)
        part_r = np.argmax(neighbour_fields, axis=1)
        log_p = a * np.log(fields[np.arange(len(points)), part_p])
        log_r = a * np.log(np.maximum(fields[np.arange(len(points)), part_r], 1e-300))
        # the weight of part p in eq. (3), φ_p^a / (φ_p^a + φ_r^a), written to stay finite in the log domain
        weight_p = 1.0 / (1.0 + np.exp(np.clip(log_r - log_p, -50, 50)))
        frames = self._forward(theta)[0]
        local_p = np.einsum("nji,nj->ni", frames[part_p, :3, :3], points - frames[part_p, :3, 3])
        local_r = np.einsum("nji,nj->ni", frames[part_r, :3, :3], points - frames[part_r, :3, 3])
        return TextureBinding(part_p, part_r, weight_p, local_p, local_r)

    def transform_texture(self, binding: "TextureBinding", theta: np.ndarray) -> np.ndarray:
        """Blended motion T(X, Θ) of eq. (3) for bound texture points.

        Parameters
        ----------
        binding : TextureBinding
            From :meth:`texture_binding`.
        theta : array_like, shape (27,)
            Pose (mm for DOFs 0-2, radians for the others).

        Returns
        -------
        numpy.ndarray, shape (N, 3)
            The moved texture, mm.
        """
        binding = check_binding(binding)
        theta = self.check_theta(theta)
        return self._transform_texture(binding, theta)

    def _transform_texture(self, binding: "TextureBinding", theta: np.ndarray) -> np.ndarray:
        """:meth:`transform_texture` on checked input (the EM loops call it)."""
        frames = self._forward(theta)[0]
        world_p, world_r = binding.world_points(frames)
        w = binding.weight_p[:, None]
        # eq. (3): T(X, Θ) = (φ_p^a T_p X + φ_r^a T_r X) / (φ_p^a + φ_r^a), with w = φ_p^a / (φ_p^a + φ_r^a)
        return w * world_p + (1 - w) * world_r

    def texture_jacobian(self, binding: "TextureBinding", theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Blended positions (N, 3) and their analytic Jacobian d T(X, Θ)/dΘ, shape (N, 3, 27).

        For a revolute DOF k with world axis ω_k through o_k, a point x rigidly attached to a part
        it moves has dx/dθ_k = ω_k × (x - o_k); for the palm translation dx/dt = e_t. Eq. (3) mixes
        the two parts' derivatives with the same (frozen) weights.

        Parameters
        ----------
        binding : TextureBinding
            From :meth:`texture_binding`.
        theta : array_like, shape (27,)
            Pose (mm for DOFs 0-2, radians for the others).

        Returns
        -------
        positions : numpy.ndarray, shape (N, 3)
            T(X, Θ), mm.
        jacobian : numpy.ndarray, shape (N, 3, 27)
            dT/dΘ: mm per mm for the palm translation, mm per radian for the rest.
        """
        binding = check_binding(binding)
        theta = self.check_theta(theta)
        return self._texture_jacobian(binding, theta)

    def _texture_jacobian(self, binding: "TextureBinding", theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`texture_jacobian` on checked input (the M-step's Gauss-Newton loop calls it)."""
        frames, axes, origins = self._forward(theta)
        world_p, world_r = binding.world_points(frames)
        w = binding.weight_p[:, None]
        jac = np.empty((len(w), 3, self.n_dof))
        jac[:, :, :3] = np.eye(3)
        # ω_k × (x - o_k) for every point and revolute DOF at once, zero where DOF k does not move the part
        share_p = w * self._dof_moves_part[3:, binding.part_p].T  # (N, 24): weight of part p's motion
        share_r = (1 - w) * self._dof_moves_part[3:, binding.part_r].T
        blended = (share_p[..., None] * _axis_levers(axes[3:], origins[3:], world_p)
                   + share_r[..., None] * _axis_levers(axes[3:], origins[3:], world_r))
        jac[:, :, 3:] = blended.transpose(0, 2, 1)
        return w * world_p + (1 - w) * world_r, jac

    def move_texture(self, points: object, theta_from: object, theta_to: object, a: float = 2.0) -> np.ndarray:
        """Move texture points observed at pose ``theta_from`` to pose ``theta_to`` (eq. 3).

        Parameters
        ----------
        points : array_like, shape (N, 3)
            Texture points at ``theta_from``, mm.
        theta_from : array_like, shape (27,)
            Pose where the points were observed.
        theta_to : array_like, shape (27,)
            Pose to move them to.
        a : float, default 2.0
            Exponent of the weights of eq. (3), in (0, :data:`MAX_BENDING_EXPONENT`].

        Returns
        -------
        numpy.ndarray, shape (N, 3)
            The moved points, mm.
        """
        binding = self.texture_binding(points, self.check_theta(theta_from, "theta_from"), a)
        return self.transform_texture(binding, self.check_theta(theta_to, "theta_to"))


@dataclass(frozen=True)
class TextureBinding:
    """Texture points attached to two adjacent parts with the eq. (3) weight of the first.

    Parameters
    ----------
    part_p : array_like of int, shape (N,)
        Strongest part p of each point, 0 to 15.
    part_r : array_like of int, shape (N,)
        Its strongest kinematic neighbour r, 0 to 15.
    weight_p : array_like, shape (N,)
        φ_p^a / (φ_p^a + φ_r^a) of eq. (3), in [0, 1], frozen at the binding pose.
    local_p : array_like, shape (N, 3)
        The point in part p's frame, mm, within ±1e6.
    local_r : array_like, shape (N, 3)
        The point in part r's frame, mm, within ±1e6.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; eq. (3).
    """

    part_p: np.ndarray
    part_r: np.ndarray
    weight_p: np.ndarray
    local_p: np.ndarray
    local_r: np.ndarray

    def __post_init__(self) -> None:
        """Check the arrays once, as any user-built record is (the package's own bindings pass too)."""
        local_p = check_points(self.local_p, "local_p")
        object.__setattr__(self, "local_p", local_p)
        object.__setattr__(self, "local_r", as_finite_array(self.local_r, "local_r", shape=local_p.shape,
                                                            max_abs=MAX_LENGTH_MM))
        for name in ("part_p", "part_r"):
            object.__setattr__(self, name, as_finite_array(getattr(self, name), name, shape=(len(local_p),),
                                                           dtype=int, bounds=(0, HandModel.n_parts - 1)))
        object.__setattr__(self, "weight_p", as_finite_array(self.weight_p, "weight_p", shape=(len(local_p),),
                                                             bounds=(0.0, 1.0)))

    def world_points(self, frames: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Each point carried rigidly by part p and by part r (the two terms eq. 3 blends).

        Parameters
        ----------
        frames : numpy.ndarray, shape (16, 4, 4)
            Part transforms, e.g. :meth:`HandModel.part_transforms`; entries at most
            :data:`MAX_LENGTH_MM` in magnitude.

        Returns
        -------
        world_p : numpy.ndarray, shape (N, 3)
            The points moved with part p, mm.
        world_r : numpy.ndarray, shape (N, 3)
            The points moved with part r, mm.
        """
        frames = as_finite_array(frames, "frames", shape=(HandModel.n_parts, 4, 4), max_abs=MAX_LENGTH_MM)
        world_p = np.einsum("nij,nj->ni", frames[self.part_p, :3, :3], self.local_p) + frames[self.part_p, :3, 3]
        world_r = np.einsum("nij,nj->ni", frames[self.part_r, :3, :3], self.local_r) + frames[self.part_r, :3, 3]
        return world_p, world_r


def check_points(points: object, name: str) -> np.ndarray:
    """``points`` as an (N, 3) float array within ±:data:`MAX_LENGTH_MM` mm, or an error naming ``name``."""
    return as_finite_array(points, name, ndim=2, shape=(None, 3), max_abs=MAX_LENGTH_MM)


def check_hand(hand: object) -> HandModel:
    """``hand`` itself, or a ``TypeError`` when it is not a :class:`HandModel`."""
    return check_instance(hand, "hand", HandModel, what="a HandModel")


def check_binding(binding: object) -> TextureBinding:
    """``binding`` itself, or a ``TypeError`` when it is not a :class:`TextureBinding`."""
    return check_instance(binding, "binding", TextureBinding, what="a TextureBinding (HandModel.texture_binding)")
