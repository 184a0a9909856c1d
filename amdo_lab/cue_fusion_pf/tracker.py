"""The particle filter of Fig. 1 with the cues fused by eq. (6), and its result object."""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from amdo_lab.common import (MAX_ITERATIONS, MAX_SAMPLES, as_finite_array, check_choice,
                             check_image_shape, check_in_range, check_names, check_positive_int, check_sequence_of,
                             make_rng)
# shared with chapter 10 (systematic_resample is re-exported here); the kernel takes -inf log-weights (particles ruled out)
from amdo_lab.common.particles import MAX_LOG_WEIGHT, _normalised_weights, systematic_resample
from amdo_lab.cue_fusion_pf.dynamics import ARDynamics
from amdo_lab.cue_fusion_pf.likelihoods import (COLOR_SPACES, MAX_PIXELS, PAPER_SIGMAS, SIGMA_RANGE, ColorLikelihood,
                                                EdgeLikelihood, check_cues, check_frames)
from amdo_lab.cue_fusion_pf.data import SequenceWithTruth, as_ellipse
from amdo_lab.cue_fusion_pf.shape import SHAPE_KINDS, ShapeSpace, as_states
from amdo_lab.cue_fusion_pf.structure import CASCADE_SEED, StructureLikelihood, load_or_train_cascade

__all__ = ["CALIBRATED_SIGMAS", "CUES", "FUSIONS", "TRACK_DEFAULTS", "TrackResult", "WALKER_SIGMAS",
           "build_cues", "calibration_distances", "default_dynamics", "resolve_sigmas",
           "shape_space_of", "systematic_resample", "track", "weigh_and_resample", "weigh_particles"]

CUES = ("color", "edge", "structure", "oracle")
#: σ_c and σ_s chosen by :func:`calibrate_sigma` on held-out "fusion" seeds (seeds 100-104, rng=0, every 4th frame; the tests re-run it).
CALIBRATED_SIGMAS = {"color": 0.075, "structure": 0.271}
#: σ_c for the walker (16³ bins, its own colours), chosen the same way on held-out walker seeds
#: (make_walker_sequence seeds 100-104, rng=0, every 4th frame, shape="similarity", bins=16; the tests re-run it).
WALKER_SIGMAS = {"color": 0.125}
FRAME_PERIOD = 1.0 / 25.0
#: Particles smaller or larger than these multiples of the template get weight 0 (not a head on the frame).
MIN_SCALE, MAX_SCALE = 0.1, 10.0
#: Our choices for what the paper does not state: stationary std of (t_x, t_y, s) and of the AR(2).
STATIONARY_STD = (100.0, 100.0, 0.1)
#: The same choices in the similarity space (t_x, t_y, s_c, s_s): s_s is a deformation like s_c.
_SIMILARITY_DEFAULTS = {"beta": (2.0, 2.0, 10.0, 10.0), "stationary_std": (100.0, 100.0, 0.1, 0.1),
                        "init_spread": (2.0, 2.0, 0.02, 0.02)}
#: The defaults of :func:`track`'s keyword parameters (``**params``), which :func:`calibration_distances` and the peers share.
TRACK_DEFAULTS = {"shape": "translation_scale", "bins": 32, "stride": 2.0, "n_lines": 40, "half_length": 12, "p0": 0.2,
                  "sigma_e": float(np.sqrt(2.0)), "threshold": 6.0, "beta": (2.0, 2.0, 10.0),
                  "stationary_std": STATIONARY_STD, "printed_order": False, "oracle": None,
                  "init_spread": (2.0, 2.0, 0.02), "mean": None, "color_space": "rgb", "fusion": "product",
                  "edge_exponent": 1.0}
#: How :func:`track` combines the cues: eq. (6)'s product, or one cue after the other with resampling between them.
FUSIONS = ("product", "layered")


