"""The exercises of chapter 6, specified as data: expected values, hints and the wrong answers each check rejects.

The notebook's check cells call ``EXERCISES.check(k, answer_k, ...)``; the expected values are
computed here from the notebook's objects, so they are not in plain view under the answer cells.
Experiments (exercises 3, 4 and 5) re-run the filter with the setting the prompt asks for; the
unchanged notebook's value is recorded among the wrong answers.
"""

from __future__ import annotations

import numpy as np

from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer
from amdo_lab.cue_fusion_pf.dynamics import ARDynamics
from amdo_lab.cue_fusion_pf.likelihoods import edge_line_likelihood
from amdo_lab.cue_fusion_pf.data import ellipse_iou
from amdo_lab.cue_fusion_pf.tracker import WALKER_SIGMAS, track
from amdo_lab.cue_fusion_pf.walker import box_iou

__all__ = ["EXERCISES"]

#: Exercise 1: the scale's damping (Table 1), the frame period.
SCALE_BETA, FRAME_PERIOD = 10.0, 1.0 / 25.0
#: Exercise 2: eq. (13)'s parameters in the prompt.
P0, CLUTTER_DENSITY, SIGMA_E = 0.2, 0.05, float(np.sqrt(2.0))
#: Exercise 3: the agile frames, the filter seed and the two line half-lengths (px) compared.
AGILE_START, LINES_SEED, SHORT_LINES, LONG_LINES = 136, 5, 12, 30
#: Exercise 4: frames from the hand on, the filter seed and the particle count asked for.
HAND_START, PARTICLES_SEED, FEW_PARTICLES = 81, 6, 30

#: Exercise 5: the walker's filter (as the chapter runs it) and the stationary std of t_x, t_y asked for (px).
WALKER_SEED, WIDE_STD = 10_000, 400.0

_runs: dict = {}


def _printed_radius(beta: float) -> float:
    return ARDynamics([beta], [0.0], FRAME_PERIOD, [1.0], [0.0], printed_order=True,
                      allow_unstable=True).spectral_radius()


def _printed_roots(beta: float) -> np.ndarray:
    a1 = -np.exp(-2 * beta * FRAME_PERIOD)
    a0 = 2 * np.exp(-beta * FRAME_PERIOD)
    return np.sort(np.abs(np.roots([1.0, -a1, -a0])))


def _edge_pair() -> tuple[float, float]:
    return (edge_line_likelihood([1.0], P0, CLUTTER_DENSITY, SIGMA_E),
            edge_line_likelihood([], P0, CLUTTER_DENSITY, SIGMA_E))


def _edge_only_tracked(fusion, half_length: int) -> np.ndarray:
    key = ("lines", id(fusion), half_length)
    if key not in _runs:
        run = track(fusion.frames[AGILE_START:], fusion.true_ellipses[AGILE_START], rng=LINES_SEED, cues=("edge",),
                    half_length=half_length)
        _runs[key] = ellipse_iou(run.ellipses, fusion.true_ellipses[AGILE_START:]) >= 0.5
    return _runs[key]


def _frames_that_differ(fusion) -> int:
    return int(np.sum(_edge_only_tracked(fusion, LONG_LINES) != _edge_only_tracked(fusion, SHORT_LINES)))


def _hand_share(fusion, n_particles: int) -> float:
    key = ("particles", id(fusion), n_particles)
    if key not in _runs:
        run = track(fusion.frames[HAND_START:], fusion.true_ellipses[HAND_START], rng=PARTICLES_SEED,
                    cues=("color", "edge", "structure"), n_particles=n_particles)
        _runs[key] = float(np.mean(ellipse_iou(run.ellipses, fusion.true_ellipses[HAND_START:]) >= 0.5))
    return _runs[key]


def _walker_share(walker, translation_std: float) -> float:
    key = ("walker", id(walker), translation_std)
    if key not in _runs:
        run = track(walker.frames, walker.template, rng=WALKER_SEED, cues=("color", "edge"), bins=16, n_lines=70,
                    shape="similarity", sigmas=WALKER_SIGMAS,
                    stationary_std=(translation_std, translation_std, 0.1, 0.1))
        outline = walker.shape_space().control_points(run.states)
        _runs[key] = float(np.mean(box_iou(outline, walker.true_control_points) >= 0.5))
    return _runs[key]


