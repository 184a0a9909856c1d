"""Chapter 2: mixtures of point distribution models for articulated shape recognition.

Al-Shaher & Hancock, AMDO 2004. Synthetic seeded 13-limb poses stand in for the paper's photos.
"""

from amdo_lab.pdm_mixtures.gmm import GaussianMixtureResult, fit_gaussian_mixture, gaussian_log_density
from amdo_lab.pdm_mixtures.pdm import (
    PointDistributionModel,
    align_to_reference,
    fit_modes,
    fit_pdm,
    generalized_procrustes,
    normalise_shape,
    pdm_from_moments,
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
    generate_pose_dataset,
    pose_modes,
    skeleton_strokes,
)
from amdo_lab.pdm_mixtures.recogniser import (
    AlignmentTrace,
    ArticulatedShapeRecogniser,
    PolarPDM,
    RecognitionTrace,
    ScoreComponents,
    hamming_distance,
    held_out_log_likelihood,
    label_string_log_prob,
)
from amdo_lab.pdm_mixtures.representation import (
    articulation_centre,
    centred_limbs,
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

from amdo_lab.common.equations import with_equation_map as _with_equation_map  # noqa: E402
from amdo_lab.pdm_mixtures.equations import EQUATIONS as _EQUATIONS, TEST_FILE as _TEST_FILE  # noqa: E402

__doc__ = _with_equation_map(__doc__, _EQUATIONS, _TEST_FILE)
