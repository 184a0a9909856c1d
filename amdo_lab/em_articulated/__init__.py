"""Chapter 1: robust EM registration of 3-D points to an articulated hand with bending surfaces.

Dewaele, Devernay, Horaud & Forbes, ECCV 2006.

One module per algorithm: ``hand`` (the model, eqs. 1-3), ``estep`` (eqs. 9, 17-18 and the targets
of eq. 20), ``kdtree`` (the truncated E-step), ``em`` (settings, M-step and the annealed EM,
eqs. 19-20), ``digits`` (the per-digit re-seeding, ours), ``surface`` (Sec. 3.4, eqs. 21-22),
``softassign`` (the Sec. 4 baseline), ``diagnostics`` (noise floor and objective climb),
``tracking`` (Sec. 5), ``data`` and ``experiments``.
"""

from amdo_lab.em_articulated.data import (
    DEFAULT_REPEATABILITY,
    RegistrationProblem,
    SkinTexture,
    TrackingSequence,
    joint_rmse_deg,
    make_registration_problem,
    make_skin_texture,
    make_tracking_sequence,
    perturb_pose,
    random_pose,
    worst_joint_deg,
)
from amdo_lab.em_articulated.diagnostics import climb_objective, fit_known_correspondences
from amdo_lab.em_articulated.digits import DigitSearchResult, refine_digits
from amdo_lab.em_articulated.em import (OUR_SETTINGS, PAPER_SETTINGS, EMResult, EMSettings, gauss_newton_step,
                                        register_em, register_em_reference)
from amdo_lab.em_articulated.estep import (PAPER_C, e_step_reference, e_step_statistics, m_step_targets,
                                           robust_log_likelihood, robust_log_likelihood_reference)
from amdo_lab.em_articulated.experiments import (SUCCESS_DEG, ObjectiveCheck, TrialSummary, noise_floor_trials,
                                                 objective_check, run_registration_trials)
from amdo_lab.em_articulated.hand import PART_NAMES, HandModel, TextureBinding
from amdo_lab.em_articulated.kdtree import e_step_statistics_kdtree
from amdo_lab.em_articulated.softassign import SoftAssignResult, register_softassign
from amdo_lab.em_articulated.surface import SurfaceFitResult, fit_surface
from amdo_lab.em_articulated.tracking import TRACKING_SETTINGS, TrackResult, track

__all__ = [
    # the hand (eqs. 1-3)
    "PART_NAMES", "HandModel", "TextureBinding",
    # data
    "DEFAULT_REPEATABILITY", "RegistrationProblem", "SkinTexture", "TrackingSequence", "joint_rmse_deg",
    "worst_joint_deg", "make_registration_problem", "make_skin_texture", "make_tracking_sequence",
    "perturb_pose", "random_pose",
    # E-step (eqs. 9, 17-18) and the targets of eq. (20)
    "PAPER_C", "e_step_reference", "e_step_statistics", "e_step_statistics_kdtree", "m_step_targets",
    "robust_log_likelihood", "robust_log_likelihood_reference",
    # the EM (eqs. 19-20)
    "EMSettings", "PAPER_SETTINGS", "OUR_SETTINGS", "EMResult", "gauss_newton_step", "register_em",
    "register_em_reference",
    # beyond the EM: digit search, surface fit (eqs. 21-22), SoftAssign, diagnostics, tracking
    "DigitSearchResult", "refine_digits", "SurfaceFitResult", "fit_surface", "SoftAssignResult",
    "register_softassign", "climb_objective", "fit_known_correspondences", "TRACKING_SETTINGS", "TrackResult",
    "track",
    # experiments
    "SUCCESS_DEG", "TrialSummary", "ObjectiveCheck", "noise_floor_trials", "objective_check",
    "run_registration_trials",
]

from amdo_lab.common.equations import with_equation_map as _with_equation_map  # noqa: E402
from amdo_lab.em_articulated.equations import EQUATIONS as _EQUATIONS, TEST_FILE as _TEST_FILE  # noqa: E402

__doc__ = _with_equation_map(__doc__, _EQUATIONS, _TEST_FILE)
