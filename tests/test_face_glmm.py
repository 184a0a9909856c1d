"""Tests for Chapter 5 (amdo_lab.face_glmm): population, PCA+LDA, experiment, GLMM."""

import dataclasses
import inspect
import sys

import numpy as np
import pandas as pd
import pytest
import scipy.linalg
from rejections import check_rejection, reject

import amdo_lab.face_glmm as fg
from amdo_lab.common import make_rng
from amdo_lab.face_glmm import (
    FactorialDesign,
    PAPER_FORMULA,
    PcaLda,
    PeerFit,
    downsample_by_two,
    fit_binomial_glmm,
    fit_with_lme4,
    make_face_population,
    lme4_available,
    make_supplement,
    parse_formula,
    preprocess_images,
    reduced_design,
    run_factorial_experiment,
    simulate_binomial_glmm,
)
from amdo_lab.face_glmm.cache import _experiment_cache_key
from amdo_lab.face_glmm.design import _build_design
from amdo_lab.face_glmm.population import _elliptical_mask


@pytest.fixture(scope="module")
def population():
    return make_face_population(40, 4, rng=3, shape=(24, 20))


@pytest.fixture(scope="module")
def reduced_table():
    return run_factorial_experiment(reduced_design(), rng=11)


def _crossed_table(n_t=6, n_p=120, seed=0):
    """A balanced t x p x (M, D, U) table, 2 x 2 x 2 rows per cell."""
    grid = pd.MultiIndex.from_product(
        [range(n_t), range(n_p), ["l2", "soft_l2"], ["fixed", "e90"], ["none", "shift"]],
        names=["t", "p", "M", "D", "U"]).to_frame(index=False)
    return grid


# --- population and preprocessing ------------------------------------------------------

def test_population_is_seeded_and_shaped(population):
    again = make_face_population(40, 4, rng=3, shape=(24, 20))
    np.testing.assert_array_equal(population.images, again.images)
    assert population.images.shape == (160, 24, 20)
    np.testing.assert_array_equal(population.labels, np.repeat(np.arange(40), 4))
    other = make_face_population(40, 4, rng=4, shape=(24, 20))
    assert not np.allclose(population.images, other.images)


def test_same_subject_images_are_closer_than_others(population):
    flat = preprocess_images(population.images).reshape(160, -1)
    d = ((flat[:, None] - flat[None]) ** 2).sum(-1)
    same = population.labels[:, None] == population.labels[None]
    np.fill_diagonal(same, False)
    other = population.labels[:, None] != population.labels[None]
    assert d[same].mean() < 0.8 * d[other].mean()


def test_power_law_texture_spreads_the_pca_spectrum():
    """texture_slope adds f^-s texture: many more eigenvectors hold 90 % of the energy (E90)."""
    from amdo_lab.face_glmm import e90_dimension, pca_basis

    def e90_of(pop):
        images = preprocess_images(pop.images).reshape(48, 4, -1)[:, 1:].reshape(144, -1)
        return e90_dimension(pca_basis(images).eigenvalues)

    smooth = make_face_population(48, 4, rng=2, shape=(40, 36), texture_slope=None)
    textured = make_face_population(48, 4, rng=2, shape=(40, 36), texture_slope=2.0, texture_amplitude=0.7)
    np.testing.assert_array_equal(smooth.difficulty, textured.difficulty)  # drawn after everything else
    assert e90_of(textured) > 2.5 * e90_of(smooth)
    default = make_face_population(48, 4, rng=2, shape=(40, 36))  # the chapter's faces: texture on
    assert e90_of(default) > 2.5 * e90_of(smooth)


def test_preprocessing_masks_equalises_and_standardises(population):
    out = preprocess_images(population.images)
    mask = _elliptical_mask(out.shape[1:])
    assert np.all(out[:, ~mask] == 0)
    inside = out[:, mask]
    np.testing.assert_allclose(inside.mean(1), 0, atol=1e-12)
    np.testing.assert_allclose(inside.std(1), 1, atol=1e-12)
    # Histogram equalisation: every image has the same (uniform) sorted value profile.
    np.testing.assert_allclose(np.sort(inside[0]), np.sort(inside[7]), atol=1e-12)


def test_downsample_has_quarter_pixels(population):
    small = downsample_by_two(population.images)
    assert small.shape[1] * small.shape[2] * 4 == population.images.shape[1] * population.images.shape[2]
    assert np.isclose(small[0, 0, 0], population.images[0, :2, :2].mean())


def test_supplements(population):
    imgs = preprocess_images(population.images[:4])
    mask = _elliptical_mask(imgs.shape[1:])
    shifted = make_supplement(imgs, "shift", rng=make_rng(0))
    np.testing.assert_allclose(shifted[:, 5, 3:10], (imgs[:, 5, 4:11] * mask[5, 3:10]))
    reflected = make_supplement(imgs, "reflection", rng=make_rng(0))
    np.testing.assert_allclose(reflected[:, :, ::-1], imgs * mask[:, ::-1])
    noisy = make_supplement(imgs, "noise", rng=make_rng(0))
    spread = (noisy - imgs)[:, mask].std(1) / (imgs.max((1, 2)) - imgs.min((1, 2)))
    np.testing.assert_allclose(spread, 0.02, rtol=0.1)


# --- PCA + LDA -------------------------------------------------------------------------

