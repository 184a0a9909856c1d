"""SIR, the annealed particle filter and the path relinking particle filter (Figs. 1 and 2) on one cost.

Every filter weighs poses with the same :class:`ObservationModel` (eqs. 5-7) and moves them with the
same system model (eq. 8 and a diffusion stage), so their results differ only by how they spend the
evaluations of the weighting function, which each :class:`TrackResult` counts frame by frame.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np

from amdo_lab.common import (MAX_LEVELS, MAX_SAMPLES, as_finite_array, check_bool, check_choice, check_in_range,
                             check_positive_int, make_rng)
from amdo_lab.common.particles import normalised_weights, systematic_resample
from amdo_lab.path_relinking_pf.body import MAX_POSE, BodyModel
from amdo_lab.path_relinking_pf.observation import MAX_ALPHA, ObservationModel, measure
from amdo_lab.path_relinking_pf.sequences import BodySequence

__all__ = ["RELINKS", "VELOCITIES", "FilterSettings", "OUR_SETTINGS", "TrackResult", "attribute_path",
           "check_sequence", "line_path", "local_search", "track_apf", "track_pfilter", "track_prpf", "track_sir"]

#: How PRPF builds new solutions from RefSet pairs: points on the segment, one limb at a time from the
#: guide (Glover's attribute relinking), or none (local search only).
RELINKS = ("line", "attribute", "none")
#: Eq. (8)'s velocity: held at 0 (our default), a random walk with the paper's update (literal eq. 8), or
#: the difference of the last two estimates.
VELOCITIES = ("zero", "random-walk", "estimate")
#: Most local-search sweeps or relinking rounds.
MAX_ROUNDS = 100


@dataclass(frozen=True)
class FilterSettings:
    """The choices the paper leaves open, shared by every filter (pixels and degrees).

    Parameters
    ----------
    alpha : float
        Eq. (7)'s constant per pixel of cost, in (0, 10.24].
    diffusion_px, diffusion_deg : float
        Standard deviations of the diffusion stage for x1, y1 and for every angle, in [0, 100].
    velocity : str
        ``"zero"``, ``"random-walk"`` (eq. 8 as printed, with Delta t one frame) or ``"estimate"`` (every
        particle moves by the difference of the last two estimates, ``chi_t - chi_{t-1}``; 0 in frame 2).
    velocity_px, velocity_deg : float
        Eq. (8)'s sigma_X of the velocity random walk, in [0, 100].
    init_px, init_deg : float
        Spread of the first frame's particles around the given start pose, in [0, 100].
    step_px, step_deg : float
        PRPF's spacing of the points on a path; the local search moves half of it, in (0, 100].

    References
    ----------
    Pantrigo et al., AMDO 2004, eqs. (7)-(8) and Sec. 4.
    """

    alpha: float = 0.01
    diffusion_px: float = 2.0
    diffusion_deg: float = 5.0
    velocity: str = "zero"
    velocity_px: float = 1.0
    velocity_deg: float = 3.0
    init_px: float = 2.0
    init_deg: float = 5.0
    step_px: float = 2.0
    step_deg: float = 4.0

    def __post_init__(self) -> None:
        as_finite_array(self.alpha, "alpha", shape=(), bounds=(0.0, MAX_ALPHA), closed="right")
        check_choice(self.velocity, "velocity", VELOCITIES)
        for name in ("diffusion_px", "diffusion_deg", "velocity_px", "velocity_deg", "init_px", "init_deg"):
            as_finite_array(getattr(self, name), name, shape=(), bounds=(0.0, 100.0))
        for name in ("step_px", "step_deg"):
            as_finite_array(getattr(self, name), name, shape=(), bounds=(0.0, 100.0), closed="right")

    def _scales(self, n_pose: int, px: str, deg: str) -> np.ndarray:
        """Per-coordinate scale ``[px, px, deg, ..., deg]`` of two of the settings (angles in radians).

        Parameters
        ----------
        n_pose : int
            Length of a pose.
        px, deg : str
            Names of the settings for x1, y1 (pixels) and for every angle (degrees).

        Returns
        -------
        numpy.ndarray
            ``(n_pose,)`` the scales.
        """
        return np.r_[np.full(2, getattr(self, px)), np.full(n_pose - 2, np.deg2rad(getattr(self, deg)))]


#: Our settings (velocity held at zero, diffusion 2 px and 5 deg, alpha 0.01 per pixel).
OUR_SETTINGS = FilterSettings()


@dataclass(frozen=True)
class TrackResult:
    """What every ``track_*`` function returns.

    Parameters
    ----------
    poses : numpy.ndarray
        ``(T, n_pose)`` the estimate of each frame (px, rad).
    evaluations : numpy.ndarray
        ``(T,)`` evaluations of the weighting function in each frame.
    seconds : float
        Wall-clock time of the run.
    rounds : numpy.ndarray
        ``(T,)`` relinking rounds run in each frame (PRPF), scatter-search iterations (ESS), 0 for the
        other filters.

    References
    ----------
    Pantrigo et al., AMDO 2004, Table 2 (N_part / frame counted as evaluations).
    """

    poses: np.ndarray
    evaluations: np.ndarray
    seconds: float
    rounds: np.ndarray


def check_sequence(sequence: object) -> BodySequence:
    """Return ``sequence`` after checking its frames, background and truth agree, or raise.

    Parameters
    ----------
    sequence : BodySequence
        Frames ``(T, rows, cols)`` uint8 with T >= 1, a background of one frame's shape, and at least
        the first true pose (the start of the filters).

    Returns
    -------
    BodySequence
        The same object.

    References
    ----------
    Pantrigo et al., AMDO 2004, Sec. 6 (the trackers start from the first frame).
    """
    if not isinstance(sequence, BodySequence):
        raise TypeError(f"sequence must be a BodySequence, got {type(sequence).__name__}")
    frames, background = sequence.frames, sequence.background
    if not isinstance(frames, np.ndarray) or frames.dtype != np.uint8 or frames.ndim != 3 or not len(frames):
        raise ValueError("sequence.frames must be a (T, rows, cols) uint8 array with T >= 1")
    if not isinstance(background, np.ndarray) or background.shape != frames.shape[1:]:
        raise ValueError("sequence.background must have the shape of one frame")
    as_finite_array(background, "sequence.background", bounds=(0.0, 255.0))  # grey levels, as the frames
    if not isinstance(sequence.model, BodyModel):
        raise TypeError(f"sequence.model must be a BodyModel, got {type(sequence.model).__name__}")
    truth = sequence.model.check_poses(sequence.truth, "sequence.truth")
    if truth.ndim != 2:
        raise ValueError(f"sequence.truth must have shape (T, {sequence.model.n_pose}), got {truth.shape}")
    return sequence


class _Run:
    """The parts every filter shares: observations, scales, the seeded generator and the counts."""

    def __init__(self, sequence, rng, n_particles, settings):
        self.sequence = check_sequence(sequence)
        self.generator = make_rng(rng, "rng")
        self.n = check_positive_int(n_particles, "n_particles", minimum=2, maximum=MAX_SAMPLES)
        if not isinstance(settings, FilterSettings):
            raise TypeError(f"settings must be a FilterSettings, got {type(settings).__name__}")
        self.settings, self.model = settings, sequence.model
        self.p = sequence.model.n_pose
        self.diffusion = settings._scales(self.p, "diffusion_px", "diffusion_deg")
        self.velocity_sigma = settings._scales(self.p, "velocity_px", "velocity_deg")
        self.steps = settings._scales(self.p, "step_px", "step_deg")
        self.groups = _limb_coordinates(self.model)
        self.began = time.perf_counter()

    def observations(self):
        """One weighting function per frame, measured as the filter reaches it."""
        for frame in self.sequence.frames:
            yield ObservationModel(measure(frame, self.sequence.background), self.model, alpha=self.settings.alpha)

    def start(self) -> np.ndarray:
        """(N, 2P) particles around the first true pose, at rest (eq. 4: pose, then velocities)."""
        spread = self.settings._scales(self.p, "init_px", "init_deg")
        pose = self.sequence.truth[0] + spread * self.generator.standard_normal((self.n, self.p))
        return np.hstack([pose, np.zeros((self.n, self.p))])

    def predict(self, particles: np.ndarray, estimates: list) -> np.ndarray:
        """Eq. (8) with Delta t one frame, then the diffusion stage; ``estimates``: the poses so far."""
        pose, velocity = particles[:, :self.p], particles[:, self.p:]
        if self.settings.velocity == "estimate":  # xdot_t = chi_t - chi_{t-1}, the same for every particle
            velocity = np.broadcast_to(_estimated_velocity(estimates, self.p), velocity.shape)
        pose = pose + velocity  # eq. (8): x_{t+1} = x_t + xdot_t
        if self.settings.velocity == "random-walk":  # eq. (8): xdot_{t+1} = xdot_t + G_x
            velocity = velocity + self.velocity_sigma * self.generator.standard_normal(velocity.shape)
        return self.diffuse(np.hstack([pose, velocity]), self.diffusion)

    def diffuse(self, particles: np.ndarray, scale: np.ndarray) -> np.ndarray:
        """The diffusion stage (Fig. 1): Gaussian noise of ``scale`` on the pose, velocities kept."""
        moved = particles.copy()
        moved[:, :self.p] += scale * self.generator.standard_normal((len(particles), self.p))
        return moved

    def result(self, poses, evaluations, rounds=None) -> TrackResult:
        rounds = np.zeros(len(poses), int) if rounds is None else np.asarray(rounds)
        return TrackResult(np.asarray(poses), np.asarray(evaluations), time.perf_counter() - self.began, rounds)


@contextmanager
def _global_numpy_seeded(generator: np.random.Generator) -> Iterator[None]:
    """Seed NumPy's global generator by one draw of ``generator`` (for a peer that uses it); restore it after."""
    saved = np.random.get_state()
    np.random.seed(int(generator.integers(2**32 - 1)))
    try:
        yield
    finally:
        np.random.set_state(saved)


