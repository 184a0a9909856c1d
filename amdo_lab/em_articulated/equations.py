"""The equation map of chapter 1: each equation the notebook cites, its code and its test.

Shown by ``help(amdo_lab.em_articulated)``; checked by ``tests/test_equation_paths.py``.
"""

from __future__ import annotations

from amdo_lab.common.equations import EquationPath

TEST_FILE = "test_em_articulated.py"

_FOLDED_INTO_C = ('the priors v/V and (V - nv)/V (eqs. 4-5) and the outlier '
                  'density 1/V (eq. 7) are divided out of eqs. (15) and (9); what remains is the one '
                  'constant c of eq. (18), PAPER_C, so the code never computes v or V')

EQUATIONS: dict[int, EquationPath] = {
    1: EquationPath(code='amdo_lab.em_articulated.hand.HandModel.part_fields',
                    test='test_part_fields_are_eq1_of_the_part_distances'),
    2: EquationPath(code='amdo_lab.em_articulated.hand.HandModel.surface_distance',
                    test='test_surface_distance_jacobian_matches_finite_differences'),
    3: EquationPath(code='amdo_lab.em_articulated.hand.HandModel.transform_texture',
                    test='test_transform_texture_is_eq3_blend_of_the_two_part_motions'),
    4: EquationPath(reason=_FOLDED_INTO_C),
    5: EquationPath(reason=_FOLDED_INTO_C),
    6: EquationPath(code='amdo_lab.em_articulated.estep.e_step_reference',
                    test='test_e_step_reference_equals_the_streamed_e_step'),
    7: EquationPath(reason=_FOLDED_INTO_C),
    8: EquationPath(code='amdo_lab.em_articulated.estep.robust_log_likelihood_reference',
                    test='test_robust_log_likelihood_reference_equals_the_streamed_path'),
    9: EquationPath(code='amdo_lab.em_articulated.estep.robust_log_likelihood_reference',
                    test='test_robust_log_likelihood_reference_equals_the_streamed_path'),
    15: EquationPath(reason=("Bayes' rule in its general form, which the chapter divides through to "
                             'eq. (17); the code implements eq. (17), in e_step_reference')),
    16: EquationPath(reason=('the normalised Gaussian of eq. (6) written out; its normalisation '
                             'cancels into c (eq. 18), so the code evaluates only its exponential, in '
                             'e_step_reference (eq. 17)')),
    17: EquationPath(code='amdo_lab.em_articulated.estep.e_step_reference',
                     test='test_e_step_reference_equals_the_streamed_e_step'),
    18: EquationPath(code='amdo_lab.em_articulated.estep.e_step_reference',
                     test='test_e_step_reference_single_exact_match_is_one_over_one_plus_c'),
    19: EquationPath(code='amdo_lab.em_articulated.em.register_em_reference',
                     test='test_register_em_reference_equals_the_fast_em'),
    20: EquationPath(code='amdo_lab.em_articulated.em.register_em_reference',
                     test='test_register_em_reference_equals_the_fast_em'),
    21: EquationPath(code='amdo_lab.em_articulated.surface.fit_surface',
                     test='test_fit_surface_eq21_reaches_the_minimum_scipy_finds'),
    22: EquationPath(code='amdo_lab.em_articulated.surface.fit_surface',
                     test='test_fit_surface_eq22_ignores_far_points'),
}
