"""Tests for chapter 2 (amdo_lab.pdm_mixtures): generator invariants, PDM, polar representation,
Gaussian-mixture EM against scikit-learn, the hierarchical recogniser and bad input."""

import warnings

import numpy as np
import pytest
from rejections import check_rejection, reject
from sklearn.exceptions import NotFittedError

import amdo_lab.pdm_mixtures as pm
from amdo_lab.common import make_rng, procrustes_align, rotation_2d, spawn_rngs
from amdo_lab.pdm_mixtures import (
    LIMB_PARENTS,
    POSE_MODES,
    POSES,
    TABLE1_CLASSES,
    ArticulatedShapeRecogniser,
    RecogniserSettings,
    NearestProcrustesMeanClassifier,
    classical_mds,
    fit_gaussian_mixture,
    fit_modes,
    fit_pdm,
    generalized_procrustes,
    make_pose_dataset,
    hamming_distance,
    label_string_log_prob,
    limb_angles,
    limb_centres,
    pairwise_distances,
    polar_shape_vector,
    reconstruct,
    skeleton_strokes,
    wrap_angle,
)
from amdo_lab.pdm_mixtures.gmm import _gaussian_log_density
from amdo_lab.pdm_mixtures.pdm import _align_to_reference, _normalise_shape, _check_labels
from amdo_lab.pdm_mixtures.polar_mixture import angles_about_mean
from amdo_lab.pdm_mixtures.recognition import MAX_RECOGNITION_ITER, _class_posteriors
from amdo_lab.pdm_mixtures.poses import MEAN_LENGTHS

ONE_COMPONENT = RecogniserSettings(n_shape_components=1)  # ours with one polar PDM per class


@pytest.fixture(scope="module")
def small_problem():
    train_rng, test_rng = spawn_rngs(7, 2)
    train = make_pose_dataset(TABLE1_CLASSES, 12, rng=train_rng)
    test = make_pose_dataset(TABLE1_CLASSES, 30, rng=test_rng)
    recogniser = ArticulatedShapeRecogniser(rng=0).fit(train.shapes, train.labels)
    return train, test, recogniser


# ---------------------------------------------------------------- generator
def test_generator_shapes_labels_and_determinism():
    data = make_pose_dataset(TABLE1_CLASSES, 5, rng=3, landmarks_per_limb=7)
    assert data.shapes.shape == (30, 13, 7, 2)
    assert [int(np.sum(data.labels == c)) for c in TABLE1_CLASSES] == [5] * 6
    again = make_pose_dataset(TABLE1_CLASSES, 5, rng=3, landmarks_per_limb=7)
    np.testing.assert_array_equal(data.shapes, again.shapes)
    other = make_pose_dataset(TABLE1_CLASSES, 5, rng=4, landmarks_per_limb=7)
    assert not np.allclose(data.shapes, other.shapes)


def test_generator_limb_lengths_and_joint_connectivity_without_noise():
    data = make_pose_dataset(TABLE1_CLASSES, 4, rng=11, noise=0.0)
    strokes = data.shapes
    measured = np.linalg.norm(strokes[:, :, -1] - strokes[:, :, 0], axis=-1)
    np.testing.assert_allclose(measured, data.limb_lengths, rtol=1e-12)
    # Landmarks are evenly spaced along a straight stroke.
    steps = np.linalg.norm(np.diff(strokes, axis=2), axis=-1)
    np.testing.assert_allclose(steps, np.repeat(steps[:, :, :1], steps.shape[2], axis=2), rtol=1e-9)
    # A child limb without shoulder/hip offset starts where its parent ends.
    for limb, parent in enumerate(LIMB_PARENTS):
        if parent >= 0 and limb not in (3, 5):
            np.testing.assert_allclose(strokes[:, limb, 0], strokes[:, parent, -1], atol=1e-12)


def _template_distance(a, b):
    strokes = skeleton_strokes(np.array([a, b], float), np.repeat(MEAN_LENGTHS[None], 2, axis=0), 6)
    return procrustes_align(strokes[0].reshape(-1, 2), strokes[1].reshape(-1, 2)).rms_error


def test_generator_confusable_classes_share_limb_configurations():
    modes = {c: list(POSE_MODES[c].values()) for c in TABLE1_CLASSES}
    def closest(a, b):
        return min(_template_distance(x, y) for x in modes[a] for y in modes[b])
    assert closest("kicking", "shooting") < closest("kicking", "stretching")
    assert closest("picking", "shooting") < closest("picking", "stretching")
    # Kicking shares both arms and the support leg with shooting; picking shares the right arm and
    # the support leg; all three raise the right (swing) thigh forward.
    for name, shared in (("kicking", [3, 4, 5, 6, 7, 8, 9]), ("picking", [5, 6, 7, 8, 9])):
        np.testing.assert_array_equal(np.array(modes[name][0])[shared], np.array(modes["shooting"][0])[shared])
    assert all(mode[10] >= 30 for name in ("kicking", "picking", "shooting") for mode in modes[name])


def test_generator_draws_every_articulation_mode():
    for name in TABLE1_CLASSES:
        assert len(POSE_MODES[name]) >= 2
        assert POSE_MODES[name][next(iter(POSE_MODES[name]))] == POSES[name]
        templates = list(POSE_MODES[name].values())
        # The modes are genuinely different articulations (at least 25 degrees on some limb).
        assert np.max(np.abs(np.subtract(templates[0], templates[1]))) >= 25
    data = make_pose_dataset(TABLE1_CLASSES, 30, rng=9, noise=0.0, joint_jitter_deg=0.0, length_jitter=0.0,
                                 max_rotation_deg=0.0)
    for name in TABLE1_CLASSES:
        mask = data.labels == name
        assert set(data.modes[mask]) == set(POSE_MODES[name])
        # Without jitter, every example equals its mode's template up to a similarity.
        for shape, mode in zip(data.shapes[mask], data.modes[mask]):
            template = skeleton_strokes(np.array([POSE_MODES[name][mode]], float), MEAN_LENGTHS[None], 6)[0]
            fit = procrustes_align(template.reshape(-1, 2), shape.reshape(-1, 2))
            assert fit.rms_error < 1e-9


# ---------------------------------------------------------------- PDM and representation
def test_pdm_modes_are_orthonormal_and_reproduce_training_data():
    rng = make_rng(0)
    basis = rng.standard_normal((10, 2))
    data = rng.standard_normal((40, 2)) @ basis.T * [1.0] + 5.0
    model = fit_pdm(data, variance_fraction=0.999)
    np.testing.assert_allclose(model.modes.T @ model.modes, np.eye(model.n_modes), atol=1e-12)
    assert model.n_modes == 2
    gamma = fit_modes(model, data, clamp=False)
    np.testing.assert_allclose(reconstruct(model, gamma), data, atol=1e-9)
    # Eq. 1 covariance eigenvalues.
    np.testing.assert_allclose(model.variances, np.linalg.eigvalsh(np.cov(data.T, bias=True))[::-1][:2], rtol=1e-9)


def test_pdm_clamp_limits_coefficients_to_three_sigma():
    rng = make_rng(1)
    data = rng.standard_normal((30, 4)) * [3.0, 2.0, 1.0, 0.5]
    model = fit_pdm(data)
    far = model.mean + 100 * model.modes[:, 0]
    gamma = fit_modes(model, far[None])
    assert gamma[0, 0] == pytest.approx(3 * np.sqrt(model.variances[0]))


def test_polar_representation_angles_and_wrapping():
    centres = np.array([[[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]]])
    shapes = np.repeat(centres[:, :, None, :], 3, axis=2)
    np.testing.assert_allclose(limb_centres(shapes), centres)
    np.testing.assert_allclose(np.rad2deg(limb_angles(centres)[0]), [180.0, 0.0, -90.0, 90.0])
    vector = polar_shape_vector(shapes)
    assert vector.shape == (1, 12)
    wrapped = wrap_angle(np.array([np.pi, -np.pi, 3 * np.pi / 2, 0.1]))
    np.testing.assert_allclose(wrapped, [np.pi, np.pi, -np.pi / 2, 0.1])


