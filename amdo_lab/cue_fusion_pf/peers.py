"""Peers on the same frames: OpenCV's CamShift (mean shift on a colour back-projection, ref. [13]) and TrackerMIL,
and our likelihood inside the generic particle filter of the ``pfilter`` package."""

from __future__ import annotations

import time

import cv2
import numpy as np

from amdo_lab.common import MAX_SIDE
from amdo_lab.common import check_positive_int, make_rng
from amdo_lab.cue_fusion_pf.data import as_ellipse
from amdo_lab.cue_fusion_pf.likelihoods import check_frames
from amdo_lab.cue_fusion_pf.tracker import TRACK_DEFAULTS, TrackResult, _check_run, build_cues, default_dynamics, shape_space_of

__all__ = ["track_camshift", "track_mil", "track_pfilter"]


def track_camshift(frames: np.ndarray, init: np.ndarray, *, hue_bins: int = 32) -> TrackResult:
    """Track with ``cv2.CamShift`` on the back-projection of the initial ellipse's hue histogram.

    The usual OpenCV recipe: a hue histogram of the target (pixels with saturation and value above
    a floor), back-projected on each frame, and CamShift's window started from the last one.
    ``states`` holds ``(cx, cy, s)`` with s the relative change of the larger semi-axis.

    Parameters
    ----------
    frames : numpy.ndarray
        (T, H, W, 3) uint8 RGB.
    init : numpy.ndarray
        Initial ellipse ``(cx, cy, a, b, angle)``, entries within ±1e6 (:func:`as_ellipse`).
    hue_bins : int
        Bins of the hue histogram. At most :data:`amdo_lab.common.MAX_SIDE` (4,096).

    Returns
    -------
    TrackResult
        Ellipses from CamShift's rotated rectangles (``ess`` is NaN: there are no particles).

    References
    ----------
    Li & Chaumette, AMDO 2004 (the task); Comaniciu, Ramesh & Meer, CVPR 2000 (ref. [13]).
    """
    frames = check_frames(frames)
    init = as_ellipse(init, "init")
    hue_bins = check_positive_int(hue_bins, "hue_bins", minimum=2, maximum=MAX_SIDE)
    began = time.perf_counter()
    height, width = frames.shape[1:3]
    cx, cy, a, b, _ = init
    window = (int(max(cx - a, 0)), int(max(cy - b, 0)), int(2 * a), int(2 * b))
    hsv = cv2.cvtColor(frames[0], cv2.COLOR_RGB2HSV)
    mask = cv2.inRange(hsv, (0, 40, 40), (180, 255, 255))
    x, y, w, h = window
    histogram = cv2.calcHist([hsv[y : y + h, x : x + w]], [0], mask[y : y + h, x : x + w], [hue_bins], [0, 180])
    cv2.normalize(histogram, histogram, 0, 255, cv2.NORM_MINMAX)
    criteria = (cv2.TERM_CRITERIA_EPS | cv2.TERM_CRITERIA_COUNT, 10, 1)
    ellipses = np.empty((len(frames), 5))
    for k, frame in enumerate(frames):
        hsv = cv2.cvtColor(frame, cv2.COLOR_RGB2HSV)
        back = cv2.calcBackProject([hsv], [0], histogram, [0, 180], 1)
        back &= cv2.inRange(hsv, (0, 40, 40), (180, 255, 255))
        box, window = cv2.CamShift(back, window, criteria)
        (bx, by), (bw, bh), angle = box
        if bw <= 0 or bh <= 0 or window[2] <= 0 or window[3] <= 0:  # lost: keep the last ellipse
            ellipses[k] = ellipses[k - 1] if k else init
            window = (int(np.clip(ellipses[k, 0] - a, 0, width - 2)), int(np.clip(ellipses[k, 1] - b, 0, height - 2)),
                      int(2 * a), int(2 * b))
            continue
        ellipses[k] = (bx, by, bw / 2.0, bh / 2.0, np.deg2rad(angle))
    seconds = time.perf_counter() - began
    scale = np.maximum(ellipses[:, 2], ellipses[:, 3]) / max(a, b) - 1.0
    states = np.column_stack([ellipses[:, :2], scale])
    return TrackResult(states, ellipses, ellipses[:, :2].copy(), np.full(len(frames), np.nan), seconds,
                       states[:, None, :], np.ones((len(frames), 1)))


