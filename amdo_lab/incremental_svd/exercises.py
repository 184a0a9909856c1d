"""The exercises of chapter 7, checked from the notebook's check cells (see ``amdo_lab.common.exercises``).

Only what is not secret lives here: the hints, the tolerances, the recorded wrong answers and, for the
"implement it" exercise, the reference (the package's mean update) and the maker of its cases. The
targets of the value exercises sit in the source notebook's hidden tests.
"""

from __future__ import annotations

import numpy as np

from amdo_lab.common import make_rng
from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer
from amdo_lab.incremental_svd.svd_update import update_with_mean

__all__ = ["EXERCISES", "mean_update_case", "mean_update_reference"]

#: The case exercise 5 shows in the notebook (the unseen ones are registered by the hidden test).
EXAMPLE_SEED = 5


def mean_update_case(seed: int) -> dict:
    """One case of exercise 5: a model of a few two-pixel images and the images to append.

    Parameters
    ----------
    seed : int
        Seed of the draw.

    Returns
    -------
    dict
        Keyword arguments ``U`` (2 x r), ``s`` (r,), ``V`` (q x r), ``mean`` (2,) of the model of ``q``
        images (3 to 8, centred on their mean), and ``I`` (2 x c), c = 1 to 3 new images (one for the
        example seed).
    """
    rng = make_rng(seed)
    q = int(rng.integers(3, 9))
    c = 1 if seed == EXAMPLE_SEED else int(rng.integers(1, 4))
    centre = rng.normal(2.0, 1.0, 2)
    old = centre[:, None] + rng.normal(0, [[1.5], [0.5]], (2, q))
    mean = old.mean(axis=1)
    U, s, Vt = np.linalg.svd(old - mean[:, None], full_matrices=False)
    keep = s > 1e-12 * s.max()
    new = centre[:, None] + rng.normal(0, 1.0, (2, c)) + rng.normal(0, 1.0, (2, 1))  # the mean moves
    return {"U": U[:, keep], "s": s[keep], "V": Vt[keep].T, "mean": mean, "I": new}


