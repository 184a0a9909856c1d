"""On-the-fly face training (Sec. 3.2): align each frame to the region models, then learn it.

The paper aligns with the tracker of its reference [7], which it does not give. We align by
Gauss-Newton on a similarity (shift, rotation, scale), minimising the part of the region images that
the current models cannot explain: ``sum_r ||(I - U_r U_r^T)(o_r(a) - m_r)||^2``. The non-causal
peer reads [7] as: align every frame, take a batch SVD of all aligned regions, re-align, three rounds.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from amdo_lab.common import (MAX_SIDE, as_bool_mask, as_finite_array, check_choice, check_positive, check_positive_int,
                             one_blas_thread)
from amdo_lab.incremental_svd.face import _place
from amdo_lab.incremental_svd.svd_update import IncrementalSVD, SvdState, estimate_noise, noise_edge, tau_schedule

__all__ = ["TAU_MODES", "TrainingResult", "train_non_causal", "train_on_the_fly"]

#: ``"noise-edge"``: drop directions below σ(√p + √q); ``"paper"``: τ from 0.5 to 0.5e-3 over 25 frames.
TAU_MODES = ("noise-edge", "paper")
#: Most re-alignment rounds of :func:`train_non_causal` (each is a batch SVD and a tracking pass).
MAX_ROUNDS = 100
_ITERATIONS, _STEP_PX = 20, 1e-3   # Gauss-Newton: at most 20 steps, stop when no corner moves 1e-3 px


@dataclass(frozen=True)
class TrainingResult:
    """Placements and region models learnt from a sequence.

    Parameters
    ----------
    params : ndarray, shape (T, 4)
        Placement of the masks in each frame, ``(tx, ty, angle, log_scale)`` (px, px, rad, natural
        log; x right, y down; see :func:`~amdo_lab.incremental_svd.similarity_points`).
    models : dict of str to SvdState
        Final model ``(U, s, V, mean)`` of each region.
    ranks : ndarray of int, shape (T, n_regions)
        Directions kept by each region's model after each frame (the last round's for the non-causal).
    seconds : float
        Wall time of the whole training.
    peak_bytes : int
        Largest number of bytes held by the arrays the method keeps between frames: the region
        models, and for the non-causal method also every frame's regions.
    noise : float
        The pixel noise σ of the noise edge: the one given, or the one estimated from the first frame
        (:func:`~amdo_lab.incremental_svd.estimate_noise`).

    References
    ----------
    Melenchón, Meler & Iriondo, AMDO 2004, Sec. 3.2 and Fig. 3.
    """

    params: np.ndarray
    models: dict[str, SvdState]
    ranks: np.ndarray
    seconds: float
    peak_bytes: int
    noise: float


def _check_masks(masks: object, shape: tuple[int, ...]) -> dict[str, np.ndarray]:
    """Non-empty, disjoint boolean masks of the frames' size, by region name (a size mismatch names both
    arguments, since either may be at fault)."""
    if not isinstance(masks, dict) or not masks:
        raise ValueError("masks must be a non-empty dict of region name to boolean mask")
    checked, taken = {}, np.zeros(shape, bool)
    for name, mask in masks.items():
        mask = as_bool_mask(mask, f"masks[{name!r}] (on the pixels of frames)", shape=shape)
        if not mask.any() or np.any(taken & mask):
            raise ValueError(f"masks must be non-empty and must not overlap; {name!r} is empty or overlaps")
        taken |= mask
        checked[name] = mask
    return checked


def _check_training(frames: object, masks: object, init: object, max_rank: object, tau: object,
                    noise: object) -> tuple[np.ndarray, dict, np.ndarray, int, float]:
    """The inputs both trainers share: frames, masks, first placement, rank cap, threshold mode, noise (None:
    estimated from the first frame, which a causal learner has seen)."""
    frames = as_finite_array(frames, "frames", ndim=3, max_abs=1e6)
    check_positive_int(frames.shape[0], "frames' number of frames", minimum=2)
    masks = _check_masks(masks, frames.shape[1:])
    init = as_finite_array(init, "init", shape=(4,), max_abs=1e3)
    check_choice(tau, "tau", TAU_MODES)
    max_rank = check_positive_int(max_rank, "max_rank", maximum=MAX_SIDE)
    noise = estimate_noise(frames[0]) if noise is None else check_positive(noise, "noise")
    return frames, masks, init, max_rank, noise


class _Regions:
    """The masks' reference pixels, and sampling of a frame's regions (and their gradients) under a placement."""

    def __init__(self, masks: dict[str, np.ndarray], frames: np.ndarray) -> None:
        self.names = list(masks)
        self.rows, self.cols = frames.shape[1:]
        points = [np.column_stack(np.nonzero(mask)[::-1]).astype(float) for mask in masks.values()]
        self.points = np.concatenate(points)                            # (x, y) of every region pixel
        self.splits = np.cumsum([p.shape[0] for p in points])[:-1]
        self.frames = frames

    def sample(self, t: int, params: np.ndarray, gradients: bool = False):
        placed = _place(params, self.points, self.rows, self.cols)
        where = [placed[:, 1], placed[:, 0]]
        values = ndimage.map_coordinates(self.frames[t], where, order=1, mode="nearest")
        if not gradients:
            return np.split(values, self.splits)
        grad_y, grad_x = np.gradient(self.frames[t])
        gx = ndimage.map_coordinates(grad_x, where, order=1, mode="nearest")
        gy = ndimage.map_coordinates(grad_y, where, order=1, mode="nearest")
        dx, dy = placed[:, 0] - (self.cols - 1) / 2 - params[0], placed[:, 1] - (self.rows - 1) / 2 - params[1]
        jacobian = np.column_stack([gx, gy, gx * -dy + gy * dx, gx * dx + gy * dy])
        return np.split(values, self.splits), np.split(jacobian, self.splits)


def _align(regions: _Regions, t: int, models: list[SvdState], start: np.ndarray) -> np.ndarray:
    """Gauss-Newton on the similarity: minimise the regions' residual outside their models' bases."""
    params, reach = start.copy(), max(regions.rows, regions.cols)
    for _ in range(_ITERATIONS):
        values, jacobians = regions.sample(t, params, gradients=True)
        normal, gradient = np.zeros((4, 4)), np.zeros(4)
        for (U, _, _, mean), o, J in zip(models, values, jacobians):
            e = o - mean
            e, J = e - U @ (U.T @ e), J - U @ (U.T @ J)
            normal += J.T @ J
            gradient += J.T @ e
        step = -np.linalg.lstsq(normal, gradient, rcond=None)[0]
        params += step
        if max(abs(step[0]), abs(step[1]), reach * abs(step[2]), reach * abs(step[3])) < _STEP_PX:
            break
    return params


def _align_frame(frame: np.ndarray, masks: dict[str, np.ndarray], models: dict[str, SvdState],
                 start: np.ndarray) -> np.ndarray:
    """Place the masks on one ``frame`` by Gauss-Newton (:func:`_align`) against fixed region ``models``,
    one per mask, from the placement ``start``. Check-free: the trainers call :func:`_align` themselves;
    the tests use this entry."""
    regions = _Regions(masks, np.asarray(frame, dtype=float)[None])
    return _align(regions, 0, [models[name] for name in regions.names], np.asarray(start, dtype=float))


def _region_tol(tau: str, t: int, noise: float, pixels: int) -> float:
    return tau_schedule(t) if tau == "paper" else noise_edge(noise, pixels, t + 1)


def train_on_the_fly(frames: np.ndarray, masks: dict[str, np.ndarray], init: np.ndarray, *, max_rank: int = 35,
                     tau: str = "noise-edge", noise: float | None = None,
                     learn_at: np.ndarray | None = None) -> TrainingResult:
    """Track and learn a face in one causal pass: align each frame to the models, then update them.

    Parameters
    ----------
    frames : ndarray, shape (T, rows, cols)
        The sequence, T >= 2.
    masks : dict of str to ndarray of bool, shape (rows, cols)
        Disjoint regions drawn on the first frame.
    init : ndarray, shape (4,)
        Placement of the masks in the first frame (the paper's a_1 = 0).
    max_rank : int
        Largest number of directions per region model.
    tau : {"noise-edge", "paper"}
        Threshold on the singular values: the noise edge σ(√p + √q) of each region, or the paper's
        schedule from 0.5 to 0.5e-3 over the first 25 frames (:func:`tau_schedule`).
    noise : float or None
        Pixel noise σ of the frames, used by ``tau="noise-edge"``. None (default): estimated from the first
        frame by :func:`~amdo_lab.incremental_svd.estimate_noise`; a value given is an oracle when it is the
        generator's true σ.
    learn_at : ndarray, shape (T, 4), optional
        Placements at which the learnt regions are cut (default: the aligner's own). Passing the true
        placements gives an oracle: models learnt from correctly placed regions, while the aligner still
        estimates every placement against them.

    Returns
    -------
    TrainingResult
        Placements, final models, ranks per frame, time and peak bytes.

    References
    ----------
    Melenchón, Meler & Iriondo, AMDO 2004, Sec. 3.2 and Fig. 3.
    """
    frames, masks, init, max_rank, noise = _check_training(frames, masks, init, max_rank, tau, noise)
    if learn_at is not None:
        learn_at = as_finite_array(learn_at, "learn_at", shape=(frames.shape[0], 4), max_abs=1e3)
    start_time = time.perf_counter()
    regions = _Regions(masks, frames)
    learners = [IncrementalSVD(max_rank=max_rank) for _ in regions.names]
    params = np.zeros((frames.shape[0], 4))
    ranks = np.zeros((frames.shape[0], len(learners)), dtype=int)
    peak = 0
    with one_blas_thread():
        for t in range(frames.shape[0]):
            if t == 0:
                params[0] = init
            else:
                params[t] = _align(regions, t, [learner.state for learner in learners], params[t - 1])
            cut_at = params[t] if learn_at is None else learn_at[t]
            for k, (learner, o) in enumerate(zip(learners, regions.sample(t, cut_at))):
                learner.tol = _region_tol(tau, t, noise, o.size)
                learner.partial_fit(o[None])
                ranks[t, k] = learner.singular_values_.size
            peak = max(peak, sum(learner.memory_bytes() for learner in learners))
    seconds = time.perf_counter() - start_time
    return TrainingResult(params, {name: m.state for name, m in zip(regions.names, learners)}, ranks, seconds,
                          int(peak), float(noise))


def _batch_model(patches: np.ndarray, max_rank: int, tol: float) -> SvdState:
    """Thin SVD of the centred patches (rows are frames), through the frames' Gram matrix."""
    mean = patches.mean(axis=0)
    centred = patches - mean
    values, vectors = np.linalg.eigh(centred @ centred.T)
    values, vectors = values[::-1], vectors[:, ::-1]
    s = np.sqrt(np.clip(values, 0, None))
    keep = min(max_rank, int(np.sum(s > max(tol, 1e-10 * s[0]))))
    V = vectors[:, :keep]
    U = centred.T @ V / s[:keep]
    return SvdState(U, s[:keep], V, mean)


def train_non_causal(frames: np.ndarray, masks: dict[str, np.ndarray], init: np.ndarray, *, max_rank: int = 35,
                     tau: str = "noise-edge", noise: float | None = None, rounds: int = 3) -> TrainingResult:
    """The batch peer: track with the first frame's regions, then fit a batch SVD and re-align, in rounds.

    Parameters
    ----------
    frames : ndarray, shape (T, rows, cols)
        The sequence, T >= 2.
    masks : dict of str to ndarray of bool, shape (rows, cols)
        Disjoint regions drawn on the first frame.
    init : ndarray, shape (4,)
        Placement of the masks in the first frame.
    max_rank : int
        Largest number of directions per region model.
    tau : {"noise-edge", "paper"}
        ``"noise-edge"`` drops directions below σ(√p + √T); ``"paper"`` uses τ's final value, 0.5e-3.
    noise : float or None
        Pixel noise σ of the frames, used by ``tau="noise-edge"``; None (default): estimated from the
        first frame, as :func:`train_on_the_fly` does.
    rounds : int
        Batch SVD and re-alignment rounds after the first tracking pass (0: the first frame as template),
        at most :data:`MAX_ROUNDS`.

    Returns
    -------
    TrainingResult
        Placements, final models, ranks (constant per round), time and peak bytes (all regions held).

    References
    ----------
    Melenchón, Meler & Iriondo, AMDO 2004, Sec. 4 and Fig. 4(b) (their non-causal method [7], read
    as described above).
    """
    frames, masks, init, max_rank, noise = _check_training(frames, masks, init, max_rank, tau, noise)
    rounds = check_positive_int(rounds, "rounds", minimum=0, maximum=MAX_ROUNDS)
    start_time = time.perf_counter()
    regions = _Regions(masks, frames)
    n_frames = frames.shape[0]
    params = np.zeros((n_frames, 4))
    params[0] = init
    with one_blas_thread():
        templates = [SvdState(np.zeros((o.size, 0)), np.zeros(0), None, o) for o in regions.sample(0, init)]
        for t in range(1, n_frames):
            params[t] = _align(regions, t, templates, params[t - 1])
        models, peak = templates, 0
        for _ in range(rounds):
            samples = [regions.sample(t, params[t]) for t in range(n_frames)]
            models = []
            for k in range(len(regions.names)):
                patches = np.stack([sample[k] for sample in samples])
                tol = 5e-4 if tau == "paper" else noise_edge(noise, patches.shape[1], n_frames)
                models.append(_batch_model(patches, max_rank, tol))
                peak = max(peak, patches.nbytes * len(regions.names) + sum(m.U.nbytes for m in models))
            params = np.stack([_align(regions, t, models, params[t]) for t in range(n_frames)])
    ranks = np.tile([m.s.size for m in models], (n_frames, 1))
    seconds = time.perf_counter() - start_time
    return TrainingResult(params, dict(zip(regions.names, models)), ranks, seconds, int(peak), float(noise))
