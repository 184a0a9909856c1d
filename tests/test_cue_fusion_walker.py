"""Chapter 6, the walker of Fig. 6: its seeded sequence, the similarity shape space (eqs. 2-3) and tracking it."""

from __future__ import annotations

import numpy as np
import pytest
from rejections import check_rejection, reject

from amdo_lab import cue_fusion_pf as cf
from amdo_lab.cue_fusion_pf import walker


@pytest.fixture(scope="module")
def sequence() -> cf.WalkerSequence:
    return cf.make_walker_sequence(rng=0)


# --- the similarity shape space -----------------------------------------------------------------

def turned(template: np.ndarray, scale: float, angle: float, shift) -> np.ndarray:
    """The template turned by ``angle``, scaled by ``scale`` about its mean, then shifted: written out by hand."""
    centred = template - template.mean(axis=0)
    rotation = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    return scale * centred @ rotation.T + np.asarray(shift)


def test_similarity_w_reproduces_a_turned_scaled_shifted_template_exactly():
    template = np.random.default_rng(0).normal(0.0, 20.0, (9, 2)) + [50.0, 80.0]
    space = cf.ShapeSpace(template, "similarity")
    scale, angle, shift = 1.3, 0.4, (120.0, -7.5)
    state = np.array([shift[0], shift[1], scale * np.cos(angle) - 1.0, scale * np.sin(angle)])
    expected = turned(template, scale, angle, shift)
    # eq. (2) as a matrix product with the four columns of W (eq. 3, right)
    w = space.shape_matrix()
    assert w.shape == (18, 4)
    stacked = w @ state + np.concatenate([space.template[:, 0], space.template[:, 1]])
    np.testing.assert_allclose(np.stack([stacked[:9], stacked[9:]], axis=1), expected, atol=1e-12)
    np.testing.assert_allclose(space.control_points(state)[0], expected, atol=1e-12)
    # and the least-squares fit recovers the state
    np.testing.assert_allclose(walker._fit_similarity(template, expected), state, atol=1e-12)
    k, rotation = space.similarity_parts(state)
    np.testing.assert_allclose(k, [scale])
    np.testing.assert_allclose(rotation[0], [[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]], atol=1e-12)


def test_similarity_ellipses_are_the_turned_ellipse():
    ellipse = np.array([100.0, 60.0, 20.0, 30.0, 0.3])
    space = cf.ShapeSpace.from_ellipse(ellipse, kind="similarity")
    scale, angle = 0.8, -0.5
    state = np.array([140.0, 70.0, scale * np.cos(angle) - 1.0, scale * np.sin(angle)])
    got = space.ellipses(state)[0]
    np.testing.assert_allclose(got, [140.0, 70.0, 16.0, 24.0, 0.3 + angle], atol=1e-9)
    # the spline of the state hugs that ellipse (the template fits its ellipse to a fraction of a pixel)
    curve = space.curve(state, 200)[0]
    c, s = np.cos(got[4]), np.sin(got[4])
    u = ((curve[:, 0] - got[0]) * c + (curve[:, 1] - got[1]) * s) / got[2]
    v = (-(curve[:, 0] - got[0]) * s + (curve[:, 1] - got[1]) * c) / got[3]
    np.testing.assert_allclose(np.hypot(u, v), 1.0, atol=0.02)


def test_translation_scale_space_is_unchanged_by_the_similarity_kind():
    space = cf.ShapeSpace.from_ellipse(np.array([100.0, 60.0, 20.0, 26.0, 0.0]))
    state = np.array([110.0, 65.0, 0.1])
    scale, rotation = space.similarity_parts(state)
    assert scale[0] == pytest.approx(1.1) and np.array_equal(rotation[0], np.eye(2))
    assert space.shape_matrix().shape[1] == 3


def test_edge_profiles_fast_path_equals_reference_in_the_similarity_space(sequence):
    space = sequence.shape_space()
    edge = cf.EdgeLikelihood(space, n_lines=70)
    states = sequence.truth[:4] + np.array([[0, 0, 0, 0], [3.0, -2.0, 0.05, 0.1], [-4.0, 1.0, -0.05, -0.2],
                                            [0.0, 5.0, 0.0, 0.3]])
    fast = edge.profiles(sequence.frames[0], states)
    reference = edge.profiles(sequence.frames[0], states, reference=True)
    np.testing.assert_allclose(fast, reference, atol=0.01)


# --- the sequence -------------------------------------------------------------------------------

def test_walker_sequence_is_seeded(sequence):
    again = cf.make_walker_sequence(rng=0)
    assert np.array_equal(again.frames, sequence.frames)
    assert np.array_equal(again.truth, sequence.truth)
    other = cf.make_walker_sequence(rng=1)
    assert not np.array_equal(other.frames[0], sequence.frames[0])


