"""Velocity solvers: operator(v) = F for the CAT stencil and for Christensen's finite differences.

Three ways to get the velocity of one registration iteration:

* ``"cat"``  the CAT stencil of :func:`~amdo_lab.cat_fluid.stencil.fluid_stencil` (eqs. 13-15),
  solved exactly;
* ``"fft"``  Christensen's PDE (eq. 17) discretised by central finite differences, solved exactly;
* ``"sor"``  the same finite-difference system by successive over-relaxation with a four-colour
  ("checkerboard") ordering, the anchor of the paper's Sec. 5.

Boundary conditions are periodic for all three (the paper does not state its own; brain images
have a dark border where the force of eq. 18 vanishes). With periodic boundaries a translation-
invariant stencil is diagonalised by the discrete Fourier transform: one 2x2 matrix per frequency.
The uniform velocity (zero frequency) is in the operator's null space and is set to zero, which
needs a zero-mean force (we remove the mean of the force first, in all three solvers).

Sign convention: the operator is L v = μΔv + (λ+μ)∇(∇·v) (negative semi-definite) and the
system solved is L v = F, as printed in eq. (17) and eq. (15) (negative centre coefficient).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from amdo_lab.cat_fluid.stencil import MAX_FIELD, NEIGHBOUR_OFFSETS, check_moduli, fluid_stencil, stencil_blocks
from amdo_lab.common import MAX_ITERATIONS
from amdo_lab.common import as_finite_array, check_choice, check_image_shape, check_in_range, check_positive_int

__all__ = ["SOLVERS", "stencil_symbol", "cat_symbol", "finite_difference_symbol",
           "solve_symbol", "sor_solve", "solve_velocity", "default_omega", "SOR_ORDERINGS", "symbol_eigenvalues",
           "solve_stencil_reference", "sor_reference", "check_sor_grid"]

SOLVERS = ("cat", "sor", "fft")
SOR_ORDERINGS = ("four-colour", "red-black", "red-black-together")
RED_BLACK = (((0, 0), (1, 1)), ((0, 1), (1, 0)))  # colours (row parity, column parity) of each half


def _frequencies(shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    w0 = 2 * np.pi * np.fft.fftfreq(shape[0])[:, None]
    w1 = 2 * np.pi * np.fft.rfftfreq(shape[1])[None, :]
    return w0, w1


def stencil_symbol(stencil: object, shape: tuple[int, int]) -> np.ndarray:
    """Fourier symbol of a centro-symmetric (2, 18) stencil in the layout of eq. (15).

    The stencil sums K_p v(x + d_p) over the neighbours d_p of :data:`NEIGHBOUR_OFFSETS`, so its
    symbol is Σ K_p exp(i ω·d_p), one 2x2 matrix per frequency ω of the real FFT of an (H, W) field.
    When K(d) = K(-d), as for the derived and the printed stencils, the sine parts cancel and the
    symbol is real.

    Parameters
    ----------
    stencil : array_like, shape (2, 18)
        Finite, centro-symmetric (K(d) = K(-d)), entries at most 1e152 in magnitude.
    shape : tuple of two int
        (H, W) of the fields the symbol acts on, positive.

    Returns
    -------
    numpy.ndarray of float, shape (2, 2, H, W//2 + 1)
        One real 2x2 matrix per frequency of the real FFT of an (H, W) field.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    eq. (15).
    """
    blocks = stencil_blocks(stencil)
    if not np.allclose(blocks, blocks[[NEIGHBOUR_OFFSETS.index((-d0, -d1)) for d0, d1 in NEIGHBOUR_OFFSETS]]):
        raise ValueError("stencil must be centro-symmetric (K(d) = K(-d)) for a real symbol")
    w0, w1 = _frequencies(check_image_shape(shape, axes="H, W"))
    phases = np.stack([np.cos(w0 * d0 + w1 * d1) for d0, d1 in NEIGHBOUR_OFFSETS])  # (9, H, W//2+1)
    return np.einsum("pij,phw->ijhw", blocks, phases)


def cat_symbol(shape: tuple[int, int], lam: float, mu: float) -> np.ndarray:
    """Fourier symbol of the CAT stencil (eq. 15, :func:`fluid_stencil`).

    Parameters
    ----------
    shape : tuple of two int
        (H, W) of the fields the symbol acts on, positive.
    lam : float
        Lamé constant λ, 0 ≤ λ ≤ 1e150 (the paper: 1).
    mu : float
        Lamé constant μ, 0 ≤ μ ≤ 1e150 (the paper: 5).

    Returns
    -------
    numpy.ndarray of float, shape (2, 2, H, W//2 + 1)
        One real 2x2 matrix per frequency of the real FFT of an (H, W) field.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    eqs. (14)-(15).
    """
    return stencil_symbol(fluid_stencil(lam, mu), shape)


def finite_difference_symbol(shape: tuple[int, int], lam: float, mu: float) -> np.ndarray:
    """Symbol of μΔ + (λ+μ)∇∇· with 3-point second differences and central mixed differences (eq. 17).

    Parameters
    ----------
    shape : tuple of two int
        (H, W) of the fields the symbol acts on, positive.
    lam : float
        Lamé constant λ, 0 ≤ λ ≤ 1e150 (the paper: 1).
    mu : float
        Lamé constant μ, 0 ≤ μ ≤ 1e150 (the paper: 5).

    Returns
    -------
    numpy.ndarray of float, shape (2, 2, H, W//2 + 1)
        One real 2x2 matrix per frequency of the real FFT of an (H, W) field.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    eq. (17);
    G. E. Christensen, S. Joshi, M. I. Miller, "Volumetric transformation of brain anatomy",
    IEEE Trans. Med. Imaging 16(6), 864-877, 1997 (the paper's reference [2]).
    """
    lam, mu = check_moduli(lam, mu)
    w0, w1 = _frequencies(check_image_shape(shape, axes="H, W"))
    d00 = 2 * np.cos(w0) - 2 + 0 * w1
    d11 = 2 * np.cos(w1) - 2 + 0 * w0
    d01 = -np.sin(w0) * np.sin(w1)  # (i sin ω0)(i sin ω1)
    laplace = mu * (d00 + d11)
    return np.array([[laplace + (lam + mu) * d00, (lam + mu) * d01],
                     [(lam + mu) * d01, laplace + (lam + mu) * d11]])


def _apply_finite_difference(velocity: np.ndarray, lam: float, mu: float) -> np.ndarray:
    """The finite-difference operator of eq. (17), μΔv + (λ+μ)∇(∇·v) by 3-point second differences
    and central mixed differences, applied to a (2, H, W) field with periodic boundaries: the operator SOR
    relaxes, which the tests compare with :func:`finite_difference_symbol`."""
    def shifted(field: np.ndarray, d0: int, d1: int) -> np.ndarray:
        return np.roll(field, (-d0, -d1), axis=(0, 1))  # value at x + (d0, d1)

    out = np.empty_like(velocity, dtype=float)
    for comp in (0, 1):
        v, w = velocity[comp], velocity[1 - comp]
        own = shifted(v, 1, 0) + shifted(v, -1, 0) if comp == 0 else shifted(v, 0, 1) + shifted(v, 0, -1)
        other = shifted(v, 0, 1) + shifted(v, 0, -1) if comp == 0 else shifted(v, 1, 0) + shifted(v, -1, 0)
        mixed = 0.25 * (shifted(w, 1, 1) - shifted(w, 1, -1) - shifted(w, -1, 1) + shifted(w, -1, -1))
        out[comp] = (lam + 2 * mu) * own + mu * other + (lam + mu) * mixed - (2 * lam + 6 * mu) * v
    return out


def symbol_eigenvalues(symbol: object, rows: object, cols: object) -> np.ndarray:
    """Eigenvalues (ascending) of the 2x2 symbol at the frequencies ``(rows[k], cols[k])``.

    Parameters
    ----------
    symbol : array_like, shape (2, 2, H, W//2 + 1)
        From :func:`stencil_symbol`, :func:`cat_symbol` or :func:`finite_difference_symbol`;
        finite and symmetric per frequency, entries at most 1e153 in magnitude (a larger 2x2
        eigenproblem overflows).
    rows : array_like of int, shape (n,)
        Indices into the symbol's axis 2 (row k is the frequency 2π fftfreq(H)[k]).
    cols : array_like of int, shape (n,)
        Indices into the symbol's axis 3, same length as ``rows``: e.g. a path through frequency
        space.

    Returns
    -------
    numpy.ndarray of float, shape (n, 2)
        Ascending eigenvalues at each frequency.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    Sec. 4, eq. (15): the symbol of its stencil.
    """
    symbol = as_finite_array(symbol, "symbol", shape=(2, 2, None, None), max_abs=1e153)
    rows = as_finite_array(rows, "rows", ndim=1, dtype=int, bounds=(0, symbol.shape[2] - 1))  # frequency indices
    # a length mismatch names both: either may be at fault
    cols = as_finite_array(cols, "cols (one per entry of rows)", shape=rows.shape, dtype=int,
                           bounds=(0, symbol.shape[3] - 1))
    matrices = np.moveaxis(symbol[:, :, rows, cols], -1, 0)  # (n, 2, 2): one matrix per frequency
    return np.linalg.eigvalsh(matrices)


def _stencil_matrix(blocks: np.ndarray, shape: tuple[int, int]) -> sp.csr_matrix:
    """The stencil of eq. (15), as its nine 2x2 ``blocks`` (:func:`stencil_blocks`), as a sparse
    (2 H W, 2 H W) matrix on an (H, W) grid, periodic: row ``i * H * W + n`` is force component i at pixel n
    (row-major), column ``c * H * W + m`` velocity component c at pixel m. The reference, pixel by pixel, for
    :func:`apply_stencil` and for the Fourier solve."""
    h, w = shape
    pixel = np.arange(h * w).reshape(h, w)
    rows, cols, values = [], [], []
    for block, (d0, d1) in zip(blocks, NEIGHBOUR_OFFSETS):
        neighbour = np.roll(pixel, (-d0, -d1), axis=(0, 1)).ravel()  # the pixel at x + d, periodic
        for i in range(2):
            for c in range(2):
                rows.append(i * h * w + pixel.ravel())
                cols.append(c * h * w + neighbour)
                values.append(np.full(h * w, block[i, c]))
    return sp.csr_matrix((np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(2 * h * w, 2 * h * w))


def solve_stencil_reference(stencil: object, force: object) -> np.ndarray:
    """Solve K v = F (eq. 15 at every pixel) with a dense solver: the reference for the FFT path.

    The uniform velocities are the null space of a consistent stencil; as in the fast path the
    mean of F is removed and the zero-mean solution returned (least squares, minimum norm).
    Dense: use it on small grids only (a 32 x 32 grid is a 2048 x 2048 system).

    Parameters
    ----------
    stencil : array_like, shape (2, 18)
        Finite stencil in the layout of eq. (15).
    force : array_like, shape (2, H, W)
        Finite right-hand side F, each component within ±1e100.

    Returns
    -------
    numpy.ndarray of float, shape (2, H, W)
        Zero-mean velocity v.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    eq. (15) solved for the velocity.
    """
    blocks = stencil_blocks(stencil)
    force = as_finite_array(force, "force", shape=(2, None, None), max_abs=MAX_FIELD)
    h, w = force.shape[1:]
    matrix = _stencil_matrix(blocks, (h, w)).toarray()
    rhs = (force - force.mean(axis=(1, 2), keepdims=True)).ravel()
    # eq. (15) at every pixel, K v = F_ext, as one dense linear system (least squares: K is singular
    # on the uniform velocity, which the mean-free force does not excite)
    velocity = np.linalg.lstsq(matrix, rhs, rcond=None)[0].reshape(2, h, w)
    return velocity - velocity.mean(axis=(1, 2), keepdims=True)


def solve_symbol(symbol: np.ndarray, force: np.ndarray) -> np.ndarray:
    """Solve symbol(ω) v̂(ω) = F̂(ω) frequency by frequency (2x2 Cramer's rule); v̂(0) = 0."""
    shape = force.shape[1:]
    rhs = np.fft.rfft2(force, axes=(1, 2))
    a, b, c, d = symbol[0, 0], symbol[0, 1], symbol[1, 0], symbol[1, 1]
    det = a * d - b * c
    det = np.where(det == 0, 1.0, det)  # only the zero frequency, whose solution is set to 0 below
    v0 = (d * rhs[0] - b * rhs[1]) / det
    v1 = (a * rhs[1] - c * rhs[0]) / det
    v0[0, 0] = v1[0, 0] = 0.0
    return np.fft.irfft2(np.stack([v0, v1]), s=shape, axes=(1, 2))


def _refresh_halo(padded: np.ndarray) -> None:
    """Copy the periodic neighbours into the one-pixel frame of a padded sub-lattice."""
    padded[0, :], padded[-1, :] = padded[-2, :], padded[1, :]
    padded[:, 0], padded[:, -1] = padded[:, -2], padded[:, 1]


def default_omega(shape: tuple[int, int]) -> float:
    """Textbook SOR factor 2 / (1 + sin(π / N)) of the N x N Laplacian, N the longer side."""
    return 2.0 / (1.0 + np.sin(np.pi / max(shape)))


def check_sor_grid(shape: tuple[int, int], name: str) -> None:
    """Refuse a grid SOR's four-colour ordering cannot sweep: H and W must be even.

    Parameters
    ----------
    shape : tuple of int
        (H, W) of the grid.
    name : str
        The argument the grid comes from, named in the error.

    Raises
    ------
    ValueError
        If H or W is odd.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85, Sec. 5 (its SOR solver).
    """
    if shape[0] % 2 or shape[1] % 2:
        raise ValueError(f"{name} must have even H and W for SOR's four-colour ordering, got {tuple(shape)}")


def _check_sor_inputs(force: object, lam: object, mu: object,
                      n_sweeps: object) -> tuple[np.ndarray, float, float, int]:
    """The inputs both SOR solvers take: a finite (2, H, W) force within ±1e100, Lamé constants with μ > 0
    (:func:`~amdo_lab.cat_fluid.stencil.check_moduli`) and 0 to 100,000 sweeps."""
    force = as_finite_array(force, "force", shape=(2, None, None), max_abs=MAX_FIELD)
    lam, mu = check_moduli(lam, mu, require_positive_mu=True)
    n_sweeps = check_positive_int(n_sweeps, "n_sweeps", minimum=0, maximum=MAX_ITERATIONS)
    return force, lam, mu, n_sweeps


def sor_solve(force: np.ndarray, lam: float, mu: float, *, n_sweeps: int = 250, omega: float | None = None,
              initial: np.ndarray | None = None, ordering: str = "four-colour") -> np.ndarray:
    """Successive over-relaxation for the finite-difference eq. (17), periodic, four-colour ordering.

    Pixels are coloured by (row parity, column parity). The 9-point stencil of eq. (17) (5-point
    second differences plus the diagonal mixed derivative) couples a pixel only to pixels of the
    three *other* colours, so updating one colour at a time, all its pixels at once, is an exact
    Gauss-Seidel ordering; SOR then converges for 0 < ω < 2 because -L is symmetric positive
    semi-definite (Ostrowski-Reich). The paper's red-black checkerboard puts the mixed term's
    diagonal neighbours in the *same* colour: updating both velocity components of a colour at
    once ("red-black-together") is then a Jacobi step on the mixed coupling and diverges at high
    ω; updating them one after the other ("red-black") is again a Gauss-Seidel ordering. Each
    colour is stored as an (H/2, W/2) sub-lattice with a periodic one-pixel frame, so H and W must
    be even.

    Parameters
    ----------
    force : array_like, shape (2, H, W)
        Finite right-hand side F of L v = F (its mean is removed), each component within ±1e100; H and
        W even.
    lam : float
        Lamé constant λ, 0 ≤ λ ≤ 1e150 (the paper: 1).
    mu : float
        Lamé constant μ, 0 < μ ≤ 1e150 (the paper: 5).
    n_sweeps : int, optional
        Number of full sweeps, ≥ 0 (default 250, the paper's count per registration iteration).
        At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).
    omega : float, optional
        Relaxation factor in (0, 2); default :func:`default_omega`.
    initial : array_like, shape (2, H, W), optional
        Starting velocity (warm start), each component within ±1e100; zero by default.
    ordering : str, optional
        "four-colour" (default), "red-black" or "red-black-together" (see above).

    Returns
    -------
    numpy.ndarray of float, shape (2, H, W)
        Velocity with zero mean.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    Sec. 5, eq. (17) and its SOR solver;
    G. E. Christensen, S. Joshi, M. I. Miller, "Volumetric transformation of brain anatomy",
    IEEE Trans. Med. Imaging 16(6), 864-877, 1997 (the paper's reference [2]).
    """
    force, lam, mu, n_sweeps = _check_sor_inputs(force, lam, mu, n_sweeps)
    check_choice(ordering, "ordering", SOR_ORDERINGS)
    h, w = force.shape[1:]
    # SOR converges for 0 < omega < 2 only
    omega = default_omega((h, w)) if omega is None else check_in_range(omega, "omega", 0, 2)
    check_sor_grid((h, w), "force")
    start = (np.zeros_like(force) if initial is None
             else as_finite_array(initial, "initial", shape=force.shape, max_abs=MAX_FIELD))
    return _sor_solve(force, lam, mu, n_sweeps, omega, start, ordering)


def _sor_solve(force: np.ndarray, lam: float, mu: float, n_sweeps: int, omega: float, start: np.ndarray,
               ordering: str = "four-colour") -> np.ndarray:
    """:func:`sor_solve` on checked input (``start`` the initial velocity, ``omega`` given): the kernel
    :func:`~amdo_lab.cat_fluid.registration.register_fluid` calls at every iteration."""
    h, w = force.shape[1:]
    force = force - force.mean(axis=(1, 2), keepdims=True)
    # pad[comp][r][s]: colour-(r, s) pixels (2a + r, 2b + s) of component comp, with a periodic frame
    pad = [[[np.pad(start[comp, r::2, s::2], 1, mode="wrap") for s in (0, 1)] for r in (0, 1)] for comp in (0, 1)]
    rhs = [[[force[comp, r::2, s::2] for s in (0, 1)] for r in (0, 1)] for comp in (0, 1)]
    n0, n1 = h // 2, w // 2
    # the SOR update v <- (1 - ω) v + ω (F - off-centre terms) / centre, with its constants folded in
    # (centre = -(2λ + 6μ)): v <- (1 - ω) v + scaled F + own·Σ own-axis + other·Σ other-axis + mixed·Σ ±diagonals
    scale = -omega / (2 * lam + 6 * mu)
    own_weight, other_weight, mixed_weight = -scale * (lam + 2 * mu), -scale * mu, -scale * 0.25 * (lam + mu)
    rhs = [[[scale * block for block in row] for row in comp] for comp in rhs]
    work = np.empty((n0, n1)), np.empty((n0, n1))  # scratch arrays, reused by every update

    def neighbour(grid: list, r: int, s: int, d0: int, d1: int) -> np.ndarray:
        """View of the values at (2a + r + d0, 2b + s + d1) for all colour-(r, s) pixels."""
        padded = grid[(r + d0) % 2][(s + d1) % 2]
        a0, a1 = 1 + (r + d0) // 2, 1 + (s + d1) // 2
        return padded[a0:a0 + n0, a1:a1 + n1]

    def relaxed(comp: int, r: int, s: int) -> np.ndarray:
        """The SOR value of component ``comp`` on colour (r, s), from the current values (a new array)."""
        v, other = pad[comp], pad[1 - comp]
        along, across = ((1, 0), (0, 1)) if comp == 0 else ((0, 1), (1, 0))
        out = np.multiply(v[r][s][1:-1, 1:-1], 1.0 - omega)
        total, scratch = work
        np.add(neighbour(v, r, s, *along), neighbour(v, r, s, -along[0], -along[1]), out=total)
        total *= own_weight
        out += total
        np.add(neighbour(v, r, s, *across), neighbour(v, r, s, -across[0], -across[1]), out=total)
        total *= other_weight
        out += total
        np.subtract(neighbour(other, r, s, 1, 1), neighbour(other, r, s, 1, -1), out=total)
        np.subtract(neighbour(other, r, s, -1, -1), neighbour(other, r, s, -1, 1), out=scratch)
        total += scratch
        total *= mixed_weight
        out += total
        out += rhs[comp][r][s]
        return out

    # each step updates a group of (component, colour) blocks from the values before the step
    if ordering == "four-colour":
        steps = [[(comp, r, s)] for r in (0, 1) for s in (0, 1) for comp in (0, 1)]
    elif ordering == "red-black":
        steps = [[(comp, r, s) for r, s in colours] for colours in RED_BLACK for comp in (0, 1)]
    else:  # "red-black-together": both components of a colour at once
        steps = [[(comp, r, s) for r, s in colours for comp in (0, 1)] for colours in RED_BLACK]
    for _ in range(n_sweeps):
        for step in steps:
            new_values = [relaxed(comp, r, s) for comp, r, s in step]
            for (comp, r, s), values in zip(step, new_values):
                pad[comp][r][s][1:-1, 1:-1] = values
                _refresh_halo(pad[comp][r][s])
    velocity = np.empty_like(force)
    for comp in (0, 1):
        for r in (0, 1):
            for s in (0, 1):
                velocity[comp, r::2, s::2] = pad[comp][r][s][1:-1, 1:-1]
    return velocity - velocity.mean(axis=(1, 2), keepdims=True)


def sor_reference(force: object, lam: float, mu: float, *, n_sweeps: int, omega: float) -> np.ndarray:
    """Pixel-by-pixel SOR on the finite-difference eq. (17), the readable twin of :func:`sor_solve`.

    Same four-colour order (colour (row parity, column parity), then component), periodic, from
    zero: a plain Python loop, for small images. Within one colour no pixel is a neighbour of
    another, so this loop and the vectorised :func:`sor_solve` give the same numbers.

    Parameters
    ----------
    force : array_like, shape (2, H, W)
        Finite right-hand side F (its mean is removed), each component within ±1e100.
    lam : float
        Lamé constant λ, 0 ≤ λ ≤ 1e150 (the paper: 1).
    mu : float
        Lamé constant μ, 0 < μ ≤ 1e150 (the paper: 5).
    n_sweeps : int
        Number of full sweeps, ≥ 0. At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).
    omega : float
        Relaxation factor in (0, 2), where SOR converges.

    Returns
    -------
    numpy.ndarray of float, shape (2, H, W)
        Velocity with zero mean.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    Sec. 5, eq. (17) and its SOR solver (their reference [2]).
    """
    force, lam, mu, n_sweeps = _check_sor_inputs(force, lam, mu, n_sweeps)
    omega = check_in_range(omega, "omega", 0, 2)  # SOR converges for 0 < omega < 2 only
    h, w = force.shape[1:]
    force = force - force.mean(axis=(1, 2), keepdims=True)
    v = np.zeros_like(force)
    centre = -(2 * lam + 6 * mu)  # eq. (17) discretised: coefficient of v_i at the pixel itself
    for _ in range(n_sweeps):
        for r in (0, 1):
            for s in (0, 1):
                for i in (0, 1):
                    along = (1, 0) if i == 0 else (0, 1)  # component i's own axis
                    across = (along[1], along[0])
                    for a in range(r, h, 2):
                        for b in range(s, w, 2):
                            def at(comp: int, d0: int, d1: int) -> float:
                                return v[comp, (a + d0) % h, (b + d1) % w]
                            # off-centre part of μΔv_i + (λ+μ)∂_i(∇·v), eq. (17)
                            off = ((lam + 2 * mu) * (at(i, *along) + at(i, -along[0], -along[1]))
                                   + mu * (at(i, *across) + at(i, -across[0], -across[1]))
                                   + (lam + mu) * 0.25 * (at(1 - i, 1, 1) - at(1 - i, 1, -1)
                                                          - at(1 - i, -1, 1) + at(1 - i, -1, -1)))
                            gauss_seidel = (force[i, a, b] - off) / centre
                            v[i, a, b] = (1 - omega) * v[i, a, b] + omega * gauss_seidel
    return v - v.mean(axis=(1, 2), keepdims=True)


def solve_velocity(force: object, method: str = "cat", lam: float = 1.0, mu: float = 5.0,
                   **sor_options: object) -> np.ndarray:
    """Velocity v with L v = F (mean of F removed) by one of :data:`SOLVERS` (see module docstring).

    Parameters
    ----------
    force : array_like, shape (2, H, W)
        Finite right-hand side F, each component within ±1e100, e.g.
        :func:`~amdo_lab.cat_fluid.registration.external_force`.
    method : str, optional
        "cat" (the CAT stencil, eq. 15, solved exactly; default), "sor" (eq. 17 by SOR) or "fft"
        (eq. 17 solved exactly).
    lam : float
        Lamé constant λ, 0 ≤ λ ≤ 1e150 (the paper: 1).
    mu : float
        Lamé constant μ, 0 < μ ≤ 1e150 (the paper: 5).
    **sor_options
        ``n_sweeps``, ``omega``, ``initial``, ``ordering`` of :func:`sor_solve`; "sor" only.

    Returns
    -------
    numpy.ndarray of float, shape (2, H, W)
        Zero-mean velocity.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    eqs. (15) and (17).

    Examples
    --------
    >>> import numpy as np
    >>> from amdo_lab.cat_fluid import apply_stencil, fluid_stencil, solve_velocity
    >>> force = np.random.default_rng(0).normal(size=(2, 16, 16))
    >>> velocity = solve_velocity(force, "cat", lam=1.0, mu=5.0)
    >>> bool(np.allclose(apply_stencil(fluid_stencil(1.0, 5.0), velocity), force - force.mean(axis=(1, 2), keepdims=True)))
    True
    >>> exact = solve_velocity(force, "fft", lam=1.0, mu=5.0)
    >>> bool(np.allclose(solve_velocity(force, "sor", lam=1.0, mu=5.0, n_sweeps=400), exact))
    True
    """
    force = as_finite_array(force, "force", ndim=3, shape=(2, None, None), max_abs=MAX_FIELD)
    check_choice(method, "method", SOLVERS)
    lam, mu = check_moduli(lam, mu, require_positive_mu=True)
    if method == "sor":
        return sor_solve(force, lam, mu, **sor_options)
    if sor_options:
        raise ValueError(f"SOR options {sorted(sor_options)} only apply to method='sor'")
    symbol = cat_symbol if method == "cat" else finite_difference_symbol
    return solve_symbol(symbol(force.shape[1:], lam, mu), force - force.mean(axis=(1, 2), keepdims=True))
