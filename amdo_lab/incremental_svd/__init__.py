"""Chapter 7: incremental SVD with mean update for on-the-fly face training.

Melenchón, Meler & Iriondo, AMDO 2004. A seeded synthetic talking face stands in for the recorded one.
"""

from amdo_lab.incremental_svd.face import (
    LATENT_NAMES,
    MOTIONS,
    PAPER_SIZE,
    SIMILARITY_BOUNDS,
    TalkingFace,
    corner_error_less_offset_px,
    corner_error_px,
    make_talking_face,
    psnr_db,
    render_faces,
    similarity_points,
)
from amdo_lab.incremental_svd.svd_update import (
    MEAN_MODES,
    IncrementalSVD,
    SvdState,
    brand_update,
    estimate_noise,
    extract_mean,
    noise_edge,
    ross_update,
    tau_schedule,
    update_with_mean,
)
from amdo_lab.incremental_svd.tracking import (
    TAU_MODES,
    TrainingResult,
    train_non_causal,
    train_on_the_fly,
)

__all__ = [
    "LATENT_NAMES",
    "PAPER_SIZE",
    "TalkingFace",
    "make_talking_face",
    "psnr_db",
    "render_faces",
    "MOTIONS",
    "SIMILARITY_BOUNDS",
    "corner_error_less_offset_px",
    "corner_error_px",
    "similarity_points",
    "TAU_MODES",
    "TrainingResult",
    "train_non_causal",
    "train_on_the_fly",
    "MEAN_MODES",
    "IncrementalSVD",
    "SvdState",
    "brand_update",
    "estimate_noise",
    "extract_mean",
    "noise_edge",
    "ross_update",
    "tau_schedule",
    "update_with_mean",
]

from amdo_lab.common.equations import with_equation_map as _with_equation_map  # noqa: E402
from amdo_lab.incremental_svd.equations import EQUATIONS as _EQUATIONS, TEST_FILE as _TEST_FILE  # noqa: E402

__doc__ = _with_equation_map(__doc__, _EQUATIONS, _TEST_FILE)