@dataclass
class TrackResult:
    """What :func:`track` returns.

    Parameters
    ----------
    states : numpy.ndarray
        (T, d) weighted-mean states ``(cx, cy, s)`` or ``(cx, cy, s_c, s_s)`` (Fig. 1, step 4).
    ellipses : numpy.ndarray
        (T, 5) their ellipses ``(cx, cy, a, b, angle)``.
    centers : numpy.ndarray
        (T, 2) ellipse centres, pixels.
    ess : numpy.ndarray
        (T,) effective sample size ``1 / Σ w²`` before resampling.
    seconds : float
        Wall-clock time of the whole run.
    particles : numpy.ndarray
        (T, N, d) particles before resampling.
    weights : numpy.ndarray
        (T, N) their normalised weights.

    References
    ----------
    Li & Chaumette, AMDO 2004, Fig. 1 (the outputs of step 4).
    """

    states: np.ndarray
    ellipses: np.ndarray
    centers: np.ndarray
    ess: np.ndarray
    seconds: float
    particles: np.ndarray
    weights: np.ndarray

    @property
    def ms_per_frame(self) -> float:
        """Milliseconds per frame of the run."""
        return 1000.0 * self.seconds / len(self.states)


def default_dynamics(mean: np.ndarray, *, beta=(2.0, 2.0, 10.0), stationary_std=STATIONARY_STD,
                     printed_order: bool = False) -> ARDynamics:
    """The AR(2) of eq. (5): β = 2 (translation), 10 (scale), ω = 0, τ = 1/25 s, about ``mean``.

    Parameters
    ----------
    mean : numpy.ndarray
        (d,) the state the process returns to (the initial state): d = 3 for the head's space,
        4 for the similarity space.
    beta : tuple of float
        (d,) damping of (t_x, t_y, s) or (t_x, t_y, s_c, s_s), 1/s.
    stationary_std : tuple of float
        (d,) stationary standard deviations: pixels, pixels, then relative scale (and s_s).
    printed_order : bool
        Eq. (4) as printed (unstable; allowed here so that it can be shown).

    Returns
    -------
    ARDynamics
        The dynamics.

    References
    ----------
    Li & Chaumette, AMDO 2004, eqs. (4)-(5) and Table 1.
    """
    mean = as_finite_array(mean, "mean", ndim=1)  # (ARDynamics checks the rest, printed_order first)
    return ARDynamics(beta, np.zeros(mean.size), FRAME_PERIOD, stationary_std, mean, printed_order=printed_order,
                      allow_unstable=printed_order)


def shape_space_of(init: object, frame_shape: tuple[int, int], kind: str = "translation_scale") -> tuple[ShapeSpace, np.ndarray]:
    """The shape space and the initial state of a contour given as an ellipse or as control points.

    Parameters
    ----------
    init : array_like
        An ellipse ``(cx, cy, a, b, angle)`` (see :func:`as_ellipse`) or (J, 2) B-spline control
        points in pixels, within ±:data:`MAX_PIXELS`; its centre must lie on the frame.
    frame_shape : tuple of int
        (H, W) of the frames, positive ints.
    kind : str
        ``"translation_scale"`` or ``"similarity"`` (eq. 3, left or right).

    Returns
    -------
    tuple
        The :class:`ShapeSpace` and the initial state ``(cx, cy, 0)`` (``(cx, cy, 0, 0)``).

    References
    ----------
    Li & Chaumette, AMDO 2004, eqs. (1)-(3).
    """
    init = as_finite_array(init, "init", max_abs=MAX_PIXELS)
    height, width = check_image_shape(frame_shape, "frame_shape", axes="H, W")
    if init.shape == (5,):  # (the shape space checks kind)
        init = as_ellipse(init, "init")
        space = ShapeSpace.from_ellipse(init, kind=kind)
        start = np.zeros(space.state_dim)
        start[:2] = init[:2]
    elif init.ndim == 2 and init.shape[1] == 2:
        space = ShapeSpace(init, kind)
        start = np.zeros(space.state_dim)
        start[:2] = space.centre
    else:
        raise ValueError(f"init must be an ellipse (cx, cy, a, b, angle) or (J, 2) control points, got shape {init.shape}")
    if not (0 <= start[0] < width and 0 <= start[1] < height):
        raise ValueError(f"init must lie on the frame ({width}×{height}), centre at ({start[0]:.1f}, {start[1]:.1f})")
    return space, start


