"""Every equation a chapter cites can be found in its package: plain numpy, numbered, tested.

One table per chapter maps every equation number the chapter's notebook cites to either

- ``("amdo_lab.<sub>.<module>.<function>", "<test>")``: the readable reference path, whose source
  carries a comment naming the equation (``# eq. (17): ...``), and the test in the chapter's test
  file that checks it (against the fast path where there is one, else against an independent
  computation); or
- ``(None, "<reason>")``: the equation has no code of its own (notation, a definition the chapter
  only discusses, a printed form the chapter shows only to explain why it is not used).

The tables list equations in their order. A notebook that cites a new equation, or stops citing
one, fails here until the table follows; so does a reference function that loses its comment or a
test that is renamed. The tests named are not run here (their own files run them).
"""

from __future__ import annotations

import ast
import functools
import importlib
import inspect
import io
import json
import re
import textwrap
import tokenize
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

# ---------------------------------------------------------------------------------------------
# Which equations a notebook cites: ``\tag{N}`` (or ``\qquad (N)``) in its LaTeX, and "eq. N",
# "eqs. N–M", "Eq. (N)", "equations N and M" in its prose (markdown cells). "\simeq 3" is not one.

_CITATION = re.compile(r"(?<![A-Za-z\\])[Ee]q(?:s|uations?)?\.?\s*"
                       r"((?:\(?\d+[a-z]?\)?(?:\s*(?:[-–,]|and|or|to)\s*)?)+)")


def _expand(numbers: str) -> set[int]:
    """Every number of "4–9", "(17)-(18)", "7, 8 and 10"; ranges are inclusive."""
    found = {int(n) for n in re.findall(r"\d+", numbers)}
    for first, last in re.findall(r"(\d+)\s*\)?\s*[-–]\s*\(?(\d+)", numbers):
        found |= set(range(int(first), int(last) + 1))
    return found


def cited_equations(text: str) -> set[int]:
    """Equation numbers cited in a text (LaTeX tags and prose citations)."""
    found = {int(n) for n in re.findall(r"\\tag\{(\d+)\}", text)}
    found |= {int(n) for n in re.findall(r"\\qquad\s*\((\d+)\)", text)}  # a display numbered by hand
    for match in _CITATION.finditer(text):
        found |= _expand(match.group(1))
    return found


def notebook_citations(chapter: int) -> set[int]:
    (path,) = sorted((ROOT / "notebooks").glob(f"{chapter:02d}_*.ipynb"))
    cells = json.loads(path.read_text(encoding="utf-8"))["cells"]
    return cited_equations("\n".join("".join(c["source"]) for c in cells if c["cell_type"] == "markdown"))


def comments_of(source: str) -> str:
    """The ``#`` comments of a piece of source code (not its strings or docstrings)."""
    tokens = tokenize.generate_tokens(io.StringIO(source).readline)
    return "\n".join(tok.string for tok in tokens if tok.type == tokenize.COMMENT)


def resolve(dotted: str) -> object:
    """The object named ``amdo_lab.sub.module.function`` or ``amdo_lab.sub.module.Class.method``."""
    parts = dotted.split(".")
    for split in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:split]))
        except ModuleNotFoundError:
            continue
        for name in parts[split:]:
            obj = getattr(obj, name)
        return obj
    raise ImportError(dotted)


@functools.lru_cache(maxsize=None)
def _test_functions(test_file: str) -> dict[str, ast.FunctionDef]:
    """{name: node} of the top-level functions of a test file (parsed, not imported)."""
    source = (ROOT / "tests" / test_file).read_text(encoding="utf-8")
    return {node.name: node for node in ast.parse(source).body if isinstance(node, ast.FunctionDef)}


def called_names(test_file: str, test_name: str) -> set[str]:
    """Names the test calls (``f(...)``, ``obj.f(...)``), also through the test file's own helper
    functions it calls (one level deep: ``_fit(...)`` whose body calls ``register_em``)."""
    functions = _test_functions(test_file)

    def calls(node: ast.AST) -> set[str]:
        found = set()
        for sub in ast.walk(node):
            if isinstance(sub, ast.Call):
                if isinstance(sub.func, ast.Name):
                    found.add(sub.func.id)
                elif isinstance(sub.func, ast.Attribute):
                    found.add(sub.func.attr)
        return found

    direct = calls(functions[test_name])
    helpers = {name for name in direct if name in functions and not name.startswith("test_")}
    return direct.union(*(calls(functions[name]) for name in helpers))


