"""The equation map of chapter 8: each equation the notebook cites, its code and its test.

Shown by ``help(amdo_lab.active_contours)``; checked by ``tests/test_equation_paths.py``.
"""

from __future__ import annotations

from amdo_lab.common.equations import EquationPath

TEST_FILE = "test_active_contours.py"

_VARIATIONAL = EquationPath(code="amdo_lab.active_contours.snakes.variational_snake",
                            test="test_variational_snake_and_its_matrix_follow_kass_finite_differences")
_DISCRETE = EquationPath(code="amdo_lab.active_contours.snakes.greedy_energies",
                         test="test_energy_terms_match_the_printed_equations")

EQUATIONS: dict[int, EquationPath] = {
    1: _VARIATIONAL,
    2: _VARIATIONAL,
    3: _VARIATIONAL,
    4: _DISCRETE,
    5: _DISCRETE,
    6: _DISCRETE,
    7: _DISCRETE,
}
