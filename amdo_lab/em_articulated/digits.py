"""Re-seeding one digit at a time from the pose the EM converged to (ours, beyond the paper)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common import MAX_ITERATIONS
from amdo_lab.common import check_positive, check_positive_int
from amdo_lab.common.threads import one_blas_thread

from amdo_lab.em_articulated.em import OUR_SETTINGS, EMSettings, check_em_settings, check_registration_input, run_em
from amdo_lab.em_articulated.estep import CHUNK, PAPER_C, dense_e_step
from amdo_lab.em_articulated.hand import DIGIT_DOFS, FINGERS, SIDEWAYS_DOFS, HandModel

__all__ = ["DigitSearchResult", "refine_digits", "digit_starts"]

#: Sideways swing of a digit's restarts, degrees.
ABDUCTION_STEP_DEG = 20.0
#: Knuckle and whole-curl flexion of a digit's restarts, degrees.
FLEXION_STEP_DEG = 25.0

#: Per digit (thumb, index, middle, ring, little): its DOFs, the one that swings it sideways at the
#: knuckle, and the ones that curl it.
_DIGIT_DOFS = tuple(np.array(dofs) for dofs in DIGIT_DOFS)
_DIGIT_ABDUCTION = tuple(dofs[0] for dofs in DIGIT_DOFS)
_DIGIT_FLEXION = tuple(np.setdiff1d(dofs, SIDEWAYS_DOFS) for dofs in DIGIT_DOFS)


@dataclass(frozen=True)
class DigitSearchResult:
    """Result of :func:`refine_digits`.

    Parameters
    ----------
    theta : numpy.ndarray, shape (27,)
        The refined pose.
    inlier_prob : numpy.ndarray, shape (M,)
        Σ_i α_ij per data point at that pose and σ_min.
    log_likelihood : float
        The criterion at ``theta``, nats.
    start_log_likelihood : float
        The criterion at the pose the search started from, nats.
    accepted : tuple of (str, float)
        (digit name, gain of the criterion in nats) per accepted move, in order.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; eq. (17) (the criterion); the search itself is ours.
    """

    theta: np.ndarray
    inlier_prob: np.ndarray
    log_likelihood: float
    start_log_likelihood: float
    accepted: tuple[tuple[str, float], ...]


def _criterion(model_points: np.ndarray, data_points: np.ndarray, sigma: float) -> tuple[float, np.ndarray]:
    """Σ_j log(c + Σ_i exp(-||Y_j - X_i||²/2σ²)) and the inlier probabilities Σ_i α_ij of eq. (17).

    The log-likelihood of the data under eq. (17)'s mixture (equal weights, a uniform outlier class)
    up to a constant, so values at the same σ and c can be compared between poses. It is a by-product
    of the dense E-step's pass (double precision: the search compares values that differ by ~1).
    """
    log_c = float(np.log(PAPER_C))
    _, _, inlier_prob, _, log_likelihood = dense_e_step(model_points, data_points, sigma, log_c, CHUNK, "double")
    return log_likelihood, inlier_prob


def digit_starts(hand: HandModel, theta: np.ndarray, digit: int, abduction_step: float,
                  flexion_step: float) -> np.ndarray:
    """Alternative starts (K, 27) that differ from ``theta`` in one digit's joint angles only.

    The digit at its rest pose; swung sideways by ± ``abduction_step`` (towards either neighbour);
    its knuckle flexed by ± ``flexion_step``; all its flexion joints by ± ``flexion_step``. Clipped to
    the joint limits; a start the clip brings back onto ``theta`` is dropped. The restarts of
    :func:`refine_digits`, on its checked input (not exported).

    Parameters
    ----------
    hand : HandModel
        The articulated model.
    theta : numpy.ndarray, shape (27,)
        The pose to start from, inside the joint limits.
    digit : int
        0 (thumb) to 4 (little finger).
    abduction_step : float
        Sideways swing, radians.
    flexion_step : float
        Flexion step, radians.

    Returns
    -------
    numpy.ndarray, shape (K, 27)
        The starts, 1 ≤ K ≤ 7.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, ECCV 2006, eq. (17) (the criterion the restarts climb); the
    search is ours, not in the paper.
    """
    dofs, abduction, flexion = _DIGIT_DOFS[digit], _DIGIT_ABDUCTION[digit], _DIGIT_FLEXION[digit]
    shifts = np.zeros((7, hand.n_dof))
    shifts[0, dofs] = hand.rest_pose()[dofs] - theta[dofs]
    shifts[1:3, abduction] = [-abduction_step, abduction_step]
    shifts[3:5, flexion[0]] = [-flexion_step, flexion_step]
    shifts[5, flexion], shifts[6, flexion] = -flexion_step, flexion_step
    limits = hand.joint_limits()
    starts = np.clip(theta + shifts, limits[:, 0], limits[:, 1])
    return starts[np.max(np.abs(starts - theta), axis=1) > 1e-3]


def refine_digits(model_points: object, data_points: object, hand: HandModel, theta_init: object, theta: object,
                  *, settings: EMSettings = OUR_SETTINGS, search_levels: int = 2, max_passes: int = 2,
                  min_gain: float = 1.0) -> DigitSearchResult:
    """Re-seed one digit at a time from the pose ``theta`` :func:`register_em` converged to (beyond the paper).

    The annealed EM can end with a finger on its neighbour's points, a local optimum it does not
    leave at small σ. This search first re-runs the last ``search_levels`` σ levels of the EM from
    ``theta``; then, for each digit (thumb, index, middle, ring, little) in turn, it restarts those
    levels from a few poses that differ from the current one in that digit's joint angles only
    (the digit's rest pose, its abduction ± 20°, its knuckle flexion and its whole curl ± 25°), the
    rest of the hand where it is. The best of
    a digit's restarts replaces the current pose when it raises the criterion by more than
    ``min_gain``; passes over the five digits repeat, up to ``max_passes``, while some restart is
    accepted.

    The criterion uses the data only (no ground truth): the log-likelihood of the data under the
    mixture of eq. (17) at σ_min, Σ_j log(c + Σ_i exp(-||Y_j - T(X_i, Θ)||²/2σ_min²)). The pose
    returned never has a lower criterion than ``theta``. Not part of Dewaele et al. (2006).

    Parameters
    ----------
    model_points : array_like, shape (N, 3)
        Texture points X_i at pose ``theta_init``, mm, within ±1e6 (as for :func:`register_em`).
    data_points : array_like, shape (M, 3)
        Observed points Y_j, mm, within ±1e6.
    hand : HandModel
        The articulated model.
    theta_init : array_like, shape (27,)
        Pose where the texture was observed, inside the joint limits.
    theta : array_like, shape (27,)
        Pose to refine, inside the joint limits (e.g. ``register_em(...).theta``).
    settings : EMSettings, default OUR_SETTINGS
        The settings of the EM that produced ``theta``, so the restarts are that EM's last levels.
    search_levels : int, default 2
        How many of the EM's last σ levels each restart runs (1 to ``settings.n_levels``).
    max_passes : int, default 2
        Most passes over the five digits (≥ 0; 0: only the re-run from ``theta``).
        At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).
    min_gain : float, default 1.0
        Smallest rise of the criterion that accepts a restart, nats (≥ 0): a margin against
        moves that only fit the noise.

    Returns
    -------
    DigitSearchResult
        The refined pose, its inlier probabilities and criterion, and the accepted moves.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; eq. (17) (the criterion); the search is
    ours, not in the paper.
    """
    model, data, theta_init = check_registration_input(model_points, data_points, hand, theta_init)
    theta = hand.check_theta(theta, "theta", within_limits=True)
    settings = check_em_settings(settings)
    search_levels = check_positive_int(search_levels, "search_levels", maximum=settings.n_levels)
    max_passes = check_positive_int(max_passes, "max_passes", minimum=0, maximum=MAX_ITERATIONS)
    min_gain = check_positive(min_gain, "min_gain", allow_zero=True)
    abduction_step, flexion_step = np.radians(ABDUCTION_STEP_DEG), np.radians(FLEXION_STEP_DEG)
    binding = hand.texture_binding(model, theta_init)
    sigmas = settings.sigmas[-search_levels:]

    def criterion(pose: np.ndarray) -> tuple[float, np.ndarray]:
        with one_blas_thread():
            return _criterion(hand._transform_texture(binding, pose), data, settings.sigma_min)

    def restart(start: np.ndarray) -> tuple[np.ndarray, float, np.ndarray]:
        pose = run_em(hand, binding, data, start, settings, sigmas)[0]
        return (pose, *criterion(pose))

    best, inlier_prob = criterion(theta)
    start_log_likelihood = best
    polished, polished_value, polished_prob = restart(theta)
    if polished_value >= best:  # the re-run only finishes the EM's convergence: no margin needed
        theta, best, inlier_prob = polished, polished_value, polished_prob
    accepted = []
    for _ in range(max_passes):
        changed = False
        for digit, name in enumerate(FINGERS):
            restarts = [restart(start) for start in digit_starts(hand, theta, digit, abduction_step, flexion_step)]
            if not restarts:
                continue
            pose, value, prob = max(restarts, key=lambda result: result[1])
            if value > best + min_gain:
                accepted.append((name, value - best))
                theta, best, inlier_prob, changed = pose, value, prob, True
        if not changed:
            break
    return DigitSearchResult(theta, inlier_prob, best, start_log_likelihood, tuple(accepted))
