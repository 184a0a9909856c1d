"""Tests for Chapter 1 (amdo_lab.em_articulated): Dewaele et al., ECCV 2006."""


from dataclasses import replace

import numpy as np
import pytest
from rejections import check_rejection, reject
from scipy.special import logsumexp

from amdo_lab.common import make_rng
from amdo_lab.em_articulated import (
    OUR_SETTINGS,
    PAPER_C,
    HandModel,
    TextureBinding,
    TrialSummary,
    e_step_reference,
    e_step_statistics,
    m_step_targets,
    robust_log_likelihood,
    register_em_reference,
    climb_objective,
    EMSettings,
    gauss_newton_step,
    fit_known_correspondences,
    fit_surface,
    make_skin_texture,
    objective_check,
    joint_rmse_deg,
    make_registration_problem,
    make_tracking_sequence,
    noise_floor_trials,
    perturb_pose,
    random_pose,
    refine_digits,
    register_em,
    run_registration_trials,
    register_softassign,
    track,
)
from amdo_lab.em_articulated.digits import digit_starts
from amdo_lab.em_articulated.estep import robust_log_likelihood_reference
from amdo_lab.em_articulated.hand import DIGIT_DOFS


@pytest.fixture(scope="module")
def hand():
    return HandModel()


def test_kinematics_counts_and_limits(hand):
    assert hand.n_dof == 27 and hand.n_parts == 16
    limits = hand.joint_limits()
    assert limits.shape == (27, 2) and np.all(limits[:, 0] < limits[:, 1])
    rest = hand.rest_pose()
    assert np.all((rest >= limits[:, 0]) & (rest <= limits[:, 1]))
    frames = hand.part_transforms(rest)
    assert frames.shape == (16, 4, 4)
    rotations = frames[:, :3, :3]
    np.testing.assert_allclose(rotations @ np.swapaxes(rotations, 1, 2), np.broadcast_to(np.eye(3), (16, 3, 3)), atol=1e-12)


def test_palm_translation_moves_every_part(hand):
    theta = hand.rest_pose()
    shifted = theta.copy()
    shifted[:3] += [10.0, -5.0, 2.0]
    delta = hand.part_transforms(shifted)[:, :3, 3] - hand.part_transforms(theta)[:, :3, 3]
    np.testing.assert_allclose(delta, np.broadcast_to([10.0, -5.0, 2.0], (16, 3)), atol=1e-12)


def test_finger_flexion_moves_only_its_chain(hand):
    theta = hand.rest_pose()
    bent = theta.copy()
    bent[12] += 0.5  # index knuckle flexion
    moved = np.any(np.abs(hand.part_transforms(bent) - hand.part_transforms(theta)) > 1e-9, axis=(1, 2))
    assert moved.tolist() == [False, False, False, False, True, True, True] + [False] * 9


def test_surface_distance_on_sampled_surface_and_sign(hand):
    theta = hand.rest_pose()
    points = hand.sample_surface(theta, 300, rng=make_rng(1))
    assert points.shape == (300, 3)
    assert np.max(np.abs(hand.surface_distance(points, theta))) < 0.2
    normals = hand.surface_normals(points, theta)
    assert np.mean(hand.surface_distance(points + 3 * normals, theta) > 1.0) > 0.95
    assert np.mean(hand.surface_distance(points - 2 * normals, theta) < 0.0) > 0.95


def test_neighbour_rule_prevents_gluing(hand):
    """Between two touching fingers the plain sum of fields glues them; the neighbour rule does not."""
    theta = hand.rest_pose()
    frames = hand.part_transforms(theta)
    gap = 0.5 * (frames[4, :3, 3] + frames[7, :3, 3]) + np.array([0.0, 15.0, 0.0])  # index/middle gap
    plain = hand.surface_distance(gap[None], theta, neighbour_rule=False)[0]
    rule = hand.surface_distance(gap[None], theta)[0]
    assert rule > plain


def test_move_texture_identity_and_rigid_limit(hand):
    theta = hand.rest_pose()
    points = hand.sample_surface(theta, 200, rng=make_rng(2))
    np.testing.assert_allclose(hand.move_texture(points, theta, theta), points, atol=1e-10)
    moved = theta.copy()
    moved[:3] += 7.0
    np.testing.assert_allclose(hand.move_texture(points, theta, moved), points + 7.0, atol=1e-10)


def test_bending_texture_a_controls_stickiness(hand):
    """Eq. (3): with a = 10 points near a joint follow one part more rigidly than with a = 2."""
    theta = hand.rest_pose()
    points = hand.sample_surface(theta, 400, rng=make_rng(3))
    binding_2 = hand.texture_binding(points, theta, a=2.0)
    binding_10 = hand.texture_binding(points, theta, a=10.0)
    assert np.all(binding_10.weight_p >= binding_2.weight_p - 1e-12)
    assert np.mean(binding_10.weight_p > 0.99) > np.mean(binding_2.weight_p > 0.99)


def test_analytic_jacobian_matches_finite_differences(hand):
    rng = make_rng(4)
    theta = random_pose(hand, rng=rng)
    points = hand.sample_surface(theta, 150, rng=rng)
    binding = hand.texture_binding(points, theta)
    theta_eval = perturb_pose(hand, theta, 10.0, rng=rng)
    _, jac = hand.texture_jacobian(binding, theta_eval)
    eps = 1e-6
    numeric = np.stack([(hand.transform_texture(binding, theta_eval + eps * e)
                         - hand.transform_texture(binding, theta_eval - eps * e)) / (2 * eps)
                        for e in np.eye(27)], axis=-1)
    np.testing.assert_allclose(jac, numeric, atol=1e-5)


def test_e_step_log_domain_far_points_and_single_match():
    model = np.array([[0.0, 0.0, 0.0], [100.0, 0.0, 0.0]])
    data = np.array([[0.0, 0.0, 0.0], [1e6, 0.0, 0.0]])
    weights, weighted, inlier, energy = e_step_statistics(model, data, 1.0, np.log(PAPER_C))
    # a single exact match: alpha = 1 / (1 + c), eq. (17)
    assert inlier[0] == pytest.approx(1.0 / (1.0 + PAPER_C))
    assert inlier[0] == pytest.approx(0.21, abs=0.01)
    assert inlier[1] == 0.0 and np.all(np.isfinite(weighted)) and np.isfinite(energy)


@pytest.mark.parametrize("precision, rtol", [("double", 1e-10), ("single", 2e-6)])
def test_e_step_chunking_matches_dense(precision, rtol):
    rng = make_rng(5)
    model = rng.normal(size=(40, 3)) * 10
    data = rng.normal(size=(70, 3)) * 10
    dense = e_step_statistics(model, data, 3.0, 0.5, chunk=1000, precision=precision)
    chunked = e_step_statistics(model, data, 3.0, 0.5, chunk=7, precision=precision)
    for a, b in zip(dense, chunked):
        np.testing.assert_allclose(a, b, rtol=rtol, atol=rtol * np.abs(a).max())
    sq = np.sum((model[:, None] - data[None]) ** 2, axis=2)
    kernel = np.exp(-sq / 18.0)
    alpha = kernel / (kernel.sum(axis=0) + np.exp(0.5))
    np.testing.assert_allclose(dense[2], alpha.sum(axis=0), rtol=rtol)


