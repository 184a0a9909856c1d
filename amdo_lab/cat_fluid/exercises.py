"""The exercises of chapter 3, specified as data: hints, tolerances and the recorded wrong answers.

The targets are not here: each check cell of the chapter's source registers its exercise's target in
a hidden test (``EXERCISES.expect``), so the package a reader installs does not hold them. The
"implement it" exercise (7) compares the reader's flux of one dual cell with
:func:`~amdo_lab.cat_fluid.stencil.dual_cell_force` on cases drawn by :func:`flux_case`. See
:mod:`amdo_lab.common.exercises` for the mechanism.

References
----------
L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
AMDO 2004, LNCS 3179, pp. 76-85 (eqs. 7, 12-16; Sec. 5).
"""

from __future__ import annotations

import numpy as np

from amdo_lab.cat_fluid.stencil import dual_cell_force
from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer

__all__ = ["EXERCISES", "cell_flux", "flux_case"]

FLUX_EXAMPLE_SEED = 7
"""The seed of the case Exercise 7 shows in the notebook (its unseen cases use others)."""


def cell_flux(velocity: np.ndarray, lam: float, mu: float) -> np.ndarray:
    """Exercise 7's reference: ∮ σ n dl over the dual cell of the middle pixel of a 3 x 3 velocity patch.

    A thin wrapper of :func:`~amdo_lab.cat_fluid.stencil.dual_cell_force` for an array input.

    Parameters
    ----------
    velocity : numpy.ndarray, shape (2, 3, 3)
        ``velocity[:, 1 + d1, 1 + d2]`` is the velocity at the neighbour offset (d1, d2).
    lam, mu : float
        Lamé constants λ and μ.

    Returns
    -------
    numpy.ndarray, shape (2,)
        The internal force on the dual cell (eq. 14 without its minus sign).
    """
    patch = np.asarray(velocity, float)
    return dual_cell_force(lambda i, j: patch[:, 1 + i, 1 + j], lam=lam, mu=mu)


def flux_case(seed: int) -> dict:
    """One case of Exercise 7: a random 3 x 3 velocity patch and Lamé constants (rounded to 2 decimals).

    Parameters
    ----------
    seed : int
        The case's seed.

    Returns
    -------
    dict
        Keyword arguments of :func:`cell_flux`: ``velocity`` (2, 3, 3), ``lam``, ``mu``.
    """
    rng = np.random.default_rng(seed)
    return {"velocity": rng.normal(size=(2, 3, 3)).round(2), "lam": round(float(rng.uniform(0.5, 3.0)), 2),
            "mu": round(float(rng.uniform(1.0, 6.0)), 2)}


def _half_side_flux(velocity: np.ndarray, lam: float, mu: float, *, halves: bool = True,
                    symmetric: bool = True, sign: float = 1.0) -> np.ndarray:
    """The flux with one of three slips: whole sides, an unsymmetrised strain, eq. 14's minus sign."""
    patch = np.asarray(velocity, float)
    offsets = (-0.25, 0.25) if halves else (0.0,)
    length = 0.5 if halves else 1.0
    sides = ([((s * 0.5, m), (s, 0.0)) for s in (1.0, -1.0) for m in offsets]
             + [((m, s * 0.5), (0.0, s)) for s in (1.0, -1.0) for m in offsets])
    total = np.zeros(2)
    for point, normal in sides:
        a, b = int(np.floor(point[0])), int(np.floor(point[1]))
        s, t = point[0] - a, point[1] - b
        corner = lambda p, q: patch[:, 1 + a + p, 1 + b + q]  # noqa: E731
        d = np.column_stack([(1 - t) * (corner(1, 0) - corner(0, 0)) + t * (corner(1, 1) - corner(0, 1)),
                             (1 - s) * (corner(0, 1) - corner(0, 0)) + s * (corner(1, 1) - corner(1, 0))])
        strain_twice = d + d.T if symmetric else 2 * d
        total += length * (lam * np.trace(d) * np.eye(2) + mu * strain_twice) @ np.array(normal)
    return sign * total


def _external_sign(velocity: np.ndarray, lam: float, mu: float) -> np.ndarray:
    return _half_side_flux(velocity, lam, mu, sign=-1.0)


def _whole_sides(velocity: np.ndarray, lam: float, mu: float) -> np.ndarray:
    return _half_side_flux(velocity, lam, mu, halves=False)


def _unsymmetrised(velocity: np.ndarray, lam: float, mu: float) -> np.ndarray:
    return _half_side_flux(velocity, lam, mu, symmetric=False)


