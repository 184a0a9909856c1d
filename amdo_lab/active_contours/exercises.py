"""The exercises of chapter 8, checked from the notebook's check cells (see ``amdo_lab.common.exercises``).

Only what is not secret lives here: hints, tolerances, the wrong answers a reader plausibly gives, and for
exercise 4 ("implement it") the package's reference pass, the cases it is checked on and wrong functions.
The targets of exercises 1-3 sit in the source notebook's hidden tests.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from amdo_lab.active_contours.snakes import TABLE_1, _edge_of, _floor, _image_term, _offsets, dp_pass
from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer

__all__ = ["EXERCISES", "dp_case", "reference_dp_pass"]


def dp_case(seed: int) -> dict:
    """A small unseen case for exercise 4: a smooth random 24 x 24 potential and an 8-point ring in it.

    Parameters
    ----------
    seed : int
        The case's seed.

    Returns
    -------
    dict
        ``potential`` (24, 24) with values in [0, 15] and ``points`` (8, 2) whole (row, col) pixels.
    """
    rng = np.random.default_rng(seed)
    field = ndimage.gaussian_filter(rng.random((24, 24)), 2.0)
    potential = 15.0 * (field - field.min()) / (field.max() - field.min())
    theta = np.linspace(0, 2 * np.pi, 8, endpoint=False) + rng.uniform(0, np.pi / 4)
    radius = rng.uniform(5.0, 7.0)
    points = np.rint(11.5 + radius * np.column_stack([np.sin(theta), np.cos(theta)]))
    return {"potential": potential, "points": points}


def reference_dp_pass(potential: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Exercise 4's reference: :func:`~amdo_lab.active_contours.dp_pass` with point 0 fixed and Table 1's weights."""
    weights = TABLE_1["dynamic"]
    return dp_pass(potential, points, fixed=0, alpha=weights.alpha, beta=weights.beta, gamma=weights.gamma)


def _independent_moves(potential: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Wrong: every point but 0 takes its own best candidate against its neighbours' current places."""
    weights, offsets, edge = TABLE_1["dynamic"], _offsets(3), _edge_of(potential)
    d_bar = float(np.mean(np.linalg.norm(np.roll(points, -1, axis=0) - points, axis=1)))
    scale = max(d_bar, 1.0)
    n, moved = len(points), points.copy()
    for i in range(1, n):
        cands = points[i] + offsets
        e_cont = np.abs(d_bar - np.linalg.norm(cands - points[i - 1], axis=1)) / scale
        e_curv = np.sum((points[i - 1] - 2 * cands + points[(i + 1) % n]) ** 2, axis=1) / scale ** 2
        rows = np.clip(cands[:, 0], 0, edge.shape[0] - 1).astype(int)
        cols = np.clip(cands[:, 1], 0, edge.shape[1] - 1).astype(int)
        e_image = _image_term(edge[rows, cols][None], _floor(edge))[0]
        energy = weights.alpha * e_cont + weights.beta * e_curv + weights.gamma * e_image
        moved[i] = cands[int(np.argmin(energy))]
    return moved


def _without_curvature(potential: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Wrong: a first-order table (one candidate per state), i.e. the curvature term left out."""
    weights = TABLE_1["dynamic"]
    return dp_pass(potential, points, alpha=weights.alpha, beta=0.0, gamma=weights.gamma)


def _literal_image_term(potential: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Wrong: eq. (7) printed literally, -e / e_max, instead of the range over the candidates."""
    weights = TABLE_1["dynamic"]
    return dp_pass(potential, points, alpha=weights.alpha, beta=weights.beta, gamma=weights.gamma,
                   image_norm="max")


EXERCISES = ExerciseSet(chapter=8, exercises=[
    Exercise(
        1, None,
        hint="rebuild the toy's potential with potential_field(toy_image, thin=False), run greedy_snake from "
             "toy_start with the defaults, and give 100 * (area / (pi 16^2) - 1), signed, one decimal",
        wrong_answers=(
            WrongAnswer(-2.2, "the unchanged experiment (thinned edge map)", unchanged_experiment=True,
                        variable="experiment_1",
                        hint="that is the toy with the thinned edge map: set thin_1 = False and run the cell again"),
            WrongAnswer(-0.202, "a fraction, not a percentage",
                        hint="the prompt asks for percent: multiply the fraction by 100"),
            WrongAnswer(20.2, "the size of the error without its sign",
                        hint="keep the sign: is the final contour inside or outside the disc?"),
        ),
        rtol=0.0, atol=0.05, experiment=True, points=1, why_points=2),
    Exercise(
        2, None,
        hint="run greedy_snake(potential, init, gamma=2.4) on every probe start and average "
             "100 * |area / true_mm2 - 1| over the eight contours, one decimal",
        wrong_answers=(
            WrongAnswer(10.2, "the unchanged experiment (gamma 1.2)", unchanged_experiment=True,
                        variable="experiment_2",
                        hint="that is Table 1's gamma = 1.2: set gamma_2 = 2.4 and run the cell again"),
            WrongAnswer(0.104, "a fraction, not a percentage",
                        hint="the prompt asks for percent: multiply the fraction by 100"),
            WrongAnswer(10.5, "the dynamic-programming column of the probe table",
                        hint="the question is about the greedy snake with gamma = 2.4, not dynamic programming "
                             "with its own gamma: run the experiment"),
        ),
        rtol=0.0, atol=0.05, experiment=True, points=1, why_points=1),
    Exercise(
        3, None,
        hint="run greedy_snake(potential, init, window=5) on every probe start and average "
             "100 * |area / true_mm2 - 1| over the eight contours, one decimal",
        wrong_answers=(
            WrongAnswer(10.2, "the unchanged experiment (window 3)", unchanged_experiment=True,
                        variable="experiment_3",
                        hint="that is the 3 x 3 window: set window_3 = 5 and run the cell again"),
            WrongAnswer(0.094, "a fraction, not a percentage",
                        hint="the prompt asks for percent: multiply the fraction by 100"),
        ),
        rtol=0.0, atol=0.05, experiment=True, points=1, why_points=1),
    Exercise(
        4, None,
        hint="keep, for every pair (j_{i-1}, j_i) of neighbouring candidates, the cheapest chain from point 1 "
             "that ends in it; add curvature(j_{i-2}, j_{i-1}, j_i), continuity(j_{i-1}, j_i) and the image "
             "term of j_i; close with the last point's continuity and curvature to point 0; then backtrack",
        wrong_answers=(
            WrongAnswer(_independent_moves, "each point's own best move (greedy, not joint)",
                        hint="your points choose one at a time against their neighbours' current places; "
                             "dynamic programming chooses them together: a table over pairs of candidates, "
                             "then a backtrack"),
            WrongAnswer(_without_curvature, "a table over single candidates (no curvature)",
                        hint="the curvature of point i needs the candidates of i-1, i and i+1: the table's "
                             "state must be a pair of neighbouring candidates, not one"),
            WrongAnswer(_literal_image_term, "eq. (7) printed literally, -e / e_max",
                        hint="use the chapter's image term: (e_min - e) / max(e_max - e_min, floor) over each "
                             "point's nine candidates, floor = (max e - min e over the image) / 15"),
        ),
        kind="function", reference=reference_dp_pass, make_case=dp_case, example_seed=8,
        rtol=0.0, atol=0.0, points=2),
])