def track_mil(frames: np.ndarray, init: np.ndarray) -> TrackResult:
    """Track with OpenCV's ``cv2.TrackerMIL`` (online multiple-instance boosting on Haar features).

    MIL tracks a box of fixed size; the ellipse returned is the one inscribed in the box. MIL draws
    its training samples from a generator inside OpenCV that ``cv2.setRNGSeed`` does not reach, so
    two runs on the same frames can differ by a few pixels (this is why the chapter's notebook, whose
    outputs are compared run to run, leaves it to the benchmark).

    Parameters
    ----------
    frames : numpy.ndarray
        (T, H, W, 3) uint8 RGB.
    init : numpy.ndarray
        Initial ellipse ``(cx, cy, a, b, angle)``, entries within ±1e6 (:func:`as_ellipse`); MIL
        starts from its bounding box.

    Returns
    -------
    TrackResult
        Ellipses inscribed in MIL's boxes (``ess`` is NaN).

    References
    ----------
    Li & Chaumette, AMDO 2004 (the task); Babenko, Yang & Belongie, CVPR 2009 (MIL tracking).
    """
    frames = check_frames(frames)
    init = as_ellipse(init, "init")
    began = time.perf_counter()
    cx, cy, a, b, _ = init
    tracker = cv2.TrackerMIL_create()
    tracker.init(cv2.cvtColor(frames[0], cv2.COLOR_RGB2BGR), (int(round(cx - a)), int(round(cy - b)), int(round(2 * a)), int(round(2 * b))))
    ellipses = np.empty((len(frames), 5))
    ellipses[0] = init
    for k in range(1, len(frames)):
        found, (x, y, w, h) = tracker.update(cv2.cvtColor(frames[k], cv2.COLOR_RGB2BGR))
        ellipses[k] = (x + w / 2.0, y + h / 2.0, w / 2.0, h / 2.0, 0.0) if found else ellipses[k - 1]
    seconds = time.perf_counter() - began
    states = np.column_stack([ellipses[:, :2], np.maximum(ellipses[:, 2], ellipses[:, 3]) / max(a, b) - 1.0])
    return TrackResult(states, ellipses, ellipses[:, :2].copy(), np.full(len(frames), np.nan), seconds,
                       states[:, None, :], np.ones((len(frames), 1)))


def track_pfilter(frames: np.ndarray, init: np.ndarray, *, rng: int | np.random.Generator, cues=("color", "edge"),
                  n_particles: int = 300, sigmas="calibrated") -> TrackResult:
    """Our likelihoods and AR(2) dynamics inside the generic ``pfilter.ParticleFilter`` (a peer).

    pfilter works with *linear* weights, which it multiplies into the previous weights, and draws
    from numpy's global generator. So the fused log-likelihood of eq. (6) is scaled before it is
    handed over: ``exp(log L - max log L)`` (the largest weight is 1, none overflows), and the
    global generator is seeded with an integer drawn from ``rng`` (``numpy.random.seed``). A particle is the 6-vector
    ``(X_k, X_{k-1})`` so that the second-order dynamics fit pfilter's first-order interface.

    Parameters
    ----------
    frames : numpy.ndarray
        (T, H, W, 3) uint8 RGB.
    init : numpy.ndarray
        Initial ellipse or control points, as for :func:`track`.
    rng : int or numpy.random.Generator
        Seeds numpy's global generator, which pfilter draws from.
    cues : sequence of str
        Cues fused, as for :func:`track`.
    n_particles : int
        N_w. At most :data:`amdo_lab.common.MAX_SAMPLES` (1,000,000).
    sigmas : str or dict
        As for :func:`track`.

    Returns
    -------
    TrackResult
        Weighted-mean states and their ellipses (no particle history).

    Notes
    -----
    Needs the ``pfilter`` package (pip install pfilter).

    References
    ----------
    Li & Chaumette, AMDO 2004, Fig. 1 and eq. (6).
    """
    from pfilter import ParticleFilter, systematic_resample as pfilter_systematic

    frames, cues, n_particles, sigma_table = _check_run(frames, cues, n_particles, sigmas)
    global_seed = int(make_rng(rng, "rng").integers(2**32 - 1))
    space, start = shape_space_of(init, frames.shape[1:3])
    cue_objects = build_cues(cues, space, frames[0], start, sigma_table, TRACK_DEFAULTS)
    dynamics = default_dynamics(start)
    spread = np.asarray(TRACK_DEFAULTS["init_spread"])
    np.random.seed(global_seed)

    def prior(n):
        first = start + spread * np.random.standard_normal((n, 3))
        return np.hstack([first, first])  # at rest: X_{k-1} = X_k

    def move(particles, **_):  # eq. (5) without its noise; the old X_k becomes X_{k-1}
        new = dynamics.propagate(particles[:, :3], particles[:, 3:], np.zeros((len(particles), 3)))
        return np.hstack([new, particles[:, :3]])

    def add_noise(particles, **_):
        particles = particles.copy()
        particles[:, :3] += dynamics.step_std * np.random.standard_normal((len(particles), 3))
        return particles

    def observe(particles, frame=None, **_):  # the fused log-likelihood, eq. (6)
        return sum(cue.log_likelihood(frame, particles[:, :3]) for cue in cue_objects.values())[:, None]

    def weigh(log_likelihoods, _observed, **_):
        return np.exp(log_likelihoods[:, 0] - log_likelihoods[:, 0].max())

    pf = ParticleFilter(prior_fn=prior, observe_fn=observe, n_particles=n_particles, dynamics_fn=move,
                        noise_fn=add_noise, weight_fn=weigh, resample_fn=pfilter_systematic)
    began = time.perf_counter()
    states, ess = np.empty((len(frames), 3)), np.empty(len(frames))
    for k, frame in enumerate(frames):
        pf.update(np.zeros(1), frame=frame)
        states[k], ess[k] = pf.mean_state[:3], pf.n_eff * n_particles
    seconds = time.perf_counter() - began
    ellipses = space.ellipses(states)
    return TrackResult(states, ellipses, ellipses[:, :2].copy(), ess, seconds, states[:, None, :], np.ones((len(frames), 1)))
