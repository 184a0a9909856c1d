"""Chapter 7: incremental SVD with mean update (Melenchón, Meler & Iriondo, AMDO 2004)."""

from __future__ import annotations

import numpy as np
import pytest
from rejections import check_rejection, reject
from sklearn.exceptions import NotFittedError

from amdo_lab import incremental_svd as isvd
from amdo_lab.incremental_svd import (
    IncrementalSVD,
    brand_update,
    extract_mean,
    make_talking_face,
    noise_edge,
    psnr_db,
    ross_update,
    tau_schedule,
    update_with_mean,
)


def _low_rank_columns(p=1640, q=120, rank=20, seed=0):
    """A p x q matrix: rank-``rank`` signal, small noise and an offset (columns are observations)."""
    rng = np.random.default_rng(seed)
    return rng.normal(size=(p, rank)) @ rng.normal(size=(rank, q)) + 0.1 * rng.normal(size=(p, q)) + 3.0


def _stream(columns, **options):
    model = IncrementalSVD(**options)
    for column in columns.T:
        model.partial_fit(column[None])
    return model


def _empty(p):
    return np.zeros((p, 0)), np.zeros(0), np.zeros((0, 0))


@pytest.mark.parametrize("mean", ["paper", "ross", "none"])
def test_no_truncation_matches_the_exact_svd_of_the_centred_data(mean):
    M = _low_rank_columns()
    model = _stream(M, mean=mean)
    centred = M - M.mean(axis=1, keepdims=True) if mean != "none" else M
    U, s, Vt = np.linalg.svd(centred, full_matrices=False)
    r = model.singular_values_.size
    assert r == (119 if mean != "none" else 120)   # centring removes one direction
    scale = s[0]
    assert np.max(np.abs(model.singular_values_ - s[:r])) < 1e-10 * scale
    assert np.max(np.abs(model.mean_ - (M.mean(axis=1) if mean != "none" else 0))) < 1e-10
    assert np.max(np.abs(model.U_.T @ model.U_ - np.eye(r))) < 1e-10
    assert np.max(np.abs(model.reconstruct(M.T) - M.T)) < 1e-10 * scale
    if model.V_ is not None:
        rebuilt = (model.U_ * model.singular_values_) @ model.V_.T + model.mean_[:, None]
        assert np.max(np.abs(rebuilt - M)) < 1e-10 * scale
        assert np.max(np.abs(model.V_.T @ model.V_ - np.eye(r))) < 1e-10


def test_fast_update_with_mean_equals_the_printed_p_by_r_path():
    M = _low_rank_columns(p=300, q=40)
    old = M[:, :30]
    U, s, Vt = np.linalg.svd(old - old.mean(axis=1, keepdims=True), full_matrices=False)
    args = (U[:, :29], s[:29], Vt[:29].T, old.mean(axis=1), M[:, 30:])
    fast, printed = update_with_mean(*args, fast=True), update_with_mean(*args, fast=False)
    assert np.max(np.abs(fast.s - printed.s)) < 1e-10 * fast.s[0]
    np.testing.assert_allclose(fast.mean, printed.mean, atol=1e-12)
    np.testing.assert_allclose((fast.U * fast.s) @ fast.V.T, (printed.U * printed.s) @ printed.V.T, atol=1e-10)
    np.testing.assert_allclose((fast.U * fast.s) @ fast.V.T + fast.mean[:, None], M, atol=1e-10)
    assert np.allclose(fast.V.sum(axis=0), 0, atol=1e-12)   # eq. (13): V_f's columns are centred


def test_brand_update_appends_columns_and_drops_a_residual_inside_the_span():
    M = _low_rank_columns(p=200, q=30)
    U, s, Vt = np.linalg.svd(M[:, :20], full_matrices=False)
    grown = brand_update(U, s, Vt.T, M[:, 20:])
    np.testing.assert_allclose(grown.s, np.linalg.svd(M, compute_uv=False), rtol=1e-10)
    np.testing.assert_allclose((grown.U * grown.s) @ grown.V.T, M, atol=1e-10)
    inside = U[:, :5] @ np.arange(1.0, 6.0)                 # a column already in span(U): nothing to add
    same = brand_update(U, s, Vt.T, inside[:, None])
    assert same.U.shape[1] == U.shape[1] and same.V.shape == (21, U.shape[1])
    assert np.max(np.abs(U.T @ U - np.eye(20))) < 1e-12 and np.max(np.abs(same.U.T @ same.U - np.eye(20))) < 1e-12


