"""The chapters of the workbook: one entry per notebook in ``notebooks/``.

To add a chapter, add its notebook and one :class:`Chapter` entry here (see the README).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

__all__ = ["CHAPTERS", "Chapter", "NOTEBOOK_DIR", "Prerequisite", "available_chapters", "find_chapter", "reading_map"]

NOTEBOOK_DIR = Path(__file__).resolve().parent.parent / "notebooks"


@dataclass(frozen=True)
class Prerequisite:
    """Something a chapter assumes, and the chapter of this book that teaches it (None: background)."""

    topic: str
    taught_in: int | None = None


def needs(*items: str | tuple[str, int]) -> tuple[Prerequisite, ...]:
    """Shorthand for a chapter's prerequisites: ``needs("least squares", ("EM for mixtures", 2))``."""
    return tuple(Prerequisite(item) if isinstance(item, str) else Prerequisite(*item) for item in items)


@dataclass(frozen=True)
class Chapter:
    """One chapter: its number, notebook file, title, one-line summary and the paper it follows.

    The reading map of chapter 0 is generated from ``prerequisites``, ``teaches``, ``difficulty``
    and ``study_minutes`` (see :func:`reading_map`); a prerequisite taught in chapter N must be
    listed, word for word, in chapter N's ``teaches``.
    """

    number: int
    notebook: str
    title: str
    summary: str
    paper: str
    exercises: str = ""
    """Module holding the chapter's :class:`~amdo_lab.common.exercises.ExerciseSet` as ``EXERCISES``."""
    prerequisites: tuple[Prerequisite, ...] = ()
    """What the chapter assumes, each with the chapter of this book that teaches it, if one does."""
    teaches: tuple[str, ...] = ()
    """Topics the chapter teaches from first principles, as other chapters' prerequisites name them."""
    difficulty: int = 0
    """1 (introductory) to 3 (demanding); 0 when not rated."""
    study_minutes: int = 0
    """A careful first reading with the exercises, in minutes (0 when not estimated)."""

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
        teaches=("rotations and rigid motions", "Procrustes alignment", "the shared notation"),
        difficulty=1,
        study_minutes=30,
    ),
    Chapter(
        1,
        "01_em_articulated_registration.ipynb",
        "Robust EM registration of 3-D points to an articulated hand",
        "Robust EM with an explicit outlier class, built by hand on a planar arm (judged over ten draws: the "
        "paper's large-σ targets curl it, corrected ones do not) and then run on a 27-DOF hand with bending "
        "surfaces: the outlier constant derived, the variance schedule read two ways, per-digit "
        "re-seeding for gross failures, and why, with noise on both point sets, the EM's own objective rather "
        "than its optimizer keeps it above the known-match floor.",
        "G. Dewaele, F. Devernay, R. Horaud, F. Forbes. The Alignment Between 3-D Data and "
        "Articulated Shapes with Bending Surfaces. ECCV 2006, LNCS 3953, pp. 578-591.",
        exercises="amdo_lab.em_articulated.exercises",
        prerequisites=needs(("rotations and rigid motions", 0), "least squares and Gauss–Newton",
                            "Bayes' rule and the Gaussian density", ("EM for mixtures", 2)),
        teaches=("robust EM with an outlier class", "annealing the variance"),
        difficulty=3,
        study_minutes=90,
    ),
    Chapter(
        2,
        "02_pdm_mixtures.ipynb",
        "Mixtures of point distribution models for articulated shape recognition",
        "EM derived and built from scratch on a two-mode toy arm, where a single point distribution model "
        "interpolates through the gap a mixture avoids; a two-layer recogniser of limb labels and polar-PDM mixtures "
        "is followed through one shape, with eq. 11 read as printed and as we implement it; Table 1 is compared "
        "overall and class by class with intervals; a controlled experiment shows where a mixture beats one PDM "
        "per class.",
        "A. A. Al-Shaher, E. R. Hancock. A Probabilistic Framework for Articulated Shape "
        "Recognition. AMDO 2004, LNCS 3179, pp. 62-75.",
        exercises="amdo_lab.pdm_mixtures.exercises",
        prerequisites=needs("eigenvectors and least squares", "the multivariate Gaussian",
                            ("Procrustes alignment", 0)),
        teaches=("EM for mixtures", "point distribution models and PCA"),
        difficulty=2,
        study_minutes=90,
    ),
    Chapter(
        3,
        "03_cat_viscous_fluid.ipynb",
        "Viscous-fluid image registration with computational algebraic topology",
        "Builds the viscous-fluid stencil by hand on a small cubical complex (coboundary, the 2x18 stencil, its "
        "Fourier symbol, one fluid step), checks it for consistency against the printed one, compares CAT "
        "registration with Christensen's SOR, the same finite differences solved by FFT and DIPY's SyN on warped "
        "brain images, and shows that the speed-up belongs to the FFT solver, not to the CAT stencil.",
        "L. Bentabet, D. Ziou. Neuroanatomy Registration: An Algebraic-Topology Based Approach. "
        "AMDO 2004, LNCS 3179, pp. 76-85.",
        exercises="amdo_lab.cat_fluid.exercises",
        prerequisites=needs(("the shared notation", 0), "vector calculus (divergence theorem)",
                            "the discrete Fourier transform"),
        teaches=("viscous-fluid registration", "cochains and the coboundary"),
        difficulty=3,
        study_minutes=120,
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
        prerequisites=needs(("the shared notation", 0), "thresholds, connected components and thinning",
                            "nearest-neighbour matching"),
        teaches=("contour features of binary images",),
        difficulty=1,
        study_minutes=75,
    ),
    Chapter(
        5,
        "05_glmm_face_recognition.ipynb",
        "A generalized linear mixed model of a face recogniser's configuration space",
        "A random-intercept binomial model fitted from scratch (penalised IRLS and the Laplace deviance) on 20 "
        "probes, then on a 65,536-row factorial experiment over a PCA+LDA face recogniser's settings: why every "
        "test is significant, how a missing configuration-by-training-set term inflates F, why LDA must decide "
        "its rank when mirrored images make the between-class scatter singular, and which of the paper's "
        "findings survive.",
        "G. H. Givens, J. R. Beveridge, B. A. Draper, D. Bolme. Using a Generalized Linear Mixed "
        "Model to Study the Configuration Space of a PCA+LDA Human Face Recognition Algorithm. "
        "AMDO 2004, LNCS 3179, pp. 1-11.",
        exercises="amdo_lab.face_glmm.exercises",
        prerequisites=needs("logistic regression", ("point distribution models and PCA", 2),
                            "the idea of a random effect"),
        teaches=("generalized linear mixed models",),
        difficulty=2,
        study_minutes=90,
    ),
    Chapter(
        6,
        "06_cue_fusion_particle_filter.ipynb",
        "Particle filter tracking with fused colour, edge and structure cues",
        "Condensation built from scratch on a 1-D track, then a B-spline head contour with second-order dynamics "
        "(the printed coefficients are unstable; the corrected order is not) weighted by a colour histogram, a "
        "boosted Haar cascade trained in the package and an edge model derived step by step, fused in the log "
        "domain; why the printed variances make the fusion edge-only, calibrated ones, CamShift as a peer, a "
        "twin-head failure case, and a walker on which colour alone beats colour times edges until the edge "
        "factor is tempered.",
        "P. Li, F. Chaumette. Image Cues Fusion for Object Tracking Based on Particle Filter. AMDO 2004, "
        "LNCS 3179.",
        exercises="amdo_lab.cue_fusion_pf.exercises",
        prerequisites=needs(("the shared notation", 0), "Bayes' rule and the Gaussian density"),
        teaches=("particle filters",),
        difficulty=2,
        study_minutes=90,
    ),
    Chapter(
        7,
        "07_incremental_svd_face.ipynb",
        "Incremental SVD with mean update for on-the-fly face training",
        "Brand's incremental SVD and the paper's mean update built by hand on a stream of two-pixel images, then "
        "run on a 41,205-pixel synthetic talking face: 35 coefficients per frame within a fraction of a percent "
        "of the optimal rank-35 error, the garbled Table 1 and the threshold read and measured, memory against a "
        "batch SVD, scikit-learn's IncrementalPCA as a peer and Ross's mean-correction column, which needs no V; "
        "then the paper's on-the-fly face tracker, which aligns each frame with the models it is learning, and "
        "how it absorbs its own misalignment.",
        "J. Melenchón, L. Meler, I. Iriondo. On-the-Fly Training. AMDO 2004, LNCS 3179, pp. 146-153.",
        exercises="amdo_lab.incremental_svd.exercises",
        prerequisites=needs(("the shared notation", 0), ("point distribution models and PCA", 2),
                            "the SVD and the QR decomposition"),
        teaches=("incremental SVD",),
        difficulty=2,
        study_minutes=75,
    ),
    Chapter(
        8,
        "08_active_contours_muscle.ipynb",
        "Active contours for muscle recognition: greedy, dynamic programming and variational snakes",
        "A 24-point greedy snake built by hand on a noisy disc, then three ways to minimise one snake energy "
        "(Williams and Shah's greedy search, Amini's dynamic programming, Kass's variational steps pushed by the "
        "gradient vector flow) on synthetic MRI slices of Iberian hams: Table 1's weights, the pre-processing of "
        "Sec. 3.2 read and checked against OpenCV, area errors against the truth, energy evaluations nm against "
        "nm^3, muscle volumes per ripening stage, scikit-image's snake as a peer and a failure from a larger start.",
        "A. Caro, P.G. Rodríguez, M.L. Durán, M.M. Ávila, T. Antequera, R. Gallardo. A Comparison of Algorithm "
        "Design Paradigms in Active Contours for Muscle Recognition. AMDO 2004, LNCS 3179, pp. 249-258.",
        exercises="amdo_lab.active_contours.exercises",
        prerequisites=needs(("the shared notation", 0), "image gradients and Gaussian smoothing",
                            "dynamic programming"),
        teaches=("active contours",),
        difficulty=2,
        study_minutes=80,
    ),
    Chapter(
        9,
        "09_modal_matching_pedobarography.ipynb",
        "Modal matching of pedobarography objects by finite-element modes and assignment",
        "A Gaussian finite element built by hand on a 12-node and an 11-node outline: its mass and stiffness in "
        "closed form, the modes of K phi = omega^2 M phi as each node's own coordinates, the affinity matrix, "
        "mutual-best matches against the assignment problem with fictitious nodes, and ADCom for the excess "
        "nodes; then contours and isobars of a synthetic pressure sequence with the truth of every node: why "
        "the first modes are not quite rigid, why the modes' signs decide everything, raw coordinates and "
        "coherent point drift as peers, and a shifted and turned foot as the failure case.",
        "L. F. Bastos, J. M. R. S. Tavares. Improvement of Modal Matching Image Objects in Dynamic "
        "Pedobarography Using Optimization Techniques. AMDO 2004, LNCS 3179.",
        exercises="amdo_lab.modal_matching.exercises",
        prerequisites=needs(("the shared notation", 0), ("Procrustes alignment", 0),
                            "eigenvalues and eigenvectors of symmetric matrices"),
        teaches=("finite-element modes of a shape", "matching as an assignment problem"),
        difficulty=2,
        study_minutes=90,
    ),
    Chapter(
        10,
        "10_path_relinking_pf.ipynb",
        "A path relinking particle filter for 2-D body tracking",
        "Path relinking built by hand on a two-link arm (the cost of eq. 6 as an image over the two angles, the "
        "RefSet, a path and the local-search moves), then an eight-limb upper body and a five-limb jumper tracked "
        "with the cost of eqs. 5-7 counted in evaluations: SIR starves in 10 pose dimensions where PRPF, which "
        "spends fewer evaluations, does not; Table 2 read and set beside ours; SIR, pfilter and an annealed filter "
        "at equal evaluations; an ablation that finds the local search doing the work; and fast arms that lose it.",
        "J. J. Pantrigo, Á. Sánchez, K. Gianikellis, A. S. Montemayor. 2D Human Tracking by Efficient Model "
        "Fitting Using a Path Relinking Particle Filter. AMDO 2004, LNCS 3179.",
        exercises="amdo_lab.path_relinking_pf.exercises",
        prerequisites=needs(("particle filters", 6), ("rotations and rigid motions", 0),
                            "silhouettes and edge maps of an image"),
        teaches=("path relinking", "counting evaluations as the cost of a tracker"),
        difficulty=2,
        study_minutes=90,
    ),
)