def _check_state_spread(spread: object, name: str, *, state_dim: int) -> np.ndarray:
    """Return a spread of the state ``(t_x, t_y, s)`` (or ``(t_x, t_y, s_c, s_s)``) after checking its range.

    A particle whose scale leaves (MIN_SCALE - 1, MAX_SCALE - 1) or whose centre leaves
    ±:data:`MAX_PIXELS` gets no weight, so a larger spread only throws particles away.

    Parameters
    ----------
    spread : array_like
        (state_dim,) standard deviations: of t_x and t_y in pixels, in [0, MAX_PIXELS]; of s (and
        of s_s) in [0, MAX_SCALE].
    name : str
        The argument's name, used in error messages.
    state_dim : int
        3 (translation + scale) or 4 (similarity), as :func:`track` derives it from ``shape``.

    Returns
    -------
    numpy.ndarray
        (state_dim,) the spread.

    References
    ----------
    Li & Chaumette, AMDO 2004, eq. (5) and Fig. 1, step 1.
    """
    spread = as_finite_array(spread, name, shape=(state_dim,))
    if np.any(spread < 0) or np.any(spread > [MAX_PIXELS, MAX_PIXELS] + [MAX_SCALE] * (state_dim - 2)):
        raise ValueError(f"{name} must lie in [0, {MAX_PIXELS:g}] px for the centre and in [0, {MAX_SCALE:g}] for "
                         f"the scale, got {spread}")
    return spread


def resolve_sigmas(sigmas: object) -> dict[str, float]:
    """σ_c and σ_s from ``"calibrated"``, ``"paper"`` or a dict of positive values.

    Parameters
    ----------
    sigmas : str or dict
        ``"calibrated"`` (:data:`CALIBRATED_SIGMAS`), ``"paper"`` (Table 1) or a dict of values in
        :data:`SIGMA_RANGE` overriding the calibrated ones.

    Returns
    -------
    dict
        Cue name -> σ.

    References
    ----------
    Li & Chaumette, AMDO 2004, eqs. (11)-(12) and Table 1.
    """
    if isinstance(sigmas, str):
        return dict({"calibrated": CALIBRATED_SIGMAS, "paper": PAPER_SIGMAS}[check_choice(sigmas, "sigmas", ("calibrated", "paper"))])
    if isinstance(sigmas, dict):
        sigma_table = {**CALIBRATED_SIGMAS, **sigmas}
        for key, value in sigma_table.items():
            check_in_range(value, f"sigmas[{key!r}]", *SIGMA_RANGE, closed="both")
        return sigma_table
    raise TypeError(f"sigmas must be 'calibrated', 'paper' or a dict, got {type(sigmas).__name__}")


def _options(params: dict) -> dict:
    """The parameters of :func:`track`: the defaults, those of the similarity space if chosen, then ``params``."""
    defaults = dict(TRACK_DEFAULTS)
    if check_choice(params.get("shape", defaults["shape"]), "shape", SHAPE_KINDS) == "similarity":
        defaults.update(_SIMILARITY_DEFAULTS)
    return {**defaults, **params}


def build_cues(cues: Sequence[str], space: ShapeSpace, first_frame: np.ndarray, start: np.ndarray,
               sigmas: dict[str, float], params: dict) -> dict:
    """The likelihood objects of the requested cues.

    Parameters
    ----------
    cues : sequence of str
        Names from :data:`CUES` (``"oracle"`` builds nothing: it is a callable of the caller's).
    space : ShapeSpace
        The shape space of the tracked contour.
    first_frame : numpy.ndarray
        (H, W, 3) uint8 frame the colour model is taken from.
    start : numpy.ndarray
        (3,) the initial state.
    sigmas : dict
        σ per cue, as :func:`resolve_sigmas` returns.
    params : dict
        Cue parameters, with the keys of :data:`TRACK_DEFAULTS`.

    Returns
    -------
    dict
        Cue name -> likelihood object.

    References
    ----------
    Li & Chaumette, AMDO 2004, eqs. (7)-(14).
    """
    built = {}
    for name in cues:
        if name == "color":
            built[name] = ColorLikelihood(space, first_frame, start, bins=params["bins"], sigma=sigmas["color"],
                                          stride=params["stride"], color_space=params["color_space"])
        elif name == "structure":
            built[name] = StructureLikelihood(space, load_or_train_cascade(rng=CASCADE_SEED), sigma=sigmas["structure"])
        elif name == "edge":
            built[name] = EdgeLikelihood(space, n_lines=params["n_lines"], half_length=params["half_length"],
                                         p0=params["p0"], sigma_e=params["sigma_e"], threshold=params["threshold"],
                                         exponent=params["edge_exponent"])
    return built