def test_e_step_without_outlier_class():
    # log c = -inf (c = 0): every data point is fully assigned to the texture, however far it is
    weights, _, inlier, _ = e_step_statistics(np.zeros((2, 3)), np.array([[0.0, 0, 0], [500.0, 0, 0]]), 1.0, -np.inf)
    np.testing.assert_allclose(inlier, 1.0)
    np.testing.assert_allclose(weights, 1.0)


def test_register_em_exact_correspondences_converges(hand):
    rng = make_rng(6)
    theta_true = random_pose(hand, rng=rng)
    theta_init = perturb_pose(hand, theta_true, 10.0, rng=rng)
    model = hand.sample_surface(theta_init, 400, rng=rng)
    data = hand.transform_texture(hand.texture_binding(model, theta_init), theta_true)
    result = register_em(model, data, hand, theta_init, settings=EMSettings(sigma_max=10.0, sigma_min=1.0, max_iter=4))
    assert joint_rmse_deg(result.theta, theta_true) < 1.0
    assert result.history.shape[1] == 2 and result.history[-1, 0] == pytest.approx(1.0)
    limits = hand.joint_limits()
    assert np.all((result.theta >= limits[:, 0]) & (result.theta <= limits[:, 1]))


def test_register_em_inlier_prob_separates_outliers(hand):
    problem = make_registration_problem(hand, rng=7, joint_error_deg=5.0, noise_mm=1.0, outlier_ratio=1.0,
                                        n_model=300, n_data=300)
    result = register_em(problem.model_points, problem.data_points, hand, problem.theta_init,
                         settings=EMSettings(sigma_max=15.0, sigma_min=3.0))
    assert result.inlier_prob.shape == (len(problem.data_points),)
    assert np.mean(result.inlier_prob[~problem.is_outlier]) > 3 * np.mean(result.inlier_prob[problem.is_outlier])


def test_fit_surface_reduces_distance(hand):
    rng = make_rng(8)
    theta_true = random_pose(hand, rng=rng)
    data = hand.sample_surface(theta_true, 300, rng=rng)
    start = perturb_pose(hand, theta_true, 4.0, rng=rng, palm_rotation_deg=1.0, palm_translation_mm=1.0)
    before = np.sqrt(np.mean(hand.surface_distance(data, start) ** 2))
    result = fit_surface(data, hand, start, max_iter=3)
    assert result.rms_distance < 0.5 * before


def test_softassign_slack_extremes(hand):
    problem = make_registration_problem(hand, rng=9, joint_error_deg=5.0, noise_mm=1.0, outlier_ratio=0.5,
                                        n_model=150, n_data=150)
    args = (problem.model_points, problem.data_points, hand, problem.theta_init, 10.0, 3.0)
    high = register_softassign(*args, slack=1e3, n_levels=2, n_iter=1)
    low = register_softassign(*args, slack=1e-8, n_levels=2, n_iter=1)
    # too high a slack: everything is an outlier; too low: every model point gets matched
    assert np.mean(high.inlier_prob) < 0.2
    assert low.inlier_prob.sum() > 0.9 * len(problem.model_points)


def test_tracking_sequence_generator(hand):
    seq = make_tracking_sequence(hand, rng=10, n_frames=3, n_features=600, n_clutter=60)
    assert seq.poses.shape == (3, 27) and len(seq.frames) == 3
    n_surface_points = [int((~mask).sum()) for mask in seq.is_outlier]
    assert all(150 < n < 0.8 * 600 for n in n_surface_points)  # only the camera-facing side, 80 % detected


def test_digit_clearance_separates_rest_from_crossed_fingers(hand):
    assert hand.digit_clearance(hand.rest_pose()) > 0
    crossed = hand.rest_pose()
    crossed[11], crossed[15] = np.radians(20), np.radians(-20)  # index and middle turn into each other
    assert hand.digit_clearance(crossed) < -5


def test_registration_problems_never_start_with_crossed_fingers(hand):
    from amdo_lab.em_articulated.data import MIN_DIGIT_CLEARANCE_MM
    for seed in range(3):
        problem = make_registration_problem(hand, rng=seed, joint_error_deg=20.0, n_model=20, n_data=20)
        assert hand.digit_clearance(problem.theta_true) >= MIN_DIGIT_CLEARANCE_MM
        assert hand.digit_clearance(problem.theta_init) >= MIN_DIGIT_CLEARANCE_MM
        assert joint_rmse_deg(problem.theta_init, problem.theta_true) > 15.0


def test_debiased_targets_keep_a_perfect_fit_at_large_sigma(hand):
    """Data that coincide with the texture: the paper's blurred targets G_i move the hand at
    σ = 20 mm (fingers curl towards the middle), the bias-corrected ones leave it in place."""
    rng = make_rng(21)
    theta = random_pose(hand, rng=rng)
    texture = hand.sample_surface(theta, 400, rng=rng)
    paper_settings = EMSettings(sigma_max=20.0, sigma_min=19.0, n_levels=1, max_iter=5)
    paper = register_em(texture, texture, hand, theta, settings=paper_settings)
    ours = register_em(texture, texture, hand, theta, settings=replace(paper_settings, targets="debiased"))
    assert joint_rmse_deg(paper.theta, theta) > 5.0
    assert joint_rmse_deg(ours.theta, theta) < 0.1


def test_register_em_stops_a_level_once_converged(hand):
    rng = make_rng(22)
    theta = random_pose(hand, rng=rng)
    texture = hand.sample_surface(theta, 200, rng=rng)
    result = register_em(texture, texture, hand, theta,
                         settings=EMSettings(sigma_max=10.0, sigma_min=3.0, n_levels=3, targets="debiased"))
    assert len(result.history) < 3 * 10  # each level ends as soon as Θ stops changing
    assert sorted(set(result.history[:, 0]), reverse=True) == pytest.approx(np.geomspace(10.0, 3.0, 3))


def test_skin_texture_features_move_with_eq3_and_matches_are_true(hand):
    skin = make_skin_texture(hand, 300, rng=5)
    np.testing.assert_allclose(skin.positions(hand, hand.rest_pose()), skin.rest_points, atol=1e-9)
    problem = make_registration_problem(hand, rng=23, noise_mm=0.0, outlier_ratio=1.0, n_model=200, n_data=200,
                                        repeatability=0.8)
    model_index, data_index = problem.true_matches()
    assert 0.5 * 200 < len(model_index) <= 200
    assert not np.any(problem.is_outlier[data_index])
    # noise-free: the matched texture moved by eq. (3) from the initial to the true pose is its match
    binding = hand.texture_binding(problem.model_points, problem.theta_init)
    moved = hand.transform_texture(binding, problem.theta_true)
    assert np.median(np.linalg.norm(moved[model_index] - problem.data_points[data_index], axis=1)) < 1.0
    independent = make_registration_problem(hand, rng=23, n_model=50, n_data=50, repeatability=0.0)
    assert len(independent.true_matches()[0]) == 0


