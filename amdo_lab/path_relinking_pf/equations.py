"""The equation map of chapter 10: each equation the notebook cites, its code and its test.

Shown by ``help(amdo_lab.path_relinking_pf)``; checked by ``tests/test_equation_paths.py``.
"""

from __future__ import annotations

from amdo_lab.common.equations import EquationPath

TEST_FILE = "test_path_relinking_pf.py"

_SIR = EquationPath(code="amdo_lab.path_relinking_pf.filters.track_sir",
                    test="test_track_sir_weighs_n_particles_a_frame_and_predicts_by_eq8")
_COSTS = EquationPath(code="amdo_lab.path_relinking_pf.observation.ObservationModel.cost_reference",
                      test="test_fast_cost_equals_eqs_5_6_summed_over_all_pixels")

EQUATIONS: dict[int, EquationPath] = {
    1: _SIR,
    2: _SIR,
    3: _SIR,
    4: EquationPath(reason="notation: the state of a particle, the pose (x1, y1 and one angle per limb) followed "
                           "by its velocities, which the trackers keep side by side in one array"),
    5: _COSTS,
    6: _COSTS,
    7: EquationPath(code="amdo_lab.path_relinking_pf.observation.ObservationModel.log_weights",
                    test="test_log_weights_are_eq7_and_favour_the_truth"),
    8: _SIR,
}
