"""Chapter 1's exercises: the expected answers and the wrong answers each check must reject.

The notebook's check cells call ``EXERCISES.check(k, answer_k, ...)`` with the notebook objects an
exercise needs (the toy, its EM loop, the hand and a slice of its skin); the expected values are
computed here from those objects, so they are not in plain view under the answer cells.

References
----------
G. Dewaele, F. Devernay, R. Horaud, F. Forbes. The Alignment Between 3-D Data and Articulated Shapes
with Bending Surfaces. ECCV 2006, LNCS 3953, pp. 578-591 (eqs. 3, 17, 18 and Sec. 3.3).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np

from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer
from amdo_lab.em_articulated.estep import PAPER_C

__all__ = ["EXERCISES"]

#: The outlier constant of Exercise 3's run: the outlier class switched off.
NO_OUTLIER_C = 1e-9
#: Exercise 4's single σ (mm) and its number of EM iterations.
SINGLE_SIGMA_MM, SINGLE_SIGMA_ITERATIONS = 2.0, 50
#: Exercise 5's exponent a of eq. (3).
LARGE_EXPONENT = 50.0
#: Share of a point's weight above which it moves (almost) rigidly with one part, as in the chapter.
RIGID_WEIGHT = 0.99


def _worst_joint_deg(poses: list, true: np.ndarray) -> float:
    """Largest joint error (deg) of the last pose of a toy run."""
    return float(np.degrees(np.abs(np.asarray(poses[-1]) - true)).max())


def _without_outlier_class(toy, toy_em: Callable, toy_start, toy_sigmas) -> float:
    """Worst joint error (deg) of the notebook's toy EM run with c = 0 (no outlier class)."""
    return _worst_joint_deg(toy_em(toy, toy_start, toy_sigmas, c=NO_OUTLIER_C), toy.true)


def _single_sigma(toy, toy_em: Callable, toy_start) -> float:
    """Worst joint error (deg) of the notebook's toy EM at one small σ, without annealing."""
    return _worst_joint_deg(toy_em(toy, toy_start, [SINGLE_SIGMA_MM], iterations=SINGLE_SIGMA_ITERATIONS),
                            toy.true)


def _rigid_share(hand, ring, theta0, a: float = LARGE_EXPONENT) -> float:
    """Share of the ring's texture points that move (almost) rigidly with one part at exponent ``a``."""
    return float(np.mean(hand.texture_binding(ring, theta0, a=a).weight_p > RIGID_WEIGHT))


def _from(function: Callable, *names: str, scale: float = 1.0) -> Callable[[Mapping[str, object]], float]:
    """A wrong answer read from the notebook: ``function`` of the named objects, times ``scale``."""
    return lambda namespace: scale * function(*(namespace[name] for name in names))


def _annealed_worst(namespace: Mapping[str, object]) -> float:
    """What the toy's annealed run gives: the unchanged experiment of Exercises 3 and 4."""
    return _worst_joint_deg(namespace["toy_poses"], namespace["toy"].true)


_TOY = ("toy", "toy_em", "toy_start")

EXERCISES = ExerciseSet(chapter=1, exercises=[
    Exercise(
        1, lambda: 2.0,
        hint="divide the outlier term by Π_i (2πσ²)^(-1) and put in v = πσ²; σ² cancels",
        wrong_answers=(WrongAnswer(3 * np.sqrt(np.pi / 2), "the 3-D value of eq. (18)"),
                       WrongAnswer(0.5, "the ratio upside down, v / (2πσ²)"),
                       WrongAnswer(2 * np.pi, "the disc's area without its π")),
        rtol=0.01,
    ),
    Exercise(
        2, lambda: 3.0 / (3.0 + PAPER_C),
        hint="each of the three kernels is e^0 = 1; add the three α of eq. (17), which share one denominator",
        wrong_answers=(WrongAnswer(1.0 / (1.0 + PAPER_C), "one texture point only"),
                       WrongAnswer(3.0 / (1.0 + PAPER_C), "three one-point probabilities added"),
                       WrongAnswer(1.0, "the text's 'close to 1'")),
        atol=0.006, rtol=0.0,
    ),
    Exercise(
        3, lambda toy, toy_em, toy_start, toy_sigmas: _without_outlier_class(toy, toy_em, toy_start, toy_sigmas),
        hint="set the constant to 1e-9, run the cell, and take the largest |joint - truth| of the last pose, in degrees",
        wrong_answers=(WrongAnswer(_annealed_worst, "the unchanged run (c of eq. 18)", unchanged_experiment=True),
                       WrongAnswer(_from(_without_outlier_class, *_TOY, "toy_sigmas", scale=np.pi / 180),
                                   "the right run, in radians"),
                       WrongAnswer(20.0, "the start's error")),
        context=(*_TOY, "toy_sigmas"), atol=0.06, rtol=0.0, experiment=True,
    ),
    Exercise(
        4, lambda toy, toy_em, toy_start: _single_sigma(toy, toy_em, toy_start),
        hint="run one σ level of 2 mm with 50 iterations and take the largest |joint - truth| of the last pose, in degrees",
        wrong_answers=(WrongAnswer(_annealed_worst, "the unchanged, annealed run", unchanged_experiment=True),
                       WrongAnswer(_from(_single_sigma, *_TOY, scale=np.pi / 180), "the right run, in radians"),
                       WrongAnswer(20.0, "the start's error")),
        context=_TOY, atol=0.06, rtol=0.0, experiment=True,
    ),
    Exercise(
        5, lambda hand, ring, theta0: _rigid_share(hand, ring, theta0),
        hint="set a = 50 and take the mean of the boolean array (a share between 0 and 1)",
        wrong_answers=(WrongAnswer(lambda namespace: namespace["stuck"][10.0], "the unchanged a = 10",
                                   unchanged_experiment=True),
                       WrongAnswer(lambda namespace: namespace["stuck"][2.0], "the paper's a = 2"),
                       WrongAnswer(_from(_rigid_share, "hand", "ring", "theta0", scale=100.0), "a percentage"),
                       WrongAnswer(1.0, "every point rigid")),
        context=("hand", "ring", "theta0"), atol=0.006, rtol=0.0, experiment=True,
    ),
    Exercise(
        6, lambda: "the clutter",
        hint="the blur and the noise are in the annealed run too; what does the outlier class of eq. (17) discount?",
        wrong_answers=(WrongAnswer("the blur of large σ", "the large-σ blur (corrected away in the draws)"),
                       WrongAnswer("the noise on the marks", "the noise (the same in both runs)")),
        choices=("the clutter", "the blur of large σ", "the noise on the marks"),
    ),
    Exercise(
        7, lambda: "tears at the crease",
        hint="look at how many points are blended at a = 2 and at a large a, and where the blended ones lie",
        wrong_answers=(WrongAnswer("stretches smoothly", "the a = 2 behaviour"),
                       WrongAnswer("does not move", "rigid read as fixed")),
        choices=("stretches smoothly", "tears at the crease", "does not move"),
    ),
])
