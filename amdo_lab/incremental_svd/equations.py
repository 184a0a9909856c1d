"""The equation map of chapter 7: each equation the notebook cites, its code and its test.

Shown by ``help(amdo_lab.incremental_svd)``; checked by ``tests/test_equation_paths.py``.
"""

from __future__ import annotations

from amdo_lab.common.equations import EquationPath

TEST_FILE = "test_incremental_svd.py"

EQUATIONS: dict[int, EquationPath] = {
    1: EquationPath(reason=('notation: the thin SVD itself, which numpy.linalg.svd computes wherever '
                            'the chapter needs one')),
    2: EquationPath(code='amdo_lab.incremental_svd.svd_update.IncrementalSVD.reconstruct',
                    test='test_no_truncation_matches_the_exact_svd_of_the_centred_data'),
    5: EquationPath(code='amdo_lab.incremental_svd.svd_update._update_with_mean',
                    test='test_fast_update_with_mean_equals_the_printed_p_by_r_path'),
    7: EquationPath(code='amdo_lab.incremental_svd.svd_update._update_with_mean',
                    test='test_fast_update_with_mean_equals_the_printed_p_by_r_path'),
    8: EquationPath(code='amdo_lab.incremental_svd.svd_update._update_with_mean',
                    test='test_fast_update_with_mean_equals_the_printed_p_by_r_path'),
    9: EquationPath(code='amdo_lab.incremental_svd.svd_update._update_with_mean',
                    test='test_fast_update_with_mean_equals_the_printed_p_by_r_path'),
    10: EquationPath(code='amdo_lab.incremental_svd.svd_update._update_with_mean',
                     test='test_fast_update_with_mean_equals_the_printed_p_by_r_path'),
    11: EquationPath(code='amdo_lab.incremental_svd.svd_update._brand_update',
                     test='test_brand_update_appends_columns_and_drops_a_residual_inside_the_span'),
    12: EquationPath(code='amdo_lab.incremental_svd.svd_update._update_with_mean',
                     test='test_fast_update_with_mean_equals_the_printed_p_by_r_path'),
    13: EquationPath(code='amdo_lab.incremental_svd.svd_update._update_with_mean',
                     test='test_fast_update_with_mean_equals_the_printed_p_by_r_path'),
    14: EquationPath(code='amdo_lab.incremental_svd.svd_update._update_with_mean',
                     test='test_fast_update_with_mean_equals_the_printed_p_by_r_path'),
    15: EquationPath(code='amdo_lab.incremental_svd.svd_update._update_with_mean',
                     test='test_fast_update_with_mean_equals_the_printed_p_by_r_path'),
}
