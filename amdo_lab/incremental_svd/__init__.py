"""Chapter 7: incremental SVD with mean update for on-the-fly face training.

Melenchón, Meler & Iriondo, AMDO 2004. A seeded synthetic talking face stands in for the recorded one.
"""

from amdo_lab.incremental_svd.face import (
    LATENT_NAMES,
    PAPER_SIZE,
    TalkingFace,
    face_masks,
    make_talking_face,
    psnr_db,
    render_faces,
)
from amdo_lab.incremental_svd.svd_update import (
    MEAN_MODES,
    IncrementalSVD,
    SvdState,
    brand_update,
    extract_mean,
    noise_edge,
    ross_update,
    tau_schedule,
    truncate,
    update_with_mean,
)

__all__ = [
    "LATENT_NAMES",
    "PAPER_SIZE",
    "TalkingFace",
    "face_masks",
    "make_talking_face",
    "psnr_db",
    "render_faces",
    "MEAN_MODES",
    "IncrementalSVD",
    "SvdState",
    "brand_update",
    "extract_mean",
    "noise_edge",
    "ross_update",
    "tau_schedule",
    "truncate",
    "update_with_mean",
]