def test_known_correspondences_recover_the_pose(hand):
    problem = make_registration_problem(hand, rng=24, noise_mm=0.0, outlier_ratio=0.0, n_model=300, n_data=300)
    model_index, data_index = problem.true_matches()
    theta = fit_known_correspondences(problem.model_points[model_index], problem.data_points[data_index],
                                      hand, problem.theta_init)
    assert joint_rmse_deg(problem.theta_init, problem.theta_true) > 15.0
    assert joint_rmse_deg(theta, problem.theta_true) < 1.0


def test_surface_distance_jacobian_matches_finite_differences(hand):
    rng = make_rng(25)
    theta = random_pose(hand, rng=rng)
    points = hand.sample_surface(theta, 120, rng=rng) + rng.normal(scale=2.0, size=(120, 3))
    dist, jac = hand.surface_distance_jacobian(points, theta)
    np.testing.assert_allclose(dist, hand.surface_distance(points, theta), atol=1e-12)
    eps = 1e-6
    numeric = np.stack([(hand.surface_distance(points, theta + eps * e) - hand.surface_distance(points, theta - eps * e))
                        / (2 * eps) for e in np.eye(27)], axis=1)
    np.testing.assert_allclose(jac, numeric, atol=1e-5 * max(1.0, np.abs(numeric).max()))


def test_fit_surface_eq22_ignores_far_points(hand):
    rng = make_rng(26)
    theta_true = random_pose(hand, rng=rng)
    data = hand.sample_surface(theta_true, 300, rng=rng)
    clutter = rng.uniform(-100, 150, size=(300, 3))
    clutter = clutter[np.abs(hand.surface_distance(clutter, theta_true)) > 15.0]
    start = perturb_pose(hand, theta_true, 3.0, rng=rng, palm_rotation_deg=1.0, palm_translation_mm=1.0)
    robust = fit_surface(np.concatenate([data, clutter]), hand, start, max_iter=5, sigma=3.0)
    plain = fit_surface(np.concatenate([data, clutter]), hand, start, max_iter=5, sigma=None)
    assert joint_rmse_deg(robust.theta, theta_true) < joint_rmse_deg(plain.theta, theta_true)


def test_kdtree_e_step_matches_dense(hand):
    from amdo_lab.em_articulated import e_step_statistics_kdtree
    theta = hand.rest_pose()
    rng = make_rng(12)
    model = hand.sample_surface(theta, 300, rng=rng)
    data = np.concatenate([hand.sample_surface(theta, 300, rng=rng) + rng.normal(scale=2.0, size=(300, 3)),
                           rng.uniform(-100, 150, size=(100, 3))])
    for sigma in (3.0, 10.0):
        dense = e_step_statistics(model, data, sigma, np.log(PAPER_C))
        tree = e_step_statistics_kdtree(model, data, sigma, np.log(PAPER_C))
        for a, b in zip(dense[:3], tree[:3]):
            np.testing.assert_allclose(a, b, atol=2e-3 * max(1.0, np.abs(a).max()))
        assert tree[3] == pytest.approx(dense[3], rel=2e-2)
    dense_settings = EMSettings(sigma_max=10.0, sigma_min=3.0, n_levels=2)
    em_dense = register_em(model, data, hand, theta, settings=dense_settings)
    em_tree = register_em(model, data, hand, theta, settings=replace(dense_settings, e_step="kdtree"))
    assert np.max(np.abs(em_dense.theta - em_tree.theta)) < 1e-2


def _chain_reference(hand, theta):
    """Part frames by the textbook recursion, one part and one joint rotation at a time."""
    from amdo_lab.common.geometry import rotation_matrix
    frames = []
    for p, part in enumerate(hand._parts):
        frame = np.eye(4)
        if p == 0:
            frame[:3, 3] = theta[:3]
        else:
            frame = frames[part.parent] @ part.offset
        for k, axis in zip(part.dofs, part.axes):
            joint = np.eye(4)
            joint[:3, :3] = rotation_matrix(axis, theta[k])
            frame = frame @ joint
        frames.append(frame)
    return np.array(frames)


def test_batched_kinematics_match_the_part_by_part_chain(hand):
    rng = make_rng(3)
    limits = hand.joint_limits()
    for _ in range(5):
        theta = rng.uniform(np.maximum(limits[:, 0], -1.0), np.minimum(limits[:, 1], 1.0))
        np.testing.assert_allclose(hand.part_transforms(theta), _chain_reference(hand, theta), atol=1e-12)


def test_close_pair_cache_returns_the_pairs_of_a_fresh_query(hand):
    from scipy.spatial import cKDTree
    from amdo_lab.em_articulated.kdtree import ClosePairs
    rng = make_rng(4)
    data = rng.uniform(-60, 60, size=(400, 3))
    model = rng.uniform(-60, 60, size=(300, 3))
    to_data, to_self = ClosePairs(data), ClosePairs(None)
    for step, radius in [(0.0, 12.0), (0.5, 12.0), (1.0, 12.0), (6.0, 12.0), (0.5, 8.0), (20.0, 8.0)]:
        model = model + rng.normal(scale=step / np.sqrt(3), size=model.shape)
        for cache, observed in ((to_data, data), (to_self, model)):
            fresh = cKDTree(observed).sparse_distance_matrix(cKDTree(model), radius, output_type="ndarray")
            data_index, model_index, dist = cache(model, radius)
            assert sorted(zip(data_index, model_index)) == sorted(zip(fresh["i"], fresh["j"]))
            order, fresh_order = np.lexsort((model_index, data_index)), np.lexsort((fresh["j"], fresh["i"]))
            np.testing.assert_allclose(dist[order], fresh["v"][fresh_order], atol=1e-12)


def test_texture_noise_can_be_set_apart_from_the_data_noise(hand):
    exact = make_registration_problem(hand, rng=8, noise_mm=2.0, texture_noise_mm=0.0)
    noisy = make_registration_problem(hand, rng=8, noise_mm=2.0)
    # the exact texture sits on the surface (up to the slight stretch of eq. 3); 2 mm noise lifts it off
    assert np.median(np.abs(hand.surface_distance(exact.model_points, exact.theta_init))) < 0.1
    assert np.median(np.abs(hand.surface_distance(noisy.model_points, noisy.theta_init))) > 1.0


@pytest.mark.parametrize("precision, rtol", [("double", 1e-9), ("single", 2e-6)])
def test_dense_e_step_matches_a_logsumexp_reference(precision, rtol):
    from scipy.special import logsumexp
    rng = make_rng(6)
    model = rng.normal(scale=20.0, size=(40, 3))
    data = np.concatenate([model[:25] + rng.normal(scale=1.0, size=(25, 3)), [[1e4, 0.0, 0.0]]])
    for sigma, log_c in ((0.5, np.log(PAPER_C)), (3.0, -700.0), (20.0, 5.0)):
        sq = np.sum((data[:, None, :] - model[None, :, :]) ** 2, axis=2)
        log_kernel = -sq / (2 * sigma**2)
        alpha = np.exp(log_kernel - np.logaddexp(logsumexp(log_kernel, axis=1), log_c)[:, None])
        weights, weighted, inlier, energy = e_step_statistics(model, data, sigma, log_c, chunk=7, precision=precision)
        # in single precision an α below float32's smallest normal number (about 1e-38) may become 0
        tiny = 1e-300 if precision == "double" else 1e-37
        np.testing.assert_allclose(weights, alpha.sum(axis=0), rtol=rtol, atol=tiny)
        np.testing.assert_allclose(weighted, alpha.T @ data, rtol=rtol, atol=rtol * np.abs(data[:-1]).max())
        np.testing.assert_allclose(inlier, alpha.sum(axis=1), rtol=rtol, atol=tiny)
        assert energy == pytest.approx(float(np.sum(alpha * sq)), rel=rtol)
        assert np.all(np.isfinite(inlier)) and inlier[-1] < 1e-12  # the far point is an outlier, not NaN