# ---------------------------------------------------------------------------------------------
# Chapter 1, Dewaele et al. 2006: amdo_lab.em_articulated

_EM = "amdo_lab.em_articulated"
_FOLDED_INTO_C = ("no code of its own: the priors v/V and (V - nv)/V (eqs. 4-5) and the outlier density 1/V "
                  "(eq. 7) are divided out of eqs. (15) and (9); what remains is the one constant c of eq. (18), "
                  "PAPER_C, so the code never computes v or V")
CHAPTER_1 = {
    1: (f"{_EM}.hand.HandModel.part_fields", "test_part_fields_are_eq1_of_the_part_distances"),
    2: (f"{_EM}.hand.HandModel.surface_distance", "test_surface_distance_jacobian_matches_finite_differences"),
    3: (f"{_EM}.hand.HandModel.transform_texture", "test_transform_texture_is_eq3_blend_of_the_two_part_motions"),
    4: (None, _FOLDED_INTO_C),
    5: (None, _FOLDED_INTO_C),
    6: (f"{_EM}.registration.e_step_reference", "test_e_step_reference_equals_the_streamed_e_step"),
    7: (None, _FOLDED_INTO_C),
    8: (f"{_EM}.registration.robust_log_likelihood_reference",
        "test_robust_log_likelihood_reference_equals_the_streamed_path"),
    9: (f"{_EM}.registration.robust_log_likelihood_reference",
        "test_robust_log_likelihood_reference_equals_the_streamed_path"),
    15: (None, "Bayes' rule in its general form, which the chapter divides through to eq. (17); the code "
               "implements eq. (17), in e_step_reference"),
    16: (None, "the normalised Gaussian of eq. (6) written out; its normalisation cancels into c (eq. 18), so "
               "the code evaluates only its exponential, in e_step_reference (eq. 17)"),
    17: (f"{_EM}.registration.e_step_reference", "test_e_step_reference_equals_the_streamed_e_step"),
    18: (f"{_EM}.registration.e_step_reference", "test_e_step_reference_single_exact_match_is_one_over_one_plus_c"),
    19: (f"{_EM}.registration.register_em_reference", "test_register_em_reference_equals_the_fast_em"),
    20: (f"{_EM}.registration.register_em_reference", "test_register_em_reference_equals_the_fast_em"),
    21: (f"{_EM}.registration.fit_surface", "test_fit_surface_eq21_reaches_the_minimum_scipy_finds"),
    22: (f"{_EM}.registration.fit_surface", "test_fit_surface_eq22_ignores_far_points"),
}

# ---------------------------------------------------------------------------------------------
# Chapter 2, Al-Shaher & Hancock 2004: amdo_lab.pdm_mixtures

_PM = "amdo_lab.pdm_mixtures"
_REC = f"{_PM}.recogniser.ArticulatedShapeRecogniser"
CHAPTER_2 = {
    1: (f"{_PM}.pdm.fit_pdm", "test_pdm_modes_are_orthonormal_and_reproduce_training_data"),
    2: (f"{_PM}.gmm.fit_gaussian_mixture", "test_gaussian_mixture_em_matches_sklearn"),
    3: (f"{_PM}.gmm.fit_gaussian_mixture", "test_gaussian_mixture_em_matches_sklearn"),
    4: (f"{_PM}.gmm.fit_gaussian_mixture", "test_batched_mixture_em_equals_one_run_at_a_time"),
    5: (f"{_PM}.gmm.fit_gaussian_mixture", "test_batched_mixture_em_equals_one_run_at_a_time"),
    6: (f"{_PM}.gmm.gaussian_log_density_reference", "test_reference_paths_equal_fast_paths"),
    7: (f"{_PM}.gmm.fit_gaussian_mixture", "test_batched_mixture_em_equals_one_run_at_a_time"),
    8: (f"{_PM}.gmm.fit_gaussian_mixture", "test_batched_mixture_em_equals_one_run_at_a_time"),
    9: (f"{_PM}.pdm.fit_modes", "test_pdm_modes_are_orthonormal_and_reproduce_training_data"),
    10: (f"{_REC}._limb_log_posteriors", "test_limb_posteriors_are_eq10_bayes_rule_over_the_eq16_residual"),
    11: (f"{_REC}._recognise", "test_score_components_polar_term_recognises_distinct_classes"),
    12: (f"{_REC}._recognise", "test_score_components_polar_term_recognises_distinct_classes"),
    13: (f"{_REC}._recognise", "test_score_components_polar_term_recognises_distinct_classes"),
    14: (f"{_REC}._recognise", "test_recognise_relabels_the_limbs_by_eq14"),
    15: (f"{_REC}._model_limbs", "test_model_limbs_are_each_label_pdm_fitted_to_the_observed_limb_eq15"),
    16: (f"{_REC}._limb_log_posteriors", "test_limb_posteriors_are_eq10_bayes_rule_over_the_eq16_residual"),
    17: (f"{_PM}.recogniser.hamming_distance_reference", "test_reference_paths_equal_fast_paths"),
    18: (f"{_PM}.recogniser._label_string_log_prob", "test_hamming_counts_mismatches_and_label_probability"),
}