def test_walker_sequence_shape_and_segments(sequence):
    assert sequence.frames.shape == (130, 240, 640, 3) and sequence.frames.dtype == np.uint8
    assert sequence.truth.shape == (130, 4) and sequence.true_ellipses.shape == (130, 5)
    assert sequence.true_control_points.shape == (130, len(sequence.template), 2)
    start, stop = sequence.segments["clutter"]
    assert start <= 95 < stop
    assert list(sequence.segment_of_frames()[[0, 95, 129]]) == ["walking", "clutter", "after"]


def test_walker_ground_truth_is_consistent(sequence):
    space = sequence.shape_space()
    np.testing.assert_allclose(sequence.truth[0], [*sequence.template.mean(axis=0), 0.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(space.ellipses(sequence.truth), sequence.true_ellipses)
    np.testing.assert_allclose(walker._fit_similarity(sequence.template, sequence.true_control_points), sequence.truth)
    # the lens bends the outline a little: the best similarity is within 3 px of every control point
    residual = np.linalg.norm(space.control_points(sequence.truth) - sequence.true_control_points, axis=2)
    assert residual.max() < 3.0
    # the walker crosses the frame from left to right, and the lens makes it lean (rotation) near the sides
    assert sequence.truth[0, 0] < 120 and sequence.truth[-1, 0] > 520
    assert np.ptp(np.arctan2(sequence.truth[:, 3], 1.0 + sequence.truth[:, 2])) > 0.02
    # the face is where the truth says: skin-coloured pixels just below the top of the outline
    for t in (0, 60, 120):
        hips = (walker._undistort(sequence.true_control_points[t], 0.12) - walker.BODY_HEIGHT * walker._OUTLINE).mean(axis=0)
        face = walker._distort(hips + [0.0, -0.37 * walker.BODY_HEIGHT], 0.12)
        x, y = np.rint(face).astype(int)
        patch = sequence.frames[t, y - 1 : y + 2, x - 1 : x + 2].reshape(-1, 3).mean(axis=0)
        assert np.abs(patch - walker.SKIN).max() < 25, (t, patch)


def test_without_the_lens_the_truth_is_a_pure_translation():
    flat = cf.make_walker_sequence(rng=2, distortion=0.0, clutter_strength=0.0, noise_std=0.0)
    np.testing.assert_allclose(flat.truth[:, 2:], 0.0, atol=1e-9)
    np.testing.assert_allclose(flat.true_control_points - flat.true_control_points[:, :1] + flat.template[:1],
                               np.broadcast_to(flat.template, flat.true_control_points.shape), atol=1e-9)


def test_oracle_is_zero_at_the_truth_and_negative_elsewhere(sequence):
    values = sequence.oracle_log_likelihood(50, np.stack([sequence.truth[50], sequence.truth[50] + [4.0, 0, 0, 0]]))
    assert values[0] == 0.0 and values[1] == pytest.approx(-2.0)


def test_box_iou():
    square = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]])
    assert cf.box_iou(square, square) == 1.0
    assert cf.box_iou(square, square + [5.0, 0.0]) == pytest.approx(50.0 / 150.0)
    assert cf.box_iou(square, square + [20.0, 0.0]) == 0.0
    assert cf.box_iou(square[None], square[None, :3]).shape == (1,)


# --- tracking it ----------------------------------------------------------------------------------

def test_track_in_the_similarity_space_follows_the_walker(sequence):
    result = cf.track(sequence.frames[:12], sequence.template, rng=0, cues=("color", "edge"), bins=16, n_lines=70,
                      shape="similarity", n_particles=150)
    assert result.states.shape == (12, 4) and result.particles.shape == (12, 150, 4)
    iou = cf.box_iou(sequence.shape_space().control_points(result.states), sequence.true_control_points[:12])
    assert np.all(iou > 0.5)
    again = cf.track(sequence.frames[:12], sequence.template, rng=0, cues=("color", "edge"), bins=16, n_lines=70,
                     shape="similarity", n_particles=150)
    assert np.array_equal(again.states, result.states)


def test_track_mean_defaults_to_the_initial_state(sequence):
    frames = sequence.frames[:4]
    default = cf.track(frames, sequence.template, rng=3, shape="similarity", n_particles=40, n_lines=20, bins=16)
    explicit = cf.track(frames, sequence.template, rng=3, shape="similarity", n_particles=40, n_lines=20, bins=16,
                        mean=sequence.truth[0])
    elsewhere = cf.track(frames, sequence.template, rng=3, shape="similarity", n_particles=40, n_lines=20, bins=16,
                         mean=sequence.truth[0] + [300.0, 0.0, 0.0, 0.0])
    np.testing.assert_allclose(explicit.states, default.states)
    assert not np.allclose(elsewhere.states, default.states)


def test_oracle_tracks_the_walker_to_a_pixel(sequence):
    result = cf.track(sequence.frames, sequence.template, rng=0, cues=("oracle",), shape="similarity",
                      oracle=sequence.oracle_log_likelihood)
    assert np.median(np.linalg.norm(result.centers - sequence.truth[:, :2], axis=1)) < 1.5


