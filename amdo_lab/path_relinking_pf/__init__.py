"""Chapter 10: the path relinking particle filter for 2-D body tracking.

Pantrigo, Sánchez, Gianikellis & Montemayor, AMDO 2004. Seeded synthetic sequences (a frontal upper
body and a side-on jump) stand in for the recorded ones, with the exact truth of every frame.
"""

from amdo_lab.path_relinking_pf.body import ELLIPSE_VERTICES, MAX_POSE, BodyModel, Limb, edge_map, joint_errors_px
from amdo_lab.path_relinking_pf.filters import (
    OUR_SETTINGS,
    RELINKS,
    VELOCITIES,
    FilterSettings,
    TrackResult,
    attribute_path,
    check_sequence,
    line_path,
    local_search,
    track_apf,
    track_pfilter,
    track_prpf,
    track_sir,
)
from amdo_lab.path_relinking_pf.observation import PAPER_ALPHA, Measurement, ObservationModel, measure
from amdo_lab.path_relinking_pf.relinking import relink_pair, relink_stage
from amdo_lab.path_relinking_pf.scatter_search import ESS_BOX_DEG, ESS_BOX_PX, track_ess
from amdo_lab.path_relinking_pf.sequences import (
    MAX_FRAMES,
    MAX_RATE_DEG,
    BodySequence,
    make_jump_sequence,
    make_upper_body_sequence,
)

__all__ = [
    "ELLIPSE_VERTICES",
    "ESS_BOX_DEG",
    "ESS_BOX_PX",
    "MAX_FRAMES",
    "MAX_POSE",
    "MAX_RATE_DEG",
    "OUR_SETTINGS",
    "PAPER_ALPHA",
    "RELINKS",
    "VELOCITIES",
    "BodyModel",
    "BodySequence",
    "FilterSettings",
    "Limb",
    "Measurement",
    "ObservationModel",
    "TrackResult",
    "attribute_path",
    "check_sequence",
    "edge_map",
    "joint_errors_px",
    "line_path",
    "relink_pair",
    "relink_stage",
    "local_search",
    "make_jump_sequence",
    "make_upper_body_sequence",
    "measure",
    "track_apf",
    "track_ess",
    "track_pfilter",
    "track_prpf",
    "track_sir",
]

from amdo_lab.common.equations import with_equation_map as _with_equation_map  # noqa: E402
from amdo_lab.path_relinking_pf.equations import EQUATIONS as _EQUATIONS, TEST_FILE as _TEST_FILE  # noqa: E402

__doc__ = _with_equation_map(__doc__, _EQUATIONS, _TEST_FILE)
