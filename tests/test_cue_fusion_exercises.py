"""Chapter 6's weighting-and-resampling step and its "implement it" exercise.

The step is the filter's own (steps 3 and 5 of Fig. 1); the exercise's recorded wrong functions
must each be told apart from it, and from one another, on the example case and the unseen ones.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from amdo_lab import cue_fusion_pf as cf
from amdo_lab.common.particles import normalised_weights
from amdo_lab.cue_fusion_pf.exercises import EXAMPLE_SEED, EXERCISES, resampling_case

UNSEEN = (61, 62, 63)  # the seeds the chapter's hidden test registers


def test_the_step_is_the_filters_weighting_and_resampling():
    logs = np.random.default_rng(0).normal(0.0, 3.0, (3, 50))
    expected = cf.systematic_resample(normalised_weights(logs.sum(axis=0)), 0.3)
    assert np.array_equal(cf.weigh_and_resample(logs, 0.3), expected)


def test_the_step_ignores_a_constant_added_to_a_cue():
    logs = np.random.default_rng(1).normal(0.0, 1.0, (2, 40))
    shifted = logs + np.array([[1200.0], [-900.0]])
    assert np.array_equal(cf.weigh_and_resample(logs, 0.7), cf.weigh_and_resample(shifted, 0.7))


def test_the_step_copies_each_particle_floor_or_ceil_of_n_w_times():
    logs = np.random.default_rng(2).normal(0.0, 1.0, (2, 80))
    weights = normalised_weights(logs.sum(axis=0))
    copies = np.bincount(cf.weigh_and_resample(logs, 0.5), minlength=80)
    assert np.all((copies >= np.floor(80 * weights)) & (copies <= np.ceil(80 * weights)))


@pytest.mark.parametrize("seed", (EXAMPLE_SEED, *UNSEEN))
def test_every_recorded_wrong_function_differs_from_the_step_and_the_others(seed):
    exercise = EXERCISES[6]
    case = resampling_case(seed)
    assert abs(case["cue_log_likelihoods"].sum(axis=0)).min() > 750  # exp of the sum alone over- or underflows
    want = exercise.reference(**case)
    outputs = [wrong.value(**case) for wrong in exercise.wrong_answers]
    assert not any(exercise.outputs_match(got, want) for got in outputs)
    assert not any(exercise.outputs_match(a, b) for a, b in itertools.combinations(outputs, 2))


def test_the_implement_it_verdicts():
    def by_hand(cue_log_likelihoods, u):
        fused = cue_log_likelihoods.sum(axis=0)
        weights = np.exp(fused - fused.max())
        weights /= weights.sum()
        pointers = (u + np.arange(len(weights))) / len(weights)
        return np.minimum(np.searchsorted(np.cumsum(weights), pointers, side="right"), len(weights) - 1)

    exercise = EXERCISES[6]
    assert EXERCISES.verdict(6, by_hand).startswith("recorded")  # the release: right on the example case
    for wrong in exercise.wrong_answers:
        assert EXERCISES.verdict(6, wrong.value) == f"not yet: {wrong.hint}"