def test_pair_fraction_estimate_and_the_dense_switch(hand):
    from amdo_lab.em_articulated.kdtree import DENSE_PAIR_FRACTION, ClosePairs
    rng = make_rng(13)
    theta = hand.rest_pose()
    model = hand.sample_surface(theta, 300, rng=rng)
    data = model + rng.normal(scale=2.0, size=model.shape)
    for radius in (12.0, 40.0, 80.0):
        exact = np.mean(np.linalg.norm(data[:, None] - model[None], axis=2) <= radius)
        assert ClosePairs(data).pair_fraction(model, radius) == pytest.approx(exact, abs=0.05)
        exact_self = np.mean(np.linalg.norm(model[:, None] - model[None], axis=2) <= radius)
        assert ClosePairs(None).pair_fraction(model, radius) == pytest.approx(exact_self, abs=0.05)
    # at σ of 15-20 mm the 4σ balls hold more than the switch's share of all pairs, so "kdtree"
    # runs the dense E-step, and the two settings give the same pose
    assert ClosePairs(data).pair_fraction(model, 4 * 15.0) > DENSE_PAIR_FRACTION
    dense_settings = EMSettings(sigma_max=20.0, sigma_min=15.0, n_levels=2)
    em_dense = register_em(model, data, hand, theta, settings=dense_settings)
    em_tree = register_em(model, data, hand, theta, settings=replace(dense_settings, e_step="kdtree"))
    np.testing.assert_array_equal(em_dense.theta, em_tree.theta)


def test_an_int_seed_and_the_generator_it_makes_give_the_same_pose(hand):
    theta = hand.rest_pose()
    np.testing.assert_array_equal(perturb_pose(hand, theta, 10.0, rng=3), perturb_pose(hand, theta, 10.0, rng=make_rng(3)))


# ---------------------------------------------------------------- per-digit search (beyond the paper)
# the 2 mm read as 2 mm RMS in 3-D on the data only (texture exact), at 300 points for speed
_LENIENT = dict(joint_error_deg=20.0, noise_mm=2.0 / np.sqrt(3), texture_noise_mm=0.0, outlier_ratio=1.0,
                n_model=300, n_data=300)


def _worst_finger_deg(theta, theta_true):
    return float(np.degrees(np.max(np.abs(theta[6:] - theta_true[6:]))))


def test_digit_search_frees_a_finger_the_em_leaves_on_its_neighbour(hand):
    # seed 15: the annealed EM ends with the ring and little fingers up to 22 and 27 degrees off
    case = make_registration_problem(hand, rng=15, **_LENIENT)
    em = register_em(case.model_points, case.data_points, hand, case.theta_init, settings=OUR_SETTINGS)
    assert _worst_finger_deg(em.theta, case.theta_true) > 15
    args = (case.model_points, case.data_points, hand, case.theta_init, em.theta)
    rerun = refine_digits(*args, max_passes=0, settings=OUR_SETTINGS)  # the EM's last levels again, no re-seeding
    assert _worst_finger_deg(rerun.theta, case.theta_true) > 15 and rerun.accepted == ()
    search = refine_digits(*args, settings=OUR_SETTINGS)
    assert _worst_finger_deg(search.theta, case.theta_true) < 10
    assert search.accepted and all(gain > 1.0 for _, gain in search.accepted)
    assert search.log_likelihood > rerun.log_likelihood
    assert search.inlier_prob.shape == (len(case.data_points),)


def _log_likelihood_reference(hand, model_points, theta_init, theta, data, sigma):
    moved = hand.move_texture(model_points, theta_init, theta)
    log_kernel = -np.sum((data[:, None, :] - moved[None]) ** 2, axis=2) / (2 * sigma**2)
    return float(np.sum(logsumexp(np.column_stack([log_kernel, np.full(len(data), np.log(PAPER_C))]), axis=1)))


@pytest.mark.parametrize("seed", [1, 2])
def test_digit_search_never_lowers_the_criterion(hand, seed):
    case = make_registration_problem(hand, rng=seed, joint_error_deg=20.0, noise_mm=2.0, outlier_ratio=1.0,
                                     n_model=150, n_data=150)
    settings = replace(OUR_SETTINGS, max_iter=3)
    # from the start pose itself (far from converged) and from a finger bent onto the limit
    bent = case.theta_init.copy()
    bent[16:19] = hand.joint_limits()[16:19, 1]
    for theta in (case.theta_init, bent):
        search = refine_digits(case.model_points, case.data_points, hand, case.theta_init, theta,
                               search_levels=1, min_gain=0.0, max_passes=1, settings=settings)
        before = _log_likelihood_reference(hand, case.model_points, case.theta_init, theta, case.data_points, 3.0)
        after = _log_likelihood_reference(hand, case.model_points, case.theta_init, search.theta, case.data_points, 3.0)
        assert search.start_log_likelihood == pytest.approx(before, rel=1e-9)
        assert search.log_likelihood == pytest.approx(after, rel=1e-9)
        assert after >= before
        gains = [gain for _, gain in search.accepted]
        assert all(gain > 0 for gain in gains)


def test_digit_search_keeps_an_exact_fit(hand):
    theta = hand.rest_pose()
    texture = hand.sample_surface(theta, 200, rng=0)
    search = refine_digits(texture, texture, hand, theta, theta, search_levels=1, settings=OUR_SETTINGS)
    assert search.accepted == ()
    assert np.degrees(np.max(np.abs(search.theta - theta))) < 1.0
    assert search.log_likelihood >= search.start_log_likelihood


def test_robust_log_likelihood_matches_a_logsumexp_reference():
    rng = np.random.default_rng(0)
    model, data = rng.normal(0, 20, (40, 3)), rng.normal(0, 20, (70, 3)) + 500.0  # far from the origin: centring
    sigma, log_c = 3.0, np.log(PAPER_C)
    log_kernel = -np.sum((data[:, None] - model[None]) ** 2, axis=2) / (2 * sigma**2)
    per_point = logsumexp(np.column_stack([log_kernel, np.full(len(data), log_c)]), axis=1)
    value = robust_log_likelihood(model, data, sigma, PAPER_C)
    inlier_prob = e_step_statistics(model, data, sigma, log_c, chunk=16, precision="double")[2]
    assert value == pytest.approx(float(per_point.sum()), rel=1e-10)
    np.testing.assert_allclose(inlier_prob, np.exp(logsumexp(log_kernel, axis=1) - per_point), rtol=1e-9, atol=1e-300)


