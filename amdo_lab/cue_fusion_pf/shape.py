"""The contour: a periodic quadratic B-spline (eq. 1) in a shape space (eqs. 2-3).

A state ``X`` is a short vector; the spline's control points are ``Q = W X + Q̄`` (eq. 2). For the
head the shape space is translation + scale (eq. 3, left): ``Q^x = t_x + (1 + s) Q̄^x`` and
``Q^y = t_y + (1 + s) Q̄^y`` with the template ``Q̄`` centred on the origin, so ``X = (t_x, t_y, s)``
is the contour's centre in pixels and its relative change of size. For the walker it is the
similarity space (eq. 3, right): translation, scale and rotation, state ``(t_x, t_y, s_c, s_s)``.
"""

from __future__ import annotations

import numpy as np

from amdo_lab.common import MAX_SAMPLES, MAX_SIDE
from amdo_lab.common import as_finite_array, check_choice, check_positive_int

__all__ = ["MAX_STATE_ENTRY", "SHAPE_KINDS", "ShapeSpace", "as_states"]

SHAPE_KINDS = ("translation_scale", "similarity")
STATE_DIMS = {"translation_scale": 3, "similarity": 4}
#: Largest magnitude of a state entry (pixels, relative scale): far beyond any frame, so the contours'
#: pixel coordinates stay finite and within int32, and squared distances between states stay finite.
MAX_STATE_ENTRY = 1e6


def as_states(states: object, state_dim: int, name: str = "states") -> np.ndarray:
    """Return ``states`` as a float array after checking its shape, (d,) or (N, d), and its range.

    Parameters
    ----------
    states : array_like
        (state_dim,) or (N, state_dim) states; every entry within ±:data:`MAX_STATE_ENTRY`.
    state_dim : int
        d: 3 (translation + scale) or 4 (similarity).
    name : str
        The argument's name, used in error messages.

    Returns
    -------
    numpy.ndarray
        The states, float, shape as given.

    References
    ----------
    Li & Chaumette, AMDO 2004, eqs. (2)-(3) (the state of a shape space).
    """
    states = as_finite_array(states, name, allow_empty=True, max_abs=MAX_STATE_ENTRY)
    if states.ndim not in (1, 2) or states.shape[-1] != state_dim:
        raise ValueError(f"{name} must have shape ({state_dim},) or (N, {state_dim}), got shape {states.shape}")
    return states


def _bspline_basis(s: np.ndarray, n_control: int, derivative: bool = False) -> np.ndarray:
    """Periodic uniform quadratic B-spline basis ``B(s)`` of eq. (1), one row per parameter value.

    Check-free: the shape space calls it with its own parameters (``n_control`` checked when the space is made).

    Parameters
    ----------
    s : numpy.ndarray
        (n,) float curve parameters (span ``j`` is ``j <= s < j + 1``; ``L = J`` spans; taken modulo J).
    n_control : int
        J, the number of control points (at least 3).
    derivative : bool
        Return ``dB/ds`` instead of ``B``.

    Returns
    -------
    numpy.ndarray
        (n, J) basis values; rows sum to 1 (to 0 for the derivative).

    References
    ----------
    Blake & Isard, Active Contours (1998), ch. 3; Li & Chaumette, AMDO 2004, eq. (1).
    """
    s = np.mod(s, n_control)
    span = np.floor(s).astype(int)
    u = s - span
    if derivative:
        weights = np.stack([-(1.0 - u), 1.0 - 2.0 * u, u], axis=1)
    else:  # the three quadratic pieces; they sum to 1 for every u
        weights = np.stack([0.5 * (1.0 - u) ** 2, 0.5 * (-2.0 * u**2 + 2.0 * u + 1.0), 0.5 * u**2], axis=1)
    basis = np.zeros((s.size, n_control))
    rows = np.arange(s.size)
    for offset in range(3):
        np.add.at(basis, (rows, (span + offset) % n_control), weights[:, offset])
    return basis


