"""Tests of amdo_lab.cue_fusion_pf (Li & Chaumette, AMDO 2004): shape space, AR(2), cues, filter, peers."""

from __future__ import annotations

import numpy as np
import pytest

from amdo_lab import cue_fusion_pf as cf
from amdo_lab.common import make_rng
from amdo_lab.cue_fusion_pf import dynamics as dynamics_module, shape as shape_module
from rejections import check_rejection, reject


@pytest.fixture(scope="module")
def sequence():
    return cf.make_head_sequence("fusion", rng=0)


@pytest.fixture(scope="module")
def space(sequence):
    return cf.ShapeSpace.from_ellipse(sequence.true_ellipses[0])


# --- shape space, eqs. (1)-(3) -----------------------------------------------------------------

def test_bspline_basis_is_a_partition_of_unity():
    s = np.linspace(0, 7, 50, endpoint=False)
    np.testing.assert_allclose(shape_module._bspline_basis(s, 7).sum(axis=1), 1.0)
    np.testing.assert_allclose(shape_module._bspline_basis(s, 7, derivative=True).sum(axis=1), 0.0, atol=1e-12)
    # the derivative is the derivative: a finite difference agrees
    h = 1e-6
    numeric = (shape_module._bspline_basis(s + h, 7) - shape_module._bspline_basis(s - h, 7)) / (2 * h)
    np.testing.assert_allclose(shape_module._bspline_basis(s + 0.0, 7, derivative=True), numeric, atol=1e-5)


def test_template_spline_fits_its_ellipse_and_eq2_is_w_x_plus_template(space):
    ellipse = np.array([100.0, 80.0, 20.0, 26.0, 0.0])
    fitted = cf.ShapeSpace.from_ellipse(ellipse)
    curve = fitted.curve(np.array([100.0, 80.0, 0.0]), 200)[0]
    radius = np.sqrt(((curve[:, 0] - 100) / 20) ** 2 + ((curve[:, 1] - 80) / 26) ** 2)
    assert np.max(np.abs(radius - 1.0)) < 0.02
    state = np.array([10.0, -5.0, 0.2])
    stacked = fitted.shape_matrix() @ state + np.concatenate([fitted.template[:, 0], fitted.template[:, 1]])
    control = fitted.control_points(state)[0]
    np.testing.assert_allclose(control, np.stack([stacked[:12], stacked[12:]], axis=1))
    np.testing.assert_allclose(fitted.ellipses(state)[0], [10.0, -5.0, 24.0, 31.2, 0.0])
    # a general template's ellipse, from the moments of its curve, is close to the exact one
    general = cf.ShapeSpace(fitted.template)
    assert cf.ellipse_iou(general.template_ellipse, [0.0, 0.0, 20.0, 26.0, 0.0]) > 0.98
    points, normals = fitted.template_normals(40)
    np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0)
    assert np.all(np.sum(points * normals, axis=1) > 0)  # outward


# --- dynamics, eqs. (4)-(5) --------------------------------------------------------------------

def test_b0_is_the_unit_variance_gain_of_the_corrected_order():
    for beta in (0.5, 2.0, 10.0):
        a1, a0, b0 = cf.ar2_coefficients(beta, 0.0, 1 / 25)
        assert dynamics_module._ar2_stationary_variance(a0, a1, b0) == pytest.approx(1.0)
        assert dynamics_module._ar2_stationary_variance(a1, a0, b0) == np.inf  # the printed order explodes
    a1, a0, b0 = cf.ar2_coefficients(2.0, 0.0, 1 / 25)
    assert a1 == pytest.approx(-np.exp(-0.16)) and a0 == pytest.approx(2 * np.exp(-0.08))