def track(frames: np.ndarray, init: np.ndarray, *, rng: int | np.random.Generator,
          cues: Sequence[str] = ("color", "edge"), n_particles: int = 300,
          sigmas: str | dict[str, float] = "calibrated", **params) -> TrackResult:
    """Track a contour through ``frames`` with the particle filter of Fig. 1 and the fused cues of eq. (6).

    Parameters
    ----------
    frames : numpy.ndarray
        (T, H, W, 3) uint8 RGB (pixels, x right, y down).
    init : numpy.ndarray
        The contour at frame 0: an ellipse ``(cx, cy, a, b, angle)`` (semi-axes, a along x at
        angle 0, radians) or (J, 2) B-spline control points.
    rng : int or numpy.random.Generator
        The only source of randomness.
    cues : sequence of str
        Any of ``"color"``, ``"edge"``, ``"structure"`` and ``"oracle"`` (the latter needs
        ``oracle=``, a callable ``(t, states) -> (N,)`` log-likelihood, e.g.
        ``HeadSequence.oracle_log_likelihood``).
    n_particles : int
        N_w, at least 2. At most :data:`amdo_lab.common.MAX_SAMPLES` (1,000,000).
    sigmas : str or dict
        ``"calibrated"`` (:data:`CALIBRATED_SIGMAS`), ``"paper"`` (Table 1: σ_c = 5, σ_s = √15) or a
        dict of values in :data:`SIGMA_RANGE`.
    **params
        bins, stride (colour); n_lines, half_length, p0, sigma_e, threshold, edge_exponent (edges;
        the last is :class:`EdgeLikelihood`'s ``exponent``, 1 for eq. 14); beta,
        stationary_std, printed_order, mean (dynamics; mean is the state X̄ the AR(2) returns to,
        default the initial state); init_spread (std of the initial particles); color_space
        (``"rgb"``, the paper, or ``"hsv"``); fusion (``"product"``, eq. 6, or ``"layered"``: the
        particles are weighed by one cue at a time, in the order of ``cues``, and resampled between
        cues, as the sequential schemes of the paper's refs. [6]-[7]); shape, the shape
        space of eq. (3): ``"translation_scale"`` (head) or ``"similarity"`` (walker; beta,
        stationary_std and init_spread then default to four entries, the scale's value repeated for
        s_s); defaults in :data:`TRACK_DEFAULTS`, ranges in :class:`ColorLikelihood` and
        :class:`EdgeLikelihood`; stationary_std and init_spread lie in [0, :data:`MAX_PIXELS`] px for
        the centre and in [0, :data:`MAX_SCALE`] for the scale.

    Returns
    -------
    TrackResult

    References
    ----------
    Li & Chaumette, AMDO 2004, Fig. 1 and eq. (6).
    """
    frames, cues, n_particles, sigma_table = _check_run(frames, cues, n_particles, sigmas)
    unknown = set(params) - set(TRACK_DEFAULTS)
    if unknown:
        raise TypeError(f"track() got unknown parameter(s) {sorted(unknown)}; known: {sorted(TRACK_DEFAULTS)}")
    options = _options(params)
    state_dim = 4 if options["shape"] == "similarity" else 3
    init_spread = _check_state_spread(options["init_spread"], "init_spread", state_dim=state_dim)
    stationary_std = _check_state_spread(options["stationary_std"], "stationary_std", state_dim=state_dim)
    layered = check_choice(options["fusion"], "fusion", FUSIONS) == "layered"
    check_choice(options["color_space"], "color_space", COLOR_SPACES)
    if "oracle" in cues and not callable(options["oracle"]):
        raise ValueError("cues include 'oracle' but no oracle=callable(t, states) was given")
    generator = make_rng(rng, "rng")
    space, start = shape_space_of(init, frames.shape[1:3], options["shape"])
    cue_objects = build_cues(cues, space, frames[0], start, sigma_table, options)
    mean = start if options["mean"] is None else as_finite_array(options["mean"], "mean", shape=start.shape,
                                                                   max_abs=MAX_PIXELS)
    dynamics = default_dynamics(mean, beta=options["beta"], stationary_std=stationary_std,
                                printed_order=options["printed_order"])
    oracle: Callable | None = options["oracle"] if "oracle" in cues else None
    return _run_filter(frames, space, start, cues=cue_objects, oracle=oracle, dynamics=dynamics,
                       n_particles=n_particles, init_spread=init_spread, generator=generator, layered=layered)


