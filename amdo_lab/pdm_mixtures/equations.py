"""The equation map of chapter 2: each equation the notebook cites, its code and its test.

Shown by ``help(amdo_lab.pdm_mixtures)``; checked by ``tests/test_equation_paths.py``.
"""

from __future__ import annotations

from amdo_lab.common.equations import EquationPath

TEST_FILE = "test_pdm_mixtures.py"

EQUATIONS: dict[int, EquationPath] = {
    1: EquationPath(code='amdo_lab.pdm_mixtures.pdm.fit_pdm',
                    test='test_pdm_modes_are_orthonormal_and_reproduce_training_data'),
    2: EquationPath(code='amdo_lab.pdm_mixtures.gmm.fit_gaussian_mixture',
                    test='test_gaussian_mixture_em_matches_sklearn'),
    3: EquationPath(code='amdo_lab.pdm_mixtures.gmm.fit_gaussian_mixture',
                    test='test_gaussian_mixture_em_matches_sklearn'),
    4: EquationPath(code='amdo_lab.pdm_mixtures.gmm.fit_gaussian_mixture',
                    test='test_batched_mixture_em_equals_one_run_at_a_time'),
    5: EquationPath(code='amdo_lab.pdm_mixtures.gmm.fit_gaussian_mixture',
                    test='test_batched_mixture_em_equals_one_run_at_a_time'),
    6: EquationPath(code='amdo_lab.pdm_mixtures.gmm.gaussian_log_density_reference',
                    test='test_reference_paths_equal_fast_paths'),
    7: EquationPath(code='amdo_lab.pdm_mixtures.gmm.fit_gaussian_mixture',
                    test='test_batched_mixture_em_equals_one_run_at_a_time'),
    8: EquationPath(code='amdo_lab.pdm_mixtures.gmm.fit_gaussian_mixture',
                    test='test_batched_mixture_em_equals_one_run_at_a_time'),
    9: EquationPath(code='amdo_lab.pdm_mixtures.pdm.fit_modes',
                    test='test_pdm_modes_are_orthonormal_and_reproduce_training_data'),
    10: EquationPath(code='amdo_lab.pdm_mixtures.recogniser.ArticulatedShapeRecogniser._limb_log_posteriors',
                     test='test_limb_posteriors_are_eq10_bayes_rule_over_the_eq16_residual'),
    11: EquationPath(code='amdo_lab.pdm_mixtures.recogniser.ArticulatedShapeRecogniser._recognise',
                     test='test_score_components_polar_term_recognises_distinct_classes'),
    12: EquationPath(code='amdo_lab.pdm_mixtures.recogniser.ArticulatedShapeRecogniser._recognise',
                     test='test_score_components_polar_term_recognises_distinct_classes'),
    13: EquationPath(code='amdo_lab.pdm_mixtures.recogniser.ArticulatedShapeRecogniser._recognise',
                     test='test_score_components_polar_term_recognises_distinct_classes'),
    14: EquationPath(code='amdo_lab.pdm_mixtures.recogniser.ArticulatedShapeRecogniser._recognise',
                     test='test_recognise_relabels_the_limbs_by_eq14'),
    15: EquationPath(code='amdo_lab.pdm_mixtures.recogniser.ArticulatedShapeRecogniser._model_limbs',
                     test='test_model_limbs_are_each_label_pdm_fitted_to_the_observed_limb_eq15'),
    16: EquationPath(code='amdo_lab.pdm_mixtures.recogniser.ArticulatedShapeRecogniser._limb_log_posteriors',
                     test='test_limb_posteriors_are_eq10_bayes_rule_over_the_eq16_residual'),
    17: EquationPath(code='amdo_lab.pdm_mixtures.recogniser.hamming_distance_reference',
                     test='test_reference_paths_equal_fast_paths'),
    18: EquationPath(code='amdo_lab.pdm_mixtures.recogniser._label_string_log_prob',
                     test='test_hamming_counts_mismatches_and_label_probability'),
}
