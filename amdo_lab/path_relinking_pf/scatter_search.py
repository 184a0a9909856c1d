"""Scatter search in every frame, no filter: pyPESTO's enhanced scatter search (ESS) as PRPF's peer.

Path relinking comes from scatter search (Sec. 3). This peer drops the particle filter: in each frame
ESS minimises the same cost (eqs. 5-6, :meth:`ObservationModel.cost`) over a box around the last
estimate, with a cap on its evaluations, and its best point is the estimate.
"""

from __future__ import annotations

import logging
import time
import warnings
from math import ceil, sqrt

import numpy as np

from amdo_lab.common import MAX_SAMPLES, check_positive_int, make_rng
from amdo_lab.path_relinking_pf.filters import TrackResult, _global_numpy_seeded, check_sequence
from amdo_lab.path_relinking_pf.observation import ObservationModel, measure
from amdo_lab.path_relinking_pf.sequences import BodySequence

__all__ = ["ESS_BOX_DEG", "ESS_BOX_PX", "track_ess"]

#: Half-width of the search box around the last estimate: x1, y1 (px) and every angle (deg).
ESS_BOX_PX = 8.0
ESS_BOX_DEG = 25.0


def _refset_size(n_pose: int) -> int:
    """The smallest b with b (b - 1) >= 10 n_pose: one ESS iteration (b (b - 1) ordered pairs combined)
    costs about as many evaluations as the 10 n_pose random points that seed the RefSet (11 for 10)."""
    return ceil((1 + sqrt(1 + 40 * n_pose)) / 2)


def track_ess(sequence: BodySequence, *, rng: int | np.random.Generator,
              evaluations_per_frame: int) -> TrackResult:
    """Track by pyPESTO's enhanced scatter search in each frame: no filter, the same cost as PRPF.

    In frame t, ESS minimises :meth:`ObservationModel.cost` over the box of +-``ESS_BOX_PX`` px and
    +-``ESS_BOX_DEG`` degrees around the estimate of frame t - 1 (the first true pose in frame 1), with
    ``max_eval`` set to ``evaluations_per_frame``, a RefSet of the smallest b with b (b - 1) >= 10 P
    (11 for the upper body's P = 10 numbers), 10 P random points to start it, and no local optimiser
    (the cost has no gradient). Every cost call counts as an evaluation; ESS checks its cap
    once per combination batch, so a frame may exceed it by a few evaluations (``.evaluations`` holds
    the true count). pyPESTO draws from NumPy's global generator: it is seeded from ``rng`` for the run
    and restored afterwards, so a seed gives the same result.

    Parameters
    ----------
    sequence : BodySequence
        Frames, background, body model, first true pose.
    rng : int or numpy.random.Generator
        Seed of every draw (through NumPy's global generator).
    evaluations_per_frame : int
        ESS's ``max_eval`` in each frame, from 10 P (the random points that start the RefSet; P the
        pose length) to 1,000,000.

    Returns
    -------
    TrackResult
        Poses (ESS's best point), evaluations and ESS iterations a frame (in ``rounds``), seconds.

    References
    ----------
    Egea, Martí & Banga, Computers & Operations Research 37, 2010 (ESS); pyPESTO,
    https://github.com/ICB-DCM/pyPESTO; Pantrigo et al., AMDO 2004, Sec. 3.

    Examples
    --------
    >>> from amdo_lab.path_relinking_pf import make_upper_body_sequence
    >>> result = track_ess(make_upper_body_sequence(rng=0, n_frames=2), rng=0, evaluations_per_frame=150)
    >>> bool(result.evaluations.min() >= 150)
    True
    """
    import pypesto
    from pypesto.optimize.ess import ESSOptimizer

    sequence = check_sequence(sequence)
    generator = make_rng(rng, "rng")
    n_pose = sequence.model.n_pose
    budget = check_positive_int(evaluations_per_frame, "evaluations_per_frame", minimum=10 * n_pose,
                                maximum=MAX_SAMPLES)
    began = time.perf_counter()
    half_width = np.r_[ESS_BOX_PX, ESS_BOX_PX, np.full(n_pose - 2, np.radians(ESS_BOX_DEG))]
    with warnings.catch_warnings():  # pyPESTO points to pyscat, a package around this same optimiser
        warnings.simplefilter("ignore", DeprecationWarning)
        optimizer = ESSOptimizer(dim_refset=_refset_size(n_pose), n_diverse=10 * n_pose, max_eval=budget)
    optimizer.logger.setLevel(logging.WARNING)  # its progress report is logged at INFO
    estimate, poses, evaluations, iterations = sequence.truth[0], [], [], []
    with _global_numpy_seeded(generator):
        for frame in sequence.frames:
            observation = ObservationModel(measure(frame, sequence.background), sequence.model)
            objective = pypesto.Objective(fun=lambda pose, weigh=observation._cost: float(weigh(pose[None])[0]))
            box = pypesto.Problem(objective, lb=estimate - half_width, ub=estimate + half_width)
            estimate = np.array(optimizer.minimize(box).optimize_result[0].x, dtype=float)
            poses.append(estimate)
            evaluations.append(observation.n_evaluations)
            iterations.append(optimizer.n_iter)
    return TrackResult(np.array(poses), np.array(evaluations), time.perf_counter() - began, np.array(iterations))