def test_printed_eq4_is_unstable_and_the_corrected_one_is_stable():
    kwargs = dict(beta=[2.0], omega=[0.0], tau=1 / 25, stationary_std=[1.0], mean=[0.0])
    printed = cf.ARDynamics(**kwargs, printed_order=True, allow_unstable=True)
    assert printed.spectral_radius() == pytest.approx(1.85, abs=0.01)
    corrected = cf.ARDynamics(**kwargs)
    assert corrected.spectral_radius() == pytest.approx(np.exp(-0.08))
    # no noise, one unit step: the printed recursion grows by ~10^7 in 30 frames, the corrected settles
    for model, check in ((printed, lambda v: v > 1e7), (corrected, lambda v: v < 10.0)):
        before, previous = np.zeros((1, 1)), np.ones((1, 1))
        for _ in range(30):
            previous, before = model.propagate(previous, before, np.zeros((1, 1))), previous
        assert check(abs(previous[0, 0]))


def test_corrected_dynamics_reach_their_stationary_std():
    model = cf.ARDynamics([10.0], [0.0], 1 / 25, [3.0], [5.0])
    rng = make_rng(0)
    previous, before = np.full((4000, 1), 5.0), np.full((4000, 1), 5.0)
    for _ in range(150):
        previous, before = model.step(previous, before, rng=rng), previous
    assert previous.mean() == pytest.approx(5.0, abs=0.2)
    assert previous.std() == pytest.approx(3.0, rel=0.05)


def test_step_samples_the_prediction_of_eq16():
    # eq. (16) for a Gaussian posterior of (X_{k-1}, X_{k-2}) and the linear AR(2) is Gaussian with
    # mean X̄ + a0 (m1 - X̄) + a1 (m2 - X̄) and variance a0² v1 + a1² v2 + 2 a0 a1 c12 + (b0 σ)²
    model = cf.ARDynamics([2.0], [0.0], 1 / 25, [3.0], [1.0])
    rng = make_rng(5)
    previous = 4.0 + 2.0 * rng.standard_normal((200_000, 1))
    before = previous - 0.5 + 0.5 * rng.standard_normal((200_000, 1))  # correlated with X_{k-1}
    predicted = model.step(previous, before, rng=6)[:, 0]
    a0, a1, gain = model.first_lag[0], model.second_lag[0], model.step_std[0]
    covariance = np.cov(previous[:, 0], before[:, 0])
    mean = 1.0 + a0 * (previous.mean() - 1.0) + a1 * (before.mean() - 1.0)
    variance = a0**2 * covariance[0, 0] + a1**2 * covariance[1, 1] + 2 * a0 * a1 * covariance[0, 1] + gain**2
    assert predicted.mean() == pytest.approx(mean, abs=0.01)
    assert predicted.var() == pytest.approx(variance, rel=0.01)


# --- data and ellipse overlap ------------------------------------------------------------------

def test_head_sequence_layout(sequence):
    assert sequence.frames.shape == (164, 192, 256, 3) and sequence.frames.dtype == np.uint8
    assert sequence.truth.shape == (164, 3) and sequence.true_ellipses.shape == (164, 5)
    assert list(sequence.segments) == ["calm", "lighting", "distractor", "turned away", "agile"]
    assert sequence.segments["lighting"] == (29, 81)
    assert np.all(sequence.segment_of_frames() != None)  # noqa: E711  every frame has a segment
    assert np.all((sequence.truth[:, 0] > 30) & (sequence.truth[:, 0] < 226))
    oracle = sequence.oracle_log_likelihood(10, sequence.truth[10] + np.array([[0, 0, 0], [3, 0, 0]]))
    assert oracle[0] == 0.0 and oracle[1] < oracle[0]
    # the colour cast: the face's mean colour changes on the lighting frames
    cx, cy = sequence.truth[50, :2].astype(int)
    assert sequence.frames[50, cy, cx, 0] < 0.7 * sequence.frames[10, sequence.truth[10, 1].astype(int), sequence.truth[10, 0].astype(int), 0]