def _estimated_velocity(estimates: list, n_pose: int) -> np.ndarray:
    """The difference of the last two estimates (zeros before the second frame)."""
    return estimates[-1] - estimates[-2] if len(estimates) > 1 else np.zeros(n_pose)


def _weighted_mean(weights: np.ndarray, poses: np.ndarray) -> np.ndarray:
    return (weights[:, None] * poses).sum(axis=0)  # the weighted mean: our reading of the lost eq. (3)


def track_sir(sequence: BodySequence, *, rng: int | np.random.Generator, n_particles: int,
              settings: FilterSettings = OUR_SETTINGS) -> TrackResult:
    """Sampling importance resampling (Fig. 1): N evaluations a frame, the weighted mean as estimate.

    Parameters
    ----------
    sequence : BodySequence
        Frames, background, body model, and the first true pose (the start).
    rng : int or numpy.random.Generator
        Seed of every draw.
    n_particles : int
        N, 2 to 1,000,000.
    settings : FilterSettings
        Alpha, diffusion and eq. (8)'s velocity.

    Returns
    -------
    TrackResult
        Poses, evaluations a frame (N), seconds.

    References
    ----------
    Pantrigo et al., AMDO 2004, Sec. 2, Fig. 1 and eqs. (1)-(2), (7)-(8).

    Examples
    --------
    >>> from amdo_lab.path_relinking_pf import make_upper_body_sequence
    >>> result = track_sir(make_upper_body_sequence(rng=0, n_frames=3), rng=0, n_particles=20)
    >>> result.evaluations.tolist()
    [20, 20, 20]
    """
    run = _Run(sequence, rng, n_particles, settings)
    particles, poses, evaluations = run.start(), [], []
    for t, observation in enumerate(run.observations()):
        if t:
            particles = run.predict(particles, poses)  # eqs. (1), (8): the prediction by the system model
        costs = observation._cost(particles[:, :run.p])
        weights = normalised_weights(observation.alpha * -costs)  # eqs. (2), (7)
        poses.append(_weighted_mean(weights, particles[:, :run.p]))
        particles = particles[systematic_resample(weights, run.generator.random())]
        evaluations.append(observation.n_evaluations)
    return run.result(poses, evaluations)


