"""Bad-input table of ``amdo_lab.cat_fluid``: a valid call and the kind of each argument.

The valid inputs are tiny (8 x 8 images, two iterations, two SOR sweeps) so that a spoiled call that
is wrongly accepted still returns at once.
"""

from __future__ import annotations

import numpy as np

from bad_input_cases._core import Case

#: (callable, argument, spoiled label) calls known to fail the test, with the reason; each must
#: still fail (remove it once fixed).
KNOWN_FAILURES: dict[tuple[str, str, str], str] = {}

#: Public names not called with user input, with the reason.
EXEMPT = {
    "paper_table1": "takes no argument",
    "FluidResult": "a result record, built by register_fluid from checked input",
    "DipyResult": "a result record, built by register_dipy from checked input",
    "RegistrationPair": "a result record, built by make_pair from checked input",
    "CubicalComplex.edges": "takes no argument",
}

# Spoiled values that are valid input, shared by several entries.
ZERO_IS_A_COUNT = frozenset({("n_sweeps", "zero")})  # zero sweeps: the starting velocity, documented (≥ 0)


def other_size(*arguments: str) -> frozenset[tuple[str, str]]:
    """"A wrong trailing axis" of an (H, W) image or a (2, H, W) field is one more column: an image or a
    field of another size, valid where nothing else fixes the size."""
    return frozenset((argument, "a wrong trailing axis") for argument in arguments)


