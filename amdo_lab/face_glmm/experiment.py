"""The balanced factorial experiment of Sec. 4 / Table 1, vectorised.

One PCA eigen-decomposition per (training set, supplement, image size) is shared by
both PCA dimensions; one probe-by-candidate distance matrix per configuration and
metric; the 30 galleries are gathered from it by fancy indexing.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from amdo_lab.common import (MAX_ITERATIONS, MAX_SAMPLES, as_finite_array, check_image_shape, check_instance, check_names,
                             check_positive, check_positive_int, make_rng)
from amdo_lab.common.threads import one_blas_thread
from amdo_lab.face_glmm.pcalda import METRICS, PcaLda, pca_basis, weighted_sq_distances
from amdo_lab.face_glmm.population import (
    STANDARD_SHAPE,
    _elliptical_mask,
    downsample_by_two,
    make_face_population,
    preprocess_images,
)

__all__ = ["FactorialDesign", "SUPPLEMENTS", "ExperimentDraws", "experiment_draws", "run_factorial_experiment",
           "make_supplement", "paper_design", "reduced_design"]

SUPPLEMENTS = ("none", "shift", "reflection", "noise")
DIMENSIONS = ("fixed", "e90")
SIZES = ("standard", "small")
NOISE_FRACTION = 0.02  # Sec. 4: noise sd = 2 % of the image's dynamic range


@dataclass(frozen=True)
class FactorialDesign:
    """Sizes of the Table 1 design (defaults = the paper's).

    Parameters
    ----------
    n_subjects : int, default 256
        Subjects in the population, 4 to 1,000,000; each has 4 images (1 probe, 3 candidates).
    n_training_sets : int, default 8
        Training sets t drawn, 1 to :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).
    n_train_subjects : int, default 64
        Subjects per training set, in [2, n_subjects].
    n_galleries : int, default 30
        Galleries per probe, 1 to 100,000; the response Y counts rank-1 matches among them.
    supplements : tuple of str, default SUPPLEMENTS
        Non-empty subset of ("none", "shift", "reflection", "noise"), without repeats.
    shape : tuple of int, default STANDARD_SHAPE
        Standard image size (rows, cols) in pixels, each even and at least 8 (the small size halves
        each side).
    nuisance : float, default 1.35
        Per-image variation of the population, > 0 (calibrated: overall rank-1 rate about 75 %,
        paper 76 %).
    population_kwargs : dict, default {}
        Further keyword arguments of :func:`make_face_population`.

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, Sec. 4 and Table 1.
    """

    n_subjects: int = 256
    n_training_sets: int = 8
    n_train_subjects: int = 64
    n_galleries: int = 30
    supplements: tuple[str, ...] = SUPPLEMENTS
    shape: tuple[int, int] = STANDARD_SHAPE
    nuisance: float = 1.35  # calibrated: overall rank-1 rate ~ 75 %, paper 76 %
    population_kwargs: dict = field(default_factory=dict, hash=False, compare=False)

    def __post_init__(self):
        check_positive_int(self.n_subjects, "n_subjects", minimum=4, maximum=MAX_SAMPLES)
        check_positive_int(self.n_training_sets, "n_training_sets", maximum=MAX_ITERATIONS)
        check_positive_int(self.n_galleries, "n_galleries", maximum=MAX_ITERATIONS)
        check_positive(self.nuisance, "nuisance")
        check_positive_int(self.n_train_subjects, "n_train_subjects", minimum=2, maximum=self.n_subjects)
        check_names(self.supplements, "supplements", allowed=SUPPLEMENTS)
        # checked here rather than after the population is drawn: the small size halves each side
        rows, cols = check_image_shape(self.shape, minimum=8)
        if rows % 2 or cols % 2:
            raise ValueError(f"shape must have even rows and cols (the small size halves them), got {self.shape}")
        check_instance(self.population_kwargs, "population_kwargs", dict)


def paper_design() -> FactorialDesign:
    """The full design: 8 training sets x 30 galleries x 4 supplements x 2 metrics x 2 dimensions x 2 sizes.

    Returns
    -------
    FactorialDesign
        The paper's sizes: 256 subjects, 8 training sets of 64, 30 galleries (65,536 table rows).

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, Sec. 4 and Table 1.
    """
    return FactorialDesign()


def reduced_design() -> FactorialDesign:
    """A small design for tests: 64 subjects, 2 training sets of 16, 10 galleries, 32 x 28 images.

    Returns
    -------
    FactorialDesign
        The reduced sizes (all four supplements kept).

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, Sec. 4 and Table 1 (the full design this one shrinks).
    """
    return FactorialDesign(n_subjects=64, n_training_sets=2, n_train_subjects=16, n_galleries=10,
                           shape=(32, 28))


def make_supplement(images: np.ndarray, kind: str, *, rng: int | np.random.Generator) -> np.ndarray:
    """One altered copy per preprocessed training image (Sec. 4's three supplements).

    shift: one pixel to the left (the vacated column is 0, the masked background); reflection: mirror
    about the vertical mid-line; noise: Gaussian, standard deviation 2 % of each image's dynamic
    range. The face mask is re-applied so the background stays 0.

    Parameters
    ----------
    images : array_like, shape (n, rows, cols)
        Finite preprocessed images.
    kind : {"shift", "reflection", "noise"}
        The supplement.
    rng : int or numpy.random.Generator
        Seed or generator (via :func:`amdo_lab.common.make_rng`); drawn from by "noise" only.

    Returns
    -------
    ndarray, shape (n, rows, cols)
        The altered copies, 0 outside the elliptical mask.

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, Sec. 4 (the training supplements U).
    """
    images = as_finite_array(images, "images", ndim=3)
    return _make_supplement(images, kind, make_rng(rng, "rng"))


def _make_supplement(images: np.ndarray, kind: str, rng: np.random.Generator) -> np.ndarray:
    """:func:`make_supplement` on validated images (the experiment's inner call)."""
    mask = _elliptical_mask(images.shape[1:])
    if kind == "shift":
        out = np.zeros_like(images)
        out[:, :, :-1] = images[:, :, 1:]
    elif kind == "reflection":
        out = images[:, :, ::-1].copy()
    elif kind == "noise":
        dynamic = images.max(axis=(1, 2)) - images.min(axis=(1, 2))
        out = images + NOISE_FRACTION * dynamic[:, None, None] * rng.standard_normal(images.shape)
    else:
        raise ValueError(f"kind must be one of {SUPPLEMENTS[1:]}, got {kind!r}")
    return out * mask


def _rank1_counts(distance: np.ndarray, gallery_choice: np.ndarray) -> np.ndarray:
    """Per probe, the number of galleries whose nearest image is the probe's subject.

    distance : (n_probes, n_subjects, k) probe-to-candidate distances (k non-probe images)
    gallery_choice : (n_galleries, n_subjects) which candidate represents each subject.
    """
    n_subjects = distance.shape[1]
    gathered = distance[:, np.arange(n_subjects)[None, :], gallery_choice]  # (probe, g, subject)
    nearest = np.argmin(gathered, axis=2)
    return np.sum(nearest == np.arange(distance.shape[0])[:, None], axis=1)


@dataclass(frozen=True)
class ExperimentDraws:
    """Every random draw of one factorial experiment, made before any recogniser runs.

    Parameters
    ----------
    population : FacePopulation
        ``n_subjects`` x 4 raw images; image 0 of each subject is its probe, images 1-3 its candidates.
    training_sets : ndarray of int, shape (n_training_sets, n_train_subjects)
        The subjects whose three candidate images train each training set.
    gallery_choice : ndarray of int, shape (n_galleries, n_subjects)
        Which candidate (0, 1 or 2) stands for each subject in each gallery.
    noise_rngs : list of numpy.random.Generator
        One per (training set, image size), for the noise supplement.

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, Sec. 4 and Table 1.
    """

    population: object
    training_sets: np.ndarray
    gallery_choice: np.ndarray
    noise_rngs: list


def experiment_draws(design: FactorialDesign, *, rng: int | np.random.Generator) -> ExperimentDraws:
    """The population, training sets and galleries that :func:`run_factorial_experiment` uses.

    Same seed, same draws: the chapter uses it to recompute one row of the table by hand.

    Parameters
    ----------
    design : FactorialDesign
        The experiment's sizes.
    rng : int or numpy.random.Generator
        Seed or generator (via :func:`amdo_lab.common.make_rng`); four streams are spawned from it
        (population, training sets, galleries, noise supplements).

    Returns
    -------
    ExperimentDraws
        Every random draw of the experiment.

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, Sec. 4 and Table 1.
    """
    check_instance(design, "design", FactorialDesign)
    gen = make_rng(rng, "rng")
    pop_rng, split_rng, gallery_rng, noise_seed = gen.spawn(4)
    pop = make_face_population(design.n_subjects, 4, rng=pop_rng, shape=design.shape,
                                   nuisance=design.nuisance, **design.population_kwargs)
    n = design.n_subjects
    training_sets = np.stack([split_rng.permutation(n)[: design.n_train_subjects]
                              for _ in range(design.n_training_sets)])
    gallery_choice = gallery_rng.integers(0, 3, size=(design.n_galleries, n))
    noise_rngs = noise_seed.spawn(design.n_training_sets * len(SIZES))
    return ExperimentDraws(pop, training_sets, gallery_choice, noise_rngs)


def run_factorial_experiment(design: FactorialDesign, *, rng: int | np.random.Generator) -> pd.DataFrame:
    """Run the balanced factorial experiment and return the response table.

    Parameters
    ----------
    design : FactorialDesign
        The experiment's sizes (:func:`paper_design` for the paper's).
    rng : int or numpy.random.Generator
        Seed or generator (via :func:`amdo_lab.common.make_rng`); the draws are those of
        :func:`experiment_draws` with the same ``rng``.

    Returns
    -------
    pandas.DataFrame
        One row per (training set t, probe p, supplement U, metric M, PCA dimension D, image size S)
        with the inclusion flag F ("yes"/"no"), the PCA dimension used (``k``) and Y = number of
        galleries (of ``design.n_galleries``, stored in ``table.attrs["n_galleries"]``) with a rank-1
        match. U, M, D, S and F are categorical.

    References
    ----------
    Givens, Beveridge, Draper & Bolme (2004), "Using a Generalized Linear Mixed Model to Study the
    Configuration Space of a PCA+LDA Human Face Recognition Algorithm", AMDO 2004, LNCS 3179, pp. 1-11, Sec. 4 and Table 1.
    """
    with one_blas_thread():  # small matrices: threads only contend on a shared machine
        return _run(design, rng)


def _run(design: FactorialDesign, rng) -> pd.DataFrame:
    draws = experiment_draws(design, rng=rng)
    pop, training_sets, gallery_choice, noise_rngs = (draws.population, draws.training_sets,
                                                      draws.gallery_choice, draws.noise_rngs)
    n = design.n_subjects
    sized = {"standard": preprocess_images(pop.images),
             "small": preprocess_images(downsample_by_two(pop.images))}

    blocks = []
    for si, size in enumerate(SIZES):
        images = sized[size].reshape(n, 4, -1)
        probes, candidates = images[:, 0], images[:, 1:]
        shape2d = sized[size].shape[1:]
        for t, subjects in enumerate(training_sets):
            base = candidates[subjects].reshape(-1, *shape2d)
            base_labels = np.repeat(subjects, 3)
            included = np.isin(np.arange(n), subjects)
            for u in design.supplements:
                if u == "none":
                    train, labels = base, base_labels
                else:
                    extra = _make_supplement(base, u, noise_rngs[t * len(SIZES) + si])
                    train = np.concatenate([base, extra])
                    labels = np.concatenate([base_labels, base_labels])
                samples = train.reshape(train.shape[0], -1)
                basis = pca_basis(samples)  # shared by both PCA dimensions
                for d in DIMENSIONS:
                    model = PcaLda(d).fit(samples, labels, basis=basis)
                    probe_feat = model.transform(probes)
                    cand_feat = model.transform(candidates.reshape(n * 3, -1))
                    for m in METRICS:
                        dist = weighted_sq_distances(probe_feat, cand_feat, model._metric_weights(m))
                        y = _rank1_counts(dist.reshape(n, n, 3), gallery_choice)
                        blocks.append(pd.DataFrame({
                            "t": t, "p": np.arange(n), "U": u, "M": m, "D": d, "S": size,
                            "F": np.where(included, "yes", "no"), "k": model.n_pca_, "Y": y}))
    table = pd.concat(blocks, ignore_index=True)
    for name, levels in (("U", design.supplements), ("M", METRICS), ("D", DIMENSIONS),
                         ("S", SIZES), ("F", ("no", "yes"))):
        table[name] = pd.Categorical(table[name], categories=list(levels))
    table.attrs["n_galleries"] = design.n_galleries
    return table
