"""The exercises of chapter 10, checked from the notebook's check cells (see ``amdo_lab.common.exercises``).

The targets live in the chapter's hidden tests; this module records only the hints, the plausible
wrong answers and, for the "implement it" exercise, the cases its function is checked on.
"""

from __future__ import annotations

import functools

import numpy as np

from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer
from amdo_lab.path_relinking_pf.relinking import relink_pair
from amdo_lab.path_relinking_pf.observation import ObservationModel, measure
from amdo_lab.path_relinking_pf.sequences import make_upper_body_sequence

__all__ = ["EXERCISES", "PATH_STEPS", "relink_case"]

#: The path steps of our settings: 2 px for x1, y1 and 4 degrees for each of the eight angles.
PATH_STEPS = np.r_[2.0, 2.0, np.full(8, np.radians(4.0))]


@functools.lru_cache(maxsize=16)
def _frame(seed: int):
    sequence = make_upper_body_sequence(rng=seed, n_frames=2, size=(120, 120))
    return sequence, ObservationModel(measure(sequence.frames[1], sequence.background), sequence.model)


def relink_case(seed: int) -> dict:
    """Two RefSet members of frame 2 of a small upper-body sequence, the better one first.

    Parameters
    ----------
    seed : int
        Seed of the sequence and of the two poses' offsets from the truth.

    Returns
    -------
    dict
        The keyword arguments of :func:`relink_pair`: ``observation``, ``start`` (x'), ``end`` (x''),
        ``steps`` and ``start_cost``.
    """
    sequence, observation = _frame(seed)
    draw = np.random.default_rng(seed)
    scale = np.r_[2.0, 2.0, np.full(8, np.radians(8.0))]
    start = sequence.truth[1] + draw.uniform(0.2, 1.0) * scale * draw.standard_normal(10)
    end = sequence.truth[1] + draw.uniform(0.5, 2.0) * scale * draw.standard_normal(10)
    if observation.cost(end)[0] < observation.cost(start)[0]:
        start, end = end, start
    return {"observation": observation, "start": start, "end": end, "steps": PATH_STEPS.copy(),
            "start_cost": float(observation.cost(start)[0])}


def _interior(start, end, steps, parts_of):
    parts = int(np.ceil(parts_of(np.abs(end - start), steps)))
    return start + np.arange(1, parts)[:, None] / max(parts, 1) * (end - start)


def _ends_included(observation, start, end, steps, start_cost):
    path = np.vstack([start, _interior(start, end, steps, lambda d, s: np.max(d / s)), end])
    costs = observation.cost(path)
    return path[np.argmin(costs)], float(costs.min()), len(path)


def _one_step(observation, start, end, steps, start_cost):
    path = _interior(start, end, steps, lambda d, s: np.max(d) / np.min(s))
    if not len(path):
        return start, start_cost, 0
    costs = observation.cost(path)
    if costs.min() < start_cost:
        return path[np.argmin(costs)], float(costs.min()), len(path)
    return start, start_cost, len(path)


def _no_fallback(observation, start, end, steps, start_cost):
    path = _interior(start, end, steps, lambda d, s: np.max(d / s))
    if not len(path):
        return start, start_cost, 0
    costs = observation.cost(path)
    return path[np.argmin(costs)], float(costs.min()), len(path)


EXERCISES = ExerciseSet(chapter=10, exercises=[
    Exercise(
        1, None,
        "cut the segment into ceil(max_k |x''_k - x'_k| / step_k) equal parts, evaluate the points strictly "
        "between the ends, and keep the cheapest only if it costs less than x'",
        (WrongAnswer(_ends_included, "both ends evaluated again",
                     hint="x' and x'' are RefSet members whose costs are known: evaluate only the points strictly "
                          "between them"),
         WrongAnswer(_one_step, "one step (the angles' 4 degrees) for every coordinate",
                     hint="divide each coordinate's change by its own step (px for x1, y1, radians for the angles) "
                          "before taking the largest"),
         WrongAnswer(_no_fallback, "the path's best point even when it is worse than x'",
                     hint="when no point of the path costs less than x', the new solution is x' itself")),
        kind="function", reference=relink_pair, make_case=relink_case, example_seed=3, rtol=1e-9, atol=1e-9,
        points=2),
    Exercise(
        2, None,
        "halve `spread_2` (1 px and 2.5 degrees), evaluate the new cloud and compute the effective sample size "
        "of its weights at alpha = 0.01",
        (WrongAnswer(6.8, "the unchanged experiment (2 px, 5 degrees)", unchanged_experiment=True,
                     hint="that is the chapter's cloud: halve spread_2 and run the cell again",
                     variable="experiment_2"),
         WrongAnswer(1.5, "the cloud twice as wide",
                     hint="the prompt asks for half the diffusion, not twice it"),
         WrongAnswer(133.6, "alpha = 0.001 from the table above",
                     hint="keep alpha at 0.01 and change the cloud instead")),
        rtol=0.0, atol=0.15, experiment=True, why_points=1),
    Exercise(
        3, None,
        "run the answer cell's PRPF with refset_size=5 and average result.evaluations",
        (WrongAnswer(490.0, "the unchanged experiment (b = 3)", unchanged_experiment=True,
                     hint="that is b = 3: set refset_size=5 and run the cell again", variable="experiment_3"),
         WrongAnswer(200.0, "N: the particle filter stage alone",
                     hint="the PR stage's paths and local searches are evaluations too"),
         WrongAnswer(820.0, "b = 5 scaled linearly from b = 3 (491 x 5 / 3)",
                     hint="run it: the number of pairs, not b, sets the PR stage's work")),
        rtol=0.0, atol=5.0, experiment=True, why_points=1),
    Exercise(
        4, None,
        "pass settings=pr.FilterSettings(velocity='random-walk') and average the joint errors over frames and joints",
        (WrongAnswer(0.733, "the unchanged experiment (velocity held at 0)", unchanged_experiment=True,
                     hint="that is our default: pass the random-walk settings and run the cell again",
                     variable="experiment_4"),
         WrongAnswer(0.37, "half the unchanged error",
                     hint="run the experiment rather than guess the direction"),
         WrongAnswer(6.54, "the paths-only error of the ablation",
                     hint="keep the full PRPF; change only the system model")),
        rtol=0.0, atol=0.0015, experiment=True, why_points=1),
    Exercise(
        5, None,
        "pass relink='attribute' to track_prpf on `short` and average the joint errors over frames and joints",
        (WrongAnswer(0.73, "the unchanged experiment (straight segments)", unchanged_experiment=True,
                     hint="that is the straight-segment path: pass relink='attribute' and run again",
                     variable="experiment_5"),
         WrongAnswer(0.67, "the local search alone (relink='none')",
                     hint="relink='none' drops the paths; the prompt asks for attribute paths"),
         WrongAnswer(1.29, "the chapter's 30-frame error",
                     hint="the experiment runs on the ten frames of `short`")),
        rtol=0.0, atol=0.005, experiment=True, why_points=1),
])