def cases() -> dict[str, Case]:
    """The public callables of ``amdo_lab.cat_fluid``, by name."""
    from amdo_lab import cat_fluid as cf

    rows, cols = np.indices((8, 8)) - 3.5
    disc = (np.hypot(rows, cols) < 2.5).astype(float)
    moved = (np.hypot(rows - 1, cols) < 2.5).astype(float)
    field = 0.1 * np.stack([np.sin(rows), np.cos(cols)])  # a (2, 8, 8) displacement / velocity / force
    field2 = 0.1 * np.stack([np.cos(rows + cols), np.sin(rows)])
    mask = disc > 0
    stencil = cf.fluid_stencil(1.0, 5.0)
    symbol = cf.cat_symbol((8, 8), 1.0, 5.0)
    force4 = field[:, :4, :4]
    complex_ = cf.CubicalComplex((3, 4))
    pair = cf.RegistrationPair("C", disc, moved, field, mask)
    register = cf.register_fluid

    return {
        # -- the cubical complex (Sec. 2)
        "CubicalComplex": Case(cf.CubicalComplex, {"shape": (3, 4)}, {"shape": "object"}),
        "CubicalComplex.boundary": Case(lambda q: complex_.boundary(q), {"q": 1}, {"q": "count"}),
        "CubicalComplex.coboundary": Case(lambda q: complex_.coboundary(q), {"q": 0}, {"q": "count"},
                                          accept=frozenset({("q", "zero")})),  # δ_0, eq. (7)
        # -- the stencil (Sec. 4)
        "fluid_stencil": Case(cf.fluid_stencil, {"lam": 1.0, "mu": 5.0}, {"lam": "non_negative", "mu": "non_negative"}),
        "printed_stencil": Case(cf.printed_stencil, {"lam": 1.0, "mu": 5.0},
                                {"lam": "non_negative", "mu": "non_negative"}),
        "polynomial_test_fields": Case(cf.polynomial_test_fields, {"lam": 1.0, "mu": 5.0},
                                       {"lam": "non_negative", "mu": "non_negative"}),
        "stencil_blocks": Case(cf.stencil_blocks, {"stencil": stencil}, {"stencil": "array"}),
        "rotate_stencil": Case(cf.rotate_stencil, {"stencil": stencil}, {"stencil": "array"}),
        "apply_stencil": Case(cf.apply_stencil, {"stencil": stencil, "velocity": field},
                              {"stencil": "array", "velocity": "array"}, accept=other_size("velocity")),
        "stencil_at_origin": Case(cf.stencil_at_origin, {"stencil": stencil, "velocity": lambda a, b: (a, b)},
                                  {"stencil": "array", "velocity": "object"}),
        "stencil_grid": Case(cf.stencil_grid, {"stencil": stencil, "row": 1, "component": 1},
                             {"stencil": "array", "row": "count", "component": "count"},
                             accept=frozenset({("row", "zero"), ("component", "zero")})),  # indices 0 and 1
        "bilinear_gradient": Case(cf.bilinear_gradient, {"velocity": lambda i, j: (i * j, 0.0), "point": [0.25, 0.5]},
                                  {"velocity": "object", "point": "array"}),
        "viscous_stress": Case(cf.viscous_stress, {"gradient": [[0.3, -1.2], [2.0, 0.7]], "lam": 1.0, "mu": 5.0},
                               {"gradient": "array", "lam": "non_negative", "mu": "non_negative"}),
        "dual_cell_force": Case(cf.dual_cell_force, {"velocity": lambda i, j: (j * j, 0.0), "lam": 1.0, "mu": 5.0},
                                {"velocity": "object", "lam": "non_negative", "mu": "non_negative"}),
        "consistency_errors": Case(cf.consistency_errors, {"stencil": stencil, "lam": 1.0, "mu": 5.0},
                                   {"stencil": "array", "lam": "non_negative", "mu": "non_negative"}),
        # -- the solvers
        "stencil_symbol": Case(cf.stencil_symbol, {"stencil": stencil, "shape": (8, 8)},
                               {"stencil": "array", "shape": "object"}),
        "cat_symbol": Case(cf.cat_symbol, {"shape": (8, 8), "lam": 1.0, "mu": 5.0},
                           {"shape": "object", "lam": "non_negative", "mu": "non_negative"}),
        "finite_difference_symbol": Case(cf.finite_difference_symbol, {"shape": (8, 8), "lam": 1.0, "mu": 5.0},
                                         {"shape": "object", "lam": "non_negative", "mu": "non_negative"}),
        "symbol_eigenvalues": Case(cf.symbol_eigenvalues, {"symbol": symbol, "rows": [0, 1, 2], "cols": [0, 1, 2]},
                                   {"symbol": "array", "rows": "array", "cols": "array"},
                                   accept=other_size("symbol")),  # (2, 2, 8, 6): the symbol of an 8 x 10 grid
        "solve_stencil_reference": Case(cf.solve_stencil_reference, {"stencil": stencil, "force": force4},
                                        {"stencil": "array", "force": "array"}, accept=other_size("force")),
        "solve_velocity": Case(cf.solve_velocity, {"force": field, "method": "cat", "lam": 1.0, "mu": 5.0},
                               {"force": "array", "method": "name", "lam": "non_negative", "mu": "positive"},
                               accept=other_size("force")),
        "sor_solve": Case(cf.sor_solve,
                          {"force": field, "lam": 1.0, "mu": 5.0, "n_sweeps": 2, "omega": 1.5, "initial": field2,
                           "ordering": "red-black"},
                          {"force": "array", "lam": "non_negative", "mu": "positive", "n_sweeps": "count",
                           "omega": "positive", "initial": "array", "ordering": "name"},
                          accept=ZERO_IS_A_COUNT | {("omega", "None"), ("initial", "None")}),  # defaults: textbook factor, zero start
        "sor_reference": Case(cf.sor_reference, {"force": force4, "lam": 1.0, "mu": 5.0, "n_sweeps": 1, "omega": 1.5},
                              {"force": "array", "lam": "non_negative", "mu": "positive", "n_sweeps": "count",
                               "omega": "positive"},
                              accept=ZERO_IS_A_COUNT | other_size("force")),  # the plain loop takes any size
        # -- registration (Sec. 5)
        "warp_image": Case(cf.warp_image, {"image": disc, "displacement": field},
                           {"image": "image", "displacement": "array"}),
        "displacement_jacobian": Case(cf.displacement_jacobian, {"displacement": field}, {"displacement": "array"},
                                      accept=other_size("displacement")),
        "jacobian_determinant": Case(cf.jacobian_determinant, {"displacement": field}, {"displacement": "array"},
                                     accept=other_size("displacement")),
        "external_force": Case(cf.external_force, {"deformed_template": disc, "study": moved},
                               {"deformed_template": "image", "study": "image"}),
        "material_update": Case(cf.material_update, {"displacement": field, "velocity": field2, "dt": 0.5},
                                {"displacement": "array", "velocity": "array", "dt": "positive"}),
        "grey_level_difference": Case(cf.grey_level_difference,
                                      {"image": disc, "reference": moved, "mask": mask, "scale": 255.0},
                                      {"image": "image", "reference": "image", "mask": "bool_array",
                                       "scale": "positive"},
                                      accept=frozenset({("mask", "None")})),  # None: all pixels, documented
        "displacement_rmse": Case(cf.displacement_rmse, {"displacement": field, "truth": field2, "mask": mask},
                                  {"displacement": "array", "truth": "array", "mask": "bool_array"},
                                  accept=frozenset({("mask", "None")})),  # None: all pixels, documented
        "inverse_consistency_error": Case(cf.inverse_consistency_error,
                                          {"forward": field, "backward": field2, "mask": mask},
                                          {"forward": "array", "backward": "array", "mask": "bool_array"},
                                          accept=frozenset({("mask", "None")})),  # None: all pixels, documented
        "register_fluid": Case(register,
                               {"template": disc, "study": moved, "method": "cat", "lam": 1.0, "mu": 5.0,
                                "n_iter": 2, "max_step_px": 1.0, "backtrack": True, "regrid_threshold": 0.5,
                                "sor_n_sweeps": 2, "sor_omega": 1.5, "sor_warm_start": True},
                               {"template": "image", "study": "image", "method": "name", "lam": "non_negative",
                                "mu": "positive", "n_iter": "count", "max_step_px": "positive", "backtrack": "flag",
                                "regrid_threshold": "probability", "sor_n_sweeps": "count", "sor_omega": "positive",
                                "sor_warm_start": "flag"},
                               accept=frozenset({("n_iter", "None"),  # None: the paper's iteration count
                                                 ("sor_omega", "None")})),  # None: the textbook factor
        "register_fluid(method='sor')": Case(
            lambda sor_n_sweeps, sor_omega: register(disc, moved, "sor", n_iter=2, sor_n_sweeps=sor_n_sweeps,
                                                     sor_omega=sor_omega),
            {"sor_n_sweeps": 2, "sor_omega": 1.5}, {"sor_n_sweeps": "count", "sor_omega": "positive"},
            accept=frozenset({("sor_omega", "None")})),  # None: the textbook factor
        # -- data
        "load_dipy_image": Case(cf.load_dipy_image, {"name": "reg_c"}, {"name": "name"}),
        "make_pair": Case(cf.make_pair, {"name": "C", "rng": 0}, {"name": "name", "rng": "seed"}),
        # -- the peer
        "register_dipy": Case(cf.register_dipy, {"template": disc, "study": moved, "metric": "ssd", "level_iters": (2,)},
                              {"template": "image", "study": "image", "metric": "name", "level_iters": "object"}),
        # -- tables
        "grey_level_table": Case(cf.grey_level_table,
                                 {"pairs": {"C": pair}, "deformed": {"C": {"CAT": moved}}, "masked": True,
                                  "scale": 255.0},
                                 {"pairs": "object", "deformed": "object", "masked": "flag", "scale": "positive"}),
        "mean_sd_strings": Case(cf.mean_sd_strings, {"table": cf.paper_table1()}, {"table": "object"}),
        "accuracy_row": Case(cf.accuracy_row,
                             {"pair": pair, "warped": moved, "displacement": field, "backward": field2,
                              "scale": 255.0},
                             {"pair": "object", "warped": "image", "displacement": "array", "backward": "array",
                              "scale": "positive"},
                             accept=frozenset({("backward", "None")})),  # None: no inverse consistency, documented
    }