def _ellipse_points(ellipse: np.ndarray, n_points: int) -> np.ndarray:
    """``n_points`` points of the ellipse ``(cx, cy, a, b, angle)`` at equal steps of its angle parameter.

    Check-free: :meth:`ShapeSpace.from_ellipse` calls it with its checked ellipse.

    Parameters
    ----------
    ellipse : numpy.ndarray
        (5,) centre (px), semi-axes a (along x at angle 0) and b (px), angle (rad).
    n_points : int
        Number of points.

    Returns
    -------
    numpy.ndarray
        (n_points, 2) points (x, y) in pixels.

    References
    ----------
    Li & Chaumette, AMDO 2004, Sec. 2.1 (the ellipse fitted to each contour).
    """
    cx, cy, a, b, angle = ellipse
    theta = np.linspace(0.0, 2.0 * np.pi, n_points, endpoint=False)
    local = np.stack([a * np.cos(theta), b * np.sin(theta)], axis=1)
    rotation = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    return local @ rotation.T + np.array([cx, cy])


class ShapeSpace:
    """Shape space of eqs. (2-3) over a periodic quadratic B-spline template.

    Parameters
    ----------
    template : numpy.ndarray
        (J, 2) control points ``Q̄`` in pixels, within ±1e6; they are centred on their mean, which becomes the
        state's origin.
    kind : str
        ``"translation_scale"`` (the head space of eq. 3, left, state ``(t_x, t_y, s)``) or
        ``"similarity"`` (the walker space of eq. 3, right, state ``(t_x, t_y, s_c, s_s)``).
    _ellipse : numpy.ndarray, optional
        The template's exact ellipse, when known (set by :meth:`from_ellipse`).

    Notes
    -----
    The paper fits an ellipse to each particle's contour for the colour cue. In a translation +
    scale space that ellipse is the template's ellipse moved and scaled, so :meth:`ellipses` is
    exact and costs nothing; the template's ellipse comes from the second moments of the curve
    (exact when the template was made by :meth:`from_ellipse`). A similarity maps an ellipse to an
    ellipse too, so the same holds in the similarity space.

    The second W of eq. (3) is printed as ``[[1, 0, Q̄^x - Q̄^y], [0, 1, Q̄^y, Q̄^x]]``: the first
    row lost a column separator. We read it as the four columns ``(1, 0)``, ``(0, 1)``,
    ``(Q̄^x, Q̄^y)`` and ``(-Q̄^y, Q̄^x)`` (x stacked over y), the Euclidean similarity space of
    Blake & Isard (1998, ch. 4): ``Q^x = t_x + (1 + s_c) Q̄^x - s_s Q̄^y`` and
    ``Q^y = t_y + s_s Q̄^x + (1 + s_c) Q̄^y``, i.e. the template turned by ``θ`` and scaled by
    ``k`` with ``1 + s_c = k cos θ`` and ``s_s = k sin θ``, then shifted by ``(t_x, t_y)``.

    References
    ----------
    Li & Chaumette, AMDO 2004, eqs. (1)-(3).
    """

    def __init__(self, template: np.ndarray, kind: str = "translation_scale", *, _ellipse: np.ndarray | None = None):
        template = as_finite_array(template, "template", shape=(None, 2), max_abs=1e6)  # its covariance stays finite
        check_positive_int(template.shape[0], "template length", minimum=3, maximum=MAX_SIDE)
        self.kind = check_choice(kind, "kind", SHAPE_KINDS)
        self.centre = template.mean(axis=0)
        self.template = template - self.centre  # Q̄, centred
        self.n_control = template.shape[0]
        self.state_dim = STATE_DIMS[self.kind]
        if _ellipse is None:
            curve = _bspline_basis(np.linspace(0, self.n_control, 8 * self.n_control, endpoint=False), self.n_control) @ self.template
            centre = curve.mean(axis=0)
            values, vectors = np.linalg.eigh(np.cov(curve.T, bias=True))
            # points at equal steps of the angle parameter have variance a^2/2 along the major axis
            a, b = np.sqrt(2.0 * values[::-1])
            angle = float(np.arctan2(vectors[1, 1], vectors[0, 1]))
            _ellipse = np.array([centre[0], centre[1], a, b, angle])
        self.template_ellipse = np.asarray(_ellipse, float)

    @classmethod
    def from_ellipse(cls, ellipse: np.ndarray, n_control: int = 12, kind: str = "translation_scale") -> "ShapeSpace":
        """Template whose B-spline fits the ellipse ``(cx, cy, a, b, angle)`` (least squares on 8J points).

        Parameters
        ----------
        ellipse : numpy.ndarray
            (5,) the ellipse, entries within ±1e6; axes must be positive.
        n_control : int
            J, the number of control points. At most :data:`amdo_lab.common.MAX_SIDE` (4,096).
        kind : str
            ``"translation_scale"`` or ``"similarity"``.

        Returns
        -------
        ShapeSpace
            The space; the state of that ellipse is ``(cx, cy, 0)`` (``(cx, cy, 0, 0)``).
        """
        ellipse = as_finite_array(ellipse, "ellipse", shape=(5,), max_abs=1e6)
        n_control = check_positive_int(n_control, "n_control", minimum=3, maximum=MAX_SIDE)
        if ellipse[2] <= 0 or ellipse[3] <= 0:
            raise ValueError(f"ellipse axes must be positive, got a={ellipse[2]}, b={ellipse[3]}")
        centred = ellipse.copy()
        centred[:2] = 0.0
        n_fit = 8 * n_control
        points = _ellipse_points(centred, n_fit)
        basis = _bspline_basis(np.arange(n_fit) * n_control / n_fit, n_control)
        control, *_ = np.linalg.lstsq(basis, points, rcond=None)
        return cls(control, kind, _ellipse=centred)

    # --- eq. (2): Q = W X + Q̄ ---------------------------------------------------------------
    def shape_matrix(self) -> np.ndarray:
        """W of eq. (3): left for ``"translation_scale"``, right (our reading, see the class) for ``"similarity"``.

        Returns
        -------
        numpy.ndarray
            (2J, 3) with columns (1, 0), (0, 1) and (Q̄^x, Q̄^y) stacked x over y; the similarity
            space adds a fourth column (-Q̄^y, Q̄^x).
        """
        ones, zeros = np.ones(self.n_control), np.zeros(self.n_control)
        # eq. (3): columns for x-translation, y-translation and scale about the template Q̄ (left) ...
        qx, qy = self.template[:, 0], self.template[:, 1]
        columns = [np.concatenate([ones, zeros]), np.concatenate([zeros, ones]), np.concatenate([qx, qy])]
        if self.kind == "similarity":
            columns.append(np.concatenate([-qy, qx]))  # ... and (right) the template turned by 90°: rotation
        return np.stack(columns, axis=1)

    def similarity_parts(self, states: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Scale k and rotation R of each state: its control points are ``t + k R Q̄`` (eqs. 2-3).

        Parameters
        ----------
        states : numpy.ndarray
            (N, d) or (d,) states.

        Returns
        -------
        tuple of numpy.ndarray
            (N,) scales ``k`` (``1 + s``, or ``hypot(1 + s_c, s_s)``) and (N, 2, 2) rotations
            (the identity in the translation + scale space).
        """
        states = np.atleast_2d(self.check_states(states))
        if self.kind == "translation_scale":
            return 1.0 + states[:, 2], np.broadcast_to(np.eye(2), (len(states), 2, 2)).copy()
        scale = np.hypot(1.0 + states[:, 2], states[:, 3])
        safe = np.where(scale > 0, scale, 1.0)  # a state of scale 0 has no direction: call it unturned
        cos, sin = np.where(scale > 0, (1.0 + states[:, 2]) / safe, 1.0), np.where(scale > 0, states[:, 3] / safe, 0.0)
        return scale, np.stack([np.stack([cos, -sin], axis=1), np.stack([sin, cos], axis=1)], axis=1)

    def control_points(self, states: np.ndarray) -> np.ndarray:
        """Control points of the states, eq. (2) written as a matrix product.

        Parameters
        ----------
        states : numpy.ndarray
            (N, d) or (d,) states ``(t_x, t_y, s)`` or ``(t_x, t_y, s_c, s_s)``.

        Returns
        -------
        numpy.ndarray
            (N, J, 2) control points in pixels.
        """
        states = np.atleast_2d(self.check_states(states))
        # eq. (2): Q = W X + Q̄, with Q stacked as (Q^x, Q^y)
        stacked = states @ self.shape_matrix().T + np.concatenate([self.template[:, 0], self.template[:, 1]])
        return np.stack([stacked[:, : self.n_control], stacked[:, self.n_control :]], axis=2)

    def curve(self, states: np.ndarray, n_points: int = 80) -> np.ndarray:
        """Points ``r(s)`` of eq. (1) at equal parameter steps.

        Parameters
        ----------
        states : numpy.ndarray
            (N, d) or (d,) states, entries within ±1e6.
        n_points : int
            Points per curve. At most :data:`amdo_lab.common.MAX_SAMPLES` (1,000,000).

        Returns
        -------
        numpy.ndarray
            (N, n_points, 2) curve points in pixels.
        """
        n_points = check_positive_int(n_points, "n_points", maximum=MAX_SAMPLES)
        basis = _bspline_basis(np.linspace(0, self.n_control, n_points, endpoint=False), self.n_control)
        # eq. (1): r(s) = (B(s)ᵀ Q^x, B(s)ᵀ Q^y), the quadratic B-spline through the control points
        return np.einsum("pj,njd->npd", basis, self.control_points(states))

    def template_normals(self, n_lines: int) -> tuple[np.ndarray, np.ndarray]:
        """Points of the template curve and unit outward normals at ``n_lines`` equal parameter steps.

        Parameters
        ----------
        n_lines : int
            N_e, the number of measurement lines. At most :data:`amdo_lab.common.MAX_SAMPLES` (1,000,000).

        Returns
        -------
        tuple of numpy.ndarray
            (n_lines, 2) points relative to the state's centre at scale 1, and (n_lines, 2) normals.
        """
        n_lines = check_positive_int(n_lines, "n_lines", maximum=MAX_SAMPLES)
        s = np.linspace(0, self.n_control, n_lines, endpoint=False)
        points = _bspline_basis(s, self.n_control) @ self.template
        tangents = _bspline_basis(s, self.n_control, derivative=True) @ self.template
        normals = np.stack([tangents[:, 1], -tangents[:, 0]], axis=1)
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        # outward: pointing away from the centre (the template is centred on the origin)
        normals *= np.sign(np.sum(normals * points, axis=1, keepdims=True))
        return points, normals

    def ellipses(self, states: np.ndarray) -> np.ndarray:
        """Best-fitting ellipses of the states' contours.

        Parameters
        ----------
        states : numpy.ndarray
            (N, d) or (d,) states, entries within ±1e6.

        Returns
        -------
        numpy.ndarray
            (N, 5) ellipses ``(cx, cy, a, b, angle)``.
        """
        states = np.atleast_2d(self.check_states(states))
        e = self.template_ellipse
        if self.kind == "translation_scale":
            scale = 1.0 + states[:, 2]
            return np.stack([states[:, 0] + scale * e[0], states[:, 1] + scale * e[1],
                             scale * e[2], scale * e[3], np.full(len(states), e[4])], axis=1)
        scale, rotation = self.similarity_parts(states)  # the ellipse turned by θ and scaled by k
        centre = states[:, :2] + scale[:, None] * (rotation @ e[:2])
        angle = e[4] + np.arctan2(rotation[:, 1, 0], rotation[:, 0, 0])
        return np.stack([centre[:, 0], centre[:, 1], scale * e[2], scale * e[3], angle], axis=1)

    def check_states(self, states: np.ndarray) -> np.ndarray:
        """Return ``states`` as a float array after checking its shape and range (the cues call it too).

        Parameters
        ----------
        states : array_like
            (state_dim,) or (N, state_dim) states; every entry within ±:data:`MAX_STATE_ENTRY`.

        Returns
        -------
        numpy.ndarray
            The states, float, shape as given.

        References
        ----------
        Li & Chaumette, AMDO 2004, eqs. (2)-(3) (the state of a shape space).
        """
        return as_states(states, self.state_dim)
