"""Tests for chapter 2 (amdo_lab.pdm_mixtures): generator invariants, PDM, polar representation,
Gaussian-mixture EM against scikit-learn, the hierarchical recogniser and bad input."""

import warnings

import numpy as np
import pytest

from amdo_lab.common import make_rng, procrustes_align, rotation_2d, spawn_rngs
from amdo_lab.pdm_mixtures import (
    LIMB_PARENTS,
    TABLE1_CLASSES,
    ArticulatedShapeRecognizer,
    NearestProcrustesMeanClassifier,
    classical_mds,
    fit_gaussian_mixture,
    fit_modes,
    fit_pdm,
    generalized_procrustes,
    generate_pose_dataset,
    hamming_distance,
    label_string_log_prob,
    limb_angles,
    limb_centres,
    pairwise_distances,
    polar_shape_vector,
    reconstruct,
    wrap_angle,
)


@pytest.fixture(scope="module")
def small_problem():
    train_rng, test_rng = spawn_rngs(7, 2)
    train = generate_pose_dataset(TABLE1_CLASSES, 12, train_rng)
    test = generate_pose_dataset(TABLE1_CLASSES, 30, test_rng)
    recogniser = ArticulatedShapeRecognizer().fit(train.shapes, train.labels)
    return train, test, recogniser


# ---------------------------------------------------------------- generator
def test_generator_shapes_labels_and_determinism():
    data = generate_pose_dataset(TABLE1_CLASSES, 5, 3, landmarks_per_limb=7)
    assert data.shapes.shape == (30, 13, 7, 2)
    assert [int(np.sum(data.labels == c)) for c in TABLE1_CLASSES] == [5] * 6
    again = generate_pose_dataset(TABLE1_CLASSES, 5, 3, landmarks_per_limb=7)
    np.testing.assert_array_equal(data.shapes, again.shapes)
    other = generate_pose_dataset(TABLE1_CLASSES, 5, 4, landmarks_per_limb=7)
    assert not np.allclose(data.shapes, other.shapes)


def test_generator_limb_lengths_and_joint_connectivity_without_noise():
    data = generate_pose_dataset(TABLE1_CLASSES, 4, 11, noise=0.0)
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


def test_generator_confusable_classes_are_closer_than_distinct_ones():
    data = generate_pose_dataset(TABLE1_CLASSES, 20, 5, noise=0.0, joint_jitter_deg=0.0, length_jitter=0.0,
                                 max_rotation_deg=0.0)
    means = {c: generalized_procrustes(data.shapes[data.labels == c].reshape(20, -1, 2))[1] for c in TABLE1_CLASSES}
    def dist(a, b):
        return procrustes_align(means[a], means[b]).rms_error
    assert dist("kicking", "shooting") < dist("kicking", "stretching")
    assert dist("picking", "shooting") < dist("picking", "stretching")


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
    data = generate_pose_dataset(["boxing"], 1, 2)
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
    assert accuracy > 0.85
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
    assert 1 <= trace.n_iterations <= recogniser.max_iter
    assert trace.posteriors.shape == (trace.n_iterations, len(test.shapes), 6)
    if trace.n_iterations < recogniser.max_iter:
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


# ---------------------------------------------------------------- bad input
def test_bad_input_raises_clear_errors(small_problem):
    train, test, recogniser = small_problem
    with pytest.raises(ValueError, match="unknown pose"):
        generate_pose_dataset(["boxing", "dancing"], 3, 0)
    with pytest.raises(ValueError, match="shapes"):
        recogniser.predict(test.shapes[:, :12])
    with pytest.raises(ValueError, match="landmarks per limb"):
        recogniser.predict(test.shapes[:, :, :4])
    bad = test.shapes[:3].copy()
    bad[0, 2, 1, 0] = np.nan
    with pytest.raises(ValueError, match="finite"):
        recogniser.predict(bad)
    with pytest.raises(ValueError, match="no training examples"):
        ArticulatedShapeRecognizer(classes=TABLE1_CLASSES).fit(train.shapes[train.labels != "boxing"],
                                                               train.labels[train.labels != "boxing"])
    with pytest.raises(ValueError, match="not in classes"):
        ArticulatedShapeRecognizer(classes=TABLE1_CLASSES[:5]).fit(train.shapes, train.labels)
    keep = np.r_[np.flatnonzero(train.labels != "kicking"), np.flatnonzero(train.labels == "kicking")[:2]]
    with pytest.raises(ValueError, match="at least 3 training examples"):
        ArticulatedShapeRecognizer().fit(train.shapes[keep], train.labels[keep])
    with pytest.raises(ValueError, match="labels"):
        ArticulatedShapeRecognizer().fit(train.shapes, train.labels[:-1])
    with pytest.raises(ValueError, match="fitted"):
        ArticulatedShapeRecognizer().predict(test.shapes)
    with pytest.raises(ValueError, match="n_components"):
        fit_gaussian_mixture(np.zeros((2, 2)), 3, means_init=np.zeros((3, 2)), covariances_init=np.zeros((3, 2, 2)))


def test_iterative_alignment_reduces_misfit_and_validates(small_problem):
    _, test, recogniser = small_problem
    shape = test.shapes[test.labels == "stretching"][0]
    trace = recogniser.iterative_alignment(shape, "stretching", 4)
    assert trace.model_shapes.shape == (4,) + shape.shape
    assert trace.centre_rms[-1] < trace.centre_rms[0]
    with pytest.raises(ValueError, match="class_name"):
        recogniser.iterative_alignment(shape, "dancing")


def test_score_components_polar_term_recognises_distinct_classes(small_problem):
    _, test, recogniser = small_problem
    parts = recogniser.score_components(test.shapes)
    assert parts.shape.shape == parts.limb_gate.shape == parts.label_string.shape == (len(test.shapes), 6)
    predicted = np.asarray(recogniser.classes_)[np.argmax(parts.shape, axis=1)]
    assert np.mean(predicted == test.labels) > 0.85


def test_generator_rejects_bad_parameters():
    with pytest.raises(ValueError, match="noise"):
        generate_pose_dataset(TABLE1_CLASSES, 2, 0, noise=-0.1)
    with pytest.raises(ValueError, match="n_per_class"):
        generate_pose_dataset(TABLE1_CLASSES, 0, 0)
    with pytest.raises(ValueError, match="empty"):
        generate_pose_dataset([], 2, 0)
    with pytest.raises(TypeError):
        generate_pose_dataset(TABLE1_CLASSES, 2, None)