def test_digit_starts_move_one_digit_within_the_limits(hand):
    # the digits' DOF groups cover the 21 joint angles once, and each moves only its own digit's parts
    assert np.array_equal(np.sort(np.concatenate(DIGIT_DOFS)), np.arange(6, 27))
    for digit, dofs in enumerate(map(np.array, DIGIT_DOFS)):
        moved_parts = np.flatnonzero(hand._dof_moves_part[dofs].any(axis=0))
        np.testing.assert_array_equal(moved_parts, np.arange(1 + 3 * digit, 4 + 3 * digit))
    limits = hand.joint_limits()
    theta = hand.rest_pose()
    theta[11] = limits[11, 1]  # index abduction at its limit: the move beyond it is dropped
    for digit, dofs in enumerate(map(np.array, DIGIT_DOFS)):
        starts = digit_starts(hand, theta, digit, np.radians(20.0), np.radians(25.0))
        other = np.setdiff1d(np.arange(27), dofs)
        assert 1 <= len(starts) <= 7
        np.testing.assert_array_equal(starts[:, other], np.broadcast_to(theta[other], (len(starts), len(other))))
        assert np.all((starts >= limits[:, 0]) & (starts <= limits[:, 1]))
        assert np.all(np.max(np.abs(starts - theta), axis=1) > 1e-3)
    assert len(digit_starts(hand, theta, 1, np.radians(20.0), np.radians(25.0))) == 6


def test_trials_run_the_digit_search_only_when_asked(hand):
    problem = dict(joint_error_deg=10.0, n_model=100, n_data=100)
    settings = replace(OUR_SETTINGS, max_iter=2)
    plain = run_registration_trials(hand, 1, rng=0, problem=problem, settings=settings, surface_max_iter=0)
    rerun = run_registration_trials(hand, 1, rng=0, problem=problem, settings=settings, surface_max_iter=0,
                                    digit_search=True)
    assert np.isfinite(rerun.rmse_deg).all() and rerun.rmse_deg[0] != plain.rmse_deg[0]


def test_trial_summary_success_interval_counts_the_successful_trials():
    errors = np.array([2.0, 9.9, 10.0, 25.0, 4.0])  # success means every joint strictly within SUCCESS_DEG
    summary = TrialSummary(errors / 2, errors, np.ones(5), errors / 3, errors / 3)
    interval = summary.success_interval(0.9)
    assert (interval.successes, interval.trials) == (3, 5) and interval.rate == summary.success_rate
    assert interval.low < 0.6 < interval.high and interval.confidence == 0.9


def test_noise_floor_trials_are_the_trial_runners_floors_without_the_em(hand):
    problem = dict(joint_error_deg=10.0, n_model=100, n_data=100)
    settings = replace(OUR_SETTINGS, max_iter=1)
    trials = run_registration_trials(hand, 2, rng=3, problem=problem, settings=settings, surface_max_iter=0)
    rmse, worst = noise_floor_trials(hand, 2, rng=3, problem=problem)
    np.testing.assert_array_equal(rmse, trials.oracle_rmse_deg)
    np.testing.assert_array_equal(worst, trials.oracle_max_error_deg)
    assert np.all(worst >= rmse)
    textureless, _ = noise_floor_trials(hand, 1, rng=3, problem=dict(problem, repeatability=0.0))
    assert np.isnan(textureless).all()  # no feature seen twice: no true matches, no floor


def test_e_step_reference_equals_the_streamed_e_step():
    rng = np.random.default_rng(3)
    model, data = rng.normal(0, 15, (60, 3)), rng.normal(0, 15, (90, 3))
    alpha = e_step_reference(model, data, 4.0)
    # eq. (17): each column sums to the data point's inlier probability, below 1
    assert np.all(alpha.sum(axis=0) < 1.0) and np.all(alpha >= 0)
    weights, weighted, inlier, energy = e_step_statistics(model, data, 4.0, np.log(PAPER_C), chunk=32,
                                                          precision="double")
    np.testing.assert_allclose(alpha.sum(axis=1), weights, rtol=1e-10, atol=1e-14)
    np.testing.assert_allclose(alpha @ data, weighted, rtol=1e-9, atol=1e-10)
    np.testing.assert_allclose(alpha.sum(axis=0), inlier, rtol=1e-10, atol=1e-14)
    sq = np.sum((model[:, None] - data[None]) ** 2, axis=2)
    assert np.sum(alpha * sq) == pytest.approx(energy, rel=1e-9)


def test_e_step_reference_single_exact_match_is_one_over_one_plus_c():
    alpha = e_step_reference(np.zeros((1, 3)), np.zeros((1, 3)), 2.0)
    assert alpha[0, 0] == pytest.approx(1 / (1 + 3 * np.sqrt(np.pi / 2)))


def test_m_step_targets_are_weighted_means():
    data = np.array([[0.0, 0, 0], [10.0, 0, 0], [0, 0, 5.0]])
    alpha = np.array([[0.5, 0.5, 0.0], [0.0, 0.0, 0.0], [0.1, 0.0, 0.3]])
    lam, targets = m_step_targets(alpha, data)
    np.testing.assert_allclose(lam, [1.0, 0.0, 0.4])
    np.testing.assert_allclose(targets[0], [5.0, 0, 0])
    np.testing.assert_allclose(targets[2], [0, 0, 3.75])
    assert np.all(targets[1] == 0)  # no weight: target unused


def test_public_robust_log_likelihood_matches_logsumexp():
    rng = np.random.default_rng(1)
    model, data = rng.normal(0, 20, (30, 3)), rng.normal(0, 20, (50, 3))
    log_kernel = -np.sum((data[:, None] - model[None]) ** 2, axis=2) / (2 * 3.0**2)
    expected = logsumexp(np.column_stack([log_kernel, np.full(len(data), np.log(PAPER_C))]), axis=1).sum()
    assert robust_log_likelihood(model, data, 3.0) == pytest.approx(expected, rel=1e-10)


@pytest.mark.parametrize("targets", ["paper", "debiased"])
def test_register_em_reference_equals_the_fast_em(hand, targets):
    case = make_registration_problem(hand, rng=4, joint_error_deg=10.0, noise_mm=1.0, outlier_ratio=0.5,
                                     n_model=120, n_data=120)
    settings = EMSettings(sigma_max=12.0, sigma_min=3.0, n_levels=3, max_iter=4, targets=targets)
    reference = register_em_reference(case.model_points, case.data_points, hand, case.theta_init, settings=settings)
    fast = register_em(case.model_points, case.data_points, hand, case.theta_init, settings=settings)
    assert np.max(np.abs(reference - fast.theta)) < 1e-4  # the fast path exponentiates in single precision
    assert joint_rmse_deg(reference, case.theta_init) > 1.0  # the EM moved: the comparison is not trivial