def test_weigh_particles_is_bayes_rule_with_the_fused_cues(sequence, space):
    colour = cf.ColorLikelihood(space, sequence.frames[0], sequence.truth[0], sigma=0.1)
    edge = cf.EdgeLikelihood(space, n_lines=20)
    particles = sequence.truth[12] + np.array([[0, 0, 0], [4, 0, 0.05], [-6, 3, 0], [0, 0, -0.95]])  # last: too small
    weights = cf.weigh_particles(sequence.frames[12], particles, {"color": colour, "edge": edge})
    log_likelihood = (colour.log_likelihood(sequence.frames[12], particles[:3])
                      + edge.log_likelihood(sequence.frames[12], particles[:3]))  # eq. (6)
    expected = np.exp(log_likelihood - log_likelihood.max())  # eq. (15): proportional to the likelihood
    np.testing.assert_allclose(weights[:3], expected / expected.sum(), rtol=1e-12)
    assert weights[3] == 0.0 and weights.sum() == pytest.approx(1.0)
    # far apart log-likelihoods (exp would underflow) still give weights: all on the best particle
    sharp = cf.ColorLikelihood(space, sequence.frames[0], sequence.truth[0], sigma=1e-3)
    weights = cf.weigh_particles(sequence.frames[12], particles[:3], {"color": sharp})
    assert np.isfinite(weights).all() and weights.max() == pytest.approx(1.0)


def test_ellipse_iou():
    circle = np.array([0.0, 0.0, 10.0, 10.0, 0.0])
    assert cf.ellipse_iou(circle, circle) == pytest.approx(1.0)
    assert cf.ellipse_iou(circle, circle + [50, 0, 0, 0, 0]) == 0.0
    assert cf.ellipse_iou(circle, [0, 0, 20, 20, 0], step=0.25) == pytest.approx(0.25, abs=0.01)
    # a rotated ellipse against its quarter-turned twin: the same shape
    assert cf.ellipse_iou([0, 0, 10, 5, 0], [0, 0, 5, 10, np.pi / 2]) == pytest.approx(1.0, abs=0.01)


# --- colour, eqs. (7)-(11) ----------------------------------------------------------------------

def test_fast_colour_path_equals_the_per_pixel_histogram(sequence):
    frame = sequence.frames[5]
    # integer centre and axes, scale 0: the points of the sample grid are the pixel centres
    space = cf.ShapeSpace.from_ellipse([120.0, 90.0, 20.0, 26.0, 0.0])
    state = np.array([120.0, 90.0, 0.0])
    colour = cf.ColorLikelihood(space, sequence.frames[0], sequence.truth[0], stride=1.0)
    reference = cf.bhattacharyya(cf.kernel_histogram(frame, space.ellipses(state)[0]), colour.target)
    assert colour.rho(frame, state[None])[0] == pytest.approx(reference, rel=1e-9)
    np.testing.assert_allclose(colour.target.sum(), 1.0)
    assert colour.rho(sequence.frames[0], sequence.truth[0][None])[0] > 0.85


# --- edges, eqs. (13)-(14) ----------------------------------------------------------------------