def test_extract_mean_of_sec_2_4_returns_the_centred_svd_and_the_mean():
    S = _low_rank_columns(p=150, q=25)
    U, s, Vt = np.linalg.svd(S, full_matrices=False)
    for fast in (True, False):
        out = extract_mean(U, s, Vt.T, fast=fast)
        np.testing.assert_allclose(out.mean, S.mean(axis=1), atol=1e-12)
        centred = S - S.mean(axis=1, keepdims=True)
        np.testing.assert_allclose(out.s[:24], np.linalg.svd(centred, compute_uv=False)[:24], rtol=1e-10)
        np.testing.assert_allclose((out.U * out.s) @ out.V.T, centred, atol=1e-10)


def test_ross_update_gives_the_papers_basis_singular_values_and_mean():
    M = _low_rank_columns(p=400, q=60)
    paper = _stream(M, mean="paper")
    U, s, V, mean = *_empty(400)[:2], None, np.zeros(400)
    n_seen = 0
    for start in range(0, 60, 7):                           # batches of 7 columns, the last one shorter
        U, s, V, mean = ross_update(U, s, mean, n_seen, M[:, start:start + 7])
        n_seen += M[:, start:start + 7].shape[1]
    U, s, _, mean = isvd.svd_update._truncate((U, s, None, mean))
    np.testing.assert_allclose(s, paper.singular_values_, rtol=1e-10)
    np.testing.assert_allclose(mean, paper.mean_, atol=1e-12)
    np.testing.assert_allclose(U @ U.T, paper.U_ @ paper.U_.T, atol=1e-9)


def test_rank_cap_keeps_the_error_near_the_optimal_and_the_mean_exact():
    face = make_talking_face(150, rng=3, size=(48, 50))
    X = face.frames.reshape(150, -1)
    model = IncrementalSVD(max_rank=10)
    for frame in X:
        model.partial_fit(frame[None])
    centred = X - X.mean(axis=0)
    _, _, Vt = np.linalg.svd(centred, full_matrices=False)
    optimal = np.linalg.norm(centred - centred @ Vt[:10].T @ Vt[:10])
    ours = np.linalg.norm(model.reconstruct(X) - X)
    assert optimal <= ours <= 1.01 * optimal
    np.testing.assert_allclose(model.mean_, X.mean(axis=0), atol=1e-12)
    assert np.max(np.abs(model.U_.T @ model.U_ - np.eye(10))) < 1e-12
    assert model.memory_bytes() == 8 * (2400 * 10 + 10 + 150 * 10 + 2400)


def test_tau_schedule_is_geometric_and_the_noise_edge_bounds_pure_noise():
    taus = [tau_schedule(t) for t in range(30)]
    assert taus[0] == 0.5 and taus[25] == pytest.approx(5e-4) and taus[29] == taus[25]
    assert np.allclose(np.diff(np.log(taus[:26])), np.log(1e-3) / 25)
    noise = np.random.default_rng(0).normal(scale=0.02, size=(2000, 300))
    largest = np.linalg.svd(noise, compute_uv=False)[0]
    assert 0.95 * noise_edge(0.02, 2000, 300) < largest < 1.05 * noise_edge(0.02, 2000, 300)


def test_estimate_noise_recovers_sigma_on_flat_noise_and_on_the_face():
    rng = np.random.default_rng(4)
    flat = 0.3 + rng.normal(scale=0.02, size=(150, 160))
    assert isvd.estimate_noise(flat) == pytest.approx(0.02, rel=0.05)
    ramp = flat + np.add.outer(np.linspace(0, 1, 150), np.linspace(0, 2, 160))  # a linear ramp is cancelled
    assert isvd.estimate_noise(ramp) == pytest.approx(isvd.estimate_noise(flat), rel=1e-9)
    for noise in (0.01, 0.03):  # the textured moving face at half size: within 15 % of the true sigma
        face = make_talking_face(2, rng=9, size=(101, 103), motion="similarity", noise=noise)
        assert isvd.estimate_noise(face.frames[0]) == pytest.approx(noise, rel=0.15)