def test_a_texture_binding_built_by_hand_moves_its_points_as_eq3(hand):
    """A TextureBinding built from plain lists is checked into arrays and, at its own pose, puts every
    point back where it was observed (both part motions of eq. 3 agree there)."""
    theta = random_pose(hand, rng=make_rng(31))
    points = hand.sample_surface(theta, 20, rng=make_rng(32))
    made = hand.texture_binding(points, theta)
    rebuilt = TextureBinding(made.part_p.tolist(), made.part_r.tolist(), made.weight_p.tolist(),
                             made.local_p.tolist(), made.local_r.tolist())
    assert rebuilt.part_p.dtype.kind == "i" and rebuilt.local_p.shape == (20, 3)
    np.testing.assert_allclose(hand.transform_texture(rebuilt, theta), points, atol=1e-9)


def test_gauss_newton_step_solves_the_weighted_least_squares_of_eq20():
    """Undamped, the step is the weighted least-squares solution of J ΔΘ = r (eq. 20 linearised)."""
    rng = make_rng(30)
    jacobian, residuals, weights = rng.normal(size=(40, 3, 5)), rng.normal(size=(40, 3)), rng.uniform(0, 2, 40)
    sqrt_w = np.sqrt(weights)[:, None]
    expected = np.linalg.lstsq((sqrt_w[:, :, None] * jacobian).reshape(-1, 5), (sqrt_w * residuals).ravel(),
                               rcond=None)[0]
    np.testing.assert_allclose(gauss_newton_step(jacobian, residuals, weights, damping=0.0), expected, rtol=1e-10)
    damped = gauss_newton_step(jacobian, residuals, weights)  # the M-step's 1e-3 damping changes it a little
    np.testing.assert_allclose(damped, expected, atol=1e-2 * np.abs(expected).max())
    assert not np.allclose(damped, expected, rtol=1e-10, atol=0)


def test_em_settings_name_the_paper_and_ours():
    from amdo_lab.em_articulated import PAPER_SETTINGS
    assert PAPER_SETTINGS.targets == "paper" and OUR_SETTINGS.targets == "debiased"
    assert replace(PAPER_SETTINGS, targets="debiased") == OUR_SETTINGS
    np.testing.assert_allclose(OUR_SETTINGS.sigmas, np.geomspace(20.0, 3.0, 5))


def test_climb_objective_never_lowers_the_objective(hand):
    case = make_registration_problem(hand, rng=8, joint_error_deg=10.0, noise_mm=2.0, outlier_ratio=1.0,
                                     n_model=150, n_data=150)
    binding = hand.texture_binding(case.model_points, case.theta_init)

    def objective(theta):
        return robust_log_likelihood(hand.transform_texture(binding, theta), case.data_points, 3.0)

    climbed = climb_objective(case.model_points, case.data_points, hand, case.theta_init, case.theta_true, 3.0)
    assert objective(climbed) >= objective(case.theta_true) - 1e-6


def test_objective_check_fields_agree_with_their_definitions(hand):
    from amdo_lab.em_articulated import objective_check
    problem = dict(joint_error_deg=10.0, noise_mm=2.0, outlier_ratio=1.0, n_model=150, n_data=150)
    check = objective_check(hand, 2, rng=5, problem=problem, settings=OUR_SETTINGS)
    assert check.em_rmse_deg.shape == (2,) and check.sigma == OUR_SETTINGS.sigma_min
    # the climb starts at the floor pose and only goes up
    assert np.all(check.climbed_log_likelihood >= check.floor_log_likelihood - 1e-6)


def test_per_step_schedule_runs_one_iteration_per_falling_sigma(hand):
    case = make_registration_problem(hand, rng=6, joint_error_deg=10.0, noise_mm=1.0, outlier_ratio=1.0,
                                     n_model=150, n_data=150)
    settings = EMSettings(sigma_max=20.0, sigma_min=3.0, n_levels=5, max_iter=10)
    per_step = register_em(case.model_points, case.data_points, hand, case.theta_init,
                           settings=replace(settings, schedule="per-step"))
    levels = register_em(case.model_points, case.data_points, hand, case.theta_init, settings=settings)
    # one iteration at each σ above σ_min, then up to ten at σ_min (fewer once Θ stops changing)
    np.testing.assert_allclose(per_step.history[:4, 0], np.geomspace(20.0, 3.0, 5)[:4])
    assert 1 <= len(per_step.history) - 4 <= 10 and np.all(per_step.history[4:, 0] == 3.0)
    assert len(per_step.history) < len(levels.history) <= 50


def test_bend_sequence_keeps_the_palm_still_and_the_camera_selects_the_points(hand):
    above = make_tracking_sequence(hand, rng=3, n_frames=4, motion="bend")
    side = make_tracking_sequence(hand, rng=3, n_frames=4, motion="bend", camera=np.array([500.0, 40.0, 100.0]))
    turn = make_tracking_sequence(hand, rng=3, n_frames=4)
    assert np.all(above.poses[:, 4] == above.poses[0, 4]) and np.ptp(turn.poses[:, 4]) > 0.1
    np.testing.assert_array_equal(above.poses, side.poses)  # same motion, different view
    assert not np.array_equal(above.frames[1], side.frames[1])


#: Every public function of the chapter that draws random numbers, with a cheap call that needs only
#: ``rng``: the one convention (``rng`` keyword-only, no default, errors naming ``rng``).
_DRAWING = {
    "random_pose": (random_pose, lambda hand, rng: random_pose(hand, rng=rng)),
    "perturb_pose": (perturb_pose, lambda hand, rng: perturb_pose(hand, hand.rest_pose(), 5.0, rng=rng)),
    "sample_surface": (HandModel.sample_surface, lambda hand, rng: hand.sample_surface(hand.rest_pose(), 5, rng=rng)),
    "make_skin_texture": (make_skin_texture, lambda hand, rng: make_skin_texture(hand, 5, rng=rng)),
    "make_registration_problem": (make_registration_problem,
                                  lambda hand, rng: make_registration_problem(hand, rng=rng, n_model=5, n_data=5)),
    "make_tracking_sequence": (make_tracking_sequence,
                               lambda hand, rng: make_tracking_sequence(hand, rng=rng, n_frames=2, n_features=50,
                                                                        n_clutter=3)),
    "noise_floor_trials": (noise_floor_trials, lambda hand, rng: noise_floor_trials(hand, 1, rng=rng)),
    "run_registration_trials": (run_registration_trials, lambda hand, rng: run_registration_trials(hand, 1, rng=rng)),
    "objective_check": (objective_check, lambda hand, rng: objective_check(hand, 1, rng=rng)),
}


@pytest.mark.parametrize("name", sorted(_DRAWING))
def test_drawing_functions_take_rng_keyword_only_without_default(name):
    import inspect
    parameter = inspect.signature(_DRAWING[name][0]).parameters["rng"]
    assert parameter.kind is inspect.Parameter.KEYWORD_ONLY
    assert parameter.default is inspect.Parameter.empty


@pytest.mark.parametrize("name", ["e_step_reference", "make_registration_problem", "register_em"])
def test_docstring_examples_run_and_print_what_they_show(name):
    import doctest

    import amdo_lab.em_articulated as chapter
    function = getattr(chapter, name)
    finder, runner = doctest.DocTestFinder(), doctest.DocTestRunner(optionflags=doctest.NORMALIZE_WHITESPACE)
    tests = finder.find(function, name, globs={name: function})
    assert tests and tests[0].examples
    for test in tests:
        runner.run(test)
    assert runner.failures == 0