def test_eq13_matches_simulated_lines():
    """Lines with exactly one feature at z: their rate over exp(-λL) λ is P0 + P1 N(z; 0, σ_e²)/λ."""
    p0, density, sigma_e, half = 0.2, 0.05, np.sqrt(2.0), 12.0
    n_lines = 200_000
    lines = cf.simulate_measurement_lines(n_lines, half_length=half, p0=p0, clutter_density=density,
                                          sigma_e=sigma_e, rng=0)
    single = np.array([line[0] for line in lines if len(line) == 1])
    edges = np.arange(-6.0, 6.01, 1.5)
    counts, _ = np.histogram(single, edges)
    observed = counts / (n_lines * np.diff(edges)) / (np.exp(-density * 2 * half) * density)
    centres = 0.5 * (edges[1:] + edges[:-1])
    # the bin average of eq. (13), by fine quadrature
    fine = [np.mean([cf.edge_line_likelihood([z], p0, density, sigma_e) for z in np.linspace(lo, hi, 41)])
            for lo, hi in zip(edges[:-1], edges[1:])]
    np.testing.assert_allclose(observed, fine, rtol=0.08)
    assert observed[len(centres) // 2] > 5 * observed[0]  # peaked at the contour


def test_fast_edge_path_equals_the_numpy_reference(sequence, space):
    edge = cf.EdgeLikelihood(space)
    states = sequence.truth[5] + make_rng(1).normal(size=(50, 3)) * [5, 5, 0.03]
    fast = edge.log_likelihood(sequence.frames[5], states)
    reference = edge.log_likelihood(sequence.frames[5], states, reference=True)
    np.testing.assert_allclose(fast, reference, atol=0.05)
    # the truth beats a state 6 px away
    near = edge.log_likelihood(sequence.frames[5], np.stack([sequence.truth[5], sequence.truth[5] + [6, 0, 0]]))
    assert near[0] > near[1]


def test_edge_exponent_tempers_the_log_likelihood(sequence, space):
    """exponent α multiplies eq. (14)'s log (the product of the lines raised to α); track passes it through."""
    states = sequence.truth[5] + make_rng(2).normal(size=(20, 3)) * [5, 5, 0.03]
    full = cf.EdgeLikelihood(space).log_likelihood(sequence.frames[5], states)
    tempered = cf.EdgeLikelihood(space, exponent=0.1).log_likelihood(sequence.frames[5], states)
    np.testing.assert_allclose(tempered, 0.1 * full, rtol=1e-12)
    runs = [cf.track(sequence.frames[:4], sequence.true_ellipses[0], rng=3, cues=("edge",), edge_exponent=alpha)
            for alpha in (1.0, 0.1)]
    assert runs[1].ess.mean() > runs[0].ess.mean()  # a flatter likelihood keeps more particles


def test_printed_sigmas_make_the_fusion_edge_only(sequence, space):
    """Table 1's σ_c = 5: colour weights vary by at most ×1.02 while 40 edge lines vary by > 10^13."""
    states = cf.default_dynamics(sequence.truth[0]).step(np.repeat(sequence.truth[19][None], 300, 0),
                                                          np.repeat(sequence.truth[18][None], 300, 0), rng=2)
    colour = cf.ColorLikelihood(space, sequence.frames[0], sequence.truth[0], sigma=cf.PAPER_SIGMAS["color"])
    edge = cf.EdgeLikelihood(space)
    colour_log = colour.log_likelihood(sequence.frames[20], states)
    edge_log = edge.log_likelihood(sequence.frames[20], states)
    assert np.exp(np.ptp(colour_log)) <= np.exp(1 / 50) + 1e-12
    assert np.ptp(edge_log) / np.log(10) > 13
    fused = cf.fused_log_likelihood({"c": colour, "e": edge}, sequence.frames[20], states)
    np.testing.assert_allclose(fused, colour_log + edge_log)


@pytest.mark.parametrize("cue", ["color", "structure"])
def test_calibrated_sigma_is_what_the_calibration_gives(cue):
    sequences = [cf.make_head_sequence("fusion", rng=seed) for seed in range(100, 105)]
    at_truth, at_prior = cf.calibration_distances(sequences, cue, rng=0)
    result = cf.calibrate_sigma(at_truth, at_prior)
    assert result.sigma == pytest.approx(cf.CALIBRATED_SIGMAS[cue], rel=0.01)
    assert result.scores.max() > 0 > result.scores[0]


# --- the filter, Fig. 1 -------------------------------------------------------------------------

def test_systematic_resampling_copies_each_particle_floor_or_ceil_times():
    weights = make_rng(3).dirichlet(np.ones(20))
    counts = np.bincount(cf.systematic_resample(weights, 0.37), minlength=20)
    assert counts.sum() == 20
    assert np.all(counts >= np.floor(20 * weights)) and np.all(counts <= np.ceil(20 * weights))


def test_track_follows_the_head_and_is_seeded(sequence):
    frames = sequence.frames[:30]
    first = cf.track(frames, sequence.true_ellipses[0], rng=4, n_particles=120)
    second = cf.track(frames, sequence.true_ellipses[0], rng=4, n_particles=120)
    np.testing.assert_array_equal(first.states, second.states)
    assert first.ellipses.shape == (30, 5) and first.centers.shape == (30, 2) and first.ess.shape == (30,)
    assert np.all(cf.ellipse_iou(first.ellipses, sequence.true_ellipses[:30]) > 0.5)
    assert first.seconds > 0 and np.all(first.ess >= 1)
    oracle = cf.track(frames, sequence.true_ellipses[0], rng=4, cues=("oracle",), oracle=sequence.oracle_log_likelihood)
    assert np.median(np.linalg.norm(oracle.centers - sequence.truth[:30, :2], axis=1)) < 2.0


def test_the_default_spreads_pass_their_overflow_bounds():
    from amdo_lab.cue_fusion_pf import tracker

    for name in ("stationary_std", "init_spread"):
        default = tracker.TRACK_DEFAULTS[name]
        np.testing.assert_array_equal(tracker._check_state_spread(default, name, state_dim=3), default)


def test_camshift_peer_tracks_the_calm_frames(sequence):
    result = cf.track_camshift(sequence.frames[:25], sequence.true_ellipses[0])
    assert np.mean(cf.ellipse_iou(result.ellipses, sequence.true_ellipses[:25]) > 0.5) > 0.9


# --- structure, eq. (12) ------------------------------------------------------------------------

def test_integral_image_and_haar_features_match_scikit_image():
    from skimage.feature import haar_like_feature
    from skimage.transform import integral_image as skimage_integral

    from amdo_lab.cue_fusion_pf import structure as st

    image = make_rng(5).normal(size=(20, 16))
    integral = st._integral_image(image)
    assert integral.shape == (21, 17)
    np.testing.assert_allclose(integral[1:, 1:], skimage_integral(image))
    assert integral[7, 9] == pytest.approx(image[:7, :9].sum())
    every = st._all_haar_features(16, 20)
    from skimage.feature import haar_like_feature_coord
    for kind in ("type-2-x", "type-2-y", "type-3-x", "type-3-y", "type-4"):
        coords, types = haar_like_feature_coord(16, 20, kind)
        pick = np.arange(0, len(coords), 37)  # every 37th feature of the kind, in scikit-image's order
        theirs = haar_like_feature(skimage_integral(image), 0, 0, 16, 20, feature_type=types[pick],
                                   feature_coord=coords[pick])
        mine = every.subset(np.flatnonzero(every.types == kind)[pick]).values(integral[None])[0]
        np.testing.assert_allclose(mine, theirs, atol=1e-9)
    subset = st._sample_haar_features(every, 400, make_rng(6))
    assert len(subset) == 400 and len(st._all_haar_features(16, 20)) == len(every)  # listing draws nothing
    assert np.all(np.isin(subset.types, every.types))
    again = st._sample_haar_features(every, 400, make_rng(6))
    assert all(np.array_equal(getattr(subset, name), getattr(again, name)) for name in ("rows0", "cols0", "weights"))


@pytest.fixture(scope="module")
def cascade():
    from amdo_lab.cue_fusion_pf import structure as st
    return st.load_or_train_cascade(rng=st.CASCADE_SEED)


def test_cascade_accepts_held_out_heads_and_rejects_background(cascade):
    from amdo_lab.cue_fusion_pf import structure as st

    held_out = st.make_training_set(rng=99, n_scenes=10)
    for view, patches in held_out.positives.items():
        assert np.mean(cascade.stages_passed_patches(patches) == cascade.n_stages) >= 0.85, view
    assert np.mean(cascade.stages_passed_patches(held_out.negatives) == cascade.n_stages) <= 0.01


def test_structure_likelihood_peaks_at_the_head(sequence, space, cascade):
    from amdo_lab.cue_fusion_pf import structure as st

    likelihood = st.StructureLikelihood(space, cascade)
    states = np.stack([sequence.truth[40], sequence.truth[40] + [15, 0, 0]])  # on the lighting frames
    distance = likelihood.distance(sequence.frames[40], states)
    assert distance[0] == 0.0 and distance[1] > 0.5


def test_mil_peer_tracks_the_calm_frames(sequence):
    # MIL's samples come from a generator OpenCV does not let us seed: a loose check on a few frames
    result = cf.track_mil(sequence.frames[:10], sequence.true_ellipses[0])
    assert result.ellipses.shape == (10, 5)
    assert np.all(cf.ellipse_iou(result.ellipses, sequence.true_ellipses[:10]) > 0.5)


def test_pfilter_peer_runs_our_likelihood(sequence):
    pytest.importorskip("pfilter")
    first = cf.track_pfilter(sequence.frames[:15], sequence.true_ellipses[0], rng=3, n_particles=100)
    second = cf.track_pfilter(sequence.frames[:15], sequence.true_ellipses[0], rng=3, n_particles=100)
    np.testing.assert_array_equal(first.states, second.states)  # seeded through numpy's global generator
    assert np.all(cf.ellipse_iou(first.ellipses, sequence.true_ellipses[:15]) > 0.5)


def test_cast_strength_scales_the_lighting_change():
    mild = cf.make_head_sequence("fusion", rng=0, cast_strength=0.0)
    full = cf.make_head_sequence("fusion", rng=0)
    np.testing.assert_array_equal(mild.truth, full.truth)
    assert abs(int(mild.frames[50, 5, 5, 0]) - int(mild.frames[10, 5, 5, 0])) < 30
    assert full.frames[50, 5, 5, 0] < 0.7 * full.frames[10, 5, 5, 0]


def test_track_accepts_control_points(sequence, space):
    control = space.control_points(sequence.truth[0])[0]
    result = cf.track(sequence.frames[:5], control, rng=0, cues=("color",), n_particles=50)
    assert np.all(cf.ellipse_iou(result.ellipses, sequence.true_ellipses[:5]) > 0.6)


def test_track_with_printed_eq4_diverges(sequence):
    """The filter with eq. (4) as printed throws its particles away within about a second of video."""
    with pytest.raises(RuntimeError, match="diverged"):
        cf.track(sequence.frames[:60], sequence.true_ellipses[0], rng=1, cues=("color",), n_particles=50,
                 printed_order=True)


def test_colour_distance_and_likelihood_are_eqs_9_and_11(sequence, space):
    colour = cf.ColorLikelihood(space, sequence.frames[0], sequence.truth[0], sigma=0.1)
    states = sequence.truth[5] + make_rng(7).normal(size=(20, 3)) * [6, 6, 0.05]
    rho = colour.rho(sequence.frames[5], states)
    np.testing.assert_allclose(colour.distance(sequence.frames[5], states), 1.0 - rho)  # eq. (9), squared
    expected = np.log(np.exp(-(1.0 - rho) / (2 * 0.1**2)) / (np.sqrt(2 * np.pi) * 0.1))  # eq. (11)
    np.testing.assert_allclose(colour.log_likelihood(sequence.frames[5], states), expected, rtol=1e-12)
    assert np.ptp(rho) > 0.01  # the states differ: not a constant check


def test_structure_likelihood_is_eq12_of_the_stages_passed(sequence, space, cascade):
    from amdo_lab.cue_fusion_pf import structure as st

    likelihood = st.StructureLikelihood(space, cascade, sigma=0.5)
    states = np.stack([sequence.truth[40], sequence.truth[40] + [15, 0, 0], sequence.truth[40] + [0, 40, 0]])
    passed = cascade._stages_passed(sequence.frames[40], likelihood.boxes(states))
    expected = -(1.0 - passed / cascade.n_stages) / (2 * 0.5**2) - np.log(np.sqrt(2 * np.pi) * 0.5)  # eq. (12)
    np.testing.assert_allclose(likelihood.log_likelihood(sequence.frames[40], states), expected, rtol=1e-12)
    assert len(set(passed.tolist())) > 1


# --- rejections: the rules of the method, in one table ------------------------------------------
# The generic promises (NaN, inf, 1e308, empty or mis-shaped arrays, wrong types, zero or negative
# where a positive number is due, probabilities outside [0, 1], bad seeds, each named by argument) are
# tests/test_bad_input.py's, for every argument listed in tests/bad_input_cases/cue_fusion_pf.py; this
# table holds what that test cannot know. A row's lambda names the fixtures it needs.

def _track(sequence, **change):
    """cf.track on three frames of the head sequence, with ``change`` to its arguments."""
    arguments = dict(frames=sequence.frames[:3], init=sequence.true_ellipses[0], rng=0, n_particles=10) | change
    return cf.track(**arguments)


def _colour(sequence, space, **change):
    return cf.ColorLikelihood(space, sequence.frames[0], sequence.truth[0], **change)


REJECTIONS = [
    # --- shape space, eqs. (1)-(3)
    reject("from_ellipse 2 control points", lambda: cf.ShapeSpace.from_ellipse([0, 0, 1, 2, 0], n_control=2), ValueError,
           "n_control"),
    reject("from_ellipse negative axis", lambda: cf.ShapeSpace.from_ellipse([0, 0, -1, 2, 0]), ValueError, "axes"),
    reject("ellipses overflowing scale", lambda space: space.ellipses([0.0, 0.0, 2e6]), ValueError, "states"),
    # --- dynamics, eqs. (4)-(5)
    reject("ARDynamics printed order unstable", lambda: cf.ARDynamics(
        beta=[2.0], omega=[0.0], tau=1 / 25, stationary_std=[1.0], mean=[0.0], printed_order=True), ValueError, "unstable"),
    reject("ARDynamics negative beta", lambda: cf.ARDynamics([-1.0], [0.0], 0.04, [1.0], [0.0]), ValueError, "beta"),
    reject("ARDynamics zero stationary_std", lambda: cf.ARDynamics([1.0], [0.0], 0.04, [0.0], [0.0]),
           ValueError, "stationary_std"),
    # --- data and ellipse overlap
    reject("make_head_sequence kind walker", lambda: cf.make_head_sequence("walker", rng=0), ValueError, "kind"),
    reject("ellipse_iou 2 against 3", lambda: cf.ellipse_iou(np.zeros((2, 5)) + 1, np.zeros((3, 5)) + 1),
           ValueError, "shape"),
    # --- colour, eqs. (7)-(11)
    reject("ColorLikelihood 24 bins", lambda sequence, space: _colour(sequence, space, bins=24), ValueError, "bins"),
    reject("ColorLikelihood grey reference_frame",
           lambda sequence, space: cf.ColorLikelihood(space, sequence.frames[0, :, :, 0], sequence.truth[0]),
           ValueError, "reference_frame"),
    reject("ColorLikelihood reference_state of 2", lambda sequence, space: cf.ColorLikelihood(
        space, sequence.frames[0], sequence.truth[0, :2]), ValueError, "reference_state"),
    # no sample point left inside the 20 x 26 px ellipse
    reject("ColorLikelihood stride 60", lambda sequence, space: _colour(sequence, space, stride=60.0), ValueError, "stride"),
    # σ squared underflows to 0 (-inf weights)
    reject("ColorLikelihood sigma 1e-200", lambda sequence, space: _colour(sequence, space, sigma=1e-200),
           ValueError, "sigma"),
    # --- edges, eqs. (13)-(14)
    reject("EdgeLikelihood p0 0", lambda space: cf.EdgeLikelihood(space, p0=0.0), ValueError, "p0"),
    reject("EdgeLikelihood p0 1", lambda space: cf.EdgeLikelihood(space, p0=1.0), ValueError, "p0"),
    # α = 0 switches the cue off, α > 1 sharpens the product beyond eq. (14)
    reject("EdgeLikelihood exponent 0", lambda space: cf.EdgeLikelihood(space, exponent=0.0), ValueError, "exponent"),
    reject("EdgeLikelihood exponent 2", lambda space: cf.EdgeLikelihood(space, exponent=2.0), ValueError, "exponent"),
    reject("track edge_exponent 0", lambda sequence: cf.track(sequence.frames[:2], sequence.true_ellipses[0], rng=0,
                                                              cues=("edge",), edge_exponent=0.0), ValueError, "exponent"),
    # above any grey-level gradient: no feature, ever
    reject("EdgeLikelihood threshold 300", lambda space: cf.EdgeLikelihood(space, threshold=300.0), ValueError, "threshold"),
    reject("simulate_measurement_lines clutter_density 2", lambda: cf.simulate_measurement_lines(
        3, half_length=6.0, p0=0.2, clutter_density=2.0, sigma_e=1.5, rng=0), ValueError, "clutter_density"),
    reject("edge_line_likelihood sigma_e 2e6", lambda: cf.edge_line_likelihood([0.5], 0.2, 0.1, 2e6), ValueError, "sigma_e"),
    reject("edge_line_likelihood offset 2e6", lambda: cf.edge_line_likelihood([2e6], 0.2, 0.1, 1.5), ValueError, "offsets"),
    # --- structure, eq. (12)
    # --- calibration
    reject("calibrate_sigma negative grid", lambda: cf.calibrate_sigma([0.1], [[0.2, 0.3]], grid=[0.1, -1.0]),
           ValueError, "grid"),
    reject("calibrate_sigma grid 1e-200", lambda: cf.calibrate_sigma([0.1], [[0.2, 0.3]], grid=[1e-200]),
           ValueError, "grid"),
    # --- the filter of Fig. 1
    reject("track init with a zero axis", lambda sequence: _track(sequence, init=sequence.true_ellipses[0] * [1, 1, 0, 1, 1]),
           ValueError, "init"),
    reject("track init off the frame", lambda sequence: _track(sequence, init=sequence.true_ellipses[0] + [500, 0, 0, 0, 0]),
           ValueError, "init"),
    reject("track init one column of control points", lambda sequence, space: _track(
        sequence, init=space.control_points(sequence.truth[0])[0][:, :1]), ValueError, "init"),
    reject("track one particle", lambda sequence: _track(sequence, n_particles=1), ValueError, "n_particles"),
    reject("track cue colour", lambda sequence: _track(sequence, cues=("colour",)), ValueError, "cues holds unknown"),
    reject("track no cue", lambda sequence: _track(sequence, cues=()), ValueError, "cues must hold at least one"),
    reject("track a cue twice", lambda sequence: _track(sequence, cues=("color", "color")), ValueError, "cues must not repeat"),
    reject("track sigma_c 0", lambda sequence: _track(sequence, sigmas={"color": 0.0}), ValueError, "sigmas"),
    reject("track sigma_c 1e308", lambda sequence: _track(sequence, sigmas={"color": 1e308}), ValueError, r"sigmas\['color'\]"),
    reject("track sigma_c 1e-200", lambda sequence: _track(sequence, sigmas={"color": 1e-200}), ValueError, r"sigmas\['color'\]"),
    reject("track oracle cue without oracle", lambda sequence: _track(sequence, cues=("oracle",)), ValueError, "oracle"),
    reject("track 24 bins", lambda sequence: _track(sequence, bins=24), ValueError, "bins"),
    reject("track unknown parameter", lambda sequence: _track(sequence, particles=10), TypeError, "unknown"),
    reject("track int16 frames", lambda sequence: _track(sequence, frames=sequence.frames[:3].astype(np.int16)),
           TypeError, "frames"),
    # a scale spread of 11: no particle of a plausible size
    reject("track stationary_std scale 11", lambda sequence: _track(sequence, stationary_std=(2.0, 2.0, 11.0)),
           ValueError, "stationary_std"),
    reject("track init_spread scale 11", lambda sequence: _track(sequence, init_spread=(2.0, 2.0, 11.0)),
           ValueError, "init_spread"),
    # no damping: a random walk, unstable
    reject("track beta 0", lambda sequence: _track(sequence, beta=(2.0, 2.0, 0.0)), ValueError, "beta"),
    # --- peers
    reject("track_camshift init with a zero axis", lambda sequence: cf.track_camshift(sequence.frames[:2], [10, 10, 0, 5, 0]),
           ValueError, "init"),
    reject("track_camshift init axis 2e6", lambda sequence: cf.track_camshift(
        sequence.frames[:2], sequence.true_ellipses[0] + [0, 0, 0, 0, 2e6]), ValueError, "init"),
    reject("track_mil init negative axis", lambda sequence: cf.track_mil(sequence.frames[:2], [10, 10, 5, -1, 0]),
           ValueError, "init"),
]


@pytest.mark.parametrize(("call", "error", "message"), REJECTIONS)
def test_rejections(request, call, error, message):
    check_rejection(request, call, error, message)