# ---------------------------------------------------------------------------------------------
# Chapter 3, Bentabet & Ziou 2004: amdo_lab.cat_fluid

_CF = "amdo_lab.cat_fluid"
_STEPS = "test_stencil_steps_follow_eqs_5_12_and_14_on_polynomial_fields"
CHAPTER_3 = {
    5: (f"{_CF}.stencil._bilinear_gradient", _STEPS),
    7: (f"{_CF}.complex.CubicalComplex.coboundary",
        "test_coboundary_of_a_zero_cochain_is_the_difference_of_end_values"),
    8: (f"{_CF}.stencil._flux", _STEPS),
    9: (f"{_CF}.stencil._flux", _STEPS),
    10: (f"{_CF}.stencil._flux", _STEPS),
    11: (f"{_CF}.stencil._flux", _STEPS),
    12: (f"{_CF}.stencil._stress", _STEPS),
    13: (f"{_CF}.stencil._bilinear_gradient", _STEPS),
    14: (f"{_CF}.stencil.fluid_stencil", "test_derived_stencil_exact_values"),
    15: (f"{_CF}.solvers.solve_stencil_reference", "test_dense_reference_solve_equals_the_fourier_solve"),
    16: (f"{_CF}.registration._update", "test_material_update_follows_the_flow_with_the_untransposed_jacobian"),
    17: (f"{_CF}.solvers.sor_reference", "test_pixel_loop_sor_equals_the_vectorised_four_colour_sor"),
    18: (f"{_CF}.registration._force", "test_external_force_points_down_the_ssd_gradient"),
}

# ---------------------------------------------------------------------------------------------
# Chapter 4, Choraś 2004: amdo_lab.ear_biometrics

_EB = "amdo_lab.ear_biometrics"
_DETECTOR = (f"{_EB}.features.detect_contours_reference", "test_detect_contours_reference_equals_the_filtered_detector")
CHAPTER_4 = {
    1: _DETECTOR,
    2: _DETECTOR,
    3: _DETECTOR,
    4: _DETECTOR,
    5: _DETECTOR,
    6: (f"{_EB}.features.circle_features_reference", "test_reference_of_eqs_6_and_7_equals_the_vectorised_path"),
    7: (f"{_EB}.features.circle_features_reference", "test_reference_of_eqs_6_and_7_equals_the_vectorised_path"),
    8: (f"{_EB}.features._crossing_number", "test_crossing_number_endings_and_bifurcation"),
    9: (f"{_EB}.features.topology_features", "test_topology_features_of_a_y_contour"),
}

# ---------------------------------------------------------------------------------------------
# Chapter 5, Givens et al. 2004: amdo_lab.face_glmm

_FG = "amdo_lab.face_glmm"
CHAPTER_5 = {
    1: (f"{_FG}.pcalda._weighted_sq_distances", "test_distances_l2_and_soft_l2"),
    2: (f"{_FG}.glmm._laplace_deviance_reference", "test_fast_laplace_deviance_equals_dense_reference"),
}

# ---------------------------------------------------------------------------------------------
# Chapter 6, Li & Chaumette 2004: amdo_lab.cue_fusion_pf