def test_part_fields_are_eq1_of_the_part_distances(hand):
    """Eq. (1): φ_p = exp(-d/ν), so φ_p = 1 on part p's own ellipsoid and falls by e every ν outside."""
    theta = hand.rest_pose()
    frames = hand.part_transforms(theta)
    directions = make_rng(40).normal(size=(20, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    part = 5
    # points on ellipsoid p: x = R_p (c_p + radii_p ∘ u) + t_p, the inverse of the part frame's local coordinates
    on_surface = (hand._centres[part] + hand._radii[part] * directions) @ frames[part, :3, :3].T + frames[part, :3, 3]
    np.testing.assert_allclose(hand.part_fields(on_surface, theta)[:, part], 1.0, atol=1e-9)
    points = hand.sample_surface(theta, 50, rng=make_rng(41)) + make_rng(42).normal(scale=5.0, size=(50, 3))
    expected = np.exp(-hand.part_distances(points, theta) / hand.nu)
    np.testing.assert_allclose(hand.part_fields(points, theta), expected, rtol=1e-12)


def test_transform_texture_is_eq3_blend_of_the_two_part_motions(hand):
    """Eq. (3) computed from the part fields and part motions by hand equals transform_texture and the
    positions of the analytic-Jacobian path."""
    rng = make_rng(43)
    theta_from = random_pose(hand, rng=rng)
    theta_to = perturb_pose(hand, theta_from, 15.0, rng=rng)
    points = hand.sample_surface(theta_from, 80, rng=rng)
    a = 2.0
    binding = hand.texture_binding(points, theta_from, a)
    fields = hand.part_fields(points, theta_from)
    rows = np.arange(len(points))
    phi_p, phi_r = fields[rows, binding.part_p] ** a, fields[rows, binding.part_r] ** a
    old, new = hand.part_transforms(theta_from), hand.part_transforms(theta_to)

    def rigid(part):  # T_p(Θ_to) T_p(Θ_from)^-1 X: the point carried rigidly by one part
        local = np.einsum("nji,nj->ni", old[part, :3, :3], points - old[part, :3, 3])
        return np.einsum("nij,nj->ni", new[part, :3, :3], local) + new[part, :3, 3]

    expected = (phi_p[:, None] * rigid(binding.part_p) + phi_r[:, None] * rigid(binding.part_r)) \
        / (phi_p + phi_r)[:, None]
    np.testing.assert_allclose(hand.transform_texture(binding, theta_to), expected, atol=1e-9)
    np.testing.assert_allclose(hand.texture_jacobian(binding, theta_to)[0], expected, atol=1e-9)
    assert np.max(np.linalg.norm(expected - points, axis=1)) > 1.0  # the texture moved: not a trivial check


def test_robust_log_likelihood_reference_equals_the_streamed_path():
    from amdo_lab.em_articulated.estep import robust_log_likelihood_reference
    rng = np.random.default_rng(44)
    model, data = rng.normal(0, 15, (50, 3)), rng.normal(0, 15, (80, 3))
    for sigma in (2.0, 6.0):
        assert robust_log_likelihood_reference(model, data, sigma) == pytest.approx(
            robust_log_likelihood(model, data, sigma), rel=1e-10)
    assert robust_log_likelihood_reference(model, data + 1e4, 2.0) == pytest.approx(80 * np.log(PAPER_C))


def test_fit_surface_eq21_reaches_the_minimum_scipy_finds(hand):
    """Without eq. (22)'s weights, eq. (21) is plain least squares in d(Y_j, Θ): fit_surface's
    Gauss-Newton and scipy's trust-region least squares reach the same pose."""
    from scipy.optimize import least_squares

    rng = make_rng(45)
    theta_true = random_pose(hand, rng=rng)
    data = hand.sample_surface(theta_true, 300, rng=rng) + rng.normal(scale=0.5, size=(300, 3))
    start = perturb_pose(hand, theta_true, 3.0, rng=rng, palm_rotation_deg=1.0, palm_translation_mm=1.0)
    ours = fit_surface(data, hand, start, sigma=None, max_iter=30)
    limits = hand.joint_limits()
    peer = least_squares(lambda theta: hand.surface_distance(data, theta), start,
                         jac=lambda theta: hand.surface_distance_jacobian(data, theta)[1],
                         bounds=(limits[:, 0], limits[:, 1]), xtol=1e-12, ftol=1e-12, gtol=1e-12)
    assert np.max(np.abs(ours.theta - peer.x)) < 1e-6
    assert ours.rms_distance == pytest.approx(np.sqrt(np.mean(peer.fun**2)), rel=1e-9)
    assert joint_rmse_deg(ours.theta, start) > 1.0  # the fit moved


# ---------------------------------------------------------------- rejections: one table
# tests/test_bad_input.py already spoils every argument of every public callable (NaN, inf or 1e308
# inside, empty, wrong shape, a string, None, a bool, zero/negative/float counts, bad probabilities and
# seeds) and checks that the error names the argument. This table holds what that test cannot see:
# the rules of the method (joint limits, σ_min < σ_max, posteriors in [0, 1], the documented ±1e6 bounds),
# unknown names and settings, shapes that depend on another argument, and the rng convention.
# A call's parameters without a default name the fixtures it needs.
def _points(hand):
    """Thirty points on the rest-pose surface, a valid cloud for the calls below."""
    return hand.sample_surface(hand.rest_pose(), 30, rng=0)


def _outside_limits(hand):
    """The rest pose with one finger joint (DOF 12) bent far past its limit."""
    theta = hand.rest_pose()
    theta[12] = 3.0
    return theta


REJECTIONS = [
    # the hand model's documented bounds: coordinates and pose entries within ±1e6
    reject("surface_distance points beyond 1e6 mm", lambda hand: hand.surface_distance(
        np.array([[2e6, 0, 0]]), hand.rest_pose()), ValueError, "points must be at most"),
    reject("part_transforms theta beyond 1e6", lambda hand: hand.part_transforms(np.full(27, 2e6)),
           ValueError, "theta must be at most"),
    reject("TextureBinding part beyond the hand", lambda: TextureBinding([16], [0], [0.5], [[0.0, 0, 0]],
                                                                         [[0.0, 0, 0]]),
           ValueError, r"part_p must lie in \[0, 15\]"),
    reject("transform_texture points for a binding", lambda hand: hand.transform_texture(
        _points(hand), hand.rest_pose()), TypeError, "binding must be a TextureBinding"),
    # E- and M-steps (eqs. 17-20)
    reject("e_step precision half", lambda: e_step_statistics(np.zeros((2, 3)), np.ones((3, 3)), 1.0, 0.0,
                                                             precision="half"), ValueError, "precision must be one of"),
    reject("m_step alpha columns differ from the data", lambda: m_step_targets(np.zeros((2, 4)), np.zeros((3, 3))),
           ValueError, r"alpha must have shape \(n, 3\)"),
    reject("m_step alpha above 1", lambda: m_step_targets(np.full((2, 3), 1.5), np.zeros((3, 3))),
           ValueError, r"alpha must lie in \[0, 1\]"),
    reject("m_step alpha below 0", lambda: m_step_targets(np.full((2, 3), -0.1), np.zeros((3, 3))),
           ValueError, r"alpha must lie in \[0, 1\]"),
    reject("robust_log_likelihood data beyond 1e6 mm",
           lambda: robust_log_likelihood(np.zeros((2, 3)), np.full((2, 3), 2e6), 1.0),
           ValueError, r"data_points must be at most 1e\+06"),
    reject("robust_log_likelihood_reference sigma 0", lambda: robust_log_likelihood_reference(
        np.zeros((2, 3)), np.ones((2, 3)), 0.0), ValueError, r"sigma must be in \(0, 1e\+06\]"),
    # register_em: the annealing schedule, the joint limits, the named options
    reject("EMSettings sigma_min above sigma_max", lambda: EMSettings(sigma_max=20.0, sigma_min=30.0),
           ValueError, r"sigma_min must be in \(0, 20\)"),
    reject("register_em theta_init outside the limits", lambda hand: register_em(
        _points(hand), _points(hand), hand, _outside_limits(hand)),
        ValueError, r"theta_init must lie within joint_limits\(\); DOF \[12\]"),
    reject("EMSettings targets mean", lambda: EMSettings(targets="mean"), ValueError, "targets must be one of"),
    reject("EMSettings schedule fast", lambda: EMSettings(schedule="fast"), ValueError, "schedule must be one of"),
    reject("register_em settings as a dict", lambda hand: register_em(
        _points(hand), _points(hand), hand, hand.rest_pose(), settings={"n_levels": 2}),
        TypeError, "settings must be an EMSettings"),
    reject("fit_surface weights beyond 1e6", lambda hand: fit_surface(
        _points(hand), hand, hand.rest_pose(), weights=np.full(30, 1e7)), ValueError, r"weights must lie in \[0, 1e\+06\]"),
    reject("track no frames", lambda hand: track([], hand, hand.rest_pose()),
           ValueError, "frames must be a non-empty list"),
    reject("make_tracking_sequence motion wave", lambda hand: make_tracking_sequence(hand, rng=3, n_frames=4,
                                                                                     motion="wave"),
           ValueError, "motion must be one of"),
    # the per-digit search (beyond the paper) and the trial runner that passes its settings on
    reject("refine_digits theta outside the limits", lambda hand: refine_digits(
        _points(hand), _points(hand), hand, hand.rest_pose(), np.full(27, 3.0)), ValueError, "theta must lie within"),
    reject("refine_digits search_levels above n_levels", lambda hand: refine_digits(
        _points(hand), _points(hand), hand, hand.rest_pose(), hand.rest_pose(), search_levels=6),
        ValueError, "search_levels must be at most 5"),
    reject("refine_digits unknown setting", lambda hand: refine_digits(
        _points(hand), _points(hand), hand, hand.rest_pose(), hand.rest_pose(), spread=3), TypeError, "spread"),
    # the rng convention: errors start with "rng", TypeError for a non-seed, ValueError for a negative seed
    *[reject(f"{name} rng {bad!r}", lambda hand, draw=draw, bad=bad: draw(hand, bad), error, "^rng ")
      for name, (_, draw) in sorted(_DRAWING.items()) for bad, error in (("seed", TypeError), (-1, ValueError))],
]


@pytest.mark.parametrize(("call", "error", "message"), REJECTIONS)
def test_rejections(request, call, error, message):
    check_rejection(request, call, error, message)


# --- the chapter's exercises (amdo_lab.em_articulated.exercises) -----------------------------------

from amdo_lab.common.exercises import ExerciseSet  # noqa: E402
from amdo_lab.em_articulated.exercises import EXERCISES  # noqa: E402

def _graded() -> ExerciseSet:
    """A fresh copy of the chapter's exercises with the targets the notebook's hidden tests register."""
    import nbformat

    from amdo_lab.chapters import available_chapters
    from amdo_lab.course.cells import hidden_targets

    (chapter,) = [chapter for chapter in available_chapters() if chapter.number == 1]
    graded = ExerciseSet(1, EXERCISES.exercises)
    for number, (kind, registered) in hidden_targets(nbformat.read(chapter.path, as_version=4)).items():
        graded.expect(number, seeds=registered) if kind == "seeds" else graded.expect(number, registered)
    return graded


@pytest.mark.parametrize(("number", "answer", "verdict"), [
    (1, 2.0, "correct"), (1, 2.004, "correct"), (1, 2.01, "not yet"), (1, 3.76, "not yet"), (1, 0.5, "not yet"),
    (2, 0.44, "correct"), (2, 0.21, "not yet"), (2, 0.63, "not yet"), (2, 0.56, "not yet"), (2, 1.0, "not yet"),
    (3, 14.38, "correct"), (3, 3.11, "not yet"), (3, 33.44, "not yet"), (3, 20.0, "not yet"), (3, 14.4, "not yet"),
    (4, 27.9, "correct"), (4, 0.7, "not yet"), (4, 0.49, "not yet"), (4, 28.0, "not yet"),
    (5, 0.96, "correct"), (5, 0.85, "not yet"), (5, 96.0, "not yet"), (5, 1.0, "not yet"),
    (6, 0.17, "correct"), (6, 0.04, "not yet"), (6, 0.5, "not yet"), (6, "the clutter", "not yet"),
    (3, None, "not attempted yet"), (7, None, "not attempted yet"),
])
def test_exercise_verdicts(number, answer, verdict):
    assert _graded().verdict(number, answer).split(":")[0] == verdict


def test_exercise_without_a_target_is_recorded_and_wrong_answers_get_their_hint():
    """The release has no targets: an unrecorded answer is recorded, a recorded wrong one gets its hint."""
    assert EXERCISES.verdict(3, 14.38).startswith("recorded")
    for wrong in EXERCISES[3].wrong_answers:
        assert EXERCISES.verdict(3, wrong.value) == "not yet: " + wrong.hint


def test_implement_it_rejects_each_recorded_wrong_e_step_and_accepts_eq_15():
    """Exercise 7: the E-step without the outlier class (and the other slips) get their own hints."""
    graded = _graded()
    exercise = graded[7]
    for wrong in exercise.wrong_answers:
        assert graded.verdict(7, wrong.value) == "not yet: " + wrong.hint
    assert graded.verdict(7, lambda **case: exercise.reference(**case)) == "correct"  # the reference, re-typed
    assert graded.verdict(7, lambda **case: None).startswith("not yet")
    assert graded.verdict(7, 0.5).startswith("not yet")  # a number, not a function


def test_implement_it_cases_tell_the_wrong_e_steps_apart():
    """On every case (the example and the unseen ones) each wrong E-step differs from eq. (15)."""
    exercise = EXERCISES[7]
    for seed in (exercise.example_seed, 11, 23, 37):
        case = exercise.make_case(seed)
        want = exercise.reference(**case)
        assert np.all(np.isfinite(want)) and np.all(want.sum(axis=0) < 1)
        for wrong in exercise.wrong_answers:
            assert not exercise.outputs_match(wrong.value(**case), want), (seed, wrong.why)
