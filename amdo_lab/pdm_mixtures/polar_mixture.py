"""The shape layer (Sec. 4): mixtures of polar PDMs of S = (Theta, C), learnt per class by EM.

Eq. 12's clamped fit of a polar PDM to a shape is :meth:`PolarPDM.project`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common import as_finite_array, check_positive, check_positive_int, make_rng
from amdo_lab.pdm_mixtures.gmm import fit_gaussian_mixture
from amdo_lab.pdm_mixtures.pdm import (MAX_MAGNITUDE, PointDistributionModel, _fit_modes, _pdm_from_moments,
                                       _ppca_log_density, _reconstruct, fit_pdm)
from amdo_lab.pdm_mixtures.representation import wrap_angle

__all__ = ["PolarPDM", "polar_blocks", "fit_polar_mixture", "held_out_log_likelihood", "circular_mean",
           "angles_about_mean"]

N_LIMBS = 13
#: Training shapes needed per mixture component (a covariance needs a few more rows than one).
MIN_PER_CLASS = 3
#: EM iterations of every shape-layer fit (eqs. 2-8), as the recogniser's.
N_EM_ITER = 30
#: Largest number of mixture components of one class (each needs ``MIN_PER_CLASS`` training shapes).
MAX_COMPONENTS = 100


@dataclass(frozen=True)
class PolarPDM:
    """One polar point distribution model of S = (Theta, C): one PDM per block of S (Sec. 4).

    With ``polar_model="block"`` (our default) the K angle rows and the 2K centre rows of S each get
    their own PDM, so the angle eigenvalues alpha_k that clamp the angle parameters come from the
    covariance of the angles alone, as Sec. 4 describes; with ``"joint"`` one PDM spans all 3K rows.

    Parameters
    ----------
    blocks : tuple of slice
        The rows of S each PDM models (angles ``0:K`` and centres ``K:3K``, or all ``0:3K``).
    pdms : tuple of PointDistributionModel
        One PDM per block, in deviation coordinates (angles relative to the class's circular mean).

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 4 (the polar PDM of S) and Sec. 5, eq. 12 (its clamped fit).
    """

    blocks: tuple[slice, ...]
    pdms: tuple[PointDistributionModel, ...]

    @property
    def mean(self) -> np.ndarray:
        """The mean vector S (in deviation coordinates), ``(3K,)``."""
        return np.concatenate([pdm.mean for pdm in self.pdms])

    @property
    def n_modes(self) -> int:
        """Total number of kept eigenmodes over the blocks."""
        return sum(pdm.n_modes for pdm in self.pdms)

    def project(self, deviation: np.ndarray) -> np.ndarray:
        """Project polar vectors onto the model: the clamped modal fit of every block (eq. 12), reconstructed.

        Parameters
        ----------
        deviation : (n, 3K) array_like
            Polar vectors S with angles relative to the class's circular mean (radians, wrapped).

        Returns
        -------
        numpy.ndarray
            ``(n, 3K)``: each block's model instance ``Y + Phi gamma`` with ``gamma`` clamped to
            ``+-3 sqrt(alpha_k)``.
        """
        return self._project(self._check_deviation(deviation))

    def log_density(self, deviation: np.ndarray) -> np.ndarray:
        """``ln p(S | Phi, Gamma*)``: the sum over blocks of each PDM's Gaussian (PPCA) density.

        Parameters
        ----------
        deviation : (n, 3K) array_like
            Polar vectors S with angles relative to the class's circular mean (radians, wrapped).

        Returns
        -------
        numpy.ndarray
            ``(n,)`` log-densities in nats.
        """
        return self._log_density(self._check_deviation(deviation))

    def _check_deviation(self, deviation: object) -> np.ndarray:
        width = max(block.stop for block in self.blocks)
        return as_finite_array(deviation, "deviation", shape=(None, width), max_abs=MAX_MAGNITUDE)

    def _project(self, deviation: np.ndarray) -> np.ndarray:
        # eq. (12): Gamma* = argmax_{|Gamma_k| <= 3 sqrt(alpha_k)} p(S | Phi, Gamma), for a Gaussian the
        # clamped least-squares coefficients of every block; the model instance is Y + Phi Gamma*
        return np.concatenate([_reconstruct(pdm, _fit_modes(pdm, deviation[:, block]))
                               for pdm, block in zip(self.pdms, self.blocks)], axis=1)

    def _log_density(self, deviation: np.ndarray) -> np.ndarray:
        total = np.zeros(deviation.shape[0])
        for pdm, block in zip(self.pdms, self.blocks):
            data = deviation[:, block]
            total += _ppca_log_density(pdm, data)
        return total


def circular_mean(angles: np.ndarray) -> np.ndarray:
    """Circular mean of angles over the rows: ``atan2(mean sin, mean cos)`` (a kernel: not checked).

    Parameters
    ----------
    angles : (T, K) numpy.ndarray
        Angles in radians.

    Returns
    -------
    numpy.ndarray
        ``(K,)`` mean angles, in (-pi, pi].

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 3 (limb angles in (-180, 180] degrees).
    """
    return np.arctan2(np.sin(angles).mean(axis=0), np.cos(angles).mean(axis=0))


def angles_about_mean(vectors: np.ndarray, angle_mean: np.ndarray) -> np.ndarray:
    """Polar vectors S with the K angles taken relative to a class's circular mean (wrapped).

    The polar PDMs model these deviations, so an angle near the +-180 degree cut never flips across it.
    A kernel for checked input (the recogniser's): nothing is validated here.

    Parameters
    ----------
    vectors : (n, 3K) numpy.ndarray
        Polar vectors S (angles in radians first).
    angle_mean : (K,) numpy.ndarray
        The class's circular mean angles.

    Returns
    -------
    numpy.ndarray
        ``(n, 3K)``: a copy with the angles replaced by their wrapped deviations.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 3 (the vector S) and Sec. 4 (its PDM).
    """
    out = vectors.copy()
    out[:, :N_LIMBS] = wrap_angle(vectors[:, :N_LIMBS] - angle_mean)
    return out


def polar_blocks(polar_model: str) -> tuple[slice, ...]:
    """The column blocks of the polar vector S that get one PDM each (not exported).

    Parameters
    ----------
    polar_model : {"block", "joint"}
        "block": the 13 angles and the 26 centre coordinates apart; "joint": all 39 together.

    Returns
    -------
    tuple of slice
        The blocks, in column order.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 3 (the vector S).
    """
    if polar_model == "block":
        return (slice(0, N_LIMBS), slice(N_LIMBS, 3 * N_LIMBS))
    return (slice(0, 3 * N_LIMBS),)


def _kmeans_partition(data: np.ndarray, n_clusters: int, rng: np.random.Generator, n_iter: int = 10) -> np.ndarray:
    """Seeded k-means++ start followed by Lloyd iterations; returns a cluster index per row."""
    centres = [data[rng.integers(len(data))]]
    for _ in range(1, n_clusters):
        distance = np.min(np.sum((data[:, None] - np.array(centres)[None]) ** 2, axis=2), axis=1)
        centres.append(data[rng.choice(len(data), p=distance / distance.sum())])
    centres = np.array(centres)
    for _ in range(n_iter):
        assign = np.argmin(np.sum((data[:, None] - centres[None]) ** 2, axis=2), axis=1)
        centres = np.array([data[assign == k].mean(axis=0) if np.any(assign == k) else centres[k]
                            for k in range(n_clusters)])
    return assign


def fit_polar_mixture(data: np.ndarray, n_components: int, blocks: tuple[slice, ...], rng: np.random.Generator,
                       n_iter: int, variance_fraction: float, *, ridge: float = 1e-3,
                       n_restarts: int = 1) -> tuple[list[PolarPDM], np.ndarray, np.ndarray]:
    """Mixture of polar PDMs on ``data (T, 3K)`` by EM (eqs. 2-8); returns the components, the
    mixing weights and the training responsibilities ``(T, M)``.

    One component is the PDM of every block (eq. 1, no ridge). For several, EM runs on S with each
    block divided by the square root of its total variance (so radians and shape units weigh the
    same in the k-means++ start and in the ridge; a full-covariance EM is otherwise unaffected by
    the scaling): k-means++ means, the pooled covariance as every starting covariance, a ridge of
    ``ridge`` times the mean variance (T < 3K makes component covariances singular). With
    ``n_restarts`` > 1, EM runs from that many k-means++ starts drawn in turn from ``rng`` and the
    run with the highest final log-likelihood (eq. 3) is kept. Each component's mean and covariance
    blocks, scaled back, become one PDM per block (at most ``round(T pi_m) - 1`` modes). The
    recogniser's shape layer on its checked input (not exported).

    Parameters
    ----------
    data : (T, 3K) numpy.ndarray
        Polar vectors, angles relative to the class's circular mean.
    n_components : int
        Number of mixture components M.
    blocks : tuple of slice
        Column blocks, from :func:`polar_blocks`.
    rng : numpy.random.Generator
        Source of the k-means++ starts.
    n_iter : int
        EM iterations per run.
    variance_fraction : float
        Fraction of the variance each PDM keeps, in (0, 1].
    ridge : float, default 1e-3
        Ridge on the covariances, relative to the mean variance.
    n_restarts : int, default 1
        EM runs from independent starts; the most likely is kept.

    Returns
    -------
    models : list of PolarPDM
        The components.
    weights : numpy.ndarray
        ``(M,)`` mixing weights.
    responsibilities : numpy.ndarray
        ``(T, M)`` posteriors of the training vectors.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, eqs. 1-8 (the PDM and its Gaussian mixture, applied to S).
    """
    if n_components == 1:
        pdms = tuple(fit_pdm(data[:, block], variance_fraction=variance_fraction) for block in blocks)
        return [PolarPDM(blocks, pdms)], np.ones(1), np.ones((len(data), 1))
    scale = np.empty(data.shape[1])
    for block in blocks:
        scale[block] = 1.0 / np.sqrt(data[:, block].var(axis=0).sum())
    scaled = data * scale
    spread = np.cov(scaled.T, bias=True)
    reg = ridge * float(np.trace(spread)) / data.shape[1]
    mixture = None
    for _ in range(n_restarts):
        assign = _kmeans_partition(scaled, n_components, rng)
        means_init = np.stack([scaled[assign == k].mean(axis=0) if np.any(assign == k) else scaled[k]
                               for k in range(n_components)])
        candidate = fit_gaussian_mixture(scaled, n_components, means_init=means_init,
                                         covariances_init=np.repeat(spread[None] + reg * np.eye(data.shape[1]),
                                                                    n_components, axis=0),
                                         n_iter=n_iter, reg_covar=reg)
        if mixture is None or candidate.log_likelihood[-1] > mixture.log_likelihood[-1]:
            mixture = candidate
    models = []
    for mean, cov, weight in zip(mixture.means / scale, mixture.covariances / np.outer(scale, scale), mixture.weights):
        cap = max(1, int(round(weight * len(data))) - 1)
        models.append(PolarPDM(blocks, tuple(
            _pdm_from_moments(mean[block], cov[block, block], variance_fraction, cap)
            for block in blocks)))
    return models, np.clip(mixture.weights, 1e-12, None), mixture.responsibilities


def held_out_log_likelihood(
    polar_vectors: np.ndarray,
    n_components: int,
    *,
    shape_ridge: float = 1e-3,
    n_folds: int = 5,
    rng: int | np.random.Generator,
) -> float:
    """Mean held-out log-density of one class's polar vectors under a mixture of polar PDMs.

    A generative criterion for the choices Sec. 4 leaves open (number of components, covariance
    ridge), computed from the training set alone: the rows are split into ``n_folds`` seeded folds;
    for each fold the mixture is learnt by EM (eqs. 2-8, as in the recogniser) on the other folds
    and the held-out rows are scored with ``ln sum_m pi_m p(S | Phi_m, Gamma_m*)``, the same
    clamped PPCA density the recogniser uses, with the recogniser's defaults (block polar PDMs, 95 %
    of the variance, 30 EM iterations).

    Parameters
    ----------
    polar_vectors : (T, 3K) array_like
        Polar vectors S of one class, angles relative to the class's circular mean (wrapped).
    n_components : int
        Mixture components M, at most ``MAX_COMPONENTS``.
    shape_ridge : float
        Positive EM ridge, as ``RecogniserSettings(shape_ridge=...)``.
    n_folds : int
        Number of folds, from 2 to T; every training split needs ``3 * n_components`` rows.
    rng : int or numpy.random.Generator
        Seed or generator of the fold split and of the k-means++ starts (keyword-only, no default).

    Returns
    -------
    float
        Held-out log-density summed over the folds, divided by T (nats per shape).

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 4, eqs. 2-8 (the mixture it scores); the criterion is ours.
    """
    vectors = as_finite_array(polar_vectors, "polar_vectors", shape=(None, 3 * N_LIMBS), max_abs=MAX_MAGNITUDE)
    n_components = check_positive_int(n_components, "n_components", maximum=MAX_COMPONENTS)
    shape_ridge = check_positive(shape_ridge, "shape_ridge")
    t = len(vectors)
    n_folds = check_positive_int(n_folds, "n_folds", minimum=2, maximum=t)
    smallest_split = t - -(-t // n_folds)
    if smallest_split < MIN_PER_CLASS * n_components:
        raise ValueError(f"polar_vectors: {smallest_split} rows outside a fold, too few for n_components={n_components}")
    rng = make_rng(rng, "rng")
    folds = np.empty(t, dtype=int)
    folds[rng.permutation(t)] = np.arange(t) % n_folds
    total = 0.0
    for fold in range(n_folds):
        held = folds == fold
        models, weights, _ = fit_polar_mixture(vectors[~held], n_components, polar_blocks("block"), rng, N_EM_ITER, 0.95,
                                                ridge=shape_ridge)
        scores = np.stack([np.log(w) + model._log_density(vectors[held]) for model, w in zip(models, weights)], axis=1)
        total += float(np.logaddexp.reduce(scores, axis=1).sum())
    return total / t

