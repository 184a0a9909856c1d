"""The exercises of chapter 4 (ear biometrics), checked from the notebook's check cells.

Each check computes its expected value here, from the notebook objects the check cell names, so the
value is not in plain view under the answer cell (see :mod:`amdo_lab.common.exercises`).

References
----------
M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
LNCS 3179, pp. 51-61: eq. (7) (Exercise 1), eq. (8) (Exercise 2), Sec. 5 steps 2-3 (Exercise 3).
"""

from __future__ import annotations

import functools

import numpy as np

from amdo_lab.common import paired_comparison
from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer

__all__ = ["EXERCISES"]

TEE_SIZE, TEE_ARM = 121, 48
"""Exercise 1's "T": three arms of 48 px from the centre of a 121-px image (east, north, west)."""


def tee_contours() -> np.ndarray:
    """Exercise 1's contour image: a "T" whose junction is the image centre (arms east, north, west)."""
    tee = np.zeros((TEE_SIZE, TEE_SIZE), bool)
    centre = TEE_SIZE // 2
    tee[centre, centre - TEE_ARM:centre + TEE_ARM + 1] = True
    tee[centre - TEE_ARM:centre + 1, centre] = True
    return tee


def _tee_circle(toy_circle) -> np.ndarray:
    """l_r and sum d_r of the circle r = 1 around the T's junction, by the reader's own eq. 7 code."""
    centre = np.array([TEE_SIZE // 2] * 2, float)
    count, total, _ = toy_circle(tee_contours(), centre, np.array([30.0, 30.0]), 1.0)
    return np.array([count, total], float)


def _tee_crossing_number(toy_crossing_number) -> int:
    """Eq. 8 at the centre of a T drawn with its west, east and south neighbours set."""
    tee = np.zeros((5, 5), bool)
    tee[2, 1:4] = True
    tee[3, 2] = True
    return int(toy_crossing_number(tee)[2, 2])


def _k8_against_k12(rule_first20) -> float:
    """McNemar's exact p of the paper's rule with k = 8 against k = 12, query by query (20 subjects)."""
    return paired_comparison(rule_first20(8.0), rule_first20(12.0)).p_value


def _unpaired_p(rule_first20) -> float:
    """The two-proportion z-test's p: the test that ignores that both settings see the same queries."""
    from scipy.stats import norm

    first, second = rule_first20(8.0), rule_first20(12.0)
    pooled = np.r_[first, second].mean()
    spread = np.sqrt(pooled * (1 - pooled) * 2 / len(first))
    return float(2 * norm.sf(abs(first.mean() - second.mean()) / spread)) if spread > 0 else 1.0


@functools.lru_cache(maxsize=None)
def _no_translation_row(n_subjects: int, seed: int) -> tuple[float, float]:
    """Rank-1 of ours and of HOG on the nuisance study's database with translation switched off."""
    from amdo_lab.ear_biometrics.evaluation import nuisance_study

    row = nuisance_study(n_subjects, {"no translation": ("translation",)}, rng=seed)[0]
    return row["ours rank-1"], row["HOG rank-1"]


def _who_gains(nuisance) -> str:
    """"HOG" or "ours": which rank-1 rises more when translation is switched off (or "equal")."""
    ours, hog = _no_translation_row(30, 4004)
    gain_ours, gain_hog = ours - nuisance.loc["all on", "ours rank-1"], hog - nuisance.loc["all on", "HOG rank-1"]
    if abs(gain_hog - gain_ours) < 1.5 / 30:  # within one query of each other
        return "equal"
    return "HOG" if gain_hog > gain_ours else "ours"


EXERCISES = ExerciseSet(chapter=4, exercises=[
    Exercise(
        1, _tee_circle,
        "list the angles where the circle meets the arms, then join neighbouring crossings all the way round",
        (WrongAnswer((4, 4 * np.sqrt(2)), "the '+' of the toy (four arms)"),
         WrongAnswer((3, 2 * np.sqrt(2)), "the polygon left open (two sides of sqrt 2)"),
         WrongAnswer((3, 30 * (2 + 2 * np.sqrt(2))), "the sum in pixels, not normalised units")),
        context=("toy_circle",), rtol=0.02),
    Exercise(
        2, _tee_crossing_number,
        "walk round the 8 neighbours N, NE, E, ... in order, count the 0/1 changes, then halve",
        (WrongAnswer(6, "the changes not halved"),
         WrongAnswer(1, "Yokoi's connectivity number, another reading of eq. 8"),
         WrongAnswer(2, "a line pixel (two neighbours across)")),
        context=("toy_crossing_number",), rtol=0.0, atol=0.0),
    Exercise(
        3, _k8_against_k12,
        "compare the two settings query by query (McNemar, paired_comparison), with k_tried set to 8",
        (WrongAnswer(1.0, "the unchanged experiment: k = 12 against itself", unchanged_experiment=True),
         WrongAnswer(lambda namespace: _unpaired_p(namespace["rule_first20"]),
                     "the unpaired two-proportion test"),
         WrongAnswer(0.1, "the difference of the two rates, not a p-value")),
        context=("rule_first20",), rtol=0.05, experiment=True),
    Exercise(
        4, _who_gains,
        "run the study with translation switched off and subtract the 'all on' row for each descriptor",
        (WrongAnswer("equal", "the unchanged study (no gain for either)", unchanged_experiment=True),
         WrongAnswer("ours", "the other descriptor")),
        context=("nuisance",), choices=("ours", "HOG", "equal"), experiment=True),
])