def test_exercise_5_reference_is_the_batch_svd_of_all_columns():
    from amdo_lab.incremental_svd.exercises import mean_update_case, mean_update_reference

    for seed in (1, 2, 3):
        case = mean_update_case(seed)
        old = (case["U"] * case["s"]) @ case["V"].T + case["mean"][:, None]
        every = np.hstack([old, case["I"]])
        s_f, mean_f = mean_update_reference(**case)
        np.testing.assert_allclose(mean_f, every.mean(axis=1), atol=1e-12)
        batch = np.linalg.svd(every - every.mean(axis=1, keepdims=True), compute_uv=False)
        np.testing.assert_allclose(s_f, batch[batch > 1e-12 * batch[0]], rtol=1e-10)


def test_talking_face_is_seeded_with_disjoint_masks_and_psnr_of_its_noise():
    a, b = make_talking_face(20, rng=5, size=(60, 62)), make_talking_face(20, rng=5, size=(60, 62))
    np.testing.assert_array_equal(a.frames, b.frames)
    assert a.clean.min() >= 0 and a.clean.max() <= 1 and a.latent.shape == (20, 4)
    stacked = np.sum([m.astype(int) for m in a.masks.values()], axis=0)
    assert stacked.max() == 1 and all(m.any() for m in a.masks.values())
    assert abs(psnr_db(a.frames, a.clean) - 40.0) < 0.3
    assert isvd.render_faces(a.latent[:2], size=(60, 62)).shape == (2, 60, 62)


def test_estimator_contract_and_transform():
    model = IncrementalSVD(max_rank=3)
    with pytest.raises(NotFittedError):
        model.transform(np.zeros((1, 4)))
    X = np.random.default_rng(2).normal(size=(8, 4))
    assert model.partial_fit(X[:5]) is model and model.partial_fit(X[5:]).n_seen_ == 8
    np.testing.assert_allclose(model.transform(X), (X - X.mean(axis=0)) @ model.U_)
    assert model.state.U is model.U_


REJECTIONS = [
    reject("partial_fit pixels differ", lambda: IncrementalSVD().partial_fit(np.ones((1, 4))).partial_fit(np.ones((1, 5))),
           ValueError, r"X must have shape \(n, 4\)"),
    reject("unknown mean", lambda: IncrementalSVD(mean="batch").partial_fit(np.ones((1, 4))), ValueError, "mean must be"),
    reject("max_rank zero", lambda: IncrementalSVD(max_rank=0).partial_fit(np.ones((1, 4))), ValueError, "max_rank"),
    reject("negative tol", lambda: IncrementalSVD(tol=-1.0).partial_fit(np.ones((1, 4))), ValueError, "tol"),
    reject("update columns of another length", lambda: update_with_mean(*_empty(4), np.zeros(4), np.ones((5, 1))),
           ValueError, r"I must have shape \(4, n\)"),
    reject("extract_mean with no rows", lambda: extract_mean(np.ones((4, 0)), np.zeros(0), np.zeros((0, 0))),
           ValueError, "V's number of rows \\(one per column seen\\) must be at least 1"),
    reject("negative singular value", lambda: brand_update(np.eye(3)[:, :1], [-1.0], np.ones((1, 1)), np.ones((3, 1))),
           ValueError, r"s \(one per U column\) must lie in \[0, "),
    reject("one frame", lambda: make_talking_face(1, rng=0), ValueError, "n_frames must be at least 2"),
    reject("noise above 1", lambda: make_talking_face(3, rng=0, noise=2.0), ValueError, r"noise must be in \[0, 1\]"),
    reject("latent out of range", lambda: isvd.render_faces([[2.0, 0, 0, 0]], size=(40, 40)), ValueError, "latent"),
    reject("tiny face", lambda: make_talking_face(2, rng=0, size=(10, 40)), ValueError,
           r"size\[0\] must be at least 32"),
]


@pytest.mark.parametrize(("call", "error", "message"), REJECTIONS)
def test_rejections(request, call, error, message):
    check_rejection(request, call, error, message)


