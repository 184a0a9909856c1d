"""The velocity-force stencil of the CAT viscous fluid (Sec. 4, eqs. 8-15).

Geometry (Fig. 2a). The primal complex K^p has its 0-pixels on the pixel centres; the dual
complex K^s has its 2-pixels on the pixels. The dual 2-pixel γ_F of the pixel at the origin is
the square [-1/2, 1/2]^2; it overlaps one quadrant of each of the four primal 2-pixels that have
the origin as a corner. Inside a primal 2-pixel the velocity is the bilinear interpolation of its
four corner values (eq. 13), its gradient d = ∇v gives the stress of the constitutive law
(eq. 12, pressure left out: σ = λ tr(d) I + μ (d + dᵀ)), and the force on γ_F is the stress flux
through the four 1-faces of γ_F, each 1-face split into the two halves lying in different primal
2-pixels (eqs. 9-11 and the four S_1 integrals, eq. 14). The result is linear in the nine corner
velocities around the pixel: two rows (force components) of 9 x 2 = 18 coefficients (eq. 15).

Coordinates: x1 along array axis 0 (rows), x2 along array axis 1 (columns), unit spacing;
velocity component 1 (index 0) is along x1. The 18 columns follow :data:`NEIGHBOUR_OFFSETS`,
each neighbour contributing (v_1, v_2).

Sign convention: the stencil is the *internal* force ∮ σ n dl on γ_F, which approximates
μΔv + (λ+μ)∇(∇·v), the operator on the left of eq. (17); its centre coefficient is negative, as
in the paper's printed k_{1,1}. Registration solves stencil · v = F^ext as eq. (17) is printed.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from amdo_lab.common import (MAX_SIDE, as_finite_array, check_choice, check_in_range, check_instance,
                             check_positive_int)

#: Largest stencil entry accepted: a stencil built from Lamé constants up to 1e150 has entries a few
#: times that; sums over the nine blocks and the squares in a symbol's 2x2 eigenproblem stay finite.
MAX_STENCIL_ENTRY = 1e152

__all__ = ["NEIGHBOUR_OFFSETS", "bilinear_gradient", "check_moduli", "dual_cell_force", "fluid_stencil", "printed_stencil", "apply_stencil",
           "stencil_at_origin", "rotate_stencil", "stencil_blocks", "stencil_grid", "polynomial_test_fields",
           "consistency_errors", "viscous_stress"]

#: (axis-0, axis-1) offsets of the 9 neighbours behind the 18 columns (two components each):
#: our reading of the paper's "00, 01, ..., -1-1" sequence in eq. (15). The printed k values fix
#: its shape: columns (3, 9) and (5, 11) hold opposite edge neighbours, columns 7, 13, 15 and 17
#: the diagonals, and the sequence starts at 00, 01 and ends at -1-1.
NEIGHBOUR_OFFSETS: tuple[tuple[int, int], ...] = (
    (0, 0), (0, 1), (1, 0), (1, 1), (0, -1), (-1, 0), (-1, 1), (1, -1), (-1, -1))

# the integrand along each half 1-face is linear, so the midpoint rule is exact
_HALF_FACES = (  # (point on the half-face, outward normal, length)
    *[((0.5, m), (1.0, 0.0), 0.5) for m in (-0.25, 0.25)],
    *[((-0.5, m), (-1.0, 0.0), 0.5) for m in (-0.25, 0.25)],
    *[((m, 0.5), (0.0, 1.0), 0.5) for m in (-0.25, 0.25)],
    *[((m, -0.5), (0.0, -1.0), 0.5) for m in (-0.25, 0.25)],
)


#: Largest Lamé constant accepted: the Fourier solve multiplies two symbol entries of about
#: 8 (λ + 2μ), which would overflow a float (1.8e308) above about 1e153.
MAX_MODULUS = 1e150
#: Largest entry of a velocity or force field the solvers accept: times moduli of at most
#: MAX_MODULUS, the stencil's sums stay near 1e250, below a float's overflow (1.8e308).
MAX_FIELD = 1e100


def check_moduli(lam: object, mu: object, *, require_positive_mu: bool = False) -> tuple[float, float]:
    """Validate the Lamé constants: 0 ≤ λ ≤ 1e150 and 0 ≤ μ ≤ 1e150 (μ > 0 when a velocity is solved for)."""
    return (check_in_range(lam, "lam", 0, MAX_MODULUS, closed="both"),
            check_in_range(mu, "mu", 0, MAX_MODULUS, closed="right" if require_positive_mu else "both"))


def _checked_velocity(velocity: object) -> Callable[..., np.ndarray]:
    """``velocity`` as a function whose every value is checked to be a finite 2-vector (within ±1e100)."""
    check_instance(velocity, "velocity", Callable, what="a function of (x1, x2)")
    def checked(*x: float) -> np.ndarray:
        name = f"velocity({', '.join(f'{value:g}' for value in x)})"  # the point named, e.g. velocity(0, 1)
        return as_finite_array(velocity(*x), name, shape=(2,), max_abs=MAX_FIELD)
    return checked


def _bilinear_gradient(corner_velocity: Callable[[int, int], np.ndarray], point: np.ndarray) -> np.ndarray:
    """Check-free kernel of :func:`bilinear_gradient`."""
    a, b = int(np.floor(point[0])), int(np.floor(point[1]))
    s, t = point[0] - a, point[1] - b  # local coordinates in [0, 1]^2
    v00, v10, v01, v11 = (corner_velocity(a + da, b + db) for da, db in ((0, 0), (1, 0), (0, 1), (1, 1)))
    # eq. (5), d = ∇v, of the bilinear velocity of eq. (13): each partial derivative blends the
    # differences along two opposite edges of the square, the edge values D_1 of eq. (7)
    d_dx1 = (1 - t) * (v10 - v00) + t * (v11 - v01)
    d_dx2 = (1 - s) * (v01 - v00) + s * (v11 - v10)
    return np.column_stack([d_dx1, d_dx2])


def bilinear_gradient(velocity: Callable[[int, int], object], point: object) -> np.ndarray:
    """d[i, j] = ∂v_i/∂x_j (eq. 5) of the bilinear velocity (eq. 13) at ``point``.

    Inside the primal 2-pixel whose lower corner is floor(point), the velocity is the bilinear
    interpolation of its four corner values; its gradient blends the differences along two
    opposite edges of the square.

    Parameters
    ----------
    velocity : callable
        ``velocity(i, j)`` returns the two finite velocity components (within ±1e100) at the integer
        corner (i, j) (x1 along array axis 0, unit pixel spacing).
    point : array_like, shape (2,)
        (x1, x2) where the gradient is taken, within ±4096 pixels.

    Returns
    -------
    numpy.ndarray of float, shape (2, 2)
        d, row i the velocity component, column j the derivative along x_j.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    eqs. (5) and (13).

    Examples
    --------
    >>> from amdo_lab.cat_fluid import bilinear_gradient
    >>> bilinear_gradient(lambda i, j: (i * j, 0.0), [0.25, 0.75]).tolist()  # ∂(x1 x2) = (x2, x1)
    [[0.75, 0.25], [0.0, 0.0]]
    """
    point = as_finite_array(point, "point", shape=(2,), max_abs=MAX_SIDE)
    return _bilinear_gradient(_checked_velocity(velocity), point)


def _stress(grad: np.ndarray, lam: float, mu: float) -> np.ndarray:
    """Check-free kernel of :func:`viscous_stress`."""
    # eq. (12) with ε = (d + dᵀ)/2: σ = λ tr(ε) I + μ (d + dᵀ) (no pressure term, as eq. 17)
    return lam * np.trace(grad) * np.eye(2) + mu * (grad + grad.T)


def viscous_stress(gradient: object, lam: float = 1.0, mu: float = 5.0) -> np.ndarray:
    """The stress of eq. (12) without the pressure term: σ = λ tr(ε) I + 2μ ε, ε = (d + dᵀ)/2.

    Parameters
    ----------
    gradient : array_like, shape (2, 2)
        Velocity gradient d[i, j] = ∂v_i/∂x_j (eq. 5), entries within ±1e100.
    lam : float, optional
        Lamé constant λ, 0 ≤ λ ≤ 1e150 (default 1, as the paper).
    mu : float, optional
        Lamé constant μ, 0 ≤ μ ≤ 1e150 (default 5, as the paper).

    Returns
    -------
    numpy.ndarray of float, shape (2, 2)
        σ, symmetric.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    eq. (12).

    Examples
    --------
    >>> from amdo_lab.cat_fluid import viscous_stress
    >>> viscous_stress([[1.0, 0.0], [0.0, 0.0]], lam=1.0, mu=5.0).tolist()  # a stretch along x1
    [[11.0, 0.0], [0.0, 1.0]]
    """
    gradient = as_finite_array(gradient, "gradient", shape=(2, 2), max_abs=MAX_FIELD)
    return _stress(gradient, *check_moduli(lam, mu))


def _flux(corner_velocity: Callable[[int, int], np.ndarray], lam: float, mu: float) -> np.ndarray:
    """Check-free kernel of :func:`dual_cell_force`."""
    # eqs. (8)-(11): by the divergence theorem the force on the dual cell γ_F is the flux of σ through
    # its boundary, a sum over its four sides S_i (eq. 11), each split in two halves lying in different
    # primal squares; σ is linear along a half, so its midpoint value times its length is exact.
    # Eq. (14) prints a minus sign in front of the sum; we keep the internal force +∮σn dl (see the chapter)
    force = np.zeros(2)
    for point, normal, length in _HALF_FACES:
        grad = _bilinear_gradient(corner_velocity, np.array(point))
        force += length * _stress(grad, lam, mu) @ np.array(normal)
    return force


def dual_cell_force(velocity: Callable[[int, int], object], lam: float = 1.0, mu: float = 5.0) -> np.ndarray:
    """∮ σ n dl over the dual cell γ_F of the pixel at the origin (eqs. 8-11 and 14).

    By the divergence theorem (eqs. 8-10) the viscous force on γ_F = [-1/2, 1/2]² is the flux of the
    stress (eq. 12) through its four sides (eq. 11); each side is split into the two halves lying in
    different primal 2-pixels, where the velocity is bilinear (eq. 13), and the midpoint rule is
    exact on each half. :func:`fluid_stencil` is this force for one unit corner velocity at a time.

    Parameters
    ----------
    velocity : callable
        ``velocity(i, j)`` returns the two finite velocity components (within ±1e100) at the pixel
        (i, j), i, j in {-1, 0, 1}.
    lam : float, optional
        Lamé constant λ, 0 ≤ λ ≤ 1e150 (default 1, as the paper).
    mu : float, optional
        Lamé constant μ, 0 ≤ μ ≤ 1e150 (default 5, as the paper).

    Returns
    -------
    numpy.ndarray of float, shape (2,)
        The internal force on γ_F, which approximates μΔv + (λ+μ)∇(∇·v) at the origin.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    eqs. (8)-(14).

    Examples
    --------
    >>> from amdo_lab.cat_fluid import dual_cell_force
    >>> dual_cell_force(lambda i, j: (j * j, 0.0), lam=1.0, mu=5.0).tolist()  # μ Δ(x2², 0) = (2μ, 0)
    [10.0, 0.0]
    """
    return _flux(_checked_velocity(velocity), *check_moduli(lam, mu))


def fluid_stencil(lam: float = 1.0, mu: float = 5.0) -> np.ndarray:
    """The (2, 18) CAT matrix K of eq. (15), derived by carrying out the integrals of eq. (14).

    Column ``2 p + c`` multiplies velocity component ``c`` at the neighbour
    ``NEIGHBOUR_OFFSETS[p]``; row ``i`` is force component ``i``. The integrals are exact
    (midpoint rule on integrands that are linear along each half 1-face), taken one unit corner
    velocity at a time. ``K · v`` approximates μΔv + (λ+μ)∇(∇·v) (see the module docstring).

    Parameters
    ----------
    lam : float, optional
        Lamé constant λ, 0 ≤ λ ≤ 1e150 (default 1, as the paper).
    mu : float, optional
        Lamé constant μ, 0 ≤ μ ≤ 1e150 (default 5, as the paper).

    Returns
    -------
    numpy.ndarray of float, shape (2, 18)
        K; its centre coefficients are negative and each row sums to zero.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    eqs. (8)-(15).

    Examples
    --------
    >>> from amdo_lab.cat_fluid import consistency_errors, fluid_stencil, printed_stencil
    >>> K = fluid_stencil(lam=1.0, mu=5.0)
    >>> K.shape, float(K[0, 0])
    ((2, 18), -24.0)
    >>> max(consistency_errors(K).values())  # exact on constant, linear and quadratic fields
    0.0
    >>> max(consistency_errors(printed_stencil(1.0, 5.0)).values()) > 0  # the printed k differ
    True
    """
    lam, mu = check_moduli(lam, mu)
    stencil = np.zeros((2, 18))
    for p, offset in enumerate(NEIGHBOUR_OFFSETS):
        for c in range(2):
            unit = np.eye(2)[c]

            def corner_velocity(i: int, j: int, offset: tuple[int, int] = offset, unit: np.ndarray = unit) -> np.ndarray:
                return unit if (i, j) == offset else np.zeros(2)

            # eq. (14) for a unit velocity at one neighbour: column 2p + c of the matrix K of eq. (15)
            stencil[:, 2 * p + c] = _flux(corner_velocity, lam, mu)
    return stencil


def printed_stencil(lam: float = 1.0, mu: float = 5.0) -> np.ndarray:
    """The k_{i,j} printed under eq. (15), taken literally, in the order of :data:`NEIGHBOUR_OFFSETS`.

    k11 = k22 = -9/2 μ + 3/2 λ; k13 = k19 = k24 = k2,10 = (μ - λ)/4; k15 = k1,11 = k26 = k2,12 =
    5/4 μ - 3/4 λ; k17 = k1,13 = k1,15 = k1,17 = k28 = k2,14 = k2,16 = k2,18 = 3/8 μ + 1/8 λ;
    k18 = k1,14 = k1,16 = k1,18 = k27 = k2,13 = k2,15 = k2,17 = (μ + λ)/4; the rest 0.

    Parameters
    ----------
    lam : float, optional
        Lamé constant λ, 0 ≤ λ ≤ 1e150 (default 1, as the paper).
    mu : float, optional
        Lamé constant μ, 0 ≤ μ ≤ 1e150 (default 5, as the paper).

    Returns
    -------
    numpy.ndarray of float, shape (2, 18)
        The printed coefficients, in the layout of :func:`fluid_stencil`.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    eq. (15) (the coefficients printed below it).
    """
    lam, mu = check_moduli(lam, mu)
    k = np.zeros((2, 18))
    centre, edge_a, edge_b = -4.5 * mu + 1.5 * lam, 0.25 * (mu - lam), 1.25 * mu - 0.75 * lam
    diag_same, diag_cross = 0.375 * mu + 0.125 * lam, 0.25 * (mu + lam)
    for row in range(2):  # 1-based column j of row i is index j - 1
        k[row, row] = centre
        for j in (3, 9):
            k[row, j - 1 + row] = edge_a
        for j in (5, 11):
            k[row, j - 1 + row] = edge_b
        for j in (7, 13, 15, 17):
            k[row, j - 1 + row] = diag_same
            k[row, j - row] = diag_cross
    return k


def stencil_blocks(stencil: object) -> np.ndarray:
    """The stencil as nine 2x2 blocks: block p maps v(x + d_p) to the force.

    Parameters
    ----------
    stencil : array_like, shape (2, 18)
        Finite stencil in the layout of eq. (15): column ``2 p + c`` multiplies velocity component c
        at the neighbour ``NEIGHBOUR_OFFSETS[p]``; entries at most :data:`MAX_STENCIL_ENTRY` (1e152) in
        magnitude.

    Returns
    -------
    numpy.ndarray of float, shape (9, 2, 2)
        Block p, row i, column c: the coefficient of component c at ``NEIGHBOUR_OFFSETS[p]`` in
        force component i.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    eq. (15).
    """
    stencil = as_finite_array(stencil, "stencil", shape=(2, 18), max_abs=MAX_STENCIL_ENTRY)
    return stencil.reshape(2, 9, 2).transpose(1, 0, 2)


def apply_stencil(stencil: object, velocity: object) -> np.ndarray:
    """Force Σ_p K_p v(x + d_p) of a (2, 18) stencil on a velocity field, periodic boundaries.

    Parameters
    ----------
    stencil : array_like, shape (2, 18)
        Finite stencil in the layout of eq. (15): column ``2 p + c`` multiplies velocity component c
        at the neighbour ``NEIGHBOUR_OFFSETS[p]``; entries at most :data:`MAX_STENCIL_ENTRY` (1e152) in
        magnitude.
    velocity : array_like, shape (2, H, W)
        Finite velocity field, each component within ±1e100.

    Returns
    -------
    numpy.ndarray of float, shape (2, H, W)
        The force at every pixel.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    eq. (15).
    """
    blocks = stencil_blocks(stencil)
    velocity = as_finite_array(velocity, "velocity", shape=(2, None, None), max_abs=MAX_FIELD)
    out = np.zeros_like(velocity)
    for block, (d0, d1) in zip(blocks, NEIGHBOUR_OFFSETS):
        shifted = np.roll(velocity, (-d0, -d1), axis=(1, 2))  # value at x + offset
        out += np.einsum("ij,jhw->ihw", block, shifted)
    return out


def stencil_at_origin(stencil: object, velocity: Callable[[float, float], tuple[float, float]]) -> np.ndarray:
    """Force at the origin for a velocity field given as a function of (x1, x2), e.g. a polynomial.

    Parameters
    ----------
    stencil : array_like, shape (2, 18)
        Finite stencil in the layout of eq. (15): column ``2 p + c`` multiplies velocity component c
        at the neighbour ``NEIGHBOUR_OFFSETS[p]``; entries at most :data:`MAX_STENCIL_ENTRY` (1e152) in
        magnitude.
    velocity : callable
        ``velocity(x1, x2)`` returns the two finite velocity components at that point (x1 along
        array axis 0, unit pixel spacing).

    Returns
    -------
    numpy.ndarray of float, shape (2,)
        Σ_p K_p v(d_p).

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    eq. (15).
    """
    blocks, velocity = stencil_blocks(stencil), _checked_velocity(velocity)
    return sum(block @ velocity(float(d0), float(d1)) for block, (d0, d1) in zip(blocks, NEIGHBOUR_OFFSETS))


def rotate_stencil(stencil: object) -> np.ndarray:
    """The stencil of the operator rotated by 90°: blocks K'(d) = R K(Rᵀ d) Rᵀ, R = [[0, -1], [1, 0]].

    An isotropic operator (as μΔ + (λ+μ)∇∇· is) is unchanged, which ties the v_2 row to the
    v_1 row: k_2 at offset R d equals (-k_{1, v2}, k_{1, v1}) at offset d.

    Parameters
    ----------
    stencil : array_like, shape (2, 18)
        Finite stencil in the layout of eq. (15): column ``2 p + c`` multiplies velocity component c
        at the neighbour ``NEIGHBOUR_OFFSETS[p]``; entries at most :data:`MAX_STENCIL_ENTRY` (1e152) in
        magnitude.

    Returns
    -------
    numpy.ndarray of float, shape (2, 18)
        The rotated stencil, same layout.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    eq. (15).
    """
    blocks = stencil_blocks(stencil)
    rotation = np.array([[0.0, -1.0], [1.0, 0.0]])
    index = {offset: p for p, offset in enumerate(NEIGHBOUR_OFFSETS)}
    rotated = np.empty_like(blocks)
    for p, d in enumerate(NEIGHBOUR_OFFSETS):
        source = tuple(int(x) for x in rotation.T @ np.array(d))
        rotated[p] = rotation @ blocks[index[source]] @ rotation.T
    return rotated.transpose(1, 0, 2).reshape(2, 18)


def stencil_grid(stencil: object, row: int, component: int) -> np.ndarray:
    """One block of the stencil laid out as the 3 x 3 neighbourhood it acts on.

    ``grid[d0 + 1, d1 + 1]`` is the coefficient by which velocity ``component`` at the neighbour
    (d0, d1) enters force component ``row`` (eq. 15, column 2 p + component).

    Parameters
    ----------
    stencil : array_like, shape (2, 18)
        Finite stencil in the layout of eq. (15): column ``2 p + c`` multiplies velocity component c
        at the neighbour ``NEIGHBOUR_OFFSETS[p]``; entries at most :data:`MAX_STENCIL_ENTRY` (1e152) in
        magnitude.
    row : int
        Force component, 0 or 1.
    component : int
        Velocity component, 0 or 1.

    Returns
    -------
    numpy.ndarray of float, shape (3, 3)
        The coefficients, centre at [1, 1].

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    eq. (15).
    """
    blocks = stencil_blocks(stencil)
    for value, name in ((row, "row"), (component, "component")):
        check_choice(check_positive_int(value, name, minimum=0), name, (0, 1))  # an int: True is not 1 here
    grid = np.zeros((3, 3))
    for block, (d0, d1) in zip(blocks, NEIGHBOUR_OFFSETS):
        grid[d0 + 1, d1 + 1] = block[row, component]
    return grid


# The test fields of the consistency check: name -> v(x1, x2). Constants and linear fields have
# no second derivatives, so any consistent stencil must give them zero force.
_LOW_ORDER_FIELDS: dict[str, Callable[[float, float], tuple[float, float]]] = {
    "v=(1, 0)": lambda a, b: (1.0, 0.0), "v=(0, 1)": lambda a, b: (0.0, 1.0),
    "v=(x1, 0)": lambda a, b: (a, 0.0), "v=(x2, 0)": lambda a, b: (b, 0.0),
    "v=(0, x1)": lambda a, b: (0.0, a), "v=(0, x2)": lambda a, b: (0.0, b),
}
_QUADRATIC_FIELDS: dict[str, Callable[[float, float], tuple[float, float]]] = {
    "v=(x1², 0)": lambda a, b: (a * a, 0.0), "v=(x2², 0)": lambda a, b: (b * b, 0.0),
    "v=(x1x2, 0)": lambda a, b: (a * b, 0.0), "v=(0, x2²)": lambda a, b: (0.0, b * b),
    "v=(0, x1²)": lambda a, b: (0.0, a * a), "v=(0, x1x2)": lambda a, b: (0.0, a * b),
}


def _continuous_force(name: str, lam: float, mu: float) -> tuple[float, float]:
    """μΔv + (λ+μ)∇(∇·v) (left side of eq. 17) of a quadratic test field, worked out by hand."""
    return {"v=(x1², 0)": (2 * lam + 4 * mu, 0.0),  # μ·2 + (λ+μ)·∂1(2 x1)
            "v=(x2², 0)": (2 * mu, 0.0),             # divergence-free: only μΔv
            "v=(x1x2, 0)": (0.0, lam + mu),          # ∇·v = x2, so (λ+μ)∇x2
            "v=(0, x2²)": (0.0, 2 * lam + 4 * mu),
            "v=(0, x1²)": (0.0, 2 * mu),
            "v=(0, x1x2)": (lam + mu, 0.0)}[name]


def polynomial_test_fields(lam: float = 1.0, mu: float = 5.0) -> list[tuple[str, Callable[[float, float], tuple[float, float]], tuple[float, float]]]:
    """The velocity fields a consistent stencil must get exactly right, with the force it must give.

    Constants and linear fields (force 0) and the six quadratic fields (force μΔv + (λ+μ)∇(∇·v),
    the left side of eq. 17).

    Parameters
    ----------
    lam : float, optional
        Lamé constant λ, 0 ≤ λ ≤ 1e150 (default 1, as the paper).
    mu : float, optional
        Lamé constant μ, 0 ≤ μ ≤ 1e150 (default 5, as the paper).

    Returns
    -------
    list of (str, callable, tuple of two float)
        (name, v(x1, x2), expected force at the origin), twelve entries.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    eqs. (15) and (17).
    """
    lam, mu = check_moduli(lam, mu)
    return ([(name, field, (0.0, 0.0)) for name, field in _LOW_ORDER_FIELDS.items()]
            + [(name, field, _continuous_force(name, lam, mu)) for name, field in _QUADRATIC_FIELDS.items()])


def consistency_errors(stencil: object, lam: float = 1.0, mu: float = 5.0) -> dict[str, float]:
    """Largest |stencil force - expected force| for each test field, and for the quarter turn.

    Keys are "<field> → <expected force>" and "quarter turn leaves it unchanged"; a stencil that
    discretises μΔv + (λ+μ)∇(∇·v) with Lamé constants ``lam``, ``mu`` scores 0 on all of them.

    Parameters
    ----------
    stencil : array_like, shape (2, 18)
        Finite stencil in the layout of eq. (15): column ``2 p + c`` multiplies velocity component c
        at the neighbour ``NEIGHBOUR_OFFSETS[p]``; entries at most :data:`MAX_STENCIL_ENTRY` (1e152) in
        magnitude.
    lam : float, optional
        Lamé constant λ, 0 ≤ λ ≤ 1e150 (default 1, as the paper).
    mu : float, optional
        Lamé constant μ, 0 ≤ μ ≤ 1e150 (default 5, as the paper).

    Returns
    -------
    dict of str to float
        Thirteen errors, each ≥ 0.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    eqs. (15) and (17).
    """
    stencil = as_finite_array(stencil, "stencil", shape=(2, 18), max_abs=MAX_STENCIL_ENTRY)
    errors = {}
    for name, field, expected in polynomial_test_fields(lam, mu):
        label = f"{name} → ({expected[0]:g}, {expected[1]:g})"
        errors[label] = float(np.abs(stencil_at_origin(stencil, field) - np.array(expected)).max())
    errors["quarter turn leaves it unchanged"] = float(np.abs(rotate_stencil(stencil) - stencil).max())
    return errors