_PF = "amdo_lab.cue_fusion_pf"
_SHAPE = "test_template_spline_fits_its_ellipse_and_eq2_is_w_x_plus_template"
CHAPTER_6 = {
    1: (f"{_PF}.shape.ShapeSpace.curve", _SHAPE),
    2: (f"{_PF}.shape.ShapeSpace.control_points", _SHAPE),
    3: (f"{_PF}.shape.ShapeSpace.shape_matrix", _SHAPE),
    4: (f"{_PF}.dynamics.ARDynamics.propagate", "test_printed_eq4_is_unstable_and_the_corrected_one_is_stable"),
    5: (f"{_PF}.dynamics.ARDynamics.step", "test_corrected_dynamics_reach_their_stationary_std"),
    6: (f"{_PF}.likelihoods.fused_log_likelihood", "test_printed_sigmas_make_the_fusion_edge_only"),
    7: (f"{_PF}.likelihoods.kernel_histogram", "test_fast_colour_path_equals_the_per_pixel_histogram"),
    8: (f"{_PF}.likelihoods.kernel_histogram", "test_fast_colour_path_equals_the_per_pixel_histogram"),
    9: (f"{_PF}.likelihoods.ColorLikelihood.distance", "test_colour_distance_and_likelihood_are_eqs_9_and_11"),
    10: (f"{_PF}.likelihoods.bhattacharyya", "test_fast_colour_path_equals_the_per_pixel_histogram"),
    11: (f"{_PF}.likelihoods.ColorLikelihood.log_likelihood", "test_colour_distance_and_likelihood_are_eqs_9_and_11"),
    12: (f"{_PF}.structure.StructureLikelihood.log_likelihood",
         "test_structure_likelihood_is_eq12_of_the_stages_passed"),
    13: (f"{_PF}.likelihoods.edge_line_likelihood", "test_eq13_matches_simulated_lines"),
    14: (f"{_PF}.likelihoods.EdgeLikelihood.log_likelihood", "test_fast_edge_path_equals_the_numpy_reference"),
    15: (f"{_PF}.tracker._run_filter", "test_track_follows_the_head_and_is_seeded"),
    16: (f"{_PF}.tracker._run_filter", "test_track_follows_the_head_and_is_seeded"),
}

# ---------------------------------------------------------------------------------------------
# Chapter 7, Melenchón, Meler & Iriondo 2004: amdo_lab.incremental_svd

_IS = "amdo_lab.incremental_svd.svd_update"
_MEAN_UPDATE = (f"{_IS}._update_with_mean", "test_fast_update_with_mean_equals_the_printed_p_by_r_path")
CHAPTER_7 = {
    1: (None, "notation: the thin SVD itself, which numpy.linalg.svd computes wherever the chapter needs one"),
    2: (f"{_IS}.IncrementalSVD.reconstruct", "test_no_truncation_matches_the_exact_svd_of_the_centred_data"),
    5: _MEAN_UPDATE,
    7: _MEAN_UPDATE,
    8: _MEAN_UPDATE,
    9: _MEAN_UPDATE,
    10: _MEAN_UPDATE,
    11: (f"{_IS}._brand_update", "test_brand_update_appends_columns_and_drops_a_residual_inside_the_span"),
    12: _MEAN_UPDATE,
    13: _MEAN_UPDATE,
    14: _MEAN_UPDATE,
    15: _MEAN_UPDATE,
}

# ---------------------------------------------------------------------------------------------
# Chapter 8, Caro et al. 2004: amdo_lab.active_contours

_AC = "amdo_lab.active_contours.snakes"
_VARIATIONAL = (f"{_AC}.variational_snake", "test_variational_snake_and_its_matrix_follow_kass_finite_differences")
_DISCRETE = (f"{_AC}.greedy_energies", "test_energy_terms_match_the_printed_equations")
CHAPTER_8 = {
    1: _VARIATIONAL,
    2: _VARIATIONAL,
    3: _VARIATIONAL,
    4: _DISCRETE,
    5: _DISCRETE,
    6: _DISCRETE,
    7: _DISCRETE,
}

# ---------------------------------------------------------------------------------------------

CHAPTERS = {
    1: (CHAPTER_1, "test_em_articulated.py"),
    2: (CHAPTER_2, "test_pdm_mixtures.py"),
    3: (CHAPTER_3, "test_cat_fluid.py"),
    4: (CHAPTER_4, "test_ear_biometrics.py"),
    5: (CHAPTER_5, "test_face_glmm.py"),
    6: (CHAPTER_6, "test_cue_fusion_pf.py"),
    7: (CHAPTER_7, "test_incremental_svd.py"),
    8: (CHAPTER_8, "test_active_contours.py"),
}


def _rows():
    for chapter, (table, test_file) in CHAPTERS.items():
        for equation, (dotted, second) in table.items():
            if dotted is not None:
                yield pytest.param(chapter, equation, dotted, second, test_file, id=f"ch{chapter}-eq{equation}")