def test_polar_angles_rotate_with_the_shape():
    data = make_pose_dataset(["boxing"], 1, rng=2)
    rotated = data.shapes @ rotation_2d(0.3).T
    delta = wrap_angle(limb_angles(limb_centres(rotated)) - limb_angles(limb_centres(data.shapes)))
    np.testing.assert_allclose(delta, 0.3, atol=1e-12)


# ---------------------------------------------------------------- EM vs scikit-learn
@pytest.mark.parametrize("n_iter", [1, 5, 20])
def test_gaussian_mixture_em_matches_sklearn(n_iter):
    from sklearn.exceptions import ConvergenceWarning
    from sklearn.mixture import GaussianMixture

    rng = make_rng(3)
    points = np.concatenate([rng.standard_normal((50, 3)), rng.standard_normal((40, 3)) * 0.5 + 2.0,
                             rng.standard_normal((30, 3)) + [0, 4, 0]])
    means0 = points[[0, 60, 100]]
    covs0 = np.stack([np.eye(3), 2 * np.eye(3), np.diag([1.0, 2.0, 3.0])])
    weights0 = np.array([0.5, 0.3, 0.2])
    ours = fit_gaussian_mixture(points, 3, means_init=means0, covariances_init=covs0, weights_init=weights0,
                                n_iter=n_iter)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        peer = GaussianMixture(3, means_init=means0, precisions_init=np.linalg.inv(covs0), weights_init=weights0,
                               max_iter=n_iter, tol=0, reg_covar=0).fit(points)
    np.testing.assert_allclose(ours.weights, peer.weights_, atol=1e-10)
    np.testing.assert_allclose(ours.means, peer.means_, atol=1e-10)
    np.testing.assert_allclose(ours.covariances, peer.covariances_, atol=1e-10)
    assert np.all(np.diff(ours.log_likelihood) >= -1e-12)  # EM never decreases the likelihood


# ---------------------------------------------------------------- label model
def test_hamming_counts_mismatches_and_label_probability():
    strings = np.array([[0, 1, 2], [0, 0, 0]])
    dictionary = np.array([[0, 1, 2], [1, 1, 1]])
    np.testing.assert_array_equal(hamming_distance(strings, dictionary), [[0, 2], [2, 3]])
    logp = label_string_log_prob(np.array([0, 1]), 3, 0.1)
    np.testing.assert_allclose(np.exp(logp), [0.9**3, 0.9**2 * 0.1])


# ---------------------------------------------------------------- recogniser
def test_recogniser_accuracy_and_probabilities(small_problem):
    _, test, recogniser = small_problem
    proba = recogniser.predict_proba(test.shapes)
    np.testing.assert_allclose(proba.sum(axis=1), 1.0)
    accuracy = np.mean(recogniser.predict(test.shapes) == test.labels)
    assert accuracy > 0.8
    # The clearly distinct classes are recognised almost perfectly.
    for name in ("boxing", "stretching", "relaxing"):
        mask = test.labels == name
        assert np.mean(recogniser.predict(test.shapes[mask]) == name) >= 0.9


def test_recogniser_is_similarity_invariant(small_problem):
    _, test, recogniser = small_problem
    moved = 1.7 * test.shapes[:20] @ rotation_2d(0.4).T + np.array([3.0, -2.0])
    np.testing.assert_allclose(recogniser.predict_proba(moved), recogniser.predict_proba(test.shapes[:20]),
                               atol=1e-6)


def test_recognition_trace_iterates_and_converges(small_problem):
    _, test, recogniser = small_problem
    trace = recogniser.recognise(test.shapes)
    assert 1 <= trace.n_iter <= MAX_RECOGNITION_ITER
    assert trace.posteriors.shape == (trace.n_iter, len(test.shapes), 6)
    if trace.n_iter < MAX_RECOGNITION_ITER:
        # Converged: refining labels with the final winner changes nothing.
        best = trace.posteriors[-1].argmax(axis=1)
        assert best.shape == (len(test.shapes),)


def test_baseline_and_mds_sanity(small_problem):
    train, test, _ = small_problem
    nearest = NearestProcrustesMeanClassifier().fit(train.shapes, train.labels)
    assert np.mean(nearest.predict(test.shapes[::5]) == test.labels[::5]) > 0.7
    points = make_rng(0).standard_normal((12, 3))
    embedded = classical_mds(pairwise_distances(points), 3)
    np.testing.assert_allclose(pairwise_distances(embedded), pairwise_distances(points), atol=1e-9)


def test_iterative_alignment_reduces_misfit(small_problem):
    _, test, recogniser = small_problem
    shape = test.shapes[test.labels == "stretching"][0]
    trace = recogniser.iterative_alignment(shape, "stretching", 4)
    assert trace.model_shapes.shape == (4,) + shape.shape
    assert trace.centre_rms[-1] < trace.centre_rms[0]


def test_score_components_polar_term_recognises_distinct_classes(small_problem):
    _, test, recogniser = small_problem
    parts = recogniser.score_components(test.shapes)
    assert parts.shape.shape == parts.limb_gate.shape == parts.label_string.shape == (len(test.shapes), 6, 2)
    predicted = np.asarray(recogniser.classes_)[np.argmax(parts.class_scores("shape"), axis=1)]
    assert np.mean(predicted == test.labels) > 0.8
    # All three terms together are the first iteration of recognise().
    full = parts.class_scores("shape", "limb_gate", "label_string")
    first = recogniser.recognise(test.shapes[:20]).posteriors[0]
    expected = np.exp(full[:20] - np.logaddexp.reduce(full[:20], axis=1, keepdims=True))
    np.testing.assert_allclose(first, expected, atol=1e-12)


def test_printed_eq11_scores_multiply_log_likelihood_by_gates(small_problem):
    _, test, recogniser = small_problem
    parts = recogniser.score_components(test.shapes)
    gates = np.exp(parts.limb_gate + parts.label_string)
    expected = np.einsum("cm,ncm,ncm->nc", np.exp(parts.log_weights), gates, parts.shape)
    np.testing.assert_allclose(parts.printed_eq11_scores(), expected, rtol=1e-12)
    # A class with a vanishing gate and a negative ln p scores close to 0, above a fitting class.
    classes = np.asarray(recogniser.classes_)
    ours = np.mean(classes[np.argmax(parts.class_scores("shape", "limb_gate", "label_string"), 1)] == test.labels)
    printed = np.mean(classes[np.argmax(parts.printed_eq11_scores(), 1)] == test.labels)
    assert printed < ours


def test_dictionary_has_one_string_per_class_component(small_problem):
    train, _, recogniser = small_problem
    assert recogniser.dictionary_.shape == (6, 2, 13)
    assert recogniser.dictionary_.min() >= 0 and recogniser.dictionary_.max() < recogniser.settings.n_limb_labels
    # With one component the string is the per-limb majority MAP label of the class.
    single = ArticulatedShapeRecogniser(ONE_COMPONENT, rng=0).fit(train.shapes, train.labels)
    j = single.classes_.index("boxing")
    labels = single.training_label_strings_[train.labels == "boxing"]
    majority = [np.bincount(labels[:, k], minlength=single.settings.n_limb_labels).argmax() for k in range(13)]
    np.testing.assert_array_equal(single.dictionary_[j, 0], majority)


