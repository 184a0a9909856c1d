"""Chapter 8: active contours by greedy search, dynamic programming and variational calculus.

Caro, Rodríguez, Durán, Ávila, Antequera & Gallardo, AMDO 2004: muscles of Iberian hams segmented
on MRI slices at four ripening stages, their areas summed into volumes. Seeded synthetic slices
stand in for the scans.
"""

from amdo_lab.active_contours.measure import (
    METHODS,
    polygon_area_mm2,
    segment_contour,
    segment_study,
    volume_mm3,
)
from amdo_lab.active_contours.phantom import (
    IMAGE_SHAPE,
    MUSCLES,
    PIXEL_MM,
    SLICE_MM,
    STAGE_VOLUME_FRACTION,
    STAGE_WEIGHT_LOSS,
    STAGES,
    HamSlice,
    HamStudy,
    MuscleShape,
    initial_contour,
    make_ham_slice,
    make_ham_study,
)
from amdo_lab.active_contours.potential import (
    EDGE_MODES,
    GAUSSIAN_7,
    edge_strength,
    equalise_histogram,
    gradient_vector_flow,
    potential_field,
    smooth_7x7,
)
from amdo_lab.active_contours.snakes import (
    IMAGE_NORMS,
    NORMALISATIONS,
    TABLE_1,
    SnakeResult,
    SnakeWeights,
    candidate_offsets,
    dp_pass,
    dp_snake,
    greedy_energies,
    greedy_snake,
    greedy_snake_loop,
    respace,
    variational_snake,
)

__all__ = [
    "IMAGE_SHAPE", "MUSCLES", "PIXEL_MM", "SLICE_MM", "STAGES", "STAGE_VOLUME_FRACTION", "STAGE_WEIGHT_LOSS",
    "HamSlice", "HamStudy", "MuscleShape", "initial_contour", "make_ham_slice", "make_ham_study",
    "EDGE_MODES", "GAUSSIAN_7", "edge_strength", "equalise_histogram", "gradient_vector_flow", "potential_field",
    "smooth_7x7",
    "IMAGE_NORMS", "NORMALISATIONS", "TABLE_1", "SnakeResult", "SnakeWeights", "candidate_offsets", "dp_pass", "dp_snake", "greedy_energies", "greedy_snake",
    "greedy_snake_loop", "respace", "variational_snake",
    "METHODS", "polygon_area_mm2", "segment_contour", "segment_study", "volume_mm3",
]

from amdo_lab.common.equations import with_equation_map as _with_equation_map  # noqa: E402
from amdo_lab.active_contours.equations import EQUATIONS as _EQUATIONS, TEST_FILE as _TEST_FILE  # noqa: E402

__doc__ = _with_equation_map(__doc__, _EQUATIONS, _TEST_FILE)
