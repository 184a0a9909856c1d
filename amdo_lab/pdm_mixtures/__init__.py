"""Chapter 2: mixtures of point distribution models for articulated shape recognition.

Al-Shaher & Hancock, AMDO 2004. Synthetic seeded 13-limb poses stand in for the paper's photos.
One module per step: ``poses`` (the data), ``representation`` (the polar vector S), ``pdm`` and
``gmm`` (a PDM and its mixture by EM), ``polar_mixture`` (the shape layer), ``labels`` (label
strings), ``recognition`` (one step of eqs. 11-14), ``recogniser`` (the estimator), ``baselines``.
"""

from amdo_lab.pdm_mixtures.gmm import GaussianMixtureResult, fit_gaussian_mixture
from amdo_lab.pdm_mixtures.pdm import (
    PointDistributionModel,
    fit_modes,
    fit_pdm,
    generalized_procrustes,
    ppca_log_density,
    reconstruct,
)
from amdo_lab.pdm_mixtures.poses import (
    LIMB_NAMES,
    LIMB_PARENTS,
    JITTER_SCALE,
    POSE_MODES,
    POSES,
    TABLE1_CLASSES,
    PoseDataset,
    make_pose_dataset,
    skeleton_strokes,
)
from amdo_lab.pdm_mixtures.labels import hamming_distance, label_string_log_prob
from amdo_lab.pdm_mixtures.polar_mixture import PolarPDM, held_out_log_likelihood
from amdo_lab.pdm_mixtures.recognition import (
    RecognitionTrace,
    ScoreComponents,
    gated_component_scores,
    relabel_limbs,
    winning_components,
)
from amdo_lab.pdm_mixtures.recogniser import (OUR_SETTINGS, PAPER_SETTINGS, AlignmentTrace, ArticulatedShapeRecogniser,
                                              RecogniserSettings)
from amdo_lab.pdm_mixtures.representation import (
    articulation_centre,
    limb_angles,
    limb_centres,
    polar_shape_vector,
    wrap_angle,
)
from amdo_lab.pdm_mixtures.baselines import (
    NearestProcrustesMeanClassifier,
    SingleCartesianPDMClassifier,
    SklearnGMMClassifier,
    classical_mds,
    pairwise_distances,
    pca_embedding,
)
from amdo_lab.pdm_mixtures.plotting import draw_shape
from amdo_lab.pdm_mixtures.experiments import SEPARATION_MODELS, SeparationTrial, mode_separation_trial

__all__ = [
    "GaussianMixtureResult", "fit_gaussian_mixture",
    "PointDistributionModel", "fit_modes", "fit_pdm", "generalized_procrustes",
    "ppca_log_density", "reconstruct",
    "LIMB_NAMES", "LIMB_PARENTS", "JITTER_SCALE", "POSE_MODES", "POSES", "TABLE1_CLASSES", "PoseDataset",
    "make_pose_dataset", "skeleton_strokes",
    "hamming_distance", "label_string_log_prob", "PolarPDM", "held_out_log_likelihood",
    "RecognitionTrace", "ScoreComponents", "gated_component_scores", "relabel_limbs",
    "winning_components", "AlignmentTrace", "RecogniserSettings", "PAPER_SETTINGS", "OUR_SETTINGS",
    "ArticulatedShapeRecogniser",
    "articulation_centre", "limb_angles", "limb_centres", "polar_shape_vector", "wrap_angle",
    "NearestProcrustesMeanClassifier", "SingleCartesianPDMClassifier", "SklearnGMMClassifier", "classical_mds",
    "pairwise_distances", "pca_embedding", "draw_shape", "SEPARATION_MODELS", "SeparationTrial",
    "mode_separation_trial",
]

from amdo_lab.common.equations import with_equation_map as _with_equation_map  # noqa: E402
from amdo_lab.pdm_mixtures.equations import EQUATIONS as _EQUATIONS, TEST_FILE as _TEST_FILE  # noqa: E402

__doc__ = _with_equation_map(__doc__, _EQUATIONS, _TEST_FILE)