def test_block_polar_pdm_models_angles_and_centres_separately(small_problem):
    train, _, recogniser = small_problem
    single = ArticulatedShapeRecogniser(ONE_COMPONENT, rng=0).fit(train.shapes, train.labels)
    j = single.classes_.index("stretching")
    model = single.shape_models_[j][0]
    assert [b.stop - b.start for b in model.blocks] == [13, 26]
    deviation = angles_about_mean(polar_shape_vector(single.align(train.shapes[train.labels == "stretching"])), single.angle_means_[j])
    # The angle PDM's eigenvalues are those of the angle covariance alone (the alpha_k that clamp Gamma).
    angle_cov = np.cov(deviation[:, :13].T, bias=True)
    top = np.sort(np.linalg.eigvalsh(angle_cov))[::-1][: model.pdms[0].n_modes]
    np.testing.assert_allclose(model.pdms[0].variances, top, rtol=1e-10)
    # The log-density is the sum of the two blocks' densities; a joint model has one block.
    joint_settings = RecogniserSettings(n_shape_components=1, polar_model="joint")
    joint = ArticulatedShapeRecogniser(joint_settings, rng=0).fit(train.shapes, train.labels)
    assert len(joint.shape_models_[j][0].pdms) == 1
    fitted = model.project(deviation)
    assert fitted.shape == deviation.shape
    assert np.all(np.isfinite(model.log_density(deviation)))


def test_limb_likelihood_options_give_label_posteriors(small_problem):
    train, test, recogniser = small_problem
    residual = ArticulatedShapeRecogniser(RecogniserSettings(limb_likelihood="residual"), rng=0).fit(
        train.shapes, train.labels)
    for model in (recogniser, residual):
        posteriors = model.limb_label_posteriors(test.shapes[:5])
        np.testing.assert_allclose(posteriors.sum(axis=2), 1.0)


def test_shape_level_mixture_separates_articulation_modes(small_problem):
    train, _, recogniser = small_problem
    vectors = polar_shape_vector(recogniser.align(train.shapes))
    for j, name in enumerate(recogniser.classes_):
        assert len(recogniser.shape_models_[j]) == recogniser.settings.n_shape_components == 2
        np.testing.assert_allclose(recogniser.shape_weights_[j].sum(), 1.0)
    # Boxing's and stretching's modes move the arm centres a lot: EM must put them in different components.
    for name in ("boxing", "stretching"):
        j = recogniser.classes_.index(name)
        mask = train.labels == name
        scores, _ = recogniser._component_log_likelihoods(angles_about_mean(vectors[mask], recogniser.angle_means_[j]), j)
        component = recogniser.training_components_[j]
        np.testing.assert_array_equal(component, scores.argmax(axis=1))
        for mode in POSE_MODES[name]:
            assert len(set(component[train.modes[mask] == mode])) == 1
        assert len(set(component)) == 2


def test_single_component_is_one_polar_pdm_per_class(small_problem):
    train, test, _ = small_problem
    single = ArticulatedShapeRecogniser(ONE_COMPONENT, rng=0).fit(train.shapes, train.labels)
    vectors = polar_shape_vector(single.align(train.shapes))
    j = single.classes_.index("kicking")
    deviation = angles_about_mean(vectors[train.labels == "kicking"], single.angle_means_[j])
    np.testing.assert_allclose(single.shape_models_[j][0].mean, deviation.mean(axis=0), atol=1e-12)
    np.testing.assert_allclose(single.shape_weights_[j], [1.0])
    again = ArticulatedShapeRecogniser(rng=0).fit(train.shapes, train.labels)  # the seeded EM is reproducible
    np.testing.assert_array_equal(again.predict_proba(test.shapes[:10]),
                                  ArticulatedShapeRecogniser(rng=0).fit(train.shapes, train.labels).predict_proba(test.shapes[:10]))


def test_polar_mixture_components_are_weighted_moments_in_original_units():
    from amdo_lab.pdm_mixtures.polar_mixture import fit_polar_mixture, polar_blocks

    rng = make_rng(3)
    # Two clusters; angles (radians) and centres (small units) on very different scales.
    data = np.concatenate([rng.standard_normal((15, 39)), rng.standard_normal((15, 39)) + 4.0])
    data[:, 13:] *= 1e-2
    models, weights, resp = fit_polar_mixture(data, 2, polar_blocks("block"), make_rng(0), 20, 0.95)
    np.testing.assert_allclose(weights.sum(), 1.0)
    np.testing.assert_allclose(resp.sum(axis=1), 1.0)
    for m, model in enumerate(models):
        expected = resp[:, m] @ data / resp[:, m].sum()  # eq. 7, normalised, in the data's own units
        np.testing.assert_allclose(model.mean, expected, rtol=1e-9, atol=1e-12)
    assert sorted(np.round(resp[:, 0]).astype(int).tolist()) == [0] * 15 + [1] * 15  # the clusters are found


# ---------------------------------------------------------------- open choices: ridge, restarts, held-out likelihood
def test_shape_ridge_and_n_restarts_default_to_the_previous_recogniser(small_problem):
    train, test, recogniser = small_problem
    explicit_settings = RecogniserSettings(shape_ridge=1e-3, n_restarts=1)
    explicit = ArticulatedShapeRecogniser(explicit_settings, rng=0).fit(train.shapes, train.labels)
    np.testing.assert_array_equal(explicit.predict_proba(test.shapes[:20]), recogniser.predict_proba(test.shapes[:20]))


def test_larger_shape_ridge_raises_the_component_residual_variance(small_problem):
    train, _, recogniser = small_problem
    wide = ArticulatedShapeRecogniser(RecogniserSettings(shape_ridge=1e-1), rng=0).fit(
        train.shapes, train.labels)
    for narrow_components, wide_components in zip(recogniser.shape_models_, wide.shape_models_):
        narrow_floor = min(c.pdms[1].residual_variance for c in narrow_components)
        wide_floor = min(c.pdms[1].residual_variance for c in wide_components)
        assert wide_floor > narrow_floor


def test_em_restarts_keep_the_start_with_the_highest_training_likelihood(monkeypatch):
    from amdo_lab.pdm_mixtures import polar_mixture as module

    rng = make_rng(5)
    data = np.concatenate([rng.standard_normal((12, 39)), rng.standard_normal((12, 39)) + 1.5])
    runs = []

    def recording_em(*args, **kwargs):
        result = fit_gaussian_mixture(*args, **kwargs)
        runs.append(result)
        return result

    monkeypatch.setattr(module, "fit_gaussian_mixture", recording_em)
    _, weights, resp = module.fit_polar_mixture(data, 2, module.polar_blocks("block"), make_rng(0), 15, 0.95,
                                                 n_restarts=4)
    assert len(runs) == 4
    best = max(runs, key=lambda run: run.log_likelihood[-1])
    np.testing.assert_array_equal(resp, best.responsibilities)
    runs.clear()
    _, _, first = module.fit_polar_mixture(data, 2, module.polar_blocks("block"), make_rng(0), 15, 0.95)
    assert len(runs) == 1  # one start by default, the same first start
    assert best.log_likelihood[-1] >= runs[0].log_likelihood[-1]


def test_held_out_log_likelihood_is_deterministic(small_problem):
    from amdo_lab.pdm_mixtures import held_out_log_likelihood

    train, _, recogniser = small_problem
    j = recogniser.classes_.index("boxing")
    vectors = angles_about_mean(polar_shape_vector(recogniser.align(train.shapes[train.labels == "boxing"])),
                                    recogniser.angle_means_[j])  # 12 shapes
    one = held_out_log_likelihood(vectors, 1, n_folds=4, rng=0)
    assert np.isfinite(one) and one == held_out_log_likelihood(vectors, 1, n_folds=4, rng=0)
    assert np.isfinite(held_out_log_likelihood(vectors, 2, n_folds=3, shape_ridge=1e-2, rng=0))


# ---------------------------------------------------------------- small inputs for the rejection table (end of file)
_RNG = make_rng(21)
_VECTORS = _RNG.standard_normal((10, 4))
_PDM = fit_pdm(_VECTORS)
_SHAPES = make_pose_dataset(TABLE1_CLASSES[:1], 2, rng=0).shapes
_TWO_BOXING = np.array(["boxing", "boxing"])
_EYES = np.stack([np.eye(2)] * 2)