def test_walker_calibration_distances_run_in_the_similarity_space(sequence):
    at_truth, at_prior = cf.calibration_distances([sequence], "color", rng=0, n_samples=20, frame_step=40,
                                                  shape="similarity", bins=16)
    assert at_truth.shape == (4,) and at_prior.shape == (4, 20)
    # 1 - ρ; the colour cue is weak on the walker (the clothes have the window's colours), so no ordering
    assert np.all((at_truth >= 0) & (at_truth <= 1)) and np.all((at_prior >= 0) & (at_prior <= 1))



def test_walker_sigma_is_what_the_calibration_gives_on_held_out_walker_seeds():
    """WALKER_SIGMAS is calibrate_sigma's choice on walker seeds 100-104, which neither the chapter nor the benchmark tracks."""
    sequences = [cf.make_walker_sequence(rng=seed) for seed in range(100, 105)]
    at_truth, at_prior = cf.calibration_distances(sequences, "color", rng=0, shape="similarity", bins=16)
    result = cf.calibrate_sigma(at_truth, at_prior)
    assert result.sigma == pytest.approx(cf.WALKER_SIGMAS["color"], rel=0.01)
    assert result.scores.max() > 0 > result.scores[0]
    # the walker's colours and 16^3 bins give a σ_c of its own, not the heads' one
    assert abs(result.sigma - cf.CALIBRATED_SIGMAS["color"]) > 0.2 * cf.CALIBRATED_SIGMAS["color"]

# --- rejections: the rules of the walker and its shape space, in one table -------------------
# The generic promises (NaN, empty or mis-shaped arrays, wrong types, out-of-range numbers, bad seeds,
# each named by argument) are tests/test_bad_input.py's, for every argument of the walker's entries in
# tests/bad_input_cases/cue_fusion_pf.py; this table holds what that test cannot know.

_FRAMES, _ELLIPSE = np.zeros((2, 20, 30, 3), np.uint8), np.array([15.0, 10.0, 4.0, 5.0, 0.0])

REJECTIONS = [
    # --- the sequence: the lens stays mild, the oracle knows its frames and its state size
    reject("make_walker_sequence distortion 0.9", lambda: cf.make_walker_sequence(rng=0, distortion=0.9),
           ValueError, r"distortion must be in \[0, 0.5\]"),
    reject("oracle head states", lambda sequence: sequence.oracle_log_likelihood(0, np.zeros(3)),
           ValueError, r"states must have shape \(4,\) or \(N, 4\)"),
    reject("oracle frame 500", lambda sequence: sequence.oracle_log_likelihood(500, np.zeros(4)),
           ValueError, "t must be at most 129"),
    # --- the similarity shape space (eqs. 2-3): a template with extent, outlines of its length, the named kinds
    reject("box_iou stacks that differ", lambda: cf.box_iou(np.zeros((3, 2)), np.zeros((2, 3, 2))),
           ValueError, r"first and second disagree: first has shape \(3, 2\), second \(2, 3, 2\)"),
    reject("ShapeSpace kind affine", lambda: cf.ShapeSpace(np.eye(3)[:, :2], "affine"),
           ValueError, "kind must be one of 'translation_scale', 'similarity'"),
    reject("ShapeSpace.from_ellipse kind affine",
           lambda: cf.ShapeSpace.from_ellipse(np.array([1.0, 1.0, 2.0, 3.0, 0.0]), kind="affine"),
           ValueError, "kind must be one of 'translation_scale', 'similarity'"),
    reject("similarity control_points of a head state",
           lambda: cf.ShapeSpace(np.eye(3)[:, :2], "similarity").control_points(np.zeros(3)),
           ValueError, r"states must have shape \(4,\) or \(N, 4\)"),
    # --- tracking: the named shape spaces, a spread per state entry of the chosen space
    reject("track shape affine", lambda: cf.track(_FRAMES, _ELLIPSE, rng=0, shape="affine"),
           ValueError, "shape must be one of 'translation_scale', 'similarity'"),
    reject("track similarity with a head's init_spread", lambda: cf.track(
        _FRAMES, _ELLIPSE, rng=0, shape="similarity", init_spread=(1.0, 1.0, 0.1)),
        ValueError, r"init_spread must have shape \(4,\)"),
    # --- the rng convention: errors start with "rng", TypeError for a non-seed, ValueError for a negative seed
    reject("make_walker_sequence rng 'zero'", lambda: cf.make_walker_sequence(rng="zero"), TypeError, "^rng must be"),
    reject("make_walker_sequence rng -1", lambda: cf.make_walker_sequence(rng=-1), ValueError, "^rng must be"),
]


@pytest.mark.parametrize(("call", "error", "message"), REJECTIONS)
def test_rejections(request, call, error, message):
    check_rejection(request, call, error, message)