# --- the moving face and the tracker of Sec. 3.2 ---------------------------------------------------

_HALF = (101, 103)


def test_similarity_motion_places_the_still_face_where_the_truth_says():
    still = make_talking_face(40, rng=5, size=_HALF)
    moving = make_talking_face(40, rng=5, size=_HALF, motion="similarity")
    np.testing.assert_array_equal(still.latent, moving.latent)      # same expressions, drawn first
    assert np.all(moving.truth[0] == 0) and np.all(still.truth == 0)
    assert np.all(np.abs(moving.truth).max(axis=0) <= np.array(isvd.SIMILARITY_BOUNDS) + 1e-12)
    inside = np.zeros(_HALF, bool)
    inside[30:80, 25:80] = True                                      # well inside the head
    points = np.column_stack(np.nonzero(inside)[::-1]).astype(float)
    from scipy import ndimage
    for t in (10, 39):
        placed = isvd.similarity_points(moving.truth[t], points, _HALF)
        seen = ndimage.map_coordinates(moving.clean[t], [placed[:, 1], placed[:, 0]], order=1)
        assert np.mean(np.abs(seen - still.clean[t][inside])) < 0.01
        assert np.mean(np.abs(moving.clean[t] - still.clean[t])) > 0.01  # it did move


def test_corner_error_is_zero_for_the_truth_and_the_shift_for_a_shift():
    truth = np.array([[1.0, -2.0, 0.03, 0.02]])
    assert isvd.corner_error_px(truth, truth, _HALF)[0] == 0
    shifted = truth + [[3.0, 4.0, 0.0, 0.0]]
    assert abs(isvd.corner_error_px(shifted, truth, _HALF)[0] - 5.0) < 1e-12


def test_align_frame_recovers_a_placement_against_the_first_frame():
    face = make_talking_face(2, rng=3, size=_HALF, noise=0.0)
    target = np.array([2.5, -1.5, 0.03, 0.02])
    moved = isvd.face._move(face.clean[:1], target[None], np.full(_HALF, 0.35))[0]
    models = {}
    for name, mask in face.masks.items():
        mean = face.clean[0][mask]
        models[name] = isvd.SvdState(np.zeros((mean.size, 0)), np.zeros(0), None, mean)
    found = isvd.tracking._align_frame(moved, face.masks, models, np.zeros(4))
    # 0.11 px here: the moved frame and the sampled regions are each resampled bilinearly
    assert isvd.corner_error_px(found[None], target[None], _HALF)[0] < 0.2


@pytest.fixture(scope="module")
def moving_face():
    return make_talking_face(120, rng=7, size=_HALF, motion="similarity")


def test_on_the_fly_tracks_and_learns_the_moving_face(moving_face):
    result = isvd.train_on_the_fly(moving_face.frames, moving_face.masks, np.zeros(4), max_rank=10)
    error = isvd.corner_error_px(result.params, moving_face.truth, _HALF)
    assert np.median(error) < 0.02 * _HALF[0] and error.max() < 0.04 * _HALF[0]   # 1.05 and 1.50 px here
    oracle = isvd.train_on_the_fly(moving_face.frames, moving_face.masks, np.zeros(4), max_rank=10,
                                   learn_at=moving_face.truth)
    oracle_error = isvd.corner_error_px(oracle.params, moving_face.truth, _HALF)
    assert np.median(oracle_error) < 0.2 and np.median(oracle_error) < np.median(error) / 3   # 0.09 px here
    assert result.ranks.shape == (120, 4) and result.ranks.max() <= 10 and result.ranks[-1].max() > 0
    assert set(result.models) == set(moving_face.masks) and result.peak_bytes > 0
    again = isvd.train_on_the_fly(moving_face.frames, moving_face.masks, np.zeros(4), max_rank=10)
    np.testing.assert_array_equal(result.params, again.params)      # deterministic
    paper = isvd.train_on_the_fly(moving_face.frames[:30], moving_face.masks, np.zeros(4), tau="paper")
    assert paper.ranks[-1].max() >= result.ranks[29].max()          # the literal τ keeps more


