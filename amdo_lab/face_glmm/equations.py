"""The equation map of chapter 5: each equation the notebook cites, its code and its test.

Shown by ``help(amdo_lab.face_glmm)``; checked by ``tests/test_equation_paths.py``.
"""

from __future__ import annotations

from amdo_lab.common.equations import EquationPath

TEST_FILE = "test_face_glmm.py"

EQUATIONS: dict[int, EquationPath] = {
    1: EquationPath(code='amdo_lab.face_glmm.pcalda.weighted_sq_distances',
                    test='test_distances_l2_and_soft_l2'),
    2: EquationPath(code='amdo_lab.face_glmm.laplace.laplace_deviance_reference',
                    test='test_fast_laplace_deviance_equals_dense_reference'),
}
