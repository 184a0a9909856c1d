"""The exercises of chapter 3, specified as data: expected values, hints and recorded wrong answers.

The chapter's check cells call ``EXERCISES.check(k, answer_k, ...)`` with the notebook objects each
exercise names; the expected value is computed here, out of the reader's sight. See
:mod:`amdo_lab.common.exercises` for the mechanism.

References
----------
L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
AMDO 2004, LNCS 3179, pp. 76-85 (eqs. 7, 15, 16; Sec. 5).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from amdo_lab.cat_fluid.complex import CubicalComplex
from amdo_lab.cat_fluid.registration import jacobian_determinant, material_update, register_fluid
from amdo_lab.cat_fluid.stencil import printed_stencil, stencil_at_origin
from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer, wrong_answers

__all__ = ["EXERCISES"]

EXERCISE1_PSI = (1.0, 4.0, 2.0, 7.0)  # the 0-cochain on the vertices (0,0), (0,1), (1,0), (1,1)
MU_EXPERIMENT = 1.0  # Exercise 4: the shear modulus the reader switches to
FOLD_ITERATIONS = 40  # Exercise 6: iterations of the disc-into-C run without regridding


def _coboundary_of_psi() -> np.ndarray:
    return CubicalComplex((2, 2)).coboundary(0) @ np.array(EXERCISE1_PSI)


def _printed_force(LAM: float, MU: float) -> np.ndarray:  # noqa: N803 - the notebook's names
    return stencil_at_origin(printed_stencil(LAM, MU), lambda x1, x2: (x2 * x2, 0.0))


def _material_change() -> np.ndarray:
    rows = np.indices((16, 16), dtype=float)[0]
    shear = np.stack([np.zeros((16, 16)), 0.1 * rows])  # u = (0, 0.1 x1)
    uniform = np.stack([np.ones((16, 16)), np.zeros((16, 16))])  # v = (1, 0)
    return (material_update(shear, uniform, 1.0) - shear)[:, 8, 8]


def _area_change_mu1(toy_template: np.ndarray, toy_study: np.ndarray, LAM: float) -> float:  # noqa: N803
    det = jacobian_determinant(register_fluid(toy_template, toy_study, "cat", lam=LAM, mu=MU_EXPERIMENT,
                                              n_iter=100).displacement)
    return float(np.abs(det - 1).mean())


def _signed_change_mu1(namespace: Mapping[str, object]) -> float:
    det = jacobian_determinant(register_fluid(namespace["toy_template"], namespace["toy_study"], "cat",
                                              lam=namespace["LAM"], mu=MU_EXPERIMENT, n_iter=100).displacement)
    return float((det - 1).mean())


def _less_or_more(toy_template: np.ndarray, toy_study: np.ndarray, LAM: float, toy_det: np.ndarray) -> str:  # noqa: N803
    return "less" if _area_change_mu1(toy_template, toy_study, LAM) < float(np.abs(toy_det - 1).mean()) else "more"


_FOLD_CACHE: dict[tuple, int] = {}  # the run takes a second; the self-test asks for it three times


def _first_fold(circle: np.ndarray, letter_c: np.ndarray, LAM: float, MU: float) -> int:  # noqa: N803
    key = (np.asarray(circle).tobytes(), np.asarray(letter_c).tobytes(), float(LAM), float(MU))
    if key not in _FOLD_CACHE:
        run = register_fluid(circle, letter_c, "cat", lam=LAM, mu=MU, n_iter=FOLD_ITERATIONS, regrid_threshold=0.0)
        folded = np.flatnonzero(run.history[:, 2] <= 0)
        _FOLD_CACHE[key] = int(folded[0]) if folded.size else -1
    return _FOLD_CACHE[key]


def _first_regrid(namespace: Mapping[str, object]) -> int:
    """With regridding left on (the unchanged experiment) the map never folds; the first iteration with
    min det below 0.5, where it regrids, is what a reader who did not switch it off would report."""
    history = namespace["circle_to_c"].history
    return int(np.flatnonzero(history[: FOLD_ITERATIONS + 1, 2] < 0.5)[0])


def _fold_off_by(shift: int):
    def value(namespace: Mapping[str, object]) -> int:
        return _first_fold(namespace["circle"], namespace["letter_c"], namespace["LAM"], namespace["MU"]) + shift
    return value


EXERCISES = ExerciseSet(chapter=3, exercises=[
    Exercise(1, _coboundary_of_psi, "each edge carries Ψ0(head) − Ψ0(tail), horizontal edges first",
             wrong_answers(([-3.0, -5.0, -1.0, -3.0], "tail minus head"),
                           ([5.0, 9.0, 3.0, 11.0], "head plus tail"),
                           ([1.0, 3.0, 3.0, 5.0], "the vertical edges first"))),
    Exercise(2, _printed_force, "row 2 picks up (μ+λ)/4 from each of the four diagonals, all with one sign",
             wrong_answers(([10.0, 0.0], "the continuous operator's force (the print taken as right)"),
                           ([10.0, -6.0], "a sign slip on the diagonals of row 2"),
                           ([2.0, 6.0], "the diagonals of row 1 left out")),
             context=("LAM", "MU"), rtol=0.0, atol=1e-2),
    Exercise(3, _material_change, "J has one nonzero entry, ∂u2/∂x1 = 0.1; the change is v − J v",
             wrong_answers(([1.0, 0.0], "the transposed reading Jᵀ v"),
                           ([1.0, 0.1], "v + J v, a sign slip"),
                           ([0.0, 0.1], "J v alone")),
             rtol=0.0, atol=1e-3),
    Exercise(4, _area_change_mu1, "run the experiment with mu=1.0, then np.abs(det − 1).mean() over the image",
             (WrongAnswer(lambda ns: float(np.abs(ns["toy_det"] - 1).mean()), "the unchanged experiment (μ = 5)",
                          unchanged_experiment=True),
              WrongAnswer(_signed_change_mu1, "the signed mean of det − 1 (areas gained and lost cancel)"),
              WrongAnswer(0.40, "the largest |det − 1| instead of the mean")),
             context=("toy_template", "toy_study", "LAM"), rtol=0.0, atol=1e-3, experiment=True),
    Exercise(5, _less_or_more, "compare the mean |det − 1| of the two runs",
             wrong_answers(("more", "the other way round"), ("the same", "the residuals, not the areas, compared")),
             context=("toy_template", "toy_study", "LAM", "toy_det"), choices=("less", "the same", "more")),
    Exercise(6, _first_fold, "switch regridding off (regrid_threshold=0.0); history row k is iteration k",
             (WrongAnswer(_first_regrid, "the first regridding of the unchanged run (min det < 0.5)",
                          unchanged_experiment=True),
              WrongAnswer(_fold_off_by(-1), "the last iteration before the fold"),
              WrongAnswer(_fold_off_by(+1), "rows counted from 1")),
             context=("circle", "letter_c", "LAM", "MU"), rtol=0.0, atol=0.0, experiment=True),
])
