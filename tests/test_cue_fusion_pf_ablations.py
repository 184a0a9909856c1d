"""Tests of chapter 6's ablation options (Li & Chaumette, AMDO 2004): colour space, histogram grid, layered fusion."""

from __future__ import annotations

import numpy as np
import pytest

from amdo_lab import cue_fusion_pf as cf
from amdo_lab.cue_fusion_pf import likelihoods


@pytest.fixture(scope="module")
def sequence():
    return cf.make_head_sequence("fusion", rng=0)


def test_to_color_space_keeps_rgb_and_converts_to_full_range_hsv():
    frame = np.zeros((2, 3, 3), np.uint8)
    frame[0, 0] = (255, 0, 0)      # red: hue 0
    frame[0, 1] = (0, 255, 0)      # green: a third of the hue circle
    frame[0, 2] = (0, 0, 128)      # dark blue: two thirds, value 128
    assert likelihoods._to_color_space(frame, "rgb") is frame
    hsv = likelihoods._to_color_space(frame, "hsv")
    assert hsv.dtype == np.uint8 and hsv.shape == frame.shape
    np.testing.assert_allclose(hsv[0, :, 0], [0, 255 / 3, 2 * 255 / 3], atol=1)
    np.testing.assert_array_equal(hsv[0, :, 2], [255, 255, 128])
    assert hsv[1, 0, 1] == 0  # black has no saturation


def test_hsv_fast_path_equals_the_per_pixel_histogram_of_the_converted_frame(sequence):
    frame = sequence.frames[5]
    space = cf.ShapeSpace.from_ellipse([120.0, 90.0, 20.0, 26.0, 0.0])
    state = np.array([120.0, 90.0, 0.0])
    colour = cf.ColorLikelihood(space, sequence.frames[0], sequence.truth[0], stride=1.0, color_space="hsv")
    hsv = likelihoods._to_color_space(frame, "hsv")
    reference = cf.bhattacharyya(cf.kernel_histogram(hsv, space.ellipses(state)[0]), colour.target)
    assert colour.rho(frame, state[None])[0] == pytest.approx(reference, rel=1e-9)
    assert colour.rho(sequence.frames[0], sequence.truth[0][None])[0] > 0.85
    with pytest.raises(ValueError, match="color_space"):
        cf.ColorLikelihood(space, sequence.frames[0], sequence.truth[0], color_space="HSL")


def test_layered_fusion_with_one_cue_is_the_product_and_is_seeded(sequence):
    frames, init = sequence.frames[:12], sequence.true_ellipses[0]
    product = cf.track(frames, init, rng=2, cues=("color",), n_particles=80)
    layered = cf.track(frames, init, rng=2, cues=("color",), n_particles=80, fusion="layered")
    np.testing.assert_array_equal(product.states, layered.states)  # one cue: no layer before the last
    first = cf.track(frames, init, rng=3, cues=("color", "edge"), n_particles=80, fusion="layered")
    again = cf.track(frames, init, rng=3, cues=("color", "edge"), n_particles=80, fusion="layered")
    np.testing.assert_array_equal(first.states, again.states)
    other = cf.track(frames, init, rng=3, cues=("color", "edge"), n_particles=80)
    assert not np.array_equal(first.states, other.states)  # the extra resampling changes the run
    assert np.all(cf.ellipse_iou(first.ellipses, sequence.true_ellipses[:12]) > 0.5)
    with pytest.raises(ValueError, match="fusion"):
        cf.track(frames, init, rng=3, fusion="sum")


def test_full_grid_histogram_tracks_the_calm_frames(sequence):
    run = cf.track(sequence.frames[:10], sequence.true_ellipses[0], rng=4, cues=("color",), n_particles=80, stride=1.0)
    assert np.all(cf.ellipse_iou(run.ellipses, sequence.true_ellipses[:10]) > 0.5)
    with pytest.raises(ValueError, match="color_space"):
        cf.track(sequence.frames[:2], sequence.true_ellipses[0], rng=4, cues=("color",), color_space="lab")
