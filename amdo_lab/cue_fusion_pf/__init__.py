"""Chapter 6: a particle filter fusing colour, edge and structure cues (Li & Chaumette, AMDO 2004).

Shape space and B-spline contour (eqs. 1-3), AR(2) dynamics (eqs. 4-5), colour (eqs. 7-11),
structure (eq. 12: a two-level boosted Haar cascade trained here) and edge (eqs. 13-14)
likelihoods fused in the log domain (eq. 6), the filter of Fig. 1, seeded head sequences and a
walker sequence (Fig. 6, similarity shape space) with ground truth, and OpenCV's CamShift and
TrackerMIL as peers.
"""

from amdo_lab.cue_fusion_pf.data import HEAD_AXES, SEQUENCE_KINDS, HeadSequence, ellipse_iou, head_views, make_head_sequence
from amdo_lab.cue_fusion_pf.dynamics import ARDynamics, ar2_coefficients
from amdo_lab.cue_fusion_pf.likelihoods import (
    PAPER_SIGMAS,
    CalibrationResult,
    ColorLikelihood,
    EdgeLikelihood,
    bhattacharyya,
    calibrate_sigma,
    edge_line_likelihood,
    fused_log_likelihood,
    kernel_histogram,
    simulate_measurement_lines,
)
from amdo_lab.cue_fusion_pf.peers import track_camshift, track_mil, track_pfilter
from amdo_lab.cue_fusion_pf.shape import ShapeSpace
from amdo_lab.cue_fusion_pf.structure import (
    CASCADE_SEED,
    BoostedCascade,
    StructureLikelihood,
    load_or_train_cascade,
    make_training_set,
)
from amdo_lab.cue_fusion_pf.tracker import (
    CALIBRATED_SIGMAS,
    CUES,
    STATIONARY_STD,
    WALKER_SIGMAS,
    TrackResult,
    calibration_distances,
    default_dynamics,
    systematic_resample,
    track,
    weigh_and_resample,
    weigh_particles,
)
from amdo_lab.cue_fusion_pf.walker import WALKER_SEGMENTS, WalkerSequence, box_iou, make_walker_sequence

__all__ = [
    "ARDynamics", "BoostedCascade", "CALIBRATED_SIGMAS", "WALKER_SIGMAS", "CASCADE_SEED", "CUES", "CalibrationResult", "ColorLikelihood", "EdgeLikelihood",
    "HEAD_AXES", "HeadSequence", "PAPER_SIGMAS", "SEQUENCE_KINDS", "STATIONARY_STD", "ShapeSpace", "StructureLikelihood",
    "TrackResult", "ar2_coefficients", "bhattacharyya",
    "calibrate_sigma", "calibration_distances", "default_dynamics", "edge_line_likelihood", "ellipse_iou",
    "fused_log_likelihood", "head_views", "kernel_histogram", "load_or_train_cascade",
    "make_head_sequence", "make_training_set", "simulate_measurement_lines", "systematic_resample", "track",
    "track_camshift", "track_mil", "track_pfilter", "weigh_and_resample", "weigh_particles",
    "WALKER_SEGMENTS", "WalkerSequence", "box_iou", "make_walker_sequence",
]

from amdo_lab.common.equations import with_equation_map as _with_equation_map  # noqa: E402
from amdo_lab.cue_fusion_pf.equations import EQUATIONS as _EQUATIONS, TEST_FILE as _TEST_FILE  # noqa: E402

__doc__ = _with_equation_map(__doc__, _EQUATIONS, _TEST_FILE)
