"""Chapter 1: robust EM registration of 3-D points to an articulated hand with bending surfaces.

Dewaele, Devernay, Horaud & Forbes, ECCV 2006.
"""

from amdo_lab.em_articulated.data import (
    DEFAULT_REPEATABILITY,
    RegistrationProblem,
    SkinTexture,
    make_skin_texture,
    TrackingSequence,
    joint_rmse_deg,
    worst_joint_deg,
    make_registration_problem,
    make_tracking_sequence,
    perturb_pose,
    random_pose,
    visible_points,
)
from amdo_lab.em_articulated.experiments import SUCCESS_DEG, ObjectiveCheck, objective_check, TrialSummary, noise_floor_trials, run_registration_trials
from amdo_lab.em_articulated.hand import PART_NAMES, HandModel, TextureBinding
from amdo_lab.em_articulated.registration import (
    OUR_SETTINGS,
    fit_known_correspondences,
    PAPER_C,
    PAPER_SETTINGS,
    EMResult,
    SoftAssignResult,
    SurfaceFitResult,
    dof_lever_arms,
    e_step_statistics,
    e_step_statistics_kdtree,
    e_step_reference,
    m_step_targets,
    robust_log_likelihood,
    register_em_reference,
    climb_objective,
    fit_surface,
    DigitSearchResult,
    refine_digits,
    register_em,
    softassign_register,
)
from amdo_lab.em_articulated.tracking import TRACKING_SETTINGS, TrackingResult, track_sequence

__all__ = [
    "OUR_SETTINGS", "fit_known_correspondences", "SkinTexture", "make_skin_texture", "DEFAULT_REPEATABILITY", "SUCCESS_DEG", "TrialSummary", "noise_floor_trials", "run_registration_trials", "PAPER_C", "PAPER_SETTINGS", "PART_NAMES", "EMResult", "HandModel", "RegistrationProblem", "SoftAssignResult",
    "SurfaceFitResult", "TextureBinding", "TrackingResult", "TrackingSequence", "dof_lever_arms",
    "e_step_statistics", "e_step_statistics_kdtree", "e_step_reference", "m_step_targets",
    "robust_log_likelihood", "register_em_reference", "climb_objective", "ObjectiveCheck", "objective_check",
    "fit_surface", "joint_rmse_deg", "worst_joint_deg", "make_registration_problem", "make_tracking_sequence",
    "DigitSearchResult", "refine_digits",
    "perturb_pose", "random_pose", "register_em", "softassign_register", "track_sequence", "TRACKING_SETTINGS",
    "visible_points",
]

from amdo_lab.common.equations import with_equation_map as _with_equation_map  # noqa: E402
from amdo_lab.em_articulated.equations import EQUATIONS as _EQUATIONS, TEST_FILE as _TEST_FILE  # noqa: E402

__doc__ = _with_equation_map(__doc__, _EQUATIONS, _TEST_FILE)