def test_pcalda_matches_generalised_eigenproblem(population):
    imgs = preprocess_images(population.images).reshape(160, -1)
    model = PcaLda(40).fit(imgs, population.labels)
    assert model.projection_.shape == (imgs.shape[1], 39)
    np.testing.assert_allclose(np.linalg.norm(model.projection_, axis=0), 1.0)
    assert np.all(np.diff(model.eigenvalues_) <= 1e-9)
    # Fisher criterion: the first axis's between/within ratio equals the top eigenvalue.
    feats = (imgs - model.basis_.mean) @ model.basis_.vectors[:, :40]
    means = np.stack([feats[population.labels == c].mean(0) for c in range(40)])
    sw = sum(((feats[population.labels == c] - means[c]).T @ (feats[population.labels == c] - means[c]))
             for c in range(40))
    sb = 4 * (means - feats.mean(0)).T @ (means - feats.mean(0))
    top = scipy.linalg.eigh(sb, sw, eigvals_only=True)[-1]
    assert np.isclose(model.eigenvalues_[0], top, rtol=1e-6)


def test_distances_l2_and_soft_l2(population):
    imgs = preprocess_images(population.images)
    model = PcaLda("e90").fit(imgs, population.labels)
    a, b = model.transform(imgs[:3]), model.transform(imgs[3:8])
    brute = ((a[:, None] - b[None]) ** 2 * model.eigenvalues_ ** 0.2).sum(-1)
    np.testing.assert_allclose(model.distances(imgs[:3], imgs[3:8], "soft_l2"), brute, rtol=1e-8, atol=1e-8)
    brute_l2 = ((a[:, None] - b[None]) ** 2).sum(-1)
    np.testing.assert_allclose(model.distances(imgs[:3], imgs[3:8], "l2"), brute_l2, rtol=1e-8, atol=1e-8)
    # eq. (1) itself, by the expanded square, against the sum of weighted squared differences
    np.testing.assert_allclose(fg.weighted_sq_distances(a, b, model.eigenvalues_ ** 0.2), brute, rtol=1e-8, atol=1e-8)


# --- the factorial experiment ----------------------------------------------------------

def test_reduced_experiment_table(reduced_table):
    design = reduced_design()
    assert len(reduced_table) == design.n_training_sets * design.n_subjects * 4 * 2 * 2 * 2
    assert reduced_table.Y.between(0, design.n_galleries).all()
    # inclusion flag: exactly n_train_subjects probes per training set.
    per_t = reduced_table[reduced_table.F == "yes"].groupby("t").p.nunique()
    assert (per_t == design.n_train_subjects).all()
    # better than chance by far, not perfect
    assert 0.3 < reduced_table.Y.mean() / design.n_galleries < 0.99
    again = run_factorial_experiment(design, rng=11)
    pd.testing.assert_frame_equal(reduced_table, again)


# the reflection supplement at the small size and E90 gives S_b a rank below C - 1 (class means are
# mirror-symmetric, fewer than 63 of the kept PCA directions are even); other configurations do not
KERNEL_DESIGN = dict(n_subjects=128, n_train_subjects=64, n_training_sets=1, n_galleries=10,
                     supplements=("none", "reflection"))
_KERNEL_CHILD = """
import sys, numpy as np
from amdo_lab import face_glmm as fg
table = fg.run_factorial_experiment(fg.FactorialDesign(**eval(sys.argv[1])), rng=2004)
np.save(sys.argv[2], table.Y.to_numpy())
"""


def _cpu_has_avx512() -> bool:
    try:
        with open("/proc/cpuinfo") as cpuinfo:
            return "avx512f" in cpuinfo.read()
    except OSError:
        return False


def test_fisher_rank_decision_drops_the_directions_s_b_does_not_fix():
    """Small images + reflection + E90: S_b has rank < C - 1 in PCA space; only its range is kept."""
    design = FactorialDesign(**KERNEL_DESIGN)
    draws = fg.experiment_draws(design, rng=2004)
    faces = preprocess_images(downsample_by_two(draws.population.images))
    subjects = draws.training_sets[0]
    base = faces.reshape(design.n_subjects, 4, *faces.shape[1:])[subjects, 1:].reshape(-1, *faces.shape[1:])
    train = np.concatenate([base, make_supplement(base, "reflection", rng=0)]).reshape(2 * len(base), -1)
    labels = np.tile(np.repeat(subjects, 3), 2)
    model = PcaLda("e90").fit(train, labels)
    assert model.projection_.shape[1] < design.n_train_subjects - 1   # rank decision taken here
    # every kept direction separates the classes (eigenvalue well above round-off); each kept axis is even
    assert model.eigenvalues_[-1] > 1e-4 * model.eigenvalues_[0]
    axes = model.projection_.reshape(*faces.shape[1:], -1)
    np.testing.assert_allclose(axes[:, ::-1], axes, atol=1e-8)