@pytest.fixture(scope="module")
def fitted(small_problem):
    """The fitted recogniser and baselines, training and test data and axes for the cases below."""
    import types

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    train, test, recogniser = small_problem
    baselines = {cls: _make(cls).fit(train.shapes, train.labels)
                 for cls in (pm.SingleCartesianPDMClassifier, NearestProcrustesMeanClassifier, pm.SklearnGMMClassifier)}
    fig, ax = plt.subplots()
    yield types.SimpleNamespace(train=train, test=test, recogniser=recogniser, baselines=baselines, ax=ax,
                                vector=recogniser.shape_models_[0][0].mean, labels=recogniser.dictionary_[0, 0],
                                nan_labels=np.where(train.labels == "boxing", np.nan, 1.0))
    plt.close(fig)


_BASELINES = (pm.SingleCartesianPDMClassifier, NearestProcrustesMeanClassifier, pm.SklearnGMMClassifier)


def _make(cls):
    """A baseline with its default settings (the scikit-learn mixture seeded with 0)."""
    return cls(rng=0) if cls is pm.SklearnGMMClassifier else cls()


# ---------------------------------------------------------------- mode separation, reference paths
def test_mode_separation_default_is_unchanged_and_zero_merges_the_modes():
    default = make_pose_dataset(TABLE1_CLASSES, 6, rng=11)
    explicit = make_pose_dataset(TABLE1_CLASSES, 6, rng=11, mode_separation=1.0)
    assert np.array_equal(default.shapes, explicit.shapes)
    still = dict(noise=0.0, joint_jitter_deg=0.0, length_jitter=0.0, max_rotation_deg=0.0)
    merged = make_pose_dataset(("boxing",), 8, rng=3, mode_separation=0.0, **still)
    assert len(set(merged.modes)) == 2  # both modes drawn, yet they coincide
    normalised = np.stack([_normalise_shape(s.reshape(-1, 2)) for s in merged.shapes])
    assert np.allclose(normalised, normalised[0], atol=1e-12)
    spread = {level: np.ptp(pm.limb_angles(pm.limb_centres(make_pose_dataset(
        ("boxing",), 8, rng=3, mode_separation=level, **still).shapes))[:, 3]) for level in (1.0, 1.5)}
    assert spread[1.5] > spread[1.0] > 0.1  # the left upper arm's two modes move apart


def test_ppca_log_density_is_the_gaussian_of_the_pdm_covariance():
    rng = make_rng(4)
    data = rng.standard_normal((40, 6)) @ rng.standard_normal((6, 6))
    model = pm.fit_pdm(data, variance_fraction=0.8)
    phi = model.modes
    covariance = phi @ np.diag(model.variances) @ phi.T + model.residual_variance * (np.eye(6) - phi @ phi.T)
    inside = model.mean + 0.5 * (rng.standard_normal((5, model.n_modes)) * np.sqrt(model.variances)) @ phi.T \
        + 0.01 * rng.standard_normal((5, 6))
    expected = _gaussian_log_density(inside, model.mean[None], covariance[None])[:, 0]
    assert np.allclose(pm.ppca_log_density(model, inside), expected)


def test_single_cartesian_pdm_scores_with_the_one_ppca_density(small_problem):
    train, test, _ = small_problem
    classifier = pm.SingleCartesianPDMClassifier().fit(train.shapes, train.labels)
    vectors = _align_to_reference(test.shapes[:5].reshape(5, -1, 2), classifier.reference_).reshape(5, -1)
    expected = np.stack([pm.ppca_log_density(m, vectors) for m in classifier.models_], axis=1)
    assert np.allclose(classifier.log_likelihoods(test.shapes[:5]), expected)


def test_reference_paths_equal_fast_paths():
    from amdo_lab.pdm_mixtures.gmm import gaussian_log_density_reference
    from amdo_lab.pdm_mixtures.pdm import _align_to_reference_loop
    from amdo_lab.pdm_mixtures.labels import hamming_distance_reference

    rng = make_rng(8)
    points, means = rng.standard_normal((30, 4)), rng.standard_normal((3, 4))
    factors = rng.standard_normal((3, 4, 4))
    covariances = factors @ np.swapaxes(factors, 1, 2) + 0.1 * np.eye(4)
    assert np.allclose(_gaussian_log_density(points, means, covariances),
                       gaussian_log_density_reference(points, means, covariances))
    strings, dictionary = rng.integers(0, 4, (7, 13)), rng.integers(0, 4, (5, 13))
    assert np.array_equal(pm.hamming_distance(strings, dictionary), hamming_distance_reference(strings, dictionary))
    sets = make_pose_dataset(TABLE1_CLASSES, 3, rng=5).shapes.reshape(18, -1, 2)
    reference = _normalise_shape(sets[0])
    assert np.allclose(_align_to_reference(sets, reference), _align_to_reference_loop(sets, reference), atol=1e-12)


def test_limb_label_posteriors_are_distributions(small_problem):
    _, test, recogniser = small_problem
    posteriors = recogniser.limb_label_posteriors(test.shapes[:4])
    assert posteriors.shape == (4, 13, recogniser.settings.n_limb_labels)
    assert np.allclose(posteriors.sum(axis=2), 1.0)
    gates = recogniser.score_components(test.shapes[:4]).limb_gate
    log_posteriors = recogniser.limb_label_posteriors(test.shapes[:4], log=True)
    assert np.allclose(np.exp(log_posteriors), posteriors)
    n_classes, n_components, _ = recogniser.dictionary_.shape
    for c in range(n_classes):
        for m in range(n_components):
            string = recogniser.dictionary_[c, m]
            assert np.allclose(log_posteriors[:, np.arange(13), string].sum(axis=1), gates[:, c, m])


def test_mode_separation_trial_is_deterministic():
    first = pm.mode_separation_trial(1.5, rng=3, n_train=6, n_test=2, classes=("boxing", "stretching"))
    again = pm.mode_separation_trial(1.5, rng=3, n_train=6, n_test=2, classes=("boxing", "stretching"))
    assert set(first.correct) == set(pm.SEPARATION_MODELS)
    for name in pm.SEPARATION_MODELS:
        assert first.correct[name].shape == (4,) and first.correct[name].dtype == bool
        assert np.array_equal(first.correct[name], again.correct[name])
        assert 0.0 <= first.rate(name) <= 1.0


def test_batched_mixture_em_equals_one_run_at_a_time():
    from amdo_lab.pdm_mixtures.gmm import fit_gaussian_mixtures_batch

    rng = make_rng(12)
    points = np.stack([np.concatenate([rng.standard_normal((25, 3)), rng.standard_normal((25, 3)) + 3.0])
                       for _ in range(4)])
    means = points[:, [0, 30]]
    covariances = np.repeat(np.eye(3)[None, None], 4, axis=0).repeat(2, axis=1)
    ridges = np.array([0.0, 1e-3, 1e-2, 0.1])
    weights, fitted_means, fitted_covariances, responsibilities = fit_gaussian_mixtures_batch(
        points, means, covariances, 15, ridges)
    for b in range(4):
        one = pm.fit_gaussian_mixture(points[b], 2, means_init=means[b], covariances_init=covariances[b],
                                      n_iter=15, reg_covar=ridges[b])
        assert np.allclose(weights[b], one.weights) and np.allclose(fitted_means[b], one.means)
        assert np.allclose(fitted_covariances[b], one.covariances)
        assert np.allclose(responsibilities[b], one.responsibilities)


def test_nearest_mean_distances_equal_the_procrustes_loop(small_problem):
    train, test, _ = small_problem
    classifier = pm.NearestProcrustesMeanClassifier().fit(train.shapes, train.labels)
    assert np.allclose(classifier.distances(test.shapes[:20]), classifier._distances_loop(test.shapes[:20]))


