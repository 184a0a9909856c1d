"""The exercises of chapter 4 (ear biometrics), specified as data: hints, tolerances, recorded wrong answers.

The targets are not here: each check cell of the chapter's source registers its exercise's target in
a hidden test (``EXERCISES.expect``), so the package a reader installs does not hold them. The
"implement it" exercise (5) compares the reader's crossing count of one contour with
:func:`~amdo_lab.ear_biometrics.circles.contour_crossings` on cases drawn by :func:`crossing_case`.
See :mod:`amdo_lab.common.exercises` for the mechanism.

References
----------
M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
LNCS 3179, pp. 51-61: eq. (7) (Exercises 1 and 5), eq. (8) (Exercise 2), Sec. 5 steps 2-3 (Exercise 3).
"""

from __future__ import annotations

import numpy as np

from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer
from amdo_lab.ear_biometrics.circles import contour_crossings

__all__ = ["EXERCISES", "crossing_case"]

CROSSING_EXAMPLE_SEED = 4
"""The seed of the case Exercise 5 shows in the notebook (its unseen cases use others)."""


def crossing_case(seed: int) -> dict:
    """One case of Exercise 5: a wiggly open contour around the origin, three circles and a dead band.

    The contour turns three quarters of the way round the origin while it spirals out from inside the
    smallest circle to outside the largest, its radius swinging, with small wiggles that graze the
    circles.

    Parameters
    ----------
    seed : int
        The case's seed.

    Returns
    -------
    dict
        Keyword arguments of :func:`~amdo_lab.ear_biometrics.circles.contour_crossings`: ``points``
        (200, 2), ``radii`` (3,) and ``band``.
    """
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, 200)
    radius = (0.6 + 0.8 * t + 0.2 * np.sin(2 * np.pi * rng.uniform(1.0, 2.0) * t)
              + 0.06 * np.sin(2 * np.pi * rng.uniform(10, 16) * t + rng.uniform(0, 2 * np.pi)))
    angle = rng.uniform(0, 2 * np.pi) + 1.5 * np.pi * t
    points = np.c_[radius * np.cos(angle), radius * np.sin(angle)].round(4)
    return {"points": points, "radii": np.array([0.8, 1.0, 1.2]), "band": 0.05}


def _no_band(points: np.ndarray, radii: np.ndarray, band: float) -> np.ndarray:
    return contour_crossings(points, radii, 0.0)


def _closed(points: np.ndarray, radii: np.ndarray, band: float) -> np.ndarray:
    return contour_crossings(np.vstack([points, points[:1]]), radii, band)


def _band_entries(points: np.ndarray, radii: np.ndarray, band: float) -> np.ndarray:
    """Every entry into the band counted (and every jump over it): a graze counts as a crossing."""
    radius = np.linalg.norm(np.asarray(points, float), axis=1)
    counts = []
    for circle in radii:
        side = np.where(radius < circle - band, -1, np.where(radius >= circle + band, 1, 0))
        entries = (side[1:] == 0) & (side[:-1] != 0)
        jumps = side[1:] * side[:-1] == -1
        counts.append(int(np.count_nonzero(entries | jumps)))
    return np.array(counts)


EXERCISES = ExerciseSet(chapter=4, exercises=[
    Exercise(
        1, None,
        "list the angles where the circle meets the arms, then join neighbouring crossings all the way round",
        (WrongAnswer((4, 5.66), "the '+' of the toy (four arms)",
                     hint="the T has three arms, not four: east, north and west"),
         WrongAnswer((3, 2.83), "the polygon left open (two sides of sqrt 2)",
                     hint="close the polygon: join the last crossing back to the first"),
         WrongAnswer((3, 6.28), "arc lengths instead of chords",
                     hint="d_r is the straight distance between neighbouring crossings, not the arc")),
        rtol=0.0, atol=0.005),
    Exercise(
        2, None,
        "walk round the 8 neighbours N, NE, E, ... in order, count the 0/1 changes, then halve",
        (WrongAnswer(6, "the changes not halved",
                     hint="each branch makes two changes (0 to 1 and back): halve the count"),
         WrongAnswer(1, "Yokoi's connectivity number, another reading of eq. 8",
                     hint="that is Yokoi's connectivity number; eq. 8 as we read it counts 0/1 changes"),
         WrongAnswer(2, "a line pixel (two neighbours across)",
                     hint="count the branches leaving the centre: west, east and south")),
        rtol=0.0, atol=0.0),
    Exercise(
        3, None,
        "compare the two settings query by query (McNemar, paired_comparison), with k_tried set to 8",
        (WrongAnswer(1.0, "the unchanged experiment: k = 12 against itself", unchanged_experiment=True,
                     hint="k = 12 against itself gives p = 1: set k_tried = 8.0 and rerun the cell"),
         WrongAnswer(0.51, "the unpaired two-proportion z-test",
                     hint="both settings see the same 20 queries: use the paired test (McNemar)"),
         WrongAnswer(0.72, "McNemar's chi-square with continuity correction",
                     hint="with so few discordant queries use the exact test, paired_comparison"),
         WrongAnswer(0.48, "McNemar's chi-square without continuity correction",
                     hint="with so few discordant queries use the exact test, paired_comparison"),
         WrongAnswer(0.1, "the difference of the two rates, not a p-value",
                     hint="the question asks for the p-value of the paired test, not the rates' difference")),
        rtol=0.0, atol=0.005, experiment=True, why_points=1),
    Exercise(
        4, None,
        "switch translation off in the answer cell's study and read HOG's rank-1",
        (WrongAnswer(0.233, "the unchanged study (every factor on)", unchanged_experiment=True,
                     hint="that is the study with every factor on: switch translation off "
                          '({"no translation": ("translation",)})', variable="experiment_4"),
         WrongAnswer(0.433, "the 'only translation' row of the nuisance table",
                     hint="that row has translation alone on; switch translation off and keep the rest on"),
         WrongAnswer(0.9, "ours, not HOG",
                     hint="the question asks for HOG's rank-1, not ours"),
         WrongAnswer(0.367, "the gain over the 'all on' row, not the rate",
                     hint="give HOG's rank-1 itself, not its change")),
        rtol=0.0, atol=0.0005, experiment=True, why_points=2),
    Exercise(
        5, None,
        "side -1 inside R - band, +1 outside R + band, 0 between; skip the zeros and count the changes of side",
        (WrongAnswer(_no_band, "every sign change of r - R (the band ignored)",
                     hint="a wiggle near the circle adds crossings: ignore points inside the dead band"),
         WrongAnswer(_closed, "the contour closed into a loop",
                     hint="a contour is an open line: do not join its last point back to its first"),
         WrongAnswer(_band_entries, "every entry into the band counted",
                     hint="a graze enters the band and leaves on the side it came from: count only "
                          "changes of side")),
        rtol=0.0, atol=0.0, kind="function", reference=contour_crossings, make_case=crossing_case,
        example_seed=CROSSING_EXAMPLE_SEED),
])
