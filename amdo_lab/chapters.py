"""The chapters of the workbook: one entry per notebook in ``notebooks/``.

To add a chapter, add its notebook and one :class:`Chapter` entry here (see the README).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

__all__ = ["CHAPTERS", "Chapter", "NOTEBOOK_DIR", "available_chapters", "find_chapter"]

NOTEBOOK_DIR = Path(__file__).resolve().parent.parent / "notebooks"


@dataclass(frozen=True)
class Chapter:
    """One chapter: its number, notebook file, title, one-line summary and the paper it follows."""

    number: int
    notebook: str
    title: str
    summary: str
    paper: str
    exercises: str = ""
    """Module holding the chapter's :class:`~amdo_lab.common.exercises.ExerciseSet` as ``EXERCISES``."""

    @property
    def slug(self) -> str:
        """File stem of the notebook, used for HTML pages and figure folders."""
        return Path(self.notebook).stem

    @property
    def path(self) -> Path:
        return NOTEBOOK_DIR / self.notebook


CHAPTERS: tuple[Chapter, ...] = (
    Chapter(
        0,
        "00_introduction.ipynb",
        "Introduction: how to read AMDO Lab",
        "The reading map of the chapters (what each needs and which chapter teaches it), the notation they share, "
        "how exercises are checked, a warm-up exercise on Procrustes alignment, and the plotting helpers in 2-D and 3-D.",
        "—",
        exercises="amdo_lab.introduction.exercises",
    ),
    Chapter(
        1,
        "01_em_articulated_registration.ipynb",
        "Robust EM registration of 3-D points to an articulated hand",
        "Robust EM with an explicit outlier class, built by hand on a planar arm and then run on a 27-DOF hand "
        "with bending surfaces: the outlier constant derived, the variance schedule read two ways, per-digit "
        "re-seeding for gross failures, and why, with noise on both point sets, the EM's own objective rather "
        "than its optimizer keeps it above the known-match floor.",
        "G. Dewaele, F. Devernay, R. Horaud, F. Forbes. The Alignment Between 3-D Data and "
        "Articulated Shapes with Bending Surfaces. ECCV 2006, LNCS 3953, pp. 578-591.",
        exercises="amdo_lab.em_articulated.exercises",
    ),
    Chapter(
        2,
        "02_pdm_mixtures.ipynb",
        "Mixtures of point distribution models for articulated shape recognition",
        "A two-mode toy arm shows a single point distribution model interpolating through the gap a mixture avoids; "
        "a two-layer recogniser of limb labels and polar-PDM mixtures is followed through one shape; Table 1 is "
        "reproduced within its interval; a controlled experiment shows where a mixture beats one PDM per class.",
        "A. A. Al-Shaher, E. R. Hancock. A Probabilistic Framework for Articulated Shape "
        "Recognition. AMDO 2004, LNCS 3179, pp. 62-75.",
        exercises="amdo_lab.pdm_mixtures.exercises",
    ),
    Chapter(
        3,
        "03_cat_viscous_fluid.ipynb",
        "Viscous-fluid image registration with computational algebraic topology",
        "Builds the viscous-fluid stencil by hand on a small cubical complex (coboundary, the 2x18 stencil, its "
        "Fourier symbol, one fluid step), checks it for consistency against the printed one, and compares CAT "
        "registration with Christensen's SOR, an exact FFT solve and DIPY's SyN on warped brain images.",
        "L. Bentabet, D. Ziou. Neuroanatomy Registration: An Algebraic-Topology Based Approach. "
        "AMDO 2004, LNCS 3179, pp. 76-85.",
        exercises="amdo_lab.cat_fluid.exercises",
    ),
    Chapter(
        4,
        "04_ear_geometric_features.ipynb",
        "Geometric ear-biometric features and matching",
        "Choraś's concentric-circle and contour-topology ear features, built on a toy and made invariant to "
        "rotation, scale and translation by a silhouette-moment frame applied before contour detection: copies "
        "turned by any angle are identified; HOG and LBP peers given the same frame show the frame carries most "
        "of the result, while the paper's strict decision rule stays short of error-free on synthetic ears.",
        "M. Choraś. Ear Biometrics Based on Geometrical Method of Feature Extraction. "
        "AMDO 2004, LNCS 3179, pp. 51-61.",
        exercises="amdo_lab.ear_biometrics.exercises",
    ),
    Chapter(
        5,
        "05_glmm_face_recognition.ipynb",
        "A generalized linear mixed model of a face recogniser's configuration space",
        "A random-intercept binomial model fitted from scratch (penalised IRLS and the Laplace deviance) on 20 "
        "probes, then on a 65,536-row factorial experiment over a PCA+LDA face recogniser's settings: why every "
        "test is significant, how a missing configuration-by-training-set term inflates F, and which of the "
        "paper's findings survive.",
        "G. H. Givens, J. R. Beveridge, B. A. Draper, D. Bolme. Using a Generalized Linear Mixed "
        "Model to Study the Configuration Space of a PCA+LDA Human Face Recognition Algorithm. "
        "AMDO 2004, LNCS 3179, pp. 1-11.",
        exercises="amdo_lab.face_glmm.exercises",
    ),
    Chapter(
        6,
        "06_cue_fusion_particle_filter.ipynb",
        "Particle filter tracking with fused colour, edge and structure cues",
        "Condensation built from scratch on a 1-D track, then a B-spline head contour with second-order dynamics "
        "(the printed coefficients are unstable; the corrected order is not) weighted by a colour histogram, a "
        "boosted Haar cascade trained in the package and an edge model derived step by step, fused in the log "
        "domain; why the printed variances make the fusion edge-only, calibrated ones, CamShift as a peer and a "
        "twin-head failure case.",
        "P. Li, F. Chaumette. Image Cues Fusion for Object Tracking Based on Particle Filter. AMDO 2004, "
        "LNCS 3179.",
        exercises="amdo_lab.cue_fusion_pf.exercises",
    ),
)


def available_chapters() -> list[Chapter]:
    """The registered chapters whose notebook exists (a chapter may be registered before it is written)."""
    return [chapter for chapter in CHAPTERS if chapter.path.exists()]


def find_chapter(number: int) -> Chapter:
    """Return chapter ``number`` or raise a one-line ``ValueError`` listing what exists."""
    for chapter in CHAPTERS:
        if chapter.number == number:
            if not chapter.path.exists():
                raise ValueError(
                    f"chapter {number}'s notebook {chapter.notebook} is missing from {NOTEBOOK_DIR}; "
                    f"available: {_available()}"
                )
            return chapter
    raise ValueError(f"no chapter {number}; available chapters: {_available()}")


def _available() -> str:
    return ", ".join(
        f"{chapter.number} ({chapter.notebook})" for chapter in available_chapters()
    ) or "none"