def test_draw_shape_draws_one_collection():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    pm.draw_shape(ax, make_pose_dataset(("boxing",), 1, rng=0).shapes[0], label="boxing")
    assert len(ax.collections) == 1 and ax.get_legend_handles_labels()[1] == ["boxing"]
    plt.close(fig)


# ---------------------------------------------------------------- the rng convention
_DRAWING = {
    "make_pose_dataset": (make_pose_dataset, lambda rng: make_pose_dataset(TABLE1_CLASSES, 2, rng=rng)),
    "ArticulatedShapeRecogniser": (ArticulatedShapeRecogniser,  # estimators check their settings in fit
                                   lambda rng: ArticulatedShapeRecogniser(rng=rng).fit(_SHAPES, _TWO_BOXING)),
    "SklearnGMMClassifier": (pm.SklearnGMMClassifier,
                             lambda rng: pm.SklearnGMMClassifier(rng=rng).fit(_SHAPES, _TWO_BOXING)),
    "held_out_log_likelihood": (pm.held_out_log_likelihood,
                                lambda rng: pm.held_out_log_likelihood(np.zeros((12, 39)), 1, rng=rng)),
    "mode_separation_trial": (pm.mode_separation_trial, lambda rng: pm.mode_separation_trial(1.0, rng=rng)),
}


@pytest.mark.parametrize("name", sorted(_DRAWING))
def test_drawing_functions_take_a_keyword_rng_without_default(name):
    import inspect

    parameter = inspect.signature(_DRAWING[name][0]).parameters["rng"]
    assert parameter.kind is inspect.Parameter.KEYWORD_ONLY
    assert parameter.default is inspect.Parameter.empty


def test_sklearn_baseline_takes_a_generator(fitted):
    """A Generator seeds each class's mixture with an int drawn from it; the same stream, the same fit."""
    first = pm.SklearnGMMClassifier(rng=make_rng(5)).fit(fitted.train.shapes, fitted.train.labels)
    again = pm.SklearnGMMClassifier(rng=make_rng(5)).fit(fitted.train.shapes, fitted.train.labels)
    np.testing.assert_array_equal(first.predict(fitted.test.shapes), again.predict(fitted.test.shapes))
    assert np.mean(first.predict(fitted.test.shapes) == fitted.test.labels) > 0.5


def test_docstring_examples_run_as_printed():
    import doctest

    from amdo_lab.pdm_mixtures import pdm, poses, recogniser, recognition

    for module in (poses, pdm, recogniser, recognition):
        result = doctest.testmod(module, optionflags=doctest.NORMALIZE_WHITESPACE)
        assert result.failed == 0 and result.attempted > 0, module.__name__


# ---------------------------------------------------------------- scikit-learn's estimator contract
def test_estimators_store_settings_as_given_learn_underscored_attributes_and_fit_returns_self(fitted):
    import inspect

    cases = [
        (ArticulatedShapeRecogniser, dict(settings=RecogniserSettings(n_limb_labels=np.int64(4)), rng=make_rng(0))),
        (pm.SingleCartesianPDMClassifier, dict(variance_fraction=0.9)),
        (NearestProcrustesMeanClassifier, {}),
        (pm.SklearnGMMClassifier, dict(n_components=2, rng=0)),
    ]
    for cls, settings in cases:
        model = cls(**settings)
        for name, value in settings.items():
            assert getattr(model, name) is value, (cls.__name__, name)
        assert model.fit(fitted.train.shapes, fitted.train.labels) is model
        parameters = inspect.signature(cls).parameters
        assert all(name in parameters or name.endswith("_") for name in vars(model)), cls.__name__
    with pytest.raises(ValueError, match="n_limb_labels"):  # the settings are checked when built
        RecogniserSettings(n_limb_labels=0)
    with pytest.raises(TypeError, match="settings"):  # and fit checks that it was given settings
        ArticulatedShapeRecogniser({"n_limb_labels": 4}, rng=0).fit(fitted.train.shapes, fitted.train.labels)


def test_a_refit_forgets_the_previous_fit(small_problem):
    train, test, _ = small_problem
    model = ArticulatedShapeRecogniser(ONE_COMPONENT, rng=0).fit(train.shapes, train.labels)
    fewer = train.shapes[:, :, :4]  # 4 landmarks per limb instead of 6: accepted by a fresh fit
    model.fit(fewer, train.labels)
    assert model.landmarks_per_limb_ == 4 and model.predict(test.shapes[:3, :, :4]).shape == (3,)


def test_check_labels_takes_names_or_integer_ids():
    from amdo_lab.pdm_mixtures.pdm import _check_labels

    assert _check_labels(np.array(["a", "b"]), 2).tolist() == ["a", "b"]
    assert _check_labels(np.array([0.0, 3.0]), 2).tolist() == [0.0, 3.0]  # whole floats: ids, kept as given


def test_recognise_relabels_the_limbs_by_eq14(small_problem):
    """Eq. (14) computed by hand from the first iteration's terms gives the labels of the second."""
    _, test, recogniser = small_problem
    shapes = test.shapes[:30]
    trace = recogniser.recognise(shapes)
    parts = recogniser.score_components(shapes)
    log_post = recogniser.limb_label_posteriors(shapes, log=True)
    joint = parts.log_weights[None] + parts.shape + parts.limb_gate + parts.label_string  # (n, C, M)
    best = trace.posteriors[0].argmax(axis=1)  # eq. (13)
    component = np.argmax(joint[np.arange(len(shapes)), best], axis=1)
    p = recogniser.settings.label_error_probability
    # ln P(λ | z_k) + ln P(L(λ, k) | Λ_ω): a label off the winner's dictionary string costs k_p = ln((1-p)/p)
    off_string = recogniser.dictionary_[best, component][:, :, None] != np.arange(recogniser.settings.n_limb_labels)
    expected = np.argmax(log_post - np.log((1 - p) / p) * off_string, axis=2)
    moved = trace.n_iter > 1
    assert moved, "the test set should need a relabelling"
    np.testing.assert_array_equal(trace.label_strings[1], expected)
    assert np.any(trace.label_strings[1] != trace.label_strings[0])


def test_model_limbs_are_each_label_pdm_fitted_to_the_observed_limb_eq15(small_problem):
    """Eq. (15): a limb that is an instance of its label's PDM (within the clamp) is drawn exactly."""
    _, _, recogniser = small_problem
    rng = make_rng(30)
    labels = rng.integers(0, recogniser.settings.n_limb_labels, 13)
    observed = []
    for k, label in enumerate(labels):
        model = recogniser.limb_models_[k][label]
        gamma = rng.uniform(-1.0, 1.0, model.n_modes) * np.sqrt(model.variances)  # inside ±3√α
        observed.append(reconstruct(model, gamma[None])[0])
    observed = np.stack(observed)
    vector = np.concatenate([np.zeros(13), rng.normal(size=26)])
    drawn = recogniser.model_limbs(vector, labels, observed)
    np.testing.assert_allclose(drawn, observed.reshape(13, -1, 2) + vector[13:].reshape(13, 1, 2), atol=1e-9)
    means = recogniser.model_limbs(vector, labels)
    assert np.max(np.abs(means - drawn)) > 1e-3  # the fit moved the limbs away from their mean strokes


