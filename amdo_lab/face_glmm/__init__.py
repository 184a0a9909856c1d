"""Chapter 5: a binomial GLMM of a PCA+LDA face recogniser's configuration space.

Givens, Beveridge, Draper & Bolme, AMDO 2004. Synthetic seeded faces stand in for FERET.
"""

from amdo_lab.face_glmm.crosscheck import (
    PeerFit,
    fit_gee,
    fit_naive_logistic,
    fit_with_lme4,
    lme4_available,
)
from amdo_lab.face_glmm.design import (
    PAPER_FORMULA,
    SIZE_FORMULA,
    DesignMatrix,
    group_indices,
    parse_formula,
)
from amdo_lab.face_glmm.experiment import (
    SUPPLEMENTS,
    ExperimentDraws,
    FactorialDesign,
    experiment_draws,
    make_supplement,
    paper_design,
    reduced_design,
    run_factorial_experiment,
)
from amdo_lab.face_glmm.glmm import GlmmResult, fit_binomial_glmm, laplace_deviance
from amdo_lab.face_glmm.laplace import laplace_deviance_reference
from amdo_lab.face_glmm.pcalda import PcaLda, e90_dimension, pca_basis, weighted_sq_distances
from amdo_lab.face_glmm.population import (
    SMALL_SHAPE,
    STANDARD_SHAPE,
    FacePopulation,
    downsample_by_two,
    make_face_population,
    preprocess_images,
)
from amdo_lab.face_glmm.simulate import (
    RecoverySummary,
    recovery_study,
    simulate_binomial_glmm,
)
from amdo_lab.face_glmm.cache import RESULT_MODULES, load_or_run_experiment
from amdo_lab.face_glmm.report import (
    PAPER_NUMBERS,
    PAPER_TABLE2,
    cell_predictions,
    findings,
    plot_figure1,
    plot_figure2,
    table2_comparison,
)

__all__ = [
    "PAPER_FORMULA", "SIZE_FORMULA", "SMALL_SHAPE", "STANDARD_SHAPE", "SUPPLEMENTS",
    "RESULT_MODULES", "ExperimentDraws", "experiment_draws", "DesignMatrix", "FacePopulation", "FactorialDesign", "GlmmResult", "PcaLda", "PeerFit", "RecoverySummary",
    "downsample_by_two", "e90_dimension",
    "fit_binomial_glmm", "laplace_deviance", "laplace_deviance_reference", "fit_gee", "fit_naive_logistic", "fit_with_lme4",
    "make_face_population", "group_indices", "lme4_available", "load_or_run_experiment",
    "make_supplement", "paper_design", "parse_formula", "pca_basis", "preprocess_images",
    "reduced_design", "run_factorial_experiment", "simulate_binomial_glmm",
    "weighted_sq_distances", "PAPER_NUMBERS", "PAPER_TABLE2", "cell_predictions", "findings",
    "plot_figure1", "plot_figure2", "table2_comparison", "recovery_study",
]

from amdo_lab.common.equations import with_equation_map as _with_equation_map  # noqa: E402
from amdo_lab.face_glmm.equations import EQUATIONS as _EQUATIONS, TEST_FILE as _TEST_FILE  # noqa: E402

__doc__ = _with_equation_map(__doc__, _EQUATIONS, _TEST_FILE)