def reading_map(chapters: tuple[Chapter, ...] | None = None) -> str:
    """The reading map of chapter 0 as a Markdown table, one row per chapter after the introduction.

    Parameters
    ----------
    chapters : tuple of Chapter, optional
        The chapters to list; by default every registered chapter.

    Returns
    -------
    str
        Columns: chapter, what it needs (with "ch. N" where this book teaches it), what it teaches,
        difficulty (1 to 3 stars) and study time.
    """
    chapters = CHAPTERS if chapters is None else chapters
    rows = ["| chapter | you need (where this book teaches it) | it teaches | difficulty | study time |",
            "|---|---|---|---|---|"]
    for chapter in chapters:
        if chapter.number == 0:
            continue
        need = "; ".join(item.topic + (f" (ch. {item.taught_in})" if item.taught_in is not None else "")
                         for item in chapter.prerequisites) or "—"
        teaches = "; ".join(chapter.teaches) or "—"
        stars = "★" * chapter.difficulty or "—"
        rows.append(f"| {chapter.number} · {chapter.title} | {need} | {teaches} | {stars} | "
                    f"{_study_time(chapter.study_minutes)} |")
    return "\n".join(rows)


def _study_time(minutes: int) -> str:
    if minutes <= 0:
        return "—"
    if minutes >= 120 and minutes % 60 == 0:
        return f"about {minutes // 60} h"
    return f"about {minutes} min"


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