def test_limb_posteriors_are_eq10_bayes_rule_over_the_eq16_residual(small_problem):
    """With ``limb_likelihood="residual"`` the limb-label posterior is Bayes' rule over eq. (16)'s
    isotropic Gaussian of the clamped fit residual, computed here from the public PDM functions."""
    from amdo_lab.pdm_mixtures.representation import _centred_limbs

    train, test, _ = small_problem
    residual = ArticulatedShapeRecogniser(RecogniserSettings(limb_likelihood="residual"), rng=0).fit(
        train.shapes, train.labels)
    aligned = residual.align(test.shapes[:6])
    limbs = _centred_limbs(aligned)  # (n, K, 2m)
    for k in (0, 6, 12):
        errors = np.stack([np.sum((limbs[:, k] - reconstruct(model, fit_modes(model, limbs[:, k]))) ** 2, axis=1)
                           for model in residual.limb_models_[k]], axis=1)
        log_joint = -errors / (2 * residual.limb_noise_[k]) + np.log(residual.limb_weights_[k])  # eq. (16) x prior
        expected = log_joint - np.logaddexp.reduce(log_joint, axis=1, keepdims=True)
        np.testing.assert_allclose(residual.limb_label_posteriors(test.shapes[:6], log=True)[:, k], expected,
                                   atol=1e-10)
    labels = np.argmax(residual.limb_label_posteriors(test.shapes[:6]), axis=2)  # eq. (10)
    np.testing.assert_array_equal(residual.recognise(test.shapes[:6]).label_strings[0], labels)


# ---------------------------------------------------------------- one recognition step, eqs. 11-14
def _terms(rng):
    """Random eq. 11 terms for 4 shapes, 3 classes, 2 components (log-probabilities where they must be)."""
    shape = rng.normal(-5.0, 3.0, (4, 3, 2))
    gate, string = -rng.exponential(2.0, (4, 3, 2)), -rng.exponential(1.0, (4, 3, 2))
    log_weights = np.log(rng.dirichlet(np.ones(2), 3))
    return shape, gate, string, log_weights


def test_gated_component_scores_add_the_log_terms_or_multiply_ln_p_as_printed_eq11():
    shape, gate, string, log_weights = _terms(make_rng(40))
    ours = pm.gated_component_scores(shape, gate, string, log_weights)
    np.testing.assert_allclose(np.exp(ours), np.exp(log_weights) * np.exp(gate) * np.exp(string) * np.exp(shape),
                               rtol=1e-12)  # pi G p
    printed = pm.gated_component_scores(shape, gate, string, log_weights, reading="G ln p")
    np.testing.assert_allclose(printed, np.exp(log_weights) * np.exp(gate + string) * shape, rtol=1e-12)  # pi G ln p
    # As printed, a component whose gate vanishes scores about 0: above every component that fits (ln p < 0).
    gate[0, 1] = -800.0
    assert np.argmax(pm.gated_component_scores(shape, gate, string, log_weights, reading="G ln p")[0].sum(1)) == 1


def test_class_posteriors_are_bayes_rule_over_the_summed_components_and_printed_decides_by_argmax():
    shape, gate, string, log_weights = _terms(make_rng(41))
    scores = pm.gated_component_scores(shape, gate, string, log_weights)
    prior = np.log([0.5, 0.3, 0.2])
    posterior, shares = _class_posteriors(scores, prior, "G p")
    joint = np.exp(prior) * np.exp(scores).sum(axis=2)  # P(w) sum_m pi G p
    np.testing.assert_allclose(posterior, joint / joint.sum(axis=1, keepdims=True), rtol=1e-12)
    np.testing.assert_allclose(shares, np.exp(scores) / np.exp(scores).sum(axis=2, keepdims=True), rtol=1e-12)
    printed = pm.gated_component_scores(shape, gate, string, log_weights, reading="G ln p")
    hard, hard_shares = _class_posteriors(printed, prior, "G ln p")
    np.testing.assert_array_equal(hard.argmax(axis=1), printed.sum(axis=2).argmax(axis=1))
    assert set(np.unique(hard)) == {0.0, 1.0} and np.all(hard.sum(axis=1) == 1) and np.all(hard_shares.sum(2) == 1)


def test_winning_components_take_the_map_class_and_its_best_component_eq13():
    posterior = np.array([[0.1, 0.7, 0.2], [0.6, 0.3, 0.1]])
    scores = np.zeros((2, 3, 2))
    scores[0, 1] = [-3.0, -1.0]  # the winner of shape 0 is class 1, its component 1 scores higher
    scores[1, 0] = [-0.5, -2.0]
    scores[1, 1] = [-9.0, 5.0]  # a high score in a losing class does not count
    best, component = pm.winning_components(posterior, scores)
    assert best.tolist() == [1, 0] and component.tolist() == [1, 0]


def test_relabel_limbs_charges_k_p_per_disagreement_with_the_winning_string_eq14():
    p = 0.2  # k_p = ln 4 = 1.386 nats per mismatch
    log_post = np.log(np.array([[[0.5, 0.5], [0.7, 0.3], [0.9, 0.1]]]))  # 1 shape, 3 limbs, 2 labels
    relabelled = pm.relabel_limbs(log_post, np.array([[1, 1, 1]]), p)
    # limb 0: a tie broken by the string; limb 1: ln(0.7/0.3) = 0.85 < k_p; limb 2: ln 9 = 2.2 > k_p
    assert relabelled.tolist() == [[1, 1, 0]]
    assert pm.relabel_limbs(log_post, np.array([[0, 0, 0]]), p).tolist() == [[0, 0, 0]]
    # a weaker string (p near 0.5) leaves the limbs to their own posteriors
    assert pm.relabel_limbs(log_post, np.array([[1, 1, 1]]), 0.45).tolist() == [[1, 0, 0]]


def test_polar_pdm_project_is_the_clamped_modal_fit_of_each_block_eq12(small_problem):
    train, _, recogniser = small_problem
    j = recogniser.classes_.index("boxing")
    component = recogniser.shape_models_[j][0]
    deviation = angles_about_mean(polar_shape_vector(recogniser.align(train.shapes[train.labels == "boxing"])),
                                  recogniser.angle_means_[j])
    deviation[0, :13] += 5.0  # far outside the angle modes: the clamp must act
    fitted = component.project(deviation)
    for pdm, block in zip(component.pdms, component.blocks):
        gamma = (deviation[:, block] - pdm.mean) @ pdm.modes  # least squares, then the +-3 sqrt(alpha_k) clamp
        bound = 3 * np.sqrt(pdm.variances)
        np.testing.assert_allclose(fitted[:, block], pdm.mean + np.clip(gamma, -bound, bound) @ pdm.modes.T,
                                   atol=1e-12)
    angles = component.pdms[0]
    assert np.any(np.abs((fitted[0, :13] - angles.mean) @ angles.modes) >= 3 * np.sqrt(angles.variances) - 1e-12)


def test_the_printed_eq11_reading_is_a_recogniser_option(small_problem):
    train, test, recogniser = small_problem
    printed = ArticulatedShapeRecogniser(RecogniserSettings(eq11_reading="G ln p"), rng=0).fit(
        train.shapes, train.labels)
    first = printed.recognise(test.shapes).posteriors[0]
    parts = recogniser.score_components(test.shapes)
    np.testing.assert_array_equal(first.argmax(axis=1), parts.printed_eq11_scores().argmax(axis=1))
    assert np.mean(printed.predict(test.shapes) == test.labels) < np.mean(recogniser.predict(test.shapes) == test.labels)


# ---------------------------------------------------------------- rejections: one table
# tests/test_bad_input.py already spoils every argument of every public callable (NaN, inf or 1e308
# inside, empty, a wrong trailing axis, one axis more, a string, None, a bool, zero/negative/float counts,
# probabilities outside [0, 1], bad seeds) and checks that the error names the argument. This table holds
# what that test cannot see: the rules of the method (13 limbs, enough training examples per class and
# component, positive-definite covariances, open intervals), unknown names, shapes set by another argument
# or by the fitted model, one axis too few, not-fitted errors and the rng convention.
# A call's parameters without a default name the fixtures it needs (``small_problem``, ``fitted``).
def _two_kicking(small_problem):
    """The training set with only two kicking examples: too few for two components of 3 (or 1 of 3)."""
    train, _, _ = small_problem
    keep = np.r_[np.flatnonzero(train.labels != "kicking"), np.flatnonzero(train.labels == "kicking")[:2]]
    return train.shapes[keep], train.labels[keep]


