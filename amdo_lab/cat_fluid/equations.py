"""The equation map of chapter 3: each equation the notebook cites, its code and its test.

Shown by ``help(amdo_lab.cat_fluid)``; checked by ``tests/test_equation_paths.py``.
"""

from __future__ import annotations

from amdo_lab.common.equations import EquationPath

TEST_FILE = "test_cat_fluid.py"

EQUATIONS: dict[int, EquationPath] = {
    5: EquationPath(code='amdo_lab.cat_fluid.stencil._bilinear_gradient',
                    test='test_stencil_steps_follow_eqs_5_12_and_14_on_polynomial_fields'),
    7: EquationPath(code='amdo_lab.cat_fluid.complex.CubicalComplex.coboundary',
                    test='test_coboundary_of_a_zero_cochain_is_the_difference_of_end_values'),
    8: EquationPath(code='amdo_lab.cat_fluid.stencil._flux',
                    test='test_stencil_steps_follow_eqs_5_12_and_14_on_polynomial_fields'),
    9: EquationPath(code='amdo_lab.cat_fluid.stencil._flux',
                    test='test_stencil_steps_follow_eqs_5_12_and_14_on_polynomial_fields'),
    10: EquationPath(code='amdo_lab.cat_fluid.stencil._flux',
                     test='test_stencil_steps_follow_eqs_5_12_and_14_on_polynomial_fields'),
    11: EquationPath(code='amdo_lab.cat_fluid.stencil._flux',
                     test='test_stencil_steps_follow_eqs_5_12_and_14_on_polynomial_fields'),
    12: EquationPath(code='amdo_lab.cat_fluid.stencil._stress',
                     test='test_stencil_steps_follow_eqs_5_12_and_14_on_polynomial_fields'),
    13: EquationPath(code='amdo_lab.cat_fluid.stencil._bilinear_gradient',
                     test='test_stencil_steps_follow_eqs_5_12_and_14_on_polynomial_fields'),
    14: EquationPath(code='amdo_lab.cat_fluid.stencil.fluid_stencil',
                     test='test_derived_stencil_exact_values'),
    15: EquationPath(code='amdo_lab.cat_fluid.solvers.solve_stencil_reference',
                     test='test_dense_reference_solve_equals_the_fourier_solve'),
    16: EquationPath(code='amdo_lab.cat_fluid.registration._update',
                     test='test_material_update_follows_the_flow_with_the_untransposed_jacobian'),
    17: EquationPath(code='amdo_lab.cat_fluid.solvers.sor_reference',
                     test='test_pixel_loop_sor_equals_the_vectorised_four_colour_sor'),
    18: EquationPath(code='amdo_lab.cat_fluid.registration._force',
                     test='test_external_force_points_down_the_ssd_gradient'),
}