def _better_remedy(walker, walker_share) -> str:
    return "tempering" if walker_share["colour × edges^0.1"] > _walker_share(walker, WIDE_STD) else "dynamics"


EXERCISES = ExerciseSet(chapter=6, exercises=[
    Exercise(
        1, lambda: _printed_radius(SCALE_BETA),
        "build a1 = -exp(-2βτ) and a0 = 2exp(-βτ) with β = 10, then the roots of z² - a1 z - a0 (np.roots) "
        "and the larger modulus",
        (WrongAnswer(lambda ns: _printed_radius(2.0), "the translation's β = 2 (the chapter's 1.85)"),
         WrongAnswer(lambda ns: float(_printed_roots(SCALE_BETA)[0]), "the smaller of the two moduli"),
         WrongAnswer(float(np.exp(-SCALE_BETA * FRAME_PERIOD)), "the corrected order's double root exp(-βτ)")),
        rtol=1e-3),
    Exercise(
        2, _edge_pair,
        "eq. (13): P0 + (1 - P0)/λ · Σ G(z_j) with G the Gaussian density of σ_e; an empty sum is 0",
        (WrongAnswer((float(np.exp(-0.25) / (np.sqrt(2 * np.pi) * SIGMA_E)), 0.0), "G(1) alone, and 0 for no feature"),
         WrongAnswer((P0 + (1 - P0) * CLUTTER_DENSITY * float(np.exp(-0.25) / (np.sqrt(2 * np.pi) * SIGMA_E)), P0),
                     "multiplied by λ instead of divided"),
         WrongAnswer((P0 + (1 - P0) / CLUTTER_DENSITY * float(np.exp(-0.5) / (np.sqrt(2 * np.pi) * SIGMA_E)), P0),
                     "exp(-z²/σ²) without the 2")),
        rtol=2e-3),
    Exercise(
        3, _frames_that_differ,
        "set half_length = 30 in the answer cell, run it, and count the frames where tracked_long and tracked_short differ",
        (WrongAnswer(lambda ns: ns["lines_differ"], "the unchanged experiment (both runs at ±12 px)",
                     unchanged_experiment=True),
         WrongAnswer(lambda ns: int(np.sum(~_edge_only_tracked(ns["fusion"], LONG_LINES))),
                     "the frames the ±30 px run loses"),
         WrongAnswer(lambda ns: len(ns["fusion"].frames) - AGILE_START, "every agile frame")),
        context=("fusion",), rtol=0.0, atol=0.0, experiment=True),
    Exercise(
        4, lambda fusion: _hand_share(fusion, FEW_PARTICLES),
        "set n_particles = 30 in the answer cell, run it, and give the share of frames with IoU >= 0.5 "
        "(two decimals)",
        (WrongAnswer(lambda ns: ns["share_tried"], "the unchanged experiment (300 particles)",
                     unchanged_experiment=True),
         WrongAnswer(lambda ns: 1.0 - _hand_share(ns["fusion"], FEW_PARTICLES), "the share of frames lost"),
         WrongAnswer(lambda ns: float(np.mean(ellipse_iou(ns["tracked_all"].ellipses[HAND_START:],
                                                          ns["fusion"].true_ellipses[HAND_START:]) >= 0.5)),
                     "the three-cue run of the whole sequence on these frames")),
        context=("fusion",), rtol=0.0, atol=0.006, experiment=True),

    Exercise(
        5, lambda walker: _walker_share(walker, WIDE_STD),
        "set walker_std = 400 in the answer cell, run it, and give the share of frames with box IoU >= 0.5 "
        "(two decimals)",
        (WrongAnswer(lambda ns: ns["weak_pull_share"], "the unchanged experiment (100 px)", unchanged_experiment=True),
         WrongAnswer(lambda ns: ns["walker_share"]["colour"], "colour alone"),
         WrongAnswer(lambda ns: ns["walker_share"]["colour × edges^0.1"], "the tempered edges")),
        context=("walker",), rtol=0.0, atol=0.006, experiment=True),
    Exercise(
        6, _better_remedy,
        "compare the share of frames Exercise 5 gives with the tempered run's in the chapter",
        (WrongAnswer(lambda ns: "dynamics" if _better_remedy(ns["walker"], ns["walker_share"]) == "tempering"
                     else "tempering", "the other remedy"),
         WrongAnswer("neither", "neither")),
        context=("walker", "walker_share"), choices=("dynamics", "tempering", "neither")),
])