def _check_run(frames: object, cues: object, n_particles: object, sigmas: object) -> tuple:
    """The arguments :func:`track` and the peers share, checked: frames, cue names, N_w and the σ table."""
    frames = check_frames(frames)
    cues = check_names(cues, "cues", allowed=CUES)
    n_particles = check_positive_int(n_particles, "n_particles", minimum=2, maximum=MAX_SAMPLES)
    return frames, cues, n_particles, resolve_sigmas(sigmas)


def weigh_particles(frame: np.ndarray, particles: np.ndarray, cues: dict) -> np.ndarray:
    """Step 3 of Fig. 1: the normalised weight of each particle, Bayes' rule (eq. 15) with the fused cues.

    The particles are a sample of the prediction ``p(X_k | Y_{1:k-1})`` (eq. 16, drawn by
    :meth:`ARDynamics.step`); weighting each by the likelihood ``p(Y_k | X_k)`` of eq. (6) and
    normalising makes the weighted set a sample of the posterior ``p(X_k | Y_{1:k})``. The
    normaliser of eq. (15) is the sum of the weights. A particle that is no plausible contour
    (scale outside (:data:`MIN_SCALE`, :data:`MAX_SCALE`) of the template, centre beyond
    ±:data:`MAX_PIXELS`) gets weight 0 and is not shown to the cues.

    Parameters
    ----------
    frame : numpy.ndarray
        (H, W, 3) uint8 RGB image Y_k.
    particles : numpy.ndarray
        (N, d) states X_k (d: the cues' shape space), entries within ±1e6 (``shape.MAX_STATE_ENTRY``); at
        least one plausible.
    cues : dict
        Name -> likelihood object with ``.log_likelihood(frame, states)`` (:func:`build_cues`).

    Returns
    -------
    numpy.ndarray
        (N,) weights, non-negative, summing to 1.

    References
    ----------
    Li & Chaumette, AMDO 2004, eqs. (6), (15)-(16) and Fig. 1, step 3.
    """
    cues = check_cues(cues)  # (each cue checks the frame)
    particles = np.atleast_2d(as_states(particles, next(iter(cues.values())).shape_space.state_dim, "particles"))
    valid = _plausible(particles)
    if not valid.any():
        raise ValueError("particles must hold at least one plausible contour (scale and centre in range)")
    # eq. (15): w_i ∝ p(Y_k | X_k^i), normalised by their sum p(Y_k | Y_1:k-1) (the ruled-out particles' -inf give 0)
    return _normalised_weights(_fused_log_weights(frame, particles, valid, cues.values()))


def weigh_and_resample(cue_log_likelihoods: np.ndarray, u: float) -> np.ndarray:
    """Steps 3 and 5 of Fig. 1 for one frame: fuse the cues (eq. 6), normalise the weights, resample.

    The cues' log-likelihoods of each particle add (eq. 6); the weights are their exponentials
    normalised to sum 1 (eq. 15), computed with the largest fused log-likelihood subtracted first,
    so log-likelihoods of any size give weights; :func:`systematic_resample` then draws the
    particles with the one uniform number ``u``. :func:`track` does the same on every frame.

    Parameters
    ----------
    cue_log_likelihoods : numpy.ndarray
        (n_cues, N) log-likelihood of each particle under each cue, finite (within ±1e300); they
        are defined up to an additive constant per cue.
    u : float
        One uniform number in [0, 1).

    Returns
    -------
    numpy.ndarray
        (N,) indices of the particles the resampled set copies, in increasing order.

    References
    ----------
    Li & Chaumette, AMDO 2004, eqs. (6) and (15), Fig. 1, steps 3 and 5.

    Examples
    --------
    >>> weigh_and_resample(np.array([[0.0, np.log(3.0)], [1000.0, 1000.0]]), 0.5)
    array([1, 1])
    """
    logs = as_finite_array(cue_log_likelihoods, "cue_log_likelihoods", ndim=2, max_abs=MAX_LOG_WEIGHT)
    u = check_in_range(u, "u", 0.0, 1.0, closed="left")
    fused = logs.sum(axis=0)                                   # eq. (6): the cues' log-likelihoods add
    return systematic_resample(_normalised_weights(fused), u)  # eq. (15), then Fig. 1, step 5