def test_table_is_the_same_under_every_blas_kernel(tmp_path):
    """The reduced table (with the rank-deficient configuration) is identical under 2-3 OpenBLAS kernels."""
    import os
    import subprocess

    kernels = ["Haswell", "Nehalem"] + (["SkylakeX"] if _cpu_has_avx512() else [])
    counts = {}
    for kernel in kernels:
        env = dict(os.environ, OPENBLAS_CORETYPE=kernel, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
        out = tmp_path / f"{kernel}.npy"
        subprocess.run([sys.executable, "-c", _KERNEL_CHILD, repr(KERNEL_DESIGN), str(out)], env=env,
                       check=True, timeout=120)
        counts[kernel] = np.load(out)
    for kernel in kernels[1:]:
        differ = int(np.sum(counts[kernel] != counts[kernels[0]]))
        assert differ == 0, f"{differ} counts differ between {kernels[0]} and {kernel}"


def test_rank1_counts_against_loop():
    from amdo_lab.face_glmm.experiment import _rank1_counts
    rng = make_rng(0)
    dist = rng.random((6, 6, 3))
    choice = rng.integers(0, 3, (5, 6))
    loop = [sum(int(np.argmin([dist[i, j, choice[g, j]] for j in range(6)]) == i) for g in range(5))
            for i in range(6)]
    np.testing.assert_array_equal(_rank1_counts(dist, choice), loop)


# --- formula / design ------------------------------------------------------------------

def test_parse_formula_expands_star():
    response, terms = parse_formula("Y ~ M * D + U")
    assert response == "Y"
    assert terms == [("M",), ("D",), ("U",), ("M", "D")]


def test_sum_to_zero_columns_sum_to_zero():
    table = _crossed_table(2, 4)
    design = _build_design(table, parse_formula("Y ~ U * M * D")[1])
    assert design.matrix.shape[1] == 8
    assert np.allclose(design.matrix[:, 1:].sum(0), 0)


# --- the GLMM --------------------------------------------------------------------------

TRUE_BETA = np.array([0.8, -0.4, 0.3, 0.5, 0.2])  # intercept, M, D, U, M:D


@pytest.fixture(scope="module")
def simulated():
    table = _crossed_table()
    variances = {"t": 0.05, "p": 1.2, "t:p": 0.4}
    table["Y"] = simulate_binomial_glmm(table, "Y ~ M * D + U", TRUE_BETA, variances, 30, rng=7)
    return table, variances


def test_glmm_recovers_simulated_effects(simulated):
    table, variances = simulated
    fit = fit_binomial_glmm(table, "Y ~ M * D + U", ["t", "p", "t:p"], 30)
    est = fit.coefficients.to_numpy()
    se = fit.coefficients.copy()
    se[:] = np.sqrt(np.diag(fit.covariance))
    assert np.all(np.abs(est - TRUE_BETA) < 4 * se.to_numpy())
    assert fit.variance_components["p"] == pytest.approx(1.2, rel=0.3)
    assert fit.variance_components["t:p"] == pytest.approx(0.4, rel=0.3)
    assert isinstance(fit.fixed_effects["M:D"], float)
    assert set(fit.tests.index) == {"M", "D", "U", "M:D"}
    assert 0 < fit.probe_correlation < 1


def test_glmm_reduces_to_logistic_regression_without_random_variance():
    """With all true variances 0 the fitted sigmas collapse and beta is the GLM's."""
    import statsmodels.api as sm
    table = _crossed_table(4, 60)
    table["Y"] = simulate_binomial_glmm(table, "Y ~ M * D + U", TRUE_BETA, {}, 30, rng=3)
    fit = fit_binomial_glmm(table, "Y ~ M * D + U", ["t", "p"], 30)
    x = _build_design(table, parse_formula("Y ~ M * D + U")[1]).matrix
    glm = sm.GLM(np.column_stack([table.Y, 30 - table.Y]), x, family=sm.families.Binomial()).fit()
    assert max(fit.variance_components.values()) < 0.01
    np.testing.assert_allclose(fit.coefficients.to_numpy(), glm.params, atol=5e-3)


@pytest.mark.skipif(not lme4_available(), reason="Rscript with lme4 not installed")
def test_agrees_with_lme4(simulated):
    table, _ = simulated
    ours = fit_binomial_glmm(table, "Y ~ M * D + U", ["t", "p", "t:p"], 30)
    theirs = fit_with_lme4(table, "Y ~ M * D + U", ["t", "p", "t:p"], 30)
    assert isinstance(theirs, PeerFit) and theirs.method == "lme4 glmer(nAGQ=0)" and theirs.seconds > 0
    np.testing.assert_allclose(ours.coefficients.to_numpy(), theirs.estimate.to_numpy(), atol=1e-3)
    assert np.all(theirs.se > 0)
    for term in ("p", "t:p"):
        assert ours.variance_components[term] == pytest.approx(theirs.variance_components[term], abs=1e-3)


NESTED = [("t", "p", "t:p"), ("t:p", "p"), ("t", "p", "t:p", "t:p:U")]


@pytest.mark.parametrize("random", [*NESTED, ("p",), ("t", "p", "t:p", "t:U"), ("t", "p", "t:p", "t:S")],
                         ids=["nested-in-t:p", "nested-no-small-term", "nested-two-small-terms", "one-term",
                              "function-of-cells", "row-level"])
def test_fast_laplace_deviance_equals_dense_reference(random):
    """The fast path (block elimination: big term, then the second when nested, then a dense rest)
    equals the plain dense penalised IRLS + Laplace deviance, and so does beta's precision."""
    from amdo_lab.face_glmm.glmm import _setup
    table = pd.concat([_crossed_table(3, 10).assign(S=s) for s in ("a", "b")], ignore_index=True)
    table["Y"] = simulate_binomial_glmm(table, "Y ~ M * D + U", TRUE_BETA, {"t": 0.1, "p": 1.0, "t:p": 0.3}, 30, rng=5)
    problem, start = _setup(table, "Y ~ M * D + U", random, 30)
    assert problem.nested == (random in NESTED)
    assert problem.sum_over_cells == (random != ("t", "p", "t:p", "t:S"))
    theta = np.array([0.3, 0.9, 0.5, 0.2][: len(random)])
    beta, _, _, value, chol_beta, _ = problem.solve(theta, *start)
    groups = [problem_groups for problem_groups in (pd.factorize(
        pd.MultiIndex.from_frame(table[term.split(":")].astype(str)), sort=True)[0] for term in random)]
    z = np.hstack([np.eye(g.max() + 1)[g] for g in groups])
    lam = np.concatenate([np.full(g.max() + 1, sd) for g, sd in zip(groups, theta)])
    ref_beta, _, ref_value, hessian = fg.laplace_deviance_reference(problem.y, problem.n_trials, problem.x, z, lam)
    assert value == pytest.approx(ref_value, rel=1e-10)
    np.testing.assert_allclose(beta, ref_beta, atol=1e-8)
    q = z.shape[1]   # beta's precision: the Schur complement of the u block of the penalised Hessian
    precision = hessian[q:, q:] - hessian[q:, :q] @ np.linalg.solve(hessian[:q, :q], hessian[:q, q:])
    np.testing.assert_allclose(chol_beta.T @ chol_beta, precision, rtol=1e-7)


def test_laplace_deviance_is_the_fitted_objective(simulated):
    from amdo_lab.face_glmm import laplace_deviance
    table, _ = simulated
    fit = fit_binomial_glmm(table, "Y ~ M * D + U", ["t", "p", "t:p"], 30)
    sds = np.sqrt([fit.variance_components[k] for k in ("t", "p", "t:p")])
    values = laplace_deviance(table, "Y ~ M * D + U", ["t", "p", "t:p"], [sds, sds * [1, 1.2, 1], sds * [1, 1, 0.8]], 30)
    assert values[0] == pytest.approx(fit.deviance, rel=1e-9)
    assert np.all(values[1:] > values[0])


def test_marginal_prediction_averages_logits(simulated):
    from scipy.special import logit
    table, _ = simulated
    fit = fit_binomial_glmm(table, "Y ~ M * D + U", ["p"], 30)
    full = pd.MultiIndex.from_product([["l2", "soft_l2"], ["e90", "fixed"], ["none", "shift"]],
                                      names=["M", "D", "U"]).to_frame(index=False)
    cells = logit(fit.predict(full).p.to_numpy()).reshape(2, 2, 2)
    marg = fit.predict_marginal(pd.DataFrame({"M": ["l2", "soft_l2"]}))
    np.testing.assert_allclose(logit(marg.p.to_numpy()), cells.mean(axis=(1, 2)))


def test_peer_fits_run_on_simulated_table(simulated):
    from amdo_lab.face_glmm import fit_gee, fit_naive_logistic
    table, _ = simulated
    gee = fit_gee(table, "Y ~ M * D + U", group="p")
    naive = fit_naive_logistic(table, "Y ~ M * D + U")
    for peer, method in ((gee, "GEE (exchangeable)"), (naive, "naive logistic")):
        # one result type for every peer fit: the coefficient table, no variance components, timings
        assert isinstance(peer, PeerFit) and peer.method == method and peer.finite
        assert list(peer.coefficients.columns) == ["estimate", "se"] and peer.variance_components is None
        assert peer.seconds >= 0 and peer.cpu_seconds >= 0
    assert not PeerFit("x", pd.DataFrame({"estimate": [np.nan], "se": [1.0]}), None, 0.0, 0.0).finite
    # population-averaged effects are attenuated relative to the subject-specific truth
    assert np.all(np.abs(gee.estimate.to_numpy()[1:]) < np.abs(TRUE_BETA[1:]))
    # naive standard errors are too small compared with the cluster-robust ones
    assert np.median(naive.se / gee.se) < 0.8


def test_experiment_cache_round_trip(tmp_path):
    from amdo_lab.face_glmm import FactorialDesign, load_or_run_experiment
    design = FactorialDesign(n_subjects=16, n_training_sets=1, n_train_subjects=8, n_galleries=3,
                             supplements=("none",), shape=(16, 14))
    first, hit_first = load_or_run_experiment(design, tmp_path, rng=1)
    second, hit_second = load_or_run_experiment(design, tmp_path, rng=1)
    assert (hit_first, hit_second) == (False, True)
    pd.testing.assert_frame_equal(first, second)


def test_experiment_draws_recompute_one_row_of_the_table(reduced_table):
    """One row of the table (t=0, no supplement, L2, fixed, standard) recomputed from the draws."""
    from amdo_lab.face_glmm import experiment_draws
    design = reduced_design()
    draws = experiment_draws(design, rng=11)
    n = design.n_subjects
    faces = preprocess_images(draws.population.images).reshape(n, 4, -1)
    subjects = draws.training_sets[0]
    model = PcaLda("fixed").fit(faces[subjects, 1:].reshape(-1, faces.shape[-1]), np.repeat(subjects, 3))
    dist = model.distances(faces[:, 0], faces[:, 1:].reshape(-1, faces.shape[-1]), "l2").reshape(n, n, 3)
    rows = reduced_table[(reduced_table.t == 0) & (reduced_table.U == "none") & (reduced_table.M == "l2")
                         & (reduced_table.D == "fixed") & (reduced_table.S == "standard")].set_index("p")
    for probe in range(n):
        in_gallery = dist[probe][np.arange(n), draws.gallery_choice]          # gallery x subject
        y = int(np.sum(np.argmin(in_gallery, axis=1) == probe))
        assert y == rows.loc[probe, "Y"]


def _edited_copy_of_population(tmp_path, name):
    """Import a copy of population.py in which one generator constant is changed."""
    import importlib.util
    import inspect

    from amdo_lab.face_glmm import population as original
    source = inspect.getsource(original)
    edited = source.replace("eye_dx = 0.36 + 0.04", "eye_dx = 0.37 + 0.04")
    assert edited != source  # the constant is there to edit
    path = tmp_path / f"{name}.py"
    path.write_text(edited)
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # dataclasses look their module up while the class is built
    spec.loader.exec_module(module)
    return module


def test_cache_key_changes_when_a_generator_constant_is_edited(tmp_path):
    from amdo_lab.face_glmm import RESULT_MODULES, reduced_design
    design = reduced_design()
    key = _experiment_cache_key(design, rng=1)
    assert key == _experiment_cache_key(design, rng=1, modules=RESULT_MODULES)
    assert key != _experiment_cache_key(design, rng=2)  # the seed
    assert key != _experiment_cache_key(dataclasses.replace(design, nuisance=0.9), rng=1)
    edited = _edited_copy_of_population(tmp_path, "population_edited")
    modules = tuple(edited if name.endswith(".population") else name for name in RESULT_MODULES)
    assert _experiment_cache_key(design, rng=1, modules=modules) != key


def test_cache_reruns_after_a_generator_edit(tmp_path, monkeypatch):
    from amdo_lab.face_glmm import RESULT_MODULES, cache, load_or_run_experiment
    design = FactorialDesign(n_subjects=16, n_training_sets=1, n_train_subjects=8, n_galleries=3,
                             supplements=("none",), shape=(16, 14))
    _, first_hit = load_or_run_experiment(design, tmp_path, rng=1)
    edited = _edited_copy_of_population(tmp_path, "population_edited_again")
    monkeypatch.setattr(cache, "RESULT_MODULES",
                        tuple(edited if name.endswith(".population") else name for name in RESULT_MODULES))
    _, after_edit_hit = load_or_run_experiment(design, tmp_path, rng=1)
    _, again_hit = load_or_run_experiment(design, tmp_path, rng=1)
    assert (first_hit, after_edit_hit, again_hit) == (False, False, True)
    assert len(list(tmp_path.glob("face_glmm_experiment_*.pkl"))) == 2


def test_agrees_with_statsmodels_bayes_mixed_glm_on_a_small_table():
    """Cross-check against statsmodels' BinomialBayesMixedGLM (posterior mode, Bernoulli rows).

    statsmodels only takes 0/1 responses, so the binomial counts are expanded to 30 rows each; its
    weak priors (fixed effects sd 2, log-sd of the variance component sd 1) pull the estimates a
    little, hence tolerances of a few thousandths on effects and 15 % on the variance.
    """
    from statsmodels.genmod.bayes_mixed_glm import BinomialBayesMixedGLM

    table = _crossed_table(1, 40)
    table["Y"] = simulate_binomial_glmm(table, "Y ~ M * D + U", TRUE_BETA, {"p": 1.0}, 30, rng=11)
    ours = fit_binomial_glmm(table, "Y ~ M * D + U", ["p"], 30)
    rows = table.loc[table.index.repeat(30)].reset_index(drop=True)
    rows["y"] = np.concatenate([np.r_[np.ones(k), np.zeros(30 - k)] for k in table.Y])
    model = BinomialBayesMixedGLM.from_formula(
        "y ~ C(M, Sum) * C(D, Sum) + C(U, Sum)", {"p": "0 + C(p)"}, rows)
    theirs = model.fit_map()
    np.testing.assert_allclose(ours.coefficients.to_numpy()[1:], theirs.fe_mean[1:], atol=5e-3)
    assert ours.coefficients.iloc[0] == pytest.approx(theirs.fe_mean[0], abs=2e-2)
    assert ours.variance_components["p"] == pytest.approx(np.exp(theirs.vcp_mean[0]) ** 2, rel=0.15)


# --- the randomness convention: rng keyword-only, no default, errors name rng -----------------

_DRAWING = {
    "make_face_population": lambda rng: fg.make_face_population(8, 2, rng=rng, shape=(16, 14)),
    "make_supplement": lambda rng: fg.make_supplement(np.ones((2, 8, 8)), "noise", rng=rng),
    "experiment_draws": lambda rng: fg.experiment_draws(reduced_design(), rng=rng),
    "run_factorial_experiment": lambda rng: fg.run_factorial_experiment(reduced_design(), rng=rng),
    "load_or_run_experiment": lambda rng: fg.load_or_run_experiment(reduced_design(), "unused", rng=rng),
    "simulate_binomial_glmm": lambda rng: fg.simulate_binomial_glmm(
        _crossed_table(2, 4), "Y ~ M", [0.0, 0.0], {}, 30, rng=rng),
    "recovery_study": lambda rng: fg.recovery_study(
        _crossed_table(2, 4), "Y ~ M", pd.Series([0.0, 0.0]), {"p": 1.0}, 1, rng=rng),
}


@pytest.mark.parametrize("name", sorted(_DRAWING))
def test_rng_is_keyword_only_without_default(name):
    parameter = inspect.signature(getattr(fg, name)).parameters["rng"]
    assert parameter.kind is inspect.Parameter.KEYWORD_ONLY
    assert parameter.default is inspect.Parameter.empty


def test_cache_key_of_a_generator_follows_its_seed_sequence_and_state():
    design = reduced_design()
    key = _experiment_cache_key(design, rng=make_rng(1))
    assert key == _experiment_cache_key(design, rng=make_rng(1))
    assert key != _experiment_cache_key(design, rng=make_rng(2))
    advanced = make_rng(1)
    advanced.spawn(1)  # the experiment spawns its streams: a generator that already spawned draws others
    assert key != _experiment_cache_key(design, rng=advanced)
    assert _experiment_cache_key(design, rng=1) == _experiment_cache_key(design, rng=np.int64(1))


def test_recovery_study_accepts_a_generator_with_the_seed_s_streams():
    table = _crossed_table(3, 20)
    coefficients = pd.Series([0.5, -0.3], index=["(Intercept)", "M[l2]"])
    by_seed, _ = fg.recovery_study(table, "Y ~ M", coefficients, {"p": 0.5}, 2, rng=4)
    by_generator, _ = fg.recovery_study(table, "Y ~ M", coefficients, {"p": 0.5}, 2, rng=make_rng(4))
    pd.testing.assert_frame_equal(by_seed.table, by_generator.table)


def test_pcalda_follows_the_estimator_contract(population):
    """Parameters stored as given (checked in fit), fit returns self, NotFittedError before fit."""
    from sklearn.exceptions import NotFittedError

    dimension = np.int64(20)
    model = PcaLda(dimension, base_images_per_class=3)
    assert model.pca_dimension is dimension and model.base_images_per_class == 3
    PcaLda("e95")  # a bad parameter is refused by fit, not by the constructor
    with pytest.raises(NotFittedError):
        model.transform(np.ones((2, 480)))
    imgs = preprocess_images(population.images)
    assert model.fit(imgs, population.labels) is model
    assert model.n_pca_ == 20 and model.projection_.shape == (imgs[0].size, min(20, population.n_subjects - 1))


def test_shared_checks_are_public_module_level_names():
    """The checks other modules of the chapter call return valid input (their rejections: REJECTIONS)."""
    from amdo_lab.face_glmm.glmm import response_counts
    from amdo_lab.face_glmm.population import check_image_shape
    assert check_image_shape((60, 52), minimum=8) == (60, 52)
    table = pd.DataFrame({"Y": [0, 3, 30]})
    np.testing.assert_array_equal(response_counts(table, "Y", 30), [0.0, 3.0, 30.0])


def test_findings_show_the_numbers_they_compare(reduced_table):
    fit = fit_binomial_glmm(reduced_table[reduced_table.S == "standard"], PAPER_FORMULA, ["t", "p"], 10)
    out = fg.findings(fit)
    assert list(out.columns) == ["holds for ours", "measured"] and len(out) == 11
    soft, l2 = (float(fit.predict_marginal(pd.DataFrame({"M": [m]})).p.iloc[0]) for m in ("soft_l2", "l2"))
    row = out.loc["soft L2 beats L2 overall"]
    assert row["measured"] == f"soft L2 {soft:.3f}, L2 {l2:.3f}" and row["holds for ours"] == (soft > l2)


# --- rejections: the rules of the method, in one table ---------------------------------------
# The generic promises (NaN or inf inside, empty or mis-shaped arrays, wrong types, bad counts,
# probabilities and seeds, each named by argument) are tests/test_bad_input.py's, for every argument
# of tests/bad_input_cases/face_glmm.py; this table holds what that test cannot know.

_RNG = make_rng(17)
_A, _B = _RNG.normal(size=(3, 4)), _RNG.normal(size=(5, 4))


@pytest.fixture(scope="module")
def fitted(simulated, population, reduced_table):
    """Fits, images and axes the rejection cases below work on."""
    import types

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    table, variances = simulated
    fig, axes = plt.subplots(1, 3)
    yield types.SimpleNamespace(
        table=table, variances=variances,
        fit=fit_binomial_glmm(table, "Y ~ M * D + U", ["p"], 30),  # no F: not a fit of the paper's design
        paper_fit=fit_binomial_glmm(reduced_table[reduced_table.S == "standard"], PAPER_FORMULA, ["t", "p"], 10),
        size_free=fit_binomial_glmm(reduced_table, PAPER_FORMULA, ["p"], 10),
        cell=pd.DataFrame({"M": ["l2"], "D": ["fixed"], "U": ["none"]}),
        images=preprocess_images(population.images), labels=population.labels, axes=axes)
    plt.close(fig)


def _response(f, first_value):
    """The simulated table with the first row's response replaced."""
    return f.table.assign(Y=np.where(f.table.index == 0, first_value, f.table.Y))


REJECTIONS = [
    # --- population and preprocessing: image shapes, enough subjects and pixels
    reject("make_face_population one subject", lambda: make_face_population(1, 4, rng=0),
           ValueError, "n_subjects must be at least 2"),
    reject("make_face_population 4 x 4 faces", lambda: make_face_population(4, 4, rng=0, shape=(4, 4)),
           ValueError, r"shape\[0\] must be at least 8"),
    reject("make_face_population float shape", lambda: make_face_population(3, 2, rng=0, shape=(16.7, 14)),
           TypeError, r"shape\[0\] must be an int"),
    reject("make_face_population scalar shape", lambda: make_face_population(3, 2, rng=0, shape=16),
           ValueError, "shape must be a pair"),
    reject("check_image_shape three entries", lambda: fg.population.check_image_shape((60, 52, 3), minimum=8),
           ValueError, r"shape must be a pair \(rows, cols\)"),
    reject("check_image_shape float", lambda: fg.population.check_image_shape((60.5, 52), minimum=8),
           TypeError, r"shape\[0\] must be an int"),
    reject("preprocess_images one pixel", lambda: preprocess_images(np.ones((2, 1, 1))),
           ValueError, "the pixels of images inside the elliptical mask must be at least 2"),
    reject("make_supplement one image", lambda: make_supplement(np.ones((8, 8)), "shift", rng=make_rng(0)),
           ValueError, "images must have 3 dimensions"),
    # --- PCA + LDA: enough images per subject, the named metrics and dimensions, fitted first
    reject("pca_basis one row", lambda: fg.pca_basis(np.ones((1, 5))), ValueError, r"the rows of samples \(for a covariance\) must be at least 2"),
    reject("e90_dimension all-zero spectrum", lambda: fg.e90_dimension(np.zeros(3)),
           ValueError, "the sum of eigenvalues must be positive"),
    reject("weighted_sq_distances b of another width", lambda: fg.weighted_sq_distances(_A, _B[:, :3], np.ones(4)),
           ValueError, r"b \(like a\) must have shape \(n, 4\)"),
    reject("weighted_sq_distances weights of another length", lambda: fg.weighted_sq_distances(_A, _B, np.ones(3)),
           ValueError, r"weights \(like a\) must have shape \(4,\)"),
    reject("weighted_sq_distances negative weights", lambda: fg.weighted_sq_distances(_A, _B, -np.ones(4)),
           ValueError, r"weights \(like a\) must lie in"),
    reject("PcaLda one image per subject", lambda fitted: PcaLda().fit(fitted.images[::4], fitted.labels[::4]),
           ValueError, "too few images for LDA"),
    reject("PcaLda pca_dimension e95", lambda fitted: PcaLda("e95").fit(fitted.images, fitted.labels),
           ValueError, "pca_dimension must be one of 'fixed', 'e90'"),
    reject("PcaLda metric l1", lambda fitted: PcaLda().fit(fitted.images, fitted.labels).distances(
        fitted.images[:2], fitted.images[2:4], metric="l1"), ValueError, "metric must be one of 'l2', 'soft_l2'"),
    reject("PcaLda basis not a PcaBasis", lambda fitted: PcaLda().fit(fitted.images, fitted.labels, basis="basis"),
           TypeError, "basis must be a PcaBasis"),
    reject("PcaLda basis of other images", lambda fitted: PcaLda().fit(fitted.images, fitted.labels, basis=fg.pca_basis(
        fitted.images.reshape(len(fitted.images), -1)[:, :10])),
        ValueError, r"basis \(the mean image of its images\) must have shape \(480,\)"),
    reject("PcaLda not fitted transform", lambda: PcaLda().transform(np.ones((2, 10))),
           ValueError, "estimator PcaLda is not fitted yet"),
    # --- the factorial design: its parts must fit together
    reject("FactorialDesign more training subjects than subjects",
           lambda: FactorialDesign(n_subjects=8, n_train_subjects=9),
           ValueError, "n_train_subjects must be at most 8"),
    reject("FactorialDesign supplement blur", lambda: FactorialDesign(supplements=("none", "blur")),
           ValueError, r"supplements holds unknown name\(s\) \['blur'\]"),
    reject("FactorialDesign repeated supplement", lambda: FactorialDesign(supplements=("none", "none")),
           ValueError, "supplements must not repeat a name"),
    reject("FactorialDesign odd shape", lambda: FactorialDesign(shape=(15, 14)),
           ValueError, "shape must have even rows and cols"),
    reject("FactorialDesign scalar shape", lambda: FactorialDesign(shape=16), ValueError, "shape must be a pair"),
    # --- the GLMM fit: a response of counts, a design of full rank, named random terms
    reject("fit_binomial_glmm count above n_trials",
           lambda fitted: fit_binomial_glmm(_response(fitted, 31), "Y ~ M", ["p"], 30),
           ValueError, r"response 'Y' \(integer counts, n_trials=30\) must lie in \[0, 30\]"),
    reject("fit_binomial_glmm negative count", lambda fitted: fit_binomial_glmm(_response(fitted, -1), "Y ~ M", ["p"], 30),
           ValueError, r"response 'Y' \(integer counts, n_trials=30\) must lie in \[0, 30\]"),
    reject("fit_binomial_glmm NaN count", lambda fitted: fit_binomial_glmm(_response(fitted, np.nan), "Y ~ M", ["p"], 30),
           ValueError, r"response 'Y' \(integer counts, n_trials=30\) must be finite"),
    reject("fit_binomial_glmm boolean response", lambda fitted: fit_binomial_glmm(
        fitted.table.assign(Y=fitted.table.Y > 10), "Y ~ M", ["p"], 30),
        TypeError, "response 'Y' must hold counts, got booleans"),
    reject("fit_binomial_glmm duplicated factor", lambda fitted: fit_binomial_glmm(
        fitted.table.assign(M2=fitted.table.M), "Y ~ M + M2", ["p"], 30), ValueError, r"the column rank of the fixed design \(singular\) must be at least"),
    reject("fit_binomial_glmm level with no rows", lambda fitted: fit_binomial_glmm(fitted.table.assign(
        M=pd.Categorical(fitted.table.M, categories=["l2", "soft_l2", "l1"])), "Y ~ M", ["p"], 30),
        ValueError, "factor 'M' has levels with no rows"),
    reject("fit_binomial_glmm factor not in table", lambda fitted: fit_binomial_glmm(fitted.table, "Y ~ Q", ["p"], 30),
           ValueError, r"table \(the terms of fixed\) must have columns \['Q'\], missing \['Q'\]"),
    reject("fit_binomial_glmm random term a number", lambda fitted: fit_binomial_glmm(fitted.table, "Y ~ M", [3], 30),
           TypeError, "random must hold non-empty strings"),
    reject("fit_binomial_glmm repeated random term", lambda fitted: fit_binomial_glmm(fitted.table, "Y ~ M", ["p", "p"], 30),
           ValueError, "random must not repeat a name"),
    reject("fit_binomial_glmm no rows", lambda fitted: fit_binomial_glmm(fitted.table.iloc[:0], "Y ~ M", ["p"], 30),
           ValueError, "table must have at least one row"),
    reject("laplace_deviance two sds for three terms", lambda fitted: fg.laplace_deviance(
        fitted.table, "Y ~ M * D + U", ["t", "p", "t:p"], [1.0, 1.0], 30), ValueError, r"sd must have shape \(n, 3\)"),
    reject("laplace_deviance negative sd", lambda fitted: fg.laplace_deviance(
        fitted.table, "Y ~ M * D + U", ["t", "p", "t:p"], [1.0, -1.0, 1.0], 30), ValueError, r"sd must lie in \[0, 1000\]"),
    reject("response_counts above n_trials", lambda: fg.glmm.response_counts(pd.DataFrame({"Y": [0, 3, 30]}), "Y", 10),
           ValueError, r"\(integer counts, n_trials=10\) must lie in \[0, 10\]"),
    # --- predictions from a fit: an interval strictly inside (0, 1), at least one cell
    reject("predict ci 0", lambda fitted: fitted.fit.predict(fitted.cell, ci=0.0),
           ValueError, r"ci must be in \(0, 1\), got 0.0"),
    reject("predict no rows", lambda fitted: fitted.fit.predict(fitted.cell.iloc[:0]),
           ValueError, "newdata must have at least one row"),
    # --- simulation and the recovery study: variances of named terms
    reject("simulate_binomial_glmm NaN variance", lambda fitted: simulate_binomial_glmm(
        fitted.table, "Y ~ M", [0.0, 0.0], {"p": np.nan}, 30, rng=0), ValueError, r"variances\['p'\] must be finite"),
    reject("simulate_binomial_glmm negative variance", lambda fitted: simulate_binomial_glmm(
        fitted.table, "Y ~ M", [0.0, 0.0], {"p": -1.0}, 30, rng=0), ValueError, r"variances\['p'\] must be non-negative"),
    reject("recovery_study no variances", lambda fitted: fg.recovery_study(
        fitted.table, "Y ~ M * D + U", fitted.fit.coefficients, {}, 1, rng=1),
        ValueError, r"the terms of variances \(the refits need a random effect\) must be at least 1"),
    # --- the peers: named columns and terms, counts out of n_trials
    reject("fit_gee group not a column",
           lambda fitted: fg.fit_gee(fitted.table, "Y ~ M", group="q"),
           ValueError, r"table \(its group column\) must have columns \['q'\], missing \['q'\]"),
    reject("fit_gee count above n_trials", lambda fitted: fg.fit_gee(
        fitted.table.assign(Y=fitted.table.Y + 100), "Y ~ M"),
        ValueError, r"response 'Y' \(integer counts, n_trials=30\) must lie in \[0, 30\]"),
    reject("fit_naive_logistic NaN count", lambda fitted: fg.fit_naive_logistic(_response(fitted, np.nan), "Y ~ M"),
           ValueError, r"response 'Y' \(integer counts, n_trials=30\) must be finite"),
    reject("fit_naive_logistic response not a column", lambda fitted: fg.fit_naive_logistic(fitted.table, "Z ~ M"),
           ValueError, r"table \(the response of fixed\) must have columns \['Z'\], missing \['Z'\]"),
    reject("fit_with_lme4 random term not a column", lambda fitted: fit_with_lme4(fitted.table, "Y ~ M", ["q"]),
           ValueError, r"table \(random term 'q'\) must have columns \['q'\], missing \['q'\]"),
    # --- the report: a fit of the paper's factors, three axes for Fig. 2
    reject("cell_predictions fit without the paper's factors", lambda fitted: fg.cell_predictions(fitted.fit),
           ValueError, r"result must be a fit with the paper's factors U, M, D and F"),
    reject("findings fit without F", lambda fitted: fg.findings(fitted.fit), ValueError, r"it lacks \['F'\]"),
    reject("findings size_result without image size", lambda fitted: fg.findings(fitted.paper_fit, fitted.size_free),
           ValueError, "size_result must be a fit with image-size"),
    reject("plot_figure2 two axes", lambda fitted: fg.plot_figure2(fitted.paper_fit, fitted.axes[:2]),
           ValueError, "axes must be three matplotlib Axes"),
    reject("plot_figure2 fit without the paper's factors", lambda fitted: fg.plot_figure2(fitted.fit, fitted.axes),
           ValueError, r"result must be a fit with the paper's factors"),
    # --- the rng convention: errors start with "rng", TypeError for a non-seed, ValueError for a negative seed
    *[reject(f"{name} rng {bad!r}", lambda draw=draw, bad=bad: draw(bad), error, "^rng must be")
      for name, draw in sorted(_DRAWING.items()) for bad, error in (("7", TypeError), (-1, ValueError))],
]


@pytest.mark.parametrize(("call", "error", "message"), REJECTIONS)
def test_rejections(request, call, error, message):
    check_rejection(request, call, error, message)


def test_implement_it_exercise_tells_each_recorded_wrong_function_apart():
    """Exercise 6: the reference is (F3) of the dense path; each recorded wrong (F3) gets its own hint."""
    from amdo_lab.face_glmm.exercises import EXERCISES as checks, make_toy_case, toy_laplace_deviance

    exercise = checks[6]
    checks.expect(6, seeds=(101, 202, 303))   # the seeds of the notebook's hidden test
    for seed in (0, 101, 202, 303):
        case = make_toy_case(seed)
        assert case["z"].shape == (case["y"].size, case["y"].size // 2)
        values = [wrong.value(**case) for wrong in exercise.wrong_answers]
        assert min(abs(v - toy_laplace_deviance(**case)) for v in values) > 0.1
    assert checks.verdict(6, None) == "not attempted yet"
    assert checks.verdict(6, lambda **case: toy_laplace_deviance(**case)) == "correct"  # the reference, re-typed
    assert checks.verdict(6, toy_laplace_deviance).startswith("not yet")  # the package function itself
    assert checks.verdict(6, lambda **case: None).startswith("not yet")
    for wrong in exercise.wrong_answers:
        assert checks.verdict(6, wrong.value) == "not yet: " + wrong.hint
