"""Tests of chapter 6's head sequence kinds (Li & Chaumette, AMDO 2004, Figs. 3-5): ground truth, seeds, bad kind."""

from __future__ import annotations

import numpy as np
import pytest

from amdo_lab import cue_fusion_pf as cf
from amdo_lab.cue_fusion_pf import data

SIZES = {"fusion": (164, 192, 256), "edges": (100, 192, 256), "twin": (80, 192, 256), "lighting": (100, 240, 320),
         "turn": (120, 192, 256)}


@pytest.fixture(scope="module")
def sequences():
    return {kind: cf.make_head_sequence(kind, rng=3) for kind in cf.SEQUENCE_KINDS}


@pytest.fixture(scope="module")
def cascade():
    return cf.load_or_train_cascade(rng=cf.CASCADE_SEED)


def pixel(sequence, t, dx=0.0, dy=0.0):
    """The RGB value at an offset (in head semi-axes) from the true centre of frame t."""
    cx, cy, a, b, _ = sequence.true_ellipses[t]
    return sequence.frames[t, int(round(cy + dy * b)), int(round(cx + dx * a))].astype(float)


@pytest.mark.parametrize("kind", cf.SEQUENCE_KINDS)
def test_every_kind_has_consistent_ground_truth(sequences, kind):
    sequence = sequences[kind]
    n_frames, height, width = SIZES[kind]
    assert sequence.frames.shape == (n_frames, height, width, 3) and sequence.frames.dtype == np.uint8
    assert sequence.truth.shape == (n_frames, 3) and sequence.true_ellipses.shape == (n_frames, 5)
    # segments are contiguous, in order, and cover every frame once
    bounds = list(sequence.segments.values())
    assert bounds[0][0] == 0 and bounds[-1][1] == n_frames
    assert all(stop == next_start for (_, stop), (next_start, _) in zip(bounds, bounds[1:]))
    # the ellipses are the truth's: centre, axes (1 + s) times the template, on the frame
    np.testing.assert_allclose(sequence.true_ellipses[:, :2], sequence.truth[:, :2])
    np.testing.assert_allclose(sequence.true_ellipses[:, 2:4], np.outer(1 + sequence.truth[:, 2], cf.HEAD_AXES))
    assert np.all((sequence.truth[:, 0] > 30) & (sequence.truth[:, 0] < width - 30))
    assert np.all((sequence.truth[:, 1] > 30) & (sequence.truth[:, 1] < height - 30))
    # a frontal face at frame 0: skin at the cheek (red above green above blue), where the truth says
    cheek = pixel(sequence, 0, 0.0, 0.25)
    assert cheek[0] > cheek[1] > cheek[2] and np.abs(cheek - data.SKIN).max() < 40
    assert sequence.oracle_log_likelihood(5, sequence.truth[5]) == 0.0


@pytest.mark.parametrize("kind", ["lighting", "turn"])
def test_new_kinds_are_seeded(kind):
    first, again = cf.make_head_sequence(kind, rng=7), cf.make_head_sequence(kind, rng=7)
    np.testing.assert_array_equal(first.frames, again.frames)
    np.testing.assert_array_equal(first.true_ellipses, again.true_ellipses)
    other = cf.make_head_sequence(kind, rng=8)
    assert not np.array_equal(first.truth, other.truth)


def test_unknown_kind_is_refused_by_name():
    with pytest.raises(ValueError, match="kind"):
        cf.make_head_sequence("walking", rng=0)
    with pytest.raises(ValueError, match="kind"):
        cf.make_head_sequence("", rng=0)


def test_lighting_kind_has_a_mild_then_a_strong_cast(sequences):
    sequence = sequences["lighting"]
    assert list(sequence.segments) == ["normal", "mild change", "strong change"]
    # the wall's red channel: gain 1 - 0.55 × (size of the change); the size is 0, 0.25, 1 on the three plateaus
    red = sequence.frames[:, :12, :, 0].mean(axis=(1, 2))
    np.testing.assert_allclose(red[40] / red[5], 1 - 0.55 * 0.25, atol=0.03)
    np.testing.assert_allclose(red[90] / red[5], 0.45, atol=0.03)
    weaker = cf.make_head_sequence("lighting", rng=3, cast_strength=0.0)
    np.testing.assert_array_equal(weaker.truth, sequence.truth)
    assert abs(weaker.frames[90, :12, :, 0].mean() / weaker.frames[5, :12, :, 0].mean() - 1) < 0.03


def test_turn_kind_shows_poses_a_tilt_and_the_back(sequences, cascade):
    sequence = sequences["turn"]
    assert list(sequence.segments) == ["frontal", "pose", "tilt", "turning away", "back"]
    angles = sequence.true_ellipses[:, 4]  # the ellipse's angle is the head's tilt, only in the tilt segment
    start, stop = sequence.segments["tilt"]
    assert np.all(angles[:start] == 0) and np.all(angles[stop:] == 0) and np.abs(angles).max() == pytest.approx(np.radians(15), rel=0.05)
    # the back: hair where the face was
    back = pixel(sequence, 100, 0.0, 0.25)
    assert np.abs(back - data.HAIR).max() < 40
    # the detector passes its stages on frontal and half-profile frames and none on the back
    likelihood = cf.StructureLikelihood(cf.ShapeSpace.from_ellipse(sequence.true_ellipses[0]), cascade)
    passed = np.array([1 - likelihood.distance(sequence.frames[t], sequence.truth[t][None])[0] for t in range(len(sequence.frames))])
    labels = sequence.segment_of_frames()
    assert passed[labels == "frontal"].mean() > 0.9 and passed[labels == "pose"].mean() > 0.8
    assert passed[labels == "back"].max() == 0.0


def test_fusion_kind_turns_its_back_and_jumps_in_their_own_segments(sequences):
    sequence = sequences["fusion"]
    start, stop = sequence.segments["turned away"]
    assert np.abs(pixel(sequence, 120, 0.0, 0.25) - data.HAIR).max() < 40   # the back of the head
    assert np.abs(pixel(sequence, start - 2, 0.0, 0.25) - data.SKIN).max() < 40   # the face before
    assert np.abs(pixel(sequence, stop + 2, 0.0, 0.25) - data.SKIN).max() < 40    # and after
    steps = np.linalg.norm(np.diff(sequence.truth[:, :2], axis=0), axis=1)
    big = np.flatnonzero(steps > 10) + 1
    assert len(big) == 6 and np.all(big >= sequence.segments["agile"][0])
