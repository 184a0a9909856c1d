"""The exercises of chapter 7, checked from the notebook's check cells (see ``amdo_lab.common.exercises``)."""

from __future__ import annotations

import numpy as np

from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer
from amdo_lab.incremental_svd.face import make_talking_face, psnr_db
from amdo_lab.incremental_svd.svd_update import IncrementalSVD, noise_edge

__all__ = ["EXERCISES", "directions_above_noise_edge", "stream_psnr_db"]


def stream_psnr_db(frames: np.ndarray, clean: np.ndarray, max_rank: int) -> float:
    """PSNR (dB) against ``clean`` of the frames reconstructed by a model learnt one frame at a time.

    Parameters
    ----------
    frames, clean : ndarray, shape (n, rows, cols)
        Noisy frames and their clean versions.
    max_rank : int
        The learner's rank cap.

    Returns
    -------
    float
        The PSNR of the reconstructions of ``frames`` against ``clean``.
    """
    X = frames.reshape(frames.shape[0], -1)
    model = IncrementalSVD(max_rank=max_rank)
    for frame in X:
        model.partial_fit(frame[None])
    return psnr_db(model.reconstruct(X), clean.reshape(X.shape))


def directions_above_noise_edge(n_frames: int, size: tuple[int, int], noise: float, rng: int) -> int:
    """How many singular values of a face stream learnt without a cap exceed the noise edge.

    Parameters
    ----------
    n_frames : int
        Frames streamed.
    size : pair of int
        Frame size.
    noise : float
        Pixel noise of the stream (the edge uses the same value).
    rng : int
        Seed of :func:`make_talking_face`.

    Returns
    -------
    int
        Number of singular values above ``noise_edge(noise, p, n_frames)``.
    """
    face = make_talking_face(n_frames, rng=rng, size=size, noise=noise)
    X = face.frames.reshape(n_frames, -1)
    model = IncrementalSVD()
    for frame in X:
        model.partial_fit(frame[None])
    return int(np.count_nonzero(model.singular_values_ > noise_edge(noise, X.shape[1], n_frames)))


def _two_point_singular_value(toy_points: np.ndarray) -> float:
    return float(np.linalg.norm(toy_points[1] - toy_points[0]) / np.sqrt(2))


EXERCISES = ExerciseSet(chapter=7, exercises=[
    Exercise(
        1, _two_point_singular_value,
        "centre the two points on their mean first: each sits half the gap away from it; then take the norm "
        "of the 2 x 2 centred matrix",
        (WrongAnswer(lambda ns: float(np.linalg.norm(ns["toy_points"][1] - ns["toy_points"][0])),
                     "the distance between the points (no centring)"),
         WrongAnswer(lambda ns: float(np.linalg.norm(ns["toy_points"][1] - ns["toy_points"][0]) / 2),
                     "half the distance (one point's offset only)")),
        context=("toy_points",), rtol=2e-3),
    Exercise(
        2, lambda small: stream_psnr_db(small.frames, small.clean, 5),
        "learn the same 80 half-size frames with max_rank=5 and score the reconstructions against small.clean",
        (WrongAnswer(lambda ns: ns["psnr_2"], "the unchanged experiment (rank 35)", unchanged_experiment=True),
         WrongAnswer(lambda ns: psnr_db(ns["small"].frames, ns["small"].clean), "the noisy input's PSNR")),
        context=("small",), atol=0.06, experiment=True),
    Exercise(
        3, lambda: directions_above_noise_edge(80, (101, 103), 0.03, 11),
        "regenerate the stream with noise=0.03 (same seed, size and length) and compare the singular values with "
        "the noise edge of that noise",
        (WrongAnswer(lambda ns: ns["kept_3"], "the unchanged experiment (noise 0.01)", unchanged_experiment=True),
         WrongAnswer(79, "every direction of the centred stream")),
        context=(), atol=0.5, experiment=True),
    Exercise(
        4, lambda: "V",
        "look at which factor has one row per frame seen, and at the QR of Table 1's second row",
        (WrongAnswer("U", "the p x r factor (its size does not change with the frames)"),
         WrongAnswer("Sigma", "the r x r core")),
        choices=("U", "Sigma", "V")),
])