def test_non_causal_rounds_refit_and_realign(moving_face):
    template = isvd.train_non_causal(moving_face.frames, moving_face.masks, np.zeros(4), rounds=0)
    assert np.all(template.ranks == 0)
    batch = isvd.train_non_causal(moving_face.frames, moving_face.masks, np.zeros(4), rounds=1, max_rank=10)
    assert batch.ranks.max() <= 10 and batch.ranks.max() > 0
    error = isvd.corner_error_px(batch.params, moving_face.truth, _HALF)
    assert np.median(error) < 0.02 * _HALF[0]                                        # 0.74 px here
    U, s, V, mean = batch.models["mouth"]
    assert np.max(np.abs(U.T @ U - np.eye(s.size))) < 1e-8


# --- known answers at the bounds: a finite result is not enough, it must be the right one -----------
_SCALE = 1e90  # data near MAX_ABS (1e100): the updates must stay right, not only finite


def test_updates_at_large_scale_match_the_exact_svd_and_mean():
    M = _low_rank_columns(p=60, q=12) * _SCALE
    U, s, Vt = np.linalg.svd(M[:, :10], full_matrices=False)
    grown = brand_update(U, s, Vt.T, M[:, 10:])
    np.testing.assert_allclose(grown.s, np.linalg.svd(M, compute_uv=False), rtol=1e-9, atol=1e-9 * grown.s[0])
    assert np.abs(grown.U.T @ grown.U - np.eye(grown.U.shape[1])).max() < 1e-10
    old = M[:, :10]
    U, s, Vt = np.linalg.svd(old - old.mean(axis=1, keepdims=True), full_matrices=False)
    moved = update_with_mean(U, s, Vt.T, old.mean(axis=1), M[:, 10:])
    np.testing.assert_allclose(moved.mean, M.mean(axis=1), rtol=1e-10, atol=1e-10 * _SCALE)
    np.testing.assert_allclose(extract_mean(*np.linalg.svd(M, full_matrices=False)[:2],
                                            np.linalg.svd(M, full_matrices=False)[2].T).mean,
                               M.mean(axis=1), rtol=1e-10, atol=1e-10 * _SCALE)


def test_scalar_helpers_give_their_closed_forms_at_the_bounds():
    assert noise_edge(1e100, 100, 25) == pytest.approx(1e100 * 15)
    assert tau_schedule(0) == 0.5 and tau_schedule(25) == pytest.approx(5e-4, rel=1e-12) == tau_schedule(10**6)
    points = np.array([[0.0, 0.0], [1e9, -1e9]])
    np.testing.assert_array_equal(isvd.similarity_points(np.zeros(4), points, (40, 41)), points)
    np.testing.assert_allclose(isvd.similarity_points([1e6, -1e6, 0, 0], points, (40, 41)), points + [1e6, -1e6])
    params = np.array([[1e6, -1e6, 0.5, 0.1]])
    assert isvd.corner_error_px(params, params, (40, 41))[0] == 0
    assert isvd.psnr_db(np.full(4, 0.5 + 1e-50), np.full(4, 0.5)) > 300


def test_error_less_offset_is_zero_for_a_constant_offset_and_the_error_otherwise():
    rng = np.random.default_rng(4)
    truth = rng.uniform(-1, 1, (30, 4)) * [6.0, 6.0, 0.07, 0.04]
    k_true, t_true = np.exp(truth[:, 3] + 1j * truth[:, 2]), truth[:, 0] + 1j * truth[:, 1]
    k_off, t_off = np.exp(0.01 + 0.02j), 1.5 - 0.7j                     # O: 1.5 px, 0.02 rad, 1 %
    k, t = k_true * k_off, k_true * t_off + t_true                       # estimate = truth composed with O
    estimate = np.column_stack([t.real, t.imag, np.angle(k), np.log(np.abs(k))])
    assert np.median(isvd.corner_error_px(estimate, truth, _HALF)) > 1.0
    assert np.max(isvd.corner_error_less_offset_px(estimate, truth, _HALF)) < 1e-9
    jitter = estimate + [[0.5, 0.0, 0.0, 0.0]] * np.where(np.arange(30) % 2, 1, -1)[:, None]   # ±0.5 px on top
    np.testing.assert_allclose(isvd.corner_error_less_offset_px(jitter, truth, _HALF), 0.5, atol=0.05)