def _boxing_vectors(small_problem):
    """The 12 boxing training shapes as polar deviations from their class mean."""
    train, _, recogniser = small_problem
    j = recogniser.classes_.index("boxing")
    return angles_about_mean(polar_shape_vector(recogniser.align(train.shapes[train.labels == "boxing"])),
                                 recogniser.angle_means_[j])


REJECTIONS = [
    # ------------------------------------------------------------ generator
    reject("make_pose_dataset unknown class", lambda: make_pose_dataset(["boxing", "dancing"], 3, rng=0),
           ValueError, r"classes holds unknown name\(s\) \[.dancing.\]"),
    reject("make_pose_dataset no classes", lambda: make_pose_dataset([], 2, rng=0),
           ValueError, "classes must hold at least one name"),
    reject("skeleton_strokes two directions, one length",
           lambda: skeleton_strokes(np.zeros((2, 13)), MEAN_LENGTHS[None], 6), ValueError, r"lengths must have shape \(2, 13\)"),
    reject("skeleton_strokes negative lengths", lambda: skeleton_strokes(np.zeros((1, 13)), -MEAN_LENGTHS[None], 6),
           ValueError, r"lengths must lie in \(0, 1e\+06\], got -0.2"),
    reject("skeleton_strokes one landmark per limb", lambda: skeleton_strokes(np.zeros((1, 13)), MEAN_LENGTHS[None], 1),
           ValueError, "landmarks_per_limb must be at least 2"),
    reject("mode_separation_trial n_train 2", lambda: pm.mode_separation_trial(1.0, rng=3, n_train=2),
           ValueError, "n_train must be at least 6"),
    # ------------------------------------------------------------ point distribution models
    reject("fit_pdm variance_fraction 0", lambda: fit_pdm(_VECTORS, variance_fraction=0.0),
           ValueError, r"variance_fraction must be in \(0, 1\], got 0.0"),
    reject("fit_pdm one column", lambda: fit_pdm(_VECTORS[:, :1]), ValueError,
           r"long_vectors needs at least 3 rows \(examples\) and 2 columns, got shape \(10, 1\)"),
    reject("fit_modes observed longer than the model", lambda: fit_modes(_PDM, np.ones((2, 3))),
           ValueError, r"observed must have shape \(n, 4\)"),
    reject("reconstruct gamma longer than the modes", lambda: reconstruct(_PDM, np.zeros((2, _PDM.n_modes + 1))),
           ValueError, "gamma must have shape"),
    reject("ppca_log_density observed shorter than the model",
           lambda: pm.ppca_log_density(fit_pdm(_RNG.standard_normal((10, 6))), np.zeros((2, 5))),
           ValueError, r"observed must have shape \(n, 6\)"),
    reject("generalized_procrustes coinciding set", lambda: generalized_procrustes(np.ones((3, 4, 2))),
           ValueError, "point_sets must not contain a point set whose points all coincide"),
    # ------------------------------------------------------------ polar representation: one axis too few
    reject("articulation_centre one shape's centres", lambda: pm.articulation_centre(np.ones((13, 2))),
           ValueError, "centres must have shape"),
    reject("polar_shape_vector one shape", lambda: polar_shape_vector(_SHAPES[0]), ValueError, "shapes must have shape"),
    # ------------------------------------------------------------ Gaussian mixture
    reject("fit_gaussian_mixture negative definite start",
           lambda: fit_gaussian_mixture(_RNG.standard_normal((6, 2)), 2, means_init=np.zeros((2, 2)),
                                        covariances_init=-_EYES), ValueError, "covariances_init must be positive definite"),
    reject("fit_gaussian_mixture boolean X",
           lambda: fit_gaussian_mixture(np.ones((6, 2), bool), 2, means_init=np.zeros((2, 2)), covariances_init=_EYES),
           TypeError, "X must be a numeric array"),
    reject("fit_gaussian_mixture more components than points",
           lambda: fit_gaussian_mixture(np.zeros((2, 2)), 3, means_init=np.zeros((3, 2)),
                                        covariances_init=np.zeros((3, 2, 2))),
           ValueError, "n_components must be at most 2, got 3"),
    reject("held_out_log_likelihood one fold", lambda small_problem: pm.held_out_log_likelihood(
        _boxing_vectors(small_problem), 1, n_folds=1, rng=0), ValueError, "n_folds"),
    # 9 rows per training split; 4 components need 12
    reject("held_out_log_likelihood too few rows per fold", lambda small_problem: pm.held_out_log_likelihood(
        _boxing_vectors(small_problem), 4, n_folds=4, rng=0), ValueError, "too few for n_components=4"),
    # ------------------------------------------------------------ label model
    reject("hamming_distance strings and dictionary differ",
           lambda: hamming_distance(np.zeros((2, 13), int), np.ones((3, 12), int)),
           ValueError, r"dictionary \(like label_strings\) must have shape \(n, 13\), got \(3, 12\)"),
    reject("hamming_distance one string", lambda: hamming_distance(np.zeros(13, int), np.ones((3, 13), int)),
           ValueError, "label_strings must have 2 dimensions"),
    reject("hamming_distance fractional labels", lambda: hamming_distance(np.full((2, 13), 0.5), np.ones((3, 13))),
           ValueError, "label_strings must hold whole numbers"),
    reject("label_string_log_prob error_probability 0", lambda: label_string_log_prob(np.array([1]), 13, 0.0),
           ValueError, r"error_probability must be in \(0, 1\), got 0.0"),
    reject("label_string_log_prob error_probability 1", lambda: label_string_log_prob(np.array([1]), 13, 1.0),
           ValueError, r"error_probability must be in \(0, 1\)"),
    reject("label_string_log_prob distance beyond n_limbs", lambda: label_string_log_prob(np.array([20]), 13, 0.2),
           ValueError, r"hamming must lie in \[0, 13\], got 20"),
    reject("_check_labels fractional id", lambda: _check_labels(np.array([0.0, 0.5]), 2),
           ValueError, "labels must hold whole numbers"),
    reject("_check_labels huge id", lambda: _check_labels(np.array([0.0, 1e308]), 2),
           ValueError, "labels must be at most 9.0072e"),
    reject("_check_labels NaN", lambda: _check_labels(np.array([0.0, np.nan]), 2), ValueError, "labels must be finite"),
    # ------------------------------------------------------------ embeddings
    reject("pairwise_distances one vector", lambda: pairwise_distances(np.ones(3)), ValueError, "vectors must have 2 dimensions"),
    reject("classical_mds negative distances", lambda: classical_mds(-np.ones((3, 3))),
           ValueError, r"distances must lie in \[0, 1e\+150\], got -1"),
    reject("classical_mds more dimensions than points", lambda: classical_mds(np.zeros((3, 3)), 4),
           ValueError, "n_dims must be at most 3, got 4"),
    reject("pca_embedding more dimensions than min(n, d)", lambda: pm.pca_embedding(_VECTORS, 5),
           ValueError, "n_dims must be at most 4, got 5"),
    # ------------------------------------------------------------ the recogniser: settings, training set, fitted state
    reject("recogniser limb_likelihood hamming", lambda: RecogniserSettings(limb_likelihood="hamming"),
           ValueError, "limb_likelihood"),
    reject("recogniser polar_model cartesian", lambda: RecogniserSettings(polar_model="cartesian"),
           ValueError, "polar_model"),
    reject("recogniser eq11_reading unknown", lambda: RecogniserSettings(eq11_reading="ln G + ln p"),
           ValueError, "eq11_reading"),
    reject("recogniser two examples for two components", lambda small_problem: ArticulatedShapeRecogniser(
        rng=0).fit(*_two_kicking(small_problem)), ValueError, "3 shapes per shape component"),
    reject("recogniser two examples for one component", lambda small_problem: ArticulatedShapeRecogniser(
        ONE_COMPONENT, rng=0).fit(*_two_kicking(small_problem)), ValueError, "'kicking': 2"),
    reject("recogniser one label short", lambda small_problem: ArticulatedShapeRecogniser(rng=0).fit(
        small_problem[0].shapes, small_problem[0].labels[:-1]), ValueError, "labels"),
    reject("recogniser not fitted predict", lambda small_problem: ArticulatedShapeRecogniser(rng=0).predict(
        small_problem[1].shapes), NotFittedError, "not fitted"),
    reject("recogniser not fitted align", lambda fitted: ArticulatedShapeRecogniser(rng=0).align(fitted.test.shapes),
           NotFittedError, "is not fitted yet"),
    reject("recogniser not fitted model_limbs", lambda fitted: ArticulatedShapeRecogniser(rng=0).model_limbs(
        fitted.vector, fitted.labels), NotFittedError, "is not fitted yet"),
    reject("recogniser predict 12 limbs", lambda small_problem: small_problem[2].predict(
        small_problem[1].shapes[:, :12]), ValueError, "shapes"),
    reject("recogniser predict 4 landmarks per limb after 6", lambda small_problem: small_problem[2].predict(
        small_problem[1].shapes[:, :, :4]), ValueError, r"shapes must have shape \(n, 13, 6, 2\)"),
    reject("recogniser predict a coinciding shape", lambda fitted: fitted.recogniser.predict(
        np.r_[fitted.test.shapes[:1], np.ones((1, 13, 6, 2))]), ValueError,
        r"shapes must not contain a point set whose points all coincide \(zero centroid size at index 1\)"),
    reject("recogniser limb_label_posteriors 12 limbs", lambda small_problem: small_problem[2].limb_label_posteriors(
        np.zeros((2, 12, 6, 2))), ValueError, "shapes"),
    reject("recogniser iterative_alignment unknown class", lambda small_problem: small_problem[2].iterative_alignment(
        small_problem[1].shapes[0], "dancing"), ValueError, "class_name"),
    reject("recogniser class_scores polar", lambda small_problem: small_problem[2].score_components(
        small_problem[1].shapes[:2]).class_scores("polar"), ValueError, "terms"),
    reject("model_limbs label 9 of 4", lambda fitted: fitted.recogniser.model_limbs(fitted.vector, np.full(13, 9)),
           ValueError, r"label_string must lie in \[0, 3\], got 9"),
    reject("model_limbs label -1", lambda fitted: fitted.recogniser.model_limbs(fitted.vector, np.full(13, -1)),
           ValueError, r"label_string must lie in \[0, 3\], got -1"),
    reject("model_limbs observed limbs of 5 values for 6 landmarks", lambda fitted: fitted.recogniser.model_limbs(
        fitted.vector, fitted.labels, np.zeros((13, 5))), ValueError, r"observed_limbs must have shape \(13, 12\)"),
    reject("PolarPDM log_density deviation shorter than the model",
           lambda fitted: fitted.recogniser.shape_models_[0][0].log_density(np.zeros((2, 10))),
           ValueError, r"deviation must have shape \(n, 39\)"),
    reject("draw_shape 12 limbs", lambda fitted: pm.draw_shape(fitted.ax, np.zeros((12, 6, 2))), ValueError, "shape"),
    # ------------------------------------------------------------ baselines
    *[case for cls in _BASELINES for case in (
        reject(f"{cls.__name__} one label short", lambda fitted, cls=cls: _make(cls).fit(
            fitted.train.shapes, fitted.train.labels[:-1]), ValueError, r"labels and shapes \(first axis\) must have the same shape, got \(71,\) and \(72,\)"),
        reject(f"{cls.__name__} not fitted", lambda fitted, cls=cls: _make(cls).predict(fitted.test.shapes),
               NotFittedError, "is not fitted yet"),
        reject(f"{cls.__name__} 4 landmarks per limb after 6", lambda fitted, cls=cls: fitted.baselines[cls].predict(
            fitted.test.shapes[:, :, :4]), ValueError, r"shapes must have shape \(n, 13, 6, 2\)"),
        reject(f"{cls.__name__} a coinciding shape", lambda fitted, cls=cls: fitted.baselines[cls].predict(
            np.r_[np.ones((1, 13, 6, 2)), fitted.test.shapes[:1]]), ValueError,
            "shapes must not contain a point set whose points all coincide"),
    )],
    # ------------------------------------------------------------ the rng convention
    *[reject(f"{name} rng {bad!r}", lambda draw=draw, bad=bad: draw(bad), error, message)
      for name, (_, draw) in sorted(_DRAWING.items())
      for bad, error, message in (("0", TypeError, "rng must be"), (-1, ValueError, "rng must be non-negative"))],
]


