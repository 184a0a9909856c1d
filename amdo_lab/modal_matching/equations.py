"""The equation map of chapter 9: each equation the notebook cites, its code and its test.

Shown by ``help(amdo_lab.modal_matching)``; checked by ``tests/test_equation_paths.py``.
"""

from __future__ import annotations

from amdo_lab.common.equations import EquationPath

TEST_FILE = "test_modal_matching.py"

_MODES = EquationPath(code="amdo_lab.modal_matching.modes.modal_analysis",
                      test="test_modes_solve_the_generalised_eigenproblem_of_eqs_1_and_2")
_AFFINITY = EquationPath(code="amdo_lab.modal_matching.matching.affinity_matrix",
                         test="test_affinity_is_eqs_3_and_4_on_the_mode_features")

EQUATIONS: dict[int, EquationPath] = {1: _MODES, 2: _MODES, 3: _AFFINITY, 4: _AFFINITY}