def _annealing_exponent(scaled_costs: np.ndarray, survival: float) -> float:
    """The beta whose weights exp(-beta alpha C) keep an effective sample size of ``survival`` N."""
    spread = scaled_costs - scaled_costs.min()
    low, high = -14.0, 10.0  # log(beta)
    for _ in range(40):
        middle = (low + high) / 2
        weights = np.exp(-np.exp(middle) * spread)
        weights /= weights.sum()
        if 1.0 / np.sum(weights**2) > survival * len(spread):
            low = middle
        else:
            high = middle
    return float(np.exp(low))


def track_apf(sequence: BodySequence, *, rng: int | np.random.Generator, n_particles: int, layers: int = 8,
              survival: float = 0.5, settings: FilterSettings = OUR_SETTINGS) -> TrackResult:
    """The annealed particle filter (Deutscher et al. 2000): ``layers`` weighings a frame, sharper each time.

    In layer m the weights are ``exp(-beta_m alpha C)`` with beta_m set so that the effective sample size
    is ``survival`` N; the particles are resampled and diffused by a noise that shrinks by 0.7 a layer.

    Parameters
    ----------
    sequence : BodySequence
        Frames, background, body model, first true pose.
    rng : int or numpy.random.Generator
        Seed of every draw.
    n_particles : int
        N, 2 to 1,000,000.
    layers : int
        Annealing layers, 1 to 64 (N x layers evaluations a frame).
    survival : float
        The effective sample size kept in each layer, as a fraction of N, in (0, 1).
    settings : FilterSettings
        Alpha, diffusion and eq. (8)'s velocity.

    Returns
    -------
    TrackResult
        Poses (weighted mean of the last layer), evaluations a frame, seconds.

    References
    ----------
    Deutscher, Blake & Reid, CVPR 2000 (ref. [11] of Pantrigo et al., AMDO 2004).

    Examples
    --------
    >>> from amdo_lab.path_relinking_pf import make_upper_body_sequence
    >>> track_apf(make_upper_body_sequence(rng=0, n_frames=2), rng=0, n_particles=10, layers=3).evaluations.tolist()
    [30, 30]
    """
    run = _Run(sequence, rng, n_particles, settings)
    layers = check_positive_int(layers, "layers", maximum=MAX_LEVELS)
    survival = check_in_range(survival, "survival", 0.0, 1.0)
    particles, poses, evaluations = run.start(), [], []
    for t, observation in enumerate(run.observations()):
        if t:
            particles = run.predict(particles, poses)
        for m in range(layers):
            costs = observation._cost(particles[:, :run.p])
            beta = _annealing_exponent(observation.alpha * costs, survival)
            weights = normalised_weights(beta * observation.alpha * -costs)
            if m == layers - 1:
                poses.append(_weighted_mean(weights, particles[:, :run.p]))
            particles = particles[systematic_resample(weights, run.generator.random())]
            if m < layers - 1:
                particles = run.diffuse(particles, run.diffusion * 0.7 ** (m + 1))
        evaluations.append(observation.n_evaluations)
    return run.result(poses, evaluations)