@pytest.mark.parametrize(("call", "error", "message"), REJECTIONS)
def test_rejections(request, call, error, message):
    check_rejection(request, call, error, message)


# --- the chapter's exercises (amdo_lab.pdm_mixtures.exercises) ----------------------------------------

from amdo_lab.common.exercises import ExerciseSet  # noqa: E402
from amdo_lab.pdm_mixtures.exercises import EXERCISES  # noqa: E402

#: The targets the chapter's hidden tests register (the notebook is the source of truth; these are copies).
CHAPTER_TARGETS = {1: 2.2, 2: 5.1, 3: 5, 4: 0.85, 5: 0.94}


def _graded() -> ExerciseSet:
    """A fresh copy of the chapter's exercises with the hidden tests' targets registered."""
    graded = ExerciseSet(2, EXERCISES.exercises)
    for number, target in CHAPTER_TARGETS.items():
        graded.expect(number, target)
    graded.expect(6, seeds=(5, 17, 29))
    return graded


@pytest.mark.parametrize(("number", "answer", "verdict"), [
    (1, 2.2, "correct"), (1, 2.197, "correct"), (1, 1.39, "not yet"), (1, -2.2, "not yet"), (1, 2.3, "not yet"),
    (1, 0.95, "not yet"), (1, 1.37, "not yet"),
    (2, 5.1, "correct"), (2, 148.8, "not yet"), (2, -5.1, "not yet"), (2, 13.1, "not yet"), (2, 5.2, "not yet"),
    (3, 5, "correct"), (3, 19, "not yet"), (3, 156, "not yet"), (3, 6, "not yet"), (3, 4, "not yet"),
    (4, 0.85, "correct"), (4, 0.82, "not yet"), (4, 0.98, "not yet"), (4, 0.13, "not yet"),
    (5, 0.94, "correct"), (5, 1.0, "not yet"), (5, 0.33, "not yet"), (5, 0.06, "not yet"), (5, "angles", "not yet"),
    (4, None, "not attempted yet"), (6, None, "not attempted yet"),
])
def test_exercise_verdicts(number, answer, verdict):
    assert _graded().verdict(number, answer).split(":")[0] == verdict


def test_implement_it_rejects_each_recorded_wrong_em_step_and_accepts_the_diagonal_em():
    """Exercise 6: eqs. 7-8 as printed (old mean, no division), no mixing weights, full covariances."""
    graded = _graded()
    exercise = graded[6]
    for wrong in exercise.wrong_answers:
        assert graded.verdict(6, wrong.value) == "not yet: " + wrong.hint
    assert graded.verdict(6, lambda **case: exercise.reference(**case)) == "correct"  # the reference, re-typed
    assert graded.verdict(6, lambda **case: None).startswith("not yet")
    for seed in (exercise.example_seed, 5, 17, 29):
        case = exercise.make_case(seed)
        want = exercise.reference(**case)
        assert np.isclose(want[0].sum(), 1.0) and np.all(want[2] > 0)
        for wrong in exercise.wrong_answers:
            assert not exercise.outputs_match(wrong.value(**case), want), (seed, wrong.why)