def mean_update_reference(U: np.ndarray, s: np.ndarray, V: np.ndarray, mean: np.ndarray,
                          I: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The singular values and the mean after :func:`update_with_mean` appends ``I`` (exercise 5's reference).

    Parameters
    ----------
    U, s, V, mean, I
        As in :func:`~amdo_lab.incremental_svd.update_with_mean`.

    Returns
    -------
    s_f : ndarray
        The singular values of the centred columns, descending, numerically null ones dropped.
    mean_f : ndarray
        The mean of all the columns.
    """
    state = update_with_mean(U, s, V, mean, I)
    return state.s[state.s > 1e-12 * state.s.max(initial=0.0)], state.mean


# --- plausible wrong implementations of exercise 5, each with its own hint -------------------------------

def _brand(U, s, V, I_hat):
    """Eq. (11) with a dense residual basis (enough for the two-pixel cases)."""
    L = U.T @ I_hat
    Q, R = np.linalg.qr(I_hat - U @ L)
    keep = np.abs(np.diag(R)) > 1e-10 * max(s.max(initial=0), np.abs(I_hat).max())
    Q, R = Q[:, keep], R[keep]
    K = np.block([[np.diag(s), L], [np.zeros((R.shape[0], s.size)), R]])
    U_d, s_d, V_d_t = np.linalg.svd(K, full_matrices=False)
    V_big = np.block([[V, np.zeros((V.shape[0], I_hat.shape[1]))], [np.zeros((I_hat.shape[1], s.size)),
                                                                      np.eye(I_hat.shape[1])]])
    return np.hstack([U, Q]) @ U_d, s_d, V_big @ V_d_t.T


def _move_mean(U_t, s_t, V_t, divide_by):
    v_bar = V_t.sum(axis=0) / divide_by
    Q_v, R_v = np.linalg.qr(V_t - v_bar)
    s_f = np.linalg.svd(U_t @ np.diag(s_t) @ R_v.T, compute_uv=False)
    return s_f[s_f > 1e-12 * s_f.max(initial=0.0)], U_t @ (s_t * v_bar)


def _no_mean_move(U, s, V, mean, I):
    """Brand's update of the columns centred on the old mean, and the old mean kept (eqs. 12-15 skipped)."""
    _, s_t, _ = _brand(U, s, V, I - mean[:, None])
    return s_t[s_t > 1e-12 * s_t.max(initial=0.0)], mean


def _old_mean_not_added(U, s, V, mean, I):
    """Eqs. (12)-(13) right, but the new mean is m̄_t alone (eqs. 14-15 skipped)."""
    U_t, s_t, V_t = _brand(U, s, V, I - mean[:, None])
    return _move_mean(U_t, s_t, V_t, V_t.shape[0])


def _divided_by_q(U, s, V, mean, I):
    """Table 1's first row as printed: the rows of V_t summed and divided by q, not q + c."""
    U_t, s_t, V_t = _brand(U, s, V, I - mean[:, None])
    s_f, m_bar_t = _move_mean(U_t, s_t, V_t, V.shape[0])
    return s_f, mean + m_bar_t


def _centred_on_own_mean(U, s, V, mean, I):
    """The new columns centred on their own mean instead of the model's (eq. 8 misread)."""
    U_t, s_t, V_t = _brand(U, s, V, I - I.mean(axis=1, keepdims=True))
    s_f, m_bar_t = _move_mean(U_t, s_t, V_t, V_t.shape[0])
    return s_f, mean + m_bar_t


EXERCISES = ExerciseSet(chapter=7, exercises=[
    Exercise(
        1, None,
        "centre the two points on their mean first: each sits half the gap away from it; then take the norm "
        "of the 2 x 2 centred matrix",
        (WrongAnswer(0.547, "the distance between the two points (no centring)",
                     hint="that is the distance between the two images; the model is built from the images "
                          "centred on their mean, so each is only half that distance from it"),
         WrongAnswer(0.273, "half the distance (one centred image only)",
                     hint="that is one centred image's length; the singular value is the norm of the whole "
                          "centred matrix, both columns together"),
         WrongAnswer(6.76, "the first singular value of all 30 toy images, read off the toy's output",
                     hint="that is the singular value after all 30 images; stream only the first two")),
        rtol=2e-3),
    Exercise(
        2, None,
        "generate 160 half-size frames with rng=11, learn them with max_rank=35 and score the reconstructions "
        "against the clean frames",
        (WrongAnswer(43.23, "the unchanged experiment (80 frames)", unchanged_experiment=True,
                     variable="experiment_2",
                     hint="that is the 80-frame PSNR: set n_frames_2 = 160 and run the cell again"),
         WrongAnswer(40.0, "the noisy input's PSNR",
                     hint="that is the PSNR of the noisy frames themselves; score the learner's reconstructions"),
         WrongAnswer(48.8, "the full-size 316-frame PSNR of the Fig. 2 table",
                     hint="that is the full-size, 316-frame model; the exercise asks for 160 half-size frames")),
        atol=0.006, experiment=True, why_points=1),
    Exercise(
        3, None,
        "regenerate the stream with noise=0.03 (same seed, size and length) and compare the singular values with "
        "the noise edge of that noise",
        (WrongAnswer(18, "the unchanged experiment (noise 0.01)", unchanged_experiment=True, variable="count_3",
                     hint="that is the count at noise 0.01: set noise_3 = 0.03 and run the cell again"),
         WrongAnswer(79, "every direction of the centred stream (or the edge of the old noise)",
                     hint="79 is every direction of 80 centred frames: count only those above the noise edge, "
                          "and compute the edge with the new noise")),
        atol=0.5, experiment=True, why_points=1),
    Exercise(
        4, None,
        "which array of the model has a row per frame seen, and what does eq. (2) make of that row?",
        (WrongAnswer("only Ross's model", "Ross's variant",
                     hint="look at what variants['ross'] keeps: is there any array with a row per frame?"),
         WrongAnswer("neither model", "neither model",
                     hint="eq. (2) writes every frame through the model's arrays; one of them has a row per "
                          "frame seen")),
        choices=("only the paper's model", "only Ross's model", "neither model"), why_points=1),
    Exercise(
        5, None,
        "append the new columns centred on the OLD mean with toy_brand (eqs. 7-11), then take the mean of the "
        "q + c rows of V_t out (eqs. 12-13) and add m̄_t to the old mean (eqs. 14-15); return (s_f, mean_f)",
        (WrongAnswer(_no_mean_move, "Brand's update only, the old mean kept",
                     hint="your mean does not move: after Brand's update take the mean of V_t's rows, eq. (12), "
                          "re-diagonalise, eq. (13), and add m̄_t to the old mean"),
         WrongAnswer(_old_mean_not_added, "m̄_t returned as the new mean",
                     hint="m̄_t is the mean of the columns centred on the old mean: add the old mean back "
                          "(eqs. 14-15)"),
         WrongAnswer(_divided_by_q, "Table 1's 1/q",
                     hint="v̄_t averages all q + c rows of V_t (Table 1's first row prints 1/q)"),
         WrongAnswer(_centred_on_own_mean, "new columns centred on their own mean",
                     hint="eq. (8) centres the new columns on the model's old mean, not on their own"),
         ),
        kind="function", reference=mean_update_reference, make_case=mean_update_case, example_seed=EXAMPLE_SEED,
        rtol=1e-6, atol=1e-9, points=2),
])