def line_path(start: np.ndarray, end: np.ndarray, steps: np.ndarray) -> np.ndarray:
    """The points strictly between two solutions on the segment that joins them, ``steps`` apart.

    The segment is cut into ``ceil(max_k |end_k - start_k| / steps_k)`` equal parts, so no coordinate
    moves more than its step between neighbours: far RefSet members give long paths (Sec. 4).

    Parameters
    ----------
    start, end : numpy.ndarray
        ``(P,)`` the two solutions x' and x'' (|values| at most 1e5).
    steps : numpy.ndarray
        ``(P,)`` the largest move of each coordinate between neighbouring points, each in (0, 1e5].

    Returns
    -------
    numpy.ndarray
        ``(r - 1, P)`` the interior points x(2), ..., x(r - 1) (none when the two are one step apart).

    References
    ----------
    Pantrigo et al., AMDO 2004, Sec. 3 (the path x' = x(1), ..., x(r) = x''); Glover, LNCS 1363, 1997.

    Examples
    --------
    >>> line_path(np.zeros(2), np.array([4.0, 1.0]), np.ones(2))
    array([[1.  , 0.25],
           [2.  , 0.5 ],
           [3.  , 0.75]])
    """
    start = as_finite_array(start, "start", ndim=1, max_abs=1e5)
    end = as_finite_array(end, "end", ndim=1, max_abs=1e5)
    steps = as_finite_array(steps, "steps", ndim=1, bounds=(0.0, 1e5), closed="right")
    if not start.shape == end.shape == steps.shape:
        raise ValueError(f"start, end and steps must have one shape, got {start.shape}, {end.shape}, {steps.shape}")
    return _line_path(start, end, steps)