EXERCISES = ExerciseSet(chapter=3, exercises=[
    Exercise(1, None, "each edge carries Ψ0(head) − Ψ0(tail), horizontal edges first",
             (WrongAnswer([-3.0, -5.0, -1.0, -3.0], "tail minus head",
                          hint="eq. (7) takes the head's value minus the tail's"),
              WrongAnswer([5.0, 9.0, 3.0, 11.0], "head plus tail",
                          hint="the coboundary is a difference along the edge, not a sum"),
              WrongAnswer([1.0, 3.0, 3.0, 5.0], "the vertical edges first",
                          hint="list the horizontal edges 0→1 and 2→3 first, then the vertical ones")),
             rtol=0.0, atol=0.01),
    Exercise(2, None, "row 2 picks up (μ+λ)/4 from each of the four diagonals, all with one sign",
             (WrongAnswer([10.0, 0.0], "the continuous operator's force (the print taken as right)",
                          hint="that is what the continuous operator gives; apply the printed coefficients"),
              WrongAnswer([10.0, -6.0], "a sign slip on the diagonals of row 2",
                          hint="all four printed diagonal coefficients of row 2 carry the same sign, +"),
              WrongAnswer([2.0, 6.0], "the diagonals of row 1 left out",
                          hint="row 1 also has four diagonal neighbours with x2² = 1")),
             rtol=0.0, atol=0.01, why_points=1),
    Exercise(3, None, "J has one nonzero entry, ∂u2/∂x1 = 0.1; the change is v − J v",
             (WrongAnswer([1.0, 0.0], "the transposed reading Jᵀ v",
                          hint="that is the transposed reading; ours multiplies v by J, J[i, j] = ∂u_i/∂x_j"),
              WrongAnswer([1.0, 0.1], "v + J v, a sign slip",
                          hint="eq. (16) subtracts the carried part: v − J v"),
              WrongAnswer([0.0, 0.1], "J v alone",
                          hint="the change is the velocity minus J v, not J v itself")),
             rtol=0.0, atol=1e-3),
    Exercise(4, None, "run the experiment with mu=1.0, then the mean of |det − 1| over the image",
             (WrongAnswer(0.112, "the unchanged experiment (μ = 5)", unchanged_experiment=True,
                          hint="that is the run at μ = 5: change mu in the answer cell's register_fluid call",
                          variable="experiment_4"),
              WrongAnswer(0.0, "the signed mean of det − 1 (areas gained and lost cancel)",
                          hint="take the absolute value |det − 1| before the mean: gains and losses cancel"),
              WrongAnswer(0.402, "the largest |det − 1| instead of the mean",
                          hint="the mean over the image, not the largest value")),
             rtol=0.0, atol=5e-4, experiment=True),
    Exercise(5, None, "compare the mean |det − 1| of the two runs",
             (WrongAnswer("more area change", "the other way round",
                          hint="compare your Exercise 4 value with the mean |det − 1| of toy_det"),
              WrongAnswer("the same area change", "the residuals, not the areas, compared",
                          hint="the residuals barely change; compare the area changes |det − 1|")),
             choices=("less area change", "the same area change", "more area change"), why_points=2),
    Exercise(6, None, "switch regridding off (regrid_threshold=0.0); history row k is iteration k",
             (WrongAnswer(13, "the first regridding of the unchanged run (min det < 0.5)",
                          unchanged_experiment=True,
                          hint="with regridding on the map is restarted before it folds: pass regrid_threshold=0.0"),
              WrongAnswer(22, "the last iteration before the fold",
                          hint="the first iteration whose min det is ≤ 0, not the one before it"),
              WrongAnswer(24, "rows counted from 1",
                          hint="row 0 of history is the start, so row k is iteration k")),
             rtol=0.0, atol=0.0, experiment=True, why_points=1),
    Exercise(7, None, "two halves per side, each at its midpoint with length 1/2; σ = λ tr(d) I + μ (d + dᵀ)",
             (WrongAnswer(_external_sign, "eq. (14)'s minus sign: the external force",
                          hint="return the internal force +∮ σ n dl, as the stencil does (eq. 14 prints "
                               "the external force that balances it, with a minus sign)"),
              WrongAnswer(_whole_sides, "one midpoint per whole side",
                          hint="each side runs through two primal squares: split it in two halves of "
                               "length 1/2 and take the gradient at each half's midpoint"),
              WrongAnswer(_unsymmetrised, "the strain not symmetrised (2 μ d)",
                          hint="eq. (12) uses the symmetric part: μ (d + dᵀ), not 2 μ d")),
             rtol=1e-6, atol=1e-9, kind="function", reference=cell_flux, make_case=flux_case,
             example_seed=FLUX_EXAMPLE_SEED),
])
