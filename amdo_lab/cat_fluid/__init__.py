"""Chapter 3: viscous-fluid registration with computational algebraic topology (Bentabet & Ziou, AMDO 2004)."""

from amdo_lab.cat_fluid.complex import CubicalComplex
from amdo_lab.cat_fluid.data import (BLOB_CENTRE_FRACTION, BLOB_SD, PAIR_NAMES, RegistrationPair, load_dipy_image,
                                    make_pair)
from amdo_lab.cat_fluid.peer import DipyResult, register_dipy
from amdo_lab.cat_fluid.registration import (
    HISTORY_COLUMNS,
    FluidResult,
    displacement_jacobian,
    displacement_rmse,
    external_force,
    grey_level_difference,
    inverse_consistency_error,
    jacobian_determinant,
    material_update,
    register_fluid,
    warp_image,
)
from amdo_lab.cat_fluid.reporting import PAPER_TABLE1, accuracy_row, grey_level_table, mean_sd_strings, paper_table1
from amdo_lab.cat_fluid.solvers import (
    SOLVERS,
    SOR_ORDERINGS,
    cat_symbol,
    finite_difference_symbol,
    solve_stencil_reference,
    solve_velocity,
    sor_reference,
    sor_solve,
    stencil_symbol,
    symbol_eigenvalues,
)
from amdo_lab.cat_fluid.stencil import (
    NEIGHBOUR_OFFSETS,
    apply_stencil,
    bilinear_gradient,
    consistency_errors,
    dual_cell_force,
    fluid_stencil,
    polynomial_test_fields,
    printed_stencil,
    rotate_stencil,
    stencil_at_origin,
    stencil_blocks,
    stencil_grid,
    viscous_stress,
)

__all__ = [
    "BLOB_CENTRE_FRACTION", "BLOB_SD", "CubicalComplex", "DipyResult", "FluidResult", "HISTORY_COLUMNS", "NEIGHBOUR_OFFSETS", "PAIR_NAMES", "RegistrationPair",
    "SOLVERS", "SOR_ORDERINGS", "apply_stencil", "cat_symbol",
    "displacement_jacobian", "displacement_rmse", "external_force", "finite_difference_symbol",
    "fluid_stencil", "grey_level_difference", "inverse_consistency_error",
    "jacobian_determinant", "load_dipy_image", "make_pair", "material_update", "printed_stencil",
    "register_dipy", "register_fluid", "rotate_stencil", "solve_velocity", "sor_solve", "stencil_at_origin",
    "stencil_blocks", "stencil_symbol", "warp_image",
    "PAPER_TABLE1", "accuracy_row", "consistency_errors", "grey_level_table", "mean_sd_strings", "paper_table1",
    "polynomial_test_fields", "solve_stencil_reference", "sor_reference", "stencil_grid",
    "symbol_eigenvalues", "bilinear_gradient", "dual_cell_force", "viscous_stress",
]

from amdo_lab.common.equations import with_equation_map as _with_equation_map  # noqa: E402
from amdo_lab.cat_fluid.equations import EQUATIONS as _EQUATIONS, TEST_FILE as _TEST_FILE  # noqa: E402

__doc__ = _with_equation_map(__doc__, _EQUATIONS, _TEST_FILE)