def _line_path(start: np.ndarray, end: np.ndarray, steps: np.ndarray) -> np.ndarray:
    parts = int(np.ceil(np.max(np.abs(end - start) / steps)))
    fractions = np.arange(1, parts)[:, None] / max(parts, 1)
    return start + fractions * (end - start)  # x(l) on the segment from x' to x''


def _best_on_path(path: np.ndarray, costs: np.ndarray, start: np.ndarray, start_cost: float):
    """The path's cheapest point if it costs less than the start x', else x' (Fig. 2's new solution)."""
    best = int(np.argmin(costs)) if len(costs) else -1
    if len(costs) and costs[best] < start_cost:
        return path[best], costs[best]
    return start, start_cost


def attribute_path(observation: ObservationModel, start: np.ndarray, guide: np.ndarray
                   ) -> tuple[np.ndarray, np.ndarray]:
    """Glover's attribute relinking: from ``start``, copy the guide's coordinates one limb at a time, greedily.

    The attributes are the limbs: the trunk's coordinates (x1, y1, theta_1) move together, every other limb
    has its angle. Each step tries every limb not yet copied and keeps the copy of lowest cost, so the
    path's k-th point differs from ``start`` in k limbs and the last point is the guide. A body of L limbs
    costs ``L (L + 1) / 2`` evaluations.

    Parameters
    ----------
    observation : ObservationModel
        The frame's weighting function (its body model gives the limbs).
    start, guide : numpy.ndarray
        ``(P,)`` the initiating and the guiding solution (px, rad).

    Returns
    -------
    points : numpy.ndarray
        ``(L, P)`` the path x(2), ..., x(r), the last one equal to ``guide``.
    costs : numpy.ndarray
        ``(L,)`` their costs.

    References
    ----------
    Glover, LNCS 1363, 1997 (path relinking by attributes, ref. [13] of Pantrigo et al., AMDO 2004).

    Examples
    --------
    >>> from amdo_lab.path_relinking_pf import make_upper_body_sequence, measure
    >>> seq = make_upper_body_sequence(rng=0, n_frames=2)
    >>> obs = ObservationModel(measure(seq.frames[0], seq.background), seq.model)
    >>> points, costs = attribute_path(obs, seq.truth[0], seq.truth[1])
    >>> points.shape, bool(np.array_equal(points[-1], seq.truth[1]))
    ((8, 10), True)
    """
    if not isinstance(observation, ObservationModel):
        raise TypeError(f"observation must be an ObservationModel, got {type(observation).__name__}")
    start = as_finite_array(start, "start", shape=(observation.model.n_pose,), max_abs=MAX_POSE)
    guide = as_finite_array(guide, "guide", shape=(observation.model.n_pose,), max_abs=MAX_POSE)
    points, costs = _attribute_paths(observation, start[None], guide[None], _limb_coordinates(observation.model))
    return points[0], costs[0]


def _limb_coordinates(model) -> list[np.ndarray]:
    """The pose coordinates of each limb: the trunk's x1, y1, theta_1, then one angle per limb."""
    return [np.arange(3)] + [np.array([2 + k]) for k in range(1, len(model.limbs))]


def _attribute_paths(observation, starts, guides, groups):
    """Greedy attribute paths for every (start, guide) pair at once: ``(n, L, P)`` points, ``(n, L)`` costs."""
    n, n_groups = len(starts), len(groups)
    current, remaining = starts.copy(), np.ones((n, n_groups), bool)
    points, costs = np.empty((n, n_groups, starts.shape[1])), np.empty((n, n_groups))
    for step in range(n_groups):
        pair, group = np.nonzero(remaining)  # row-major: n_groups - step entries per pair
        trials = current[pair]
        for g, columns in enumerate(groups):
            rows = np.flatnonzero(group == g)
            trials[np.ix_(rows, columns)] = guides[pair[rows]][:, columns]  # copy limb g from the guide
        trial_costs = observation._cost(trials).reshape(n, n_groups - step)
        best = np.argmin(trial_costs, axis=1)
        chosen = np.arange(n) * (n_groups - step) + best
        current = trials[chosen]
        remaining[np.arange(n), group[chosen]] = False
        points[:, step], costs[:, step] = current, trial_costs[np.arange(n), best]
    return points, costs