def _plausible(particles: np.ndarray) -> np.ndarray:
    """(N,) mask of the particles that are a contour at all: finite size, centre near any frame."""
    if particles.shape[1] == 3:
        plausible = (particles[:, 2] > MIN_SCALE - 1.0) & (particles[:, 2] < MAX_SCALE - 1.0)
    else:  # the similarity space: the scale is k = |(1 + s_c, s_s)|
        scale = np.hypot(1.0 + particles[:, 2], particles[:, 3])
        plausible = (scale > MIN_SCALE) & (scale < MAX_SCALE)
    return np.all(np.abs(particles[:, :2]) <= MAX_PIXELS, axis=1) & plausible


def _fused_log_weights(frame: np.ndarray, particles: np.ndarray, valid: np.ndarray, cues) -> np.ndarray:
    """(N,) log p(Y_k | X_k) of eq. (6), the sum of the cues' log-likelihoods; -inf where not ``valid``."""
    log_weights = np.full(len(particles), -np.inf)
    log_weights[valid] = 0.0
    for cue in cues:  # eq. (6): independent cues, so the log-likelihoods add
        log_weights[valid] += cue.log_likelihood(frame, particles[valid])
    return log_weights


def _run_filter(frames: np.ndarray, space: ShapeSpace, start: np.ndarray, *, cues: dict, oracle: Callable | None,
                dynamics: ARDynamics, n_particles: int, init_spread: np.ndarray, generator: np.random.Generator,
                layered: bool) -> TrackResult:
    """The particle filter of Fig. 1 on checked inputs (what :func:`track` runs).

    Parameters
    ----------
    frames : (T, H, W, 3) uint8 frames; space, start : the shape space and the initial state (d,).
    cues : name -> likelihood object, fused by eq. (6) (or one after the other when ``layered``).
    oracle : ``(k, states) -> (N,)`` log-likelihood added to the cues', or None.
    dynamics : the AR(2) of eq. (5) that moves the particles; n_particles : N;
    init_spread : (d,) std of the initial particles around ``start``; generator : the only source of draws.
    layered : weigh by each cue but the last alone and resample after it (a layer), then by the last.

    Returns
    -------
    TrackResult
    """
    n_frames = len(frames)
    began = time.perf_counter()
    # The loop approximates the Bayesian recursion by Monte Carlo: moving the particles through the
    # dynamics samples the prediction integral of eq. (16), and weighting them by the likelihood and
    # normalising is Bayes' rule, eq. (15); the weighted particles are a sample of p(X_k | Y_1:k).
    # 1. initialisation: particles around the initial state, at rest (X_{k-1} = X_{k-2})
    current = start + init_spread * generator.standard_normal((n_particles, start.size))
    previous = current.copy()
    states, ess = np.empty((n_frames, start.size)), np.empty(n_frames)
    all_particles, all_weights = np.empty((n_frames, n_particles, start.size)), np.empty((n_frames, n_particles))
    for k in range(n_frames):
        if k > 0:  # 2. sampling from the transition prior, eq. (5); particles carry X_k and X_{k-1}
            current, previous = dynamics._step(current, previous, generator), current
        # 3. weights: eq. (6) in the log domain, on the particles that are a contour at all, then eq. (15)
        valid = _plausible(current)
        if not valid.any():
            raise RuntimeError(f"the filter diverged at frame {k}: no particle has a finite state of a plausible size "
                               "(unstable dynamics?)")
        layers = list(cues.values())
        if layered:  # all cues but the last: weigh by that cue alone, then resample (a layer)
            for cue in layers[:-1]:
                layer_weights = _normalised_weights(_fused_log_weights(frames[k], current, valid, [cue]))
                chosen = systematic_resample(layer_weights, generator.random())
                current, previous, valid = current[chosen], previous[chosen], valid[chosen]
            layers = layers[-1:]
        log_weights = _fused_log_weights(frames[k], current, valid, layers)
        if oracle is not None:
            log_weights[valid] += oracle(k, current[valid])
        weights = _normalised_weights(log_weights)
        # 4. output: the weighted mean
        states[k] = weights[valid] @ current[valid]
        ess[k] = 1.0 / np.sum(weights**2)
        all_particles[k], all_weights[k] = current, weights
        # 5. selection
        chosen = systematic_resample(weights, generator.random())
        current, previous = current[chosen], previous[chosen]
    seconds = time.perf_counter() - began
    ellipses = space.ellipses(states)
    return TrackResult(states, ellipses, ellipses[:, :2].copy(), ess, seconds, all_particles, all_weights)


