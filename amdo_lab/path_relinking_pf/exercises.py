"""The exercises of chapter 10, checked from the notebook's check cells (see ``amdo_lab.common.exercises``)."""

from __future__ import annotations

import functools

import numpy as np

from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer
from amdo_lab.path_relinking_pf.body import joint_errors_px
from amdo_lab.path_relinking_pf.filters import FilterSettings, track_prpf
from amdo_lab.path_relinking_pf.sequences import make_upper_body_sequence

__all__ = ["EXERCISES", "SHORT_FRAMES", "short_prpf_run"]

#: Frames of the short sequence the experiments run on (seed 0, like the chapter's).
SHORT_FRAMES = 10


@functools.lru_cache(maxsize=8)
def short_prpf_run(refset_size: int, velocity: str) -> tuple[float, float]:
    """Mean evaluations a frame and mean joint error (px) of PRPF (N = 200) on the short sequence.

    Parameters
    ----------
    refset_size : int
        b.
    velocity : str
        Eq. (8)'s velocity, ``"zero"`` or ``"random-walk"``.

    Returns
    -------
    tuple of float
        (evaluations a frame, joint error px), both averaged over the frames.
    """
    sequence = make_upper_body_sequence(rng=0, n_frames=SHORT_FRAMES)
    result = track_prpf(sequence, rng=0, n_particles=200, refset_size=refset_size,
                        settings=FilterSettings(velocity=velocity))
    error = joint_errors_px(sequence.model, result.poses, sequence.truth)
    return float(result.evaluations.mean()), float(error.mean())


def _path_points(toy_a: np.ndarray, toy_b: np.ndarray, toy_step: float) -> int:
    return int(np.ceil(np.max(np.abs(toy_b - toy_a)) / toy_step)) - 1


def _carrier(ablation: dict) -> str:
    return "local search" if ablation["local search only"] < ablation["paths only"] else "paths"


EXERCISES = ExerciseSet(chapter=10, exercises=[
    Exercise(
        1, _path_points,
        "the segment is cut into equal parts so that no angle moves more than the step; the two ends are "
        "RefSet members already and are not evaluated again",
        (WrongAnswer(lambda ns: _path_points(ns["toy_a"], ns["toy_b"], ns["toy_step"]) + 1,
                     "the number of parts (one end counted)"),
         WrongAnswer(lambda ns: _path_points(ns["toy_a"], ns["toy_b"], ns["toy_step"]) + 2,
                     "every point of the path, both ends included")),
        context=("toy_a", "toy_b", "toy_step"), rtol=0.0, atol=0.1),
    Exercise(
        2, lambda: "smaller",
        "a larger alpha stretches the differences of log-weights between particles: what does that do to the "
        "largest weight?",
        (WrongAnswer("larger", "the opposite direction"), WrongAnswer("unchanged", "alpha cancels when normalising")),
        choices=("smaller", "larger", "unchanged")),
    Exercise(
        3, lambda: short_prpf_run(5, "zero")[0],
        "run the answer cell's PRPF with refset_size=5 and average result.evaluations",
        (WrongAnswer(lambda ns: float(ns["run_3"].evaluations.mean()), "the unchanged experiment (b = 3)",
                     unchanged_experiment=True),
         WrongAnswer(200.0, "N: the particle filter stage alone")),
        rtol=0.02, experiment=True),
    Exercise(
        4, lambda: short_prpf_run(3, "random-walk")[1],
        "pass settings=pr.FilterSettings(velocity='random-walk') and average the joint errors over frames and joints",
        (WrongAnswer(lambda ns: float(pr_error(ns["run_4"], ns["short"])), "the unchanged experiment (velocity 0)",
                     unchanged_experiment=True),
         WrongAnswer(lambda ns: float(pr_error(ns["run_4"], ns["short"])) / 2, "half the unchanged error")),
        atol=0.05, experiment=True),
    Exercise(
        5, _carrier,
        "compare the two ablation rows with the full PRPF: which removal costs the accuracy?",
        (WrongAnswer(lambda ns: "paths" if _carrier(ns["ablation"]) == "local search" else "local search",
                     "the other part"),
         WrongAnswer("neither", "neither part")),
        context=("ablation",), choices=("paths", "local search", "neither")),
])


def pr_error(result, sequence) -> float:
    """Mean joint error (px) of a tracking result on a sequence (for the recorded wrong answers)."""
    return float(joint_errors_px(sequence.model, result.poses, sequence.truth).mean())