def local_search(observation: ObservationModel, starts: np.ndarray, moves: np.ndarray,
                 sweeps: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """Greedy coordinate descent on the cost: try +-move on each coordinate in turn, keep what lowers it.

    All starts move together (one batched cost call per coordinate); a sweep that improves nothing ends
    the search early. Each sweep costs ``2 P`` evaluations per start.

    Parameters
    ----------
    observation : ObservationModel
        The frame's weighting function.
    starts : numpy.ndarray
        ``(n, P)`` poses to improve.
    moves : numpy.ndarray
        ``(P,)`` the trial move of each coordinate (px, rad), each in (0, 1e5].
    sweeps : int
        Sweeps over the coordinates, 1 to 100.

    Returns
    -------
    poses : numpy.ndarray
        ``(n, P)`` the improved poses.
    costs : numpy.ndarray
        ``(n,)`` their costs.

    References
    ----------
    Pantrigo et al., AMDO 2004, Secs. 3-4 (the local search of the IMPROVE stage, Fig. 2).

    Examples
    --------
    >>> from amdo_lab.path_relinking_pf import make_upper_body_sequence, measure
    >>> seq = make_upper_body_sequence(rng=0, n_frames=2)
    >>> obs = ObservationModel(measure(seq.frames[0], seq.background), seq.model)
    >>> start = seq.truth[:1] + 3.0 * np.r_[1.0, 1.0, np.zeros(8)]
    >>> bool(local_search(obs, start, np.r_[1.0, 1.0, np.full(8, 0.03)])[1][0] < obs.cost(start)[0])
    True
    """
    if not isinstance(observation, ObservationModel):
        raise TypeError(f"observation must be an ObservationModel, got {type(observation).__name__}")
    starts = np.atleast_2d(observation.model.check_poses(starts, "starts"))
    moves = as_finite_array(moves, "moves", shape=(observation.model.n_pose,), bounds=(0.0, 1e5), closed="right")
    sweeps = check_positive_int(sweeps, "sweeps", maximum=MAX_ROUNDS)
    return _local_search(observation, starts, observation._cost(starts), moves, sweeps)


def _local_search(observation, poses, costs, moves, sweeps):
    poses, costs = poses.copy(), costs.copy()
    n = len(poses)
    for _ in range(sweeps):
        improved = False
        for k in range(poses.shape[1]):
            trials = np.concatenate([poses, poses])
            trials[:n, k] += moves[k]
            trials[n:, k] -= moves[k]
            trial_costs = observation._cost(trials).reshape(2, n)
            best = np.argmin(trial_costs, axis=0)
            better = trial_costs[best, np.arange(n)] < costs
            if better.any():
                improved = True
                chosen = trials.reshape(2, n, -1)[best, np.arange(n)]
                poses[better], costs[better] = chosen[better], trial_costs[best, np.arange(n)][better]
        if not improved:
            break
    return poses, costs


def _relink(observation, refset, ref_costs, ref_velocity, run, relink, use_local_search, max_rounds):
    """The PR stage of Fig. 2: paths between every RefSet pair, local search, until the RefSet stays."""
    b = len(refset)
    rounds = 0
    for _ in range(max_rounds):
        rounds += 1
        if relink != "none":
            pairs = [(i, j) for i in range(b) for j in range(i + 1, b)]
            if relink == "line":
                paths = [_line_path(refset[i], refset[j], run.steps) for i, j in pairs]
                path_costs = np.split(observation._cost(np.concatenate(paths + [refset[:0]])),
                                      np.cumsum([len(path) for path in paths])[:-1])
            else:  # attribute relinking; the last point of a path is the guide itself
                starts, guides = (refset[[pair[side] for pair in pairs]] for side in (0, 1))
                points, costs = _attribute_paths(observation, starts, guides, run.groups)
                paths, path_costs = list(points[:, :-1]), list(costs[:, :-1])
            candidates, candidate_costs, velocities = [], [], []
            for (i, _j), path, cost in zip(pairs, paths, path_costs):
                point, point_cost = _best_on_path(path, cost, refset[i], ref_costs[i])  # else x' itself
                candidates.append(point), candidate_costs.append(point_cost)
                velocities.append(ref_velocity[i])  # the better parent's velocity
            candidates, candidate_costs = np.array(candidates), np.array(candidate_costs)
            velocities = np.array(velocities)
        else:
            candidates, candidate_costs, velocities = refset.copy(), ref_costs.copy(), ref_velocity.copy()
        _, unique = np.unique(candidates, axis=0, return_index=True)
        unique = np.sort(unique)
        candidates, candidate_costs, velocities = candidates[unique], candidate_costs[unique], velocities[unique]
        if use_local_search:
            candidates, candidate_costs = _local_search(observation, candidates, candidate_costs, run.steps / 2, 2)
        pool = np.concatenate([refset, candidates])
        pool_costs = np.concatenate([ref_costs, candidate_costs])
        pool_velocity = np.concatenate([ref_velocity, velocities])
        _, unique = np.unique(pool, axis=0, return_index=True)
        order = unique[np.argsort(pool_costs[unique], kind="stable")][:b]
        if np.array_equal(np.sort(order), np.arange(len(order))) and len(order) == b:
            break  # the new solutions did not improve the RefSet: the PR stage ends (Sec. 4)
        refset, ref_costs, ref_velocity = pool[order], pool_costs[order], pool_velocity[order]
    return refset, ref_costs, ref_velocity, rounds


def track_prpf(sequence: BodySequence, *, rng: int | np.random.Generator, n_particles: int,
               refset_size: int = 5, relink: str = "line", local_search: bool = True, max_rounds: int = 3,
               settings: FilterSettings = OUR_SETTINGS) -> TrackResult:
    """The path relinking particle filter (Fig. 2): a PF stage, then path relinking among the b best.

    Each frame: predict and weigh N particles; the RefSet is the b best; new solutions are built on the
    paths between every RefSet pair (:func:`line_path` or :func:`attribute_path`) and improved by
    :func:`local_search`; the RefSet keeps the b best until a round changes nothing (at most
    ``max_rounds``). The RefSet replaces the worst particles, the best member is the estimate, and the set is resampled.

    Parameters
    ----------
    sequence : BodySequence
        Frames, background, body model, first true pose.
    rng : int or numpy.random.Generator
        Seed of every draw.
    n_particles : int
        N, 2 to 1,000,000.
    refset_size : int
        b, from 2 to N.
    relink : str
        ``"line"`` (paths on the segments), ``"attribute"`` (one limb at a time from the guide, greedy:
        :func:`attribute_path`) or ``"none"`` (local search from the RefSet only: an ablation).
    local_search : bool
        Whether new solutions are improved by the local search (False: paths only, an ablation).
    max_rounds : int
        Most relinking rounds a frame, 1 to 100.
    settings : FilterSettings
        Alpha, diffusion, eq. (8)'s velocity, path step.

    Returns
    -------
    TrackResult
        Poses (the best RefSet member), evaluations and relinking rounds a frame, seconds.

    References
    ----------
    Pantrigo, Sánchez, Gianikellis & Montemayor, AMDO 2004, Sec. 4 and Fig. 2.

    Examples
    --------
    >>> from amdo_lab.path_relinking_pf import make_upper_body_sequence
    >>> result = track_prpf(make_upper_body_sequence(rng=0, n_frames=2), rng=0, n_particles=20, refset_size=3)
    >>> bool(result.evaluations.min() > 20)
    True
    """
    run = _Run(sequence, rng, n_particles, settings)
    b = check_positive_int(refset_size, "refset_size", minimum=2, maximum=run.n)
    relink = check_choice(relink, "relink", RELINKS)
    use_local_search = check_bool(local_search, "local_search")
    max_rounds = check_positive_int(max_rounds, "max_rounds", maximum=MAX_ROUNDS)
    particles, poses, evaluations, rounds = run.start(), [], [], []
    for t, observation in enumerate(run.observations()):
        if t:
            particles = run.predict(particles, poses)
        costs = observation._cost(particles[:, :run.p])  # EVALUATE (Fig. 2)
        best = np.argsort(costs, kind="stable")[:b]  # the RefSet: the b best particles
        refset, ref_costs, ref_velocity, used = _relink(
            observation, particles[best, :run.p], costs[best], particles[best, run.p:], run, relink,
            use_local_search, max_rounds)
        worst = np.argsort(costs, kind="stable")[::-1][:b]  # the RefSet replaces the worst particles
        particles[worst] = np.hstack([refset, ref_velocity])
        costs[worst] = ref_costs
        poses.append(refset[0])  # the estimate: the best RefSet member (our reading of the lost eq. 3)
        weights = normalised_weights(observation.alpha * -costs)
        particles = particles[systematic_resample(weights, run.generator.random())]
        evaluations.append(observation.n_evaluations)
        rounds.append(used)
    return run.result(poses, evaluations, rounds)


def track_pfilter(sequence: BodySequence, *, rng: int | np.random.Generator, n_particles: int,
                  settings: FilterSettings = OUR_SETTINGS) -> TrackResult:
    """SIR run by the ``pfilter`` package with our weighting function, system model and diffusion.

    pfilter draws from NumPy's global generator, which is seeded from ``rng`` for the run and restored
    after it; pfilter applies the dynamics and diffusion before it weighs, also in the first frame.

    Parameters
    ----------
    sequence : BodySequence
        Frames, background, body model, first true pose.
    rng : int or numpy.random.Generator
        Seed of the global generator pfilter uses.
    n_particles : int
        N, 2 to 1,000,000.
    settings : FilterSettings
        Alpha, diffusion and eq. (8)'s velocity.

    Returns
    -------
    TrackResult
        Poses (pfilter's weighted mean), evaluations a frame (N), seconds.

    References
    ----------
    Pantrigo et al., AMDO 2004, Fig. 1; pfilter (J. Williamson), https://github.com/johnhw/pfilter.

    Examples
    --------
    >>> from amdo_lab.path_relinking_pf import make_upper_body_sequence
    >>> track_pfilter(make_upper_body_sequence(rng=0, n_frames=2), rng=0, n_particles=10).evaluations.tolist()
    [10, 10]
    """
    from pfilter import ParticleFilter
    from pfilter import systematic_resample as pfilter_systematic

    run = _Run(sequence, rng, n_particles, settings)
    state = {"observation": None}

    def prior(n):
        return start[:n]

    def dynamics(particles, **_):  # eq. (8) and, with the velocity random walk, its noise
        velocity = particles[:, run.p:]
        if settings.velocity == "estimate":
            velocity = np.broadcast_to(_estimated_velocity(poses, run.p), velocity.shape)
        pose = particles[:, :run.p] + velocity
        if settings.velocity == "random-walk":
            velocity = velocity + run.velocity_sigma * np.random.standard_normal(velocity.shape)
        return np.hstack([pose, velocity])

    def noise(particles, **_):  # the diffusion stage
        moved = particles.copy()
        moved[:, :run.p] += run.diffusion * np.random.standard_normal((len(particles), run.p))
        return moved

    def observe(particles, **_):
        return state["observation"]._cost(particles[:, :run.p])[:, None]

    def weigh(costs, _observed, **_):  # eq. (7), shifted by the best cost so it never underflows to 0
        return np.exp(-settings.alpha * (costs[:, 0] - costs[:, 0].min()))

    poses, evaluations = [], []
    with _global_numpy_seeded(run.generator):
        start = run.start()
        pf = ParticleFilter(prior_fn=prior, observe_fn=observe, n_particles=run.n, dynamics_fn=dynamics,
                            noise_fn=noise, weight_fn=weigh, resample_fn=pfilter_systematic)
        for observation in run.observations():
            state["observation"] = observation
            pf.update(np.zeros(1))
            poses.append(pf.mean_state[:run.p].copy())
            evaluations.append(observation.n_evaluations)
    return run.result(poses, evaluations)