def calibration_distances(sequences: Sequence, cue: str, *, rng: int | np.random.Generator, n_samples: int = 200,
                          frame_step: int = 4, **params) -> tuple[np.ndarray, np.ndarray]:
    """A cue's distances at the true states and at prior samples around them, for :func:`calibrate_sigma`.

    For every ``frame_step``-th frame t >= 2 of each sequence (objects with ``.frames`` and
    ``.truth``), ``n_samples`` states are drawn from the dynamics of eq. (5) given the true states
    at t-1 and t-2: the particles a filter that tracked perfectly until t-1 would weigh.

    Parameters
    ----------
    sequences : sequence of HeadSequence or WalkerSequence
        Held-out sequences, at least one (each with ``.frames``, ``.truth`` and ``.true_ellipses``).
    cue : str
        ``"color"`` or ``"structure"``.
    rng : int or numpy.random.Generator
        Source of the prior samples.
    n_samples : int
        Prior samples per frame. At most :data:`amdo_lab.common.MAX_SAMPLES` (1,000,000).
    frame_step : int
        Use every ``frame_step``-th frame. At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).
    **params
        Cue and dynamics parameters, as for :func:`track`; with ``shape="similarity"`` the
        sequences are walker sequences (``.template`` gives the outline on frame 0).

    Returns
    -------
    tuple of numpy.ndarray
        (T,) distances at the truth and (T, n_samples) at the prior samples (for colour 1 - ρ,
        for structure 1 - n_s/N_s).

    References
    ----------
    Li & Chaumette, AMDO 2004, eqs. (11)-(12) (the σ being calibrated) and Table 1.
    """
    sequences = check_sequence_of(sequences, "sequences", SequenceWithTruth, what="a HeadSequence or WalkerSequence")
    check_choice(cue, "cue", ("color", "structure"))
    n_samples = check_positive_int(n_samples, "n_samples", minimum=2, maximum=MAX_SAMPLES)
    frame_step = check_positive_int(frame_step, "frame_step", maximum=MAX_ITERATIONS)
    options = _options(params)
    generator = make_rng(rng, "rng")
    at_truth, at_prior = [], []
    for sequence in sequences:
        # the walker's truth is a similarity state of its outline on frame 0 (WalkerSequence.template)
        init = sequence.template if options["shape"] == "similarity" else sequence.true_ellipses[0]
        space, start = shape_space_of(init, sequence.frames.shape[1:3], options["shape"])
        likelihood = build_cues([cue], space, sequence.frames[0], start, {"color": 1.0, "structure": 1.0}, options)[cue]
        dynamics = default_dynamics(start, beta=options["beta"], stationary_std=options["stationary_std"])
        for t in range(2, len(sequence.frames), frame_step):
            previous = np.repeat(sequence.truth[t - 1][None], n_samples, axis=0)
            before = np.repeat(sequence.truth[t - 2][None], n_samples, axis=0)
            samples = dynamics.step(previous, before, rng=generator)
            at_truth.append(likelihood.distance(sequence.frames[t], sequence.truth[t][None])[0])
            at_prior.append(likelihood.distance(sequence.frames[t], samples))
    return np.array(at_truth), np.array(at_prior)
