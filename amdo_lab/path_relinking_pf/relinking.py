"""The PR stage of PRPF (Fig. 2) as public steps: one relinking path, and one frame's rounds on a RefSet.

:func:`amdo_lab.path_relinking_pf.track_prpf` runs the same code inside its filter; these entry points let
the chapter check a path and a PR stage written from scratch against it.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from amdo_lab.common import as_finite_array, check_bool, check_choice, check_in_range, check_positive_int
from amdo_lab.path_relinking_pf.body import MAX_POSE
from amdo_lab.path_relinking_pf.filters import (MAX_ROUNDS, OUR_SETTINGS, RELINKS, FilterSettings, _best_on_path,
                                                _limb_coordinates, _line_path, _relink)
from amdo_lab.path_relinking_pf.observation import ObservationModel

__all__ = ["relink_pair", "relink_stage"]


def relink_pair(observation: ObservationModel, start: np.ndarray, end: np.ndarray, steps: np.ndarray, *,
                start_cost: float) -> tuple[np.ndarray, float, int]:
    """One relinking path of PRPF: walk from RefSet member x' to x'', keep the path's best point if it beats x'.

    The interior points of :func:`line_path` are evaluated (the two ends are RefSet members whose costs
    are known); the new solution is the cheapest of them when it costs less than x', else x' itself,
    from which the local search then starts.

    Parameters
    ----------
    observation : ObservationModel
        The frame's weighting function.
    start, end : numpy.ndarray
        ``(P,)`` the RefSet members x' (initiating, the better one) and x'' (guiding), px and rad.
    steps : numpy.ndarray
        ``(P,)`` the largest move of each coordinate between neighbouring path points, each in (0, 1e5].
    start_cost : float
        The cost of x' (eqs. 5-6), known from the filter stage, from 0 to 1e12.

    Returns
    -------
    point : numpy.ndarray
        ``(P,)`` the new solution.
    cost : float
        Its cost.
    evaluations : int
        The path points evaluated (0 when x' and x'' are one step apart).

    References
    ----------
    Pantrigo et al., AMDO 2004, Sec. 3 (the path x' = x(1), ..., x(r) = x'') and Fig. 2 (the PR stage).

    Examples
    --------
    >>> from amdo_lab.path_relinking_pf import make_upper_body_sequence, measure
    >>> seq = make_upper_body_sequence(rng=0, n_frames=2)
    >>> obs = ObservationModel(measure(seq.frames[1], seq.background), seq.model)
    >>> steps = np.r_[2.0, 2.0, np.full(8, np.radians(4.0))]
    >>> point, cost, evaluations = relink_pair(obs, seq.truth[0], seq.truth[1], steps,
    ...                                        start_cost=float(obs.cost(seq.truth[0])[0]))
    >>> bool(evaluations >= 0 and cost <= obs.cost(seq.truth[0])[0])
    True
    """
    if not isinstance(observation, ObservationModel):
        raise TypeError(f"observation must be an ObservationModel, got {type(observation).__name__}")
    shape = (observation.model.n_pose,)
    start = as_finite_array(start, "start", shape=shape, max_abs=MAX_POSE)
    end = as_finite_array(end, "end", shape=shape, max_abs=MAX_POSE)
    steps = as_finite_array(steps, "steps", shape=shape, bounds=(0.0, 1e5), closed="right")
    start_cost = check_in_range(start_cost, "start_cost", 0.0, 1e12, closed="both")
    path = _line_path(start, end, steps)
    point, cost = _best_on_path(path, observation._cost(path), start, start_cost)
    return point, float(cost), len(path)


def relink_stage(observation: ObservationModel, refset: np.ndarray, costs: np.ndarray, *,
                 settings: FilterSettings = OUR_SETTINGS, relink: str = "line", local_search: bool = True,
                 max_rounds: int = 3) -> tuple[np.ndarray, np.ndarray, int]:
    """The PR stage of Fig. 2 in one frame, as :func:`track_prpf` runs it on its RefSet.

    Each round builds one new solution per RefSet pair (i < j): the best point of the path from member i to
    member j (:func:`relink_pair`, or the attribute path), improved by the local search (half a path step,
    two sweeps); the b best of the RefSet and the new solutions form the next RefSet. The stage stops when a
    round leaves the RefSet unchanged, or after ``max_rounds``.

    Parameters
    ----------
    observation : ObservationModel
        The frame's weighting function.
    refset : numpy.ndarray
        ``(b, P)`` the RefSet, best first (b from 2 to 1,000).
    costs : numpy.ndarray
        ``(b,)`` its costs (eqs. 5-6), each from 0 to 1e12.
    settings : FilterSettings
        The path steps (``step_px``, ``step_deg``).
    relink : str
        ``"line"``, ``"attribute"`` or ``"none"`` (see :func:`track_prpf`).
    local_search : bool
        Whether new solutions are improved by the local search.
    max_rounds : int
        Most rounds, 1 to 100.

    Returns
    -------
    refset : numpy.ndarray
        ``(b, P)`` the final RefSet, best first.
    costs : numpy.ndarray
        ``(b,)`` its costs.
    rounds : int
        The rounds run.

    References
    ----------
    Pantrigo et al., AMDO 2004, Sec. 4 and Fig. 2.

    Examples
    --------
    >>> from amdo_lab.path_relinking_pf import make_upper_body_sequence, measure
    >>> seq = make_upper_body_sequence(rng=0, n_frames=2)
    >>> obs = ObservationModel(measure(seq.frames[1], seq.background), seq.model)
    >>> members = seq.truth[1] + np.r_[2.0, 0.0, np.zeros(8)] * np.arange(1, 4)[:, None]
    >>> refset, costs, rounds = relink_stage(obs, members, obs.cost(members))
    >>> refset.shape, bool(costs[0] <= obs.cost(members).min())
    ((3, 10), True)
    """
    if not isinstance(observation, ObservationModel):
        raise TypeError(f"observation must be an ObservationModel, got {type(observation).__name__}")
    if not isinstance(settings, FilterSettings):
        raise TypeError(f"settings must be a FilterSettings, got {type(settings).__name__}")
    n_pose = observation.model.n_pose
    refset = as_finite_array(refset, "refset", ndim=2, max_abs=MAX_POSE)
    if refset.shape[1] != n_pose or not 2 <= len(refset) <= 1000:
        raise ValueError(f"refset must have shape (b, {n_pose}) with b from 2 to 1000, got {refset.shape}")
    costs = as_finite_array(costs, "costs", shape=(len(refset),), bounds=(0.0, 1e12), closed="both")
    relink = check_choice(relink, "relink", RELINKS)
    use_local_search = check_bool(local_search, "local_search")
    max_rounds = check_positive_int(max_rounds, "max_rounds", maximum=MAX_ROUNDS)
    stage = SimpleNamespace(steps=settings._scales(n_pose, "step_px", "step_deg"),
                            groups=_limb_coordinates(observation.model))
    refset, costs, _, rounds = _relink(observation, refset, costs, np.zeros_like(refset), stage, relink,
                                       use_local_search, max_rounds)
    return refset, costs, rounds