@pytest.mark.parametrize("chapter", sorted(CHAPTERS))
def test_every_cited_equation_is_in_the_table(chapter):
    table = CHAPTERS[chapter][0]
    cited = notebook_citations(chapter)
    assert cited, "no citation found: the extraction is broken"
    missing, stale = sorted(cited - set(table)), sorted(set(table) - cited)
    assert not missing, f"chapter {chapter} cites equations missing from its table: {missing}"
    assert not stale, f"chapter {chapter}'s table lists equations it no longer cites: {stale}"


@pytest.mark.parametrize("chapter", sorted(CHAPTERS))
def test_tables_are_in_equation_order_and_reasons_are_given(chapter):
    table = CHAPTERS[chapter][0]
    assert list(table) == sorted(table)
    for equation, (dotted, second) in table.items():
        assert isinstance(second, str) and second.strip(), f"eq. {equation}: name a test or give a reason"
        if dotted is None:
            assert len(second.split()) >= 5, f"eq. {equation}: say why it has no code"


@pytest.mark.parametrize("chapter, equation, dotted, test_name, test_file", list(_rows()))
def test_reference_path_names_the_equation_in_a_comment(chapter, equation, dotted, test_name, test_file):
    assert dotted.startswith("amdo_lab."), dotted
    function = resolve(dotted)
    assert callable(function), dotted
    comments = comments_of(textwrap.dedent(inspect.getsource(function)))
    for kernel in private_kernels(dotted):  # a checked wrapper's maths sits in the kernel it calls
        comments += "\n" + comments_of(textwrap.dedent(inspect.getsource(kernel)))
    assert equation in cited_equations(comments), f"no comment of {dotted} names eq. ({equation})"


@pytest.mark.parametrize("chapter, equation, dotted, test_name, test_file", list(_rows()))
def test_reference_path_is_public_and_documented(chapter, equation, dotted, test_name, test_file):
    private = [part for part in dotted.split(".") if part.startswith("_")]
    assert not private, f"eq. ({equation}) maps to a private name {dotted}: map its public, checked wrapper"
    assert inspect.getdoc(resolve(dotted)), f"{dotted} has no docstring"


def private_kernels(dotted: str) -> list[object]:
    """The module-level private functions (and private methods of its class) that ``dotted`` calls by
    name: the check-free kernels of the checked-wrapper pattern."""
    function = resolve(dotted)
    owner = resolve(dotted.rsplit(".", 1)[0])
    module = importlib.import_module(function.__module__)
    source = textwrap.dedent(inspect.getsource(function))
    kernels = []
    for name in set(re.findall(r"\b(_[A-Za-z]\w*)\(", source)):
        candidate = getattr(owner, name, None) or getattr(module, name, None)
        if inspect.isfunction(candidate) and candidate.__module__.startswith("amdo_lab."):
            kernels.append(candidate)
    return kernels


def names_that_reach(dotted: str) -> set[str]:
    """The function's own name and, for a private kernel, the public names beside it that call it
    (a test reaches ``_update`` through ``material_update``)."""
    owner_name, short_name = dotted.rsplit(".", 1)
    names = {short_name}
    if short_name.startswith("_"):
        owner = resolve(owner_name)
        members = list(vars(owner).items())
        for cls in [m for n, m in members if inspect.isclass(m) and not n.startswith("_")]:
            members += list(vars(cls).items())  # the public methods of the module's classes
        for name, member in members:
            if name.startswith("_") or not inspect.isfunction(member):
                continue
            try:
                source = inspect.getsource(member)
            except OSError:  # generated (a dataclass's methods): calls nothing of ours
                continue
            if re.search(rf"\b{short_name}\(", source):
                names.add(name)
    return names


@pytest.mark.parametrize("chapter, equation, dotted, test_name, test_file", list(_rows()))
def test_reference_path_has_a_test_that_calls_it(chapter, equation, dotted, test_name, test_file):
    assert test_name in _test_functions(test_file), f"{test_name} not found in tests/{test_file}"
    names = names_that_reach(dotted)
    assert names & called_names(test_file, test_name), \
        f"{test_name} never calls {' or '.join(sorted(names))} (a mention is not a check of its output)"


def test_citation_extraction():
    text = r"eqs. 4–9, eq. (17), Eqs. (17)–(18), eqs. 7, 8 and 10, $a \simeq 3$, $$x \tag{21}$$ $$y \qquad (23)$$"
    assert cited_equations(text) == {4, 5, 6, 7, 8, 9, 10, 17, 18, 21, 23}
    assert comments_of("x = 1  # eq. (3): blend\ny = '# eq. (4)'\n") == "# eq. (3): blend"
