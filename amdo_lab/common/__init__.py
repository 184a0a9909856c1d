"""The shared floor of AMDO Lab: plotting, random generators, geometry, input validation, BLAS threads,
the uncertainty of rates and the check of the exercises.

Every chapter subpackage imports from here; nothing here imports a chapter.
"""

from amdo_lab.common.exercises import check_answer
from amdo_lab.common.geometry import (
    apply_rigid,
    apply_similarity_2d,
    planar_chain,
    procrustes_align,
    rigid_transform,
    rotation_2d,
    rotation_matrix,
    rotation_x,
    rotation_y,
    rotation_z,
)
from amdo_lab.common.particles import effective_sample_size, normalised_weights, systematic_resample
from amdo_lab.common.plotting import PALETTE, savefig, use_style
from amdo_lab.common.rng import make_rng, spawn_rngs
from amdo_lab.common.stats import PairedComparison, RateInterval, paired_comparison, rate_interval
from amdo_lab.common.threads import one_blas_thread
from amdo_lab.common.validation import (
    MAX_ITERATIONS,
    MAX_LEVELS,
    MAX_SAMPLES,
    MAX_SIDE,
    as_bool_mask,
    as_finite_array,
    as_image_pair,
    check_axes,
    check_bool,
    check_choice,
    check_dataframe,
    check_fitted,
    check_image_shape,
    check_in_range,
    check_names,
    check_odd_int,
    check_positive,
    check_positive_int,
)

__all__ = [
    "MAX_ITERATIONS",
    "MAX_LEVELS",
    "MAX_SAMPLES",
    "MAX_SIDE",
    "PALETTE",
    "PairedComparison",
    "RateInterval",
    "apply_rigid",
    "apply_similarity_2d",
    "as_bool_mask",
    "as_finite_array",
    "as_image_pair",
    "check_answer",
    "check_axes",
    "check_bool",
    "check_choice",
    "check_dataframe",
    "check_fitted",
    "check_image_shape",
    "check_in_range",
    "check_names",
    "check_odd_int",
    "check_positive",
    "check_positive_int",
    "effective_sample_size",
    "make_rng",
    "normalised_weights",
    "one_blas_thread",
    "paired_comparison",
    "planar_chain",
    "procrustes_align",
    "rate_interval",
    "rigid_transform",
    "rotation_2d",
    "rotation_matrix",
    "rotation_x",
    "rotation_y",
    "rotation_z",
    "savefig",
    "spawn_rngs",
    "systematic_resample",
    "use_style",
]
