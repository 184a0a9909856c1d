"""The exercises of chapter 8, checked from the notebook's check cells (see ``amdo_lab.common.exercises``)."""

from __future__ import annotations

import numpy as np

from amdo_lab.active_contours.measure import _polygon_area, _segment
from amdo_lab.active_contours.phantom import PIXEL_MM
from amdo_lab.active_contours.snakes import SnakeWeights
from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer

__all__ = ["EXERCISES", "greedy_probe_error"]


def greedy_probe_error(probe: list, *, gamma: float = 1.2, window: int = 3) -> float:
    """Mean |area error| (%) of the greedy snake over the probe contours, with one setting changed.

    Parameters
    ----------
    probe : list of (potential, init, true_mm2)
        The chapter's probe contours.
    gamma : float
        Image weight of eq. (4) (Table 1: 1.2).
    window : int
        Odd side of the neighbourhood.

    Returns
    -------
    float
        ``100 * mean(|found / true - 1|)``.
    """
    errors = []
    for potential, init, true_mm2 in probe:
        points, _ = _segment(potential, init, "greedy", SnakeWeights(0.4, 0.4, gamma), window)
        errors.append(abs(_polygon_area(points, np.asarray(PIXEL_MM)) / true_mm2 - 1))
    return float(100 * np.mean(errors))


def _greedy_experiment(number: int, change: str, unchanged: str, **setting: float) -> Exercise:
    """Exercise ``number``: the greedy snake's mean |area error| (%) on the probe starts with ``setting`` changed."""
    return Exercise(
        number, lambda probe: greedy_probe_error(probe, **setting),
        f"run the greedy snake on the same probe starts with {change} and average |found/true - 1| in percent",
        (WrongAnswer(lambda ns: greedy_probe_error(ns["probe"]), f"the unchanged experiment ({unchanged})",
                     unchanged_experiment=True),
         WrongAnswer(lambda ns: greedy_probe_error(ns["probe"], **setting) / 100, "a fraction, not a percentage")),
        context=("probe",), atol=0.15, rtol=0.0, experiment=True)


EXERCISES = ExerciseSet(chapter=8, exercises=[
    Exercise(
        1, lambda toy_start: len(toy_start) * 25,
        "one energy per candidate per point: count the candidates of a 5 x 5 window",
        (WrongAnswer(lambda ns: len(ns["toy_start"]) * 9, "the 3 x 3 window's count"),
         WrongAnswer(lambda ns: len(ns["toy_start"]) * 25 ** 3, "dynamic programming's n m^3")),
        context=("toy_start",), rtol=0.0, atol=0.5),
    _greedy_experiment(2, "gamma=2.4", "gamma 1.2", gamma=2.4),
    _greedy_experiment(3, "window=5", "window 3", window=5),
    Exercise(
        4, lambda probe_table: str(probe_table.abs().mean().idxmin()),
        "compare the mean absolute errors of the three columns of the probe table",
        (WrongAnswer("greedy", "the fastest method"), WrongAnswer("dynamic", "the globally optimal search")),
        context=("probe_table",), choices=("greedy", "dynamic", "variational")),
])
