"""The truncated E-step: eq. (17) on the pairs closer than 4σ only, found with a k-d tree (ours)."""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from amdo_lab.em_articulated.estep import check_e_step_inputs

__all__ = ["KDTREE_RADIUS_SIGMAS", "DENSE_PAIR_FRACTION", "e_step_statistics_kdtree", "statistics_from_pairs",
           "ClosePairs"]

#: Truncation radius of the k-d tree E-step, in σ.
KDTREE_RADIUS_SIGMAS = 4.0
#: register_em(e_step="kdtree") switches to the exact dense E-step when more than this share of all
#: pairs lies within the truncation radius: a pair costs several times more on the sparse path than in
#: the dense one's matrix products (crossover about 0.13-0.2 in `benchmarks/bench_01_em_articulated.py`).
DENSE_PAIR_FRACTION = 0.15


def e_step_statistics_kdtree(model_points: object, data_points: object, sigma: float,
                             log_c: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Truncated eq. (17): only pairs closer than 4σ (:data:`KDTREE_RADIUS_SIGMAS`), found with a k-d tree.

    Same outputs as :func:`e_step_statistics`. A pair at 4σ has kernel exp(-8) ≈ 3e-4, so the
    dropped mass is negligible next to c; memory is O(M + N + number of close pairs). The kernel
    of a kept pair is at least exp(-radius²/2), so the linear domain cannot underflow here.
    (:func:`register_em` gets the same pairs from a cache that re-measures candidates between
    iterations instead of querying anew.)

    Parameters
    ----------
    model_points : array_like, shape (N, 3)
        Moved texture points T(X_i, Θ), mm, within ±1e6.
    data_points : array_like, shape (M, 3)
        Data points Y_j, mm, within ±1e6.
    sigma : float
        σ of the Gaussian of eq. (6), mm, in (0, 1e6].
    log_c : float
        log of the outlier constant c of eq. (17), at most :data:`MAX_LOG_C` (exp of more
        overflows); -inf for no outlier class.

    Returns
    -------
    weights : numpy.ndarray, shape (N,)
        λ_i = Σ_j α_ij per model point.
    weighted_data : numpy.ndarray, shape (N, 3)
        Σ_j α_ij Y_j, mm.
    inlier_prob : numpy.ndarray, shape (M,)
        Σ_i α_ij per data point, in [0, 1).
    energy : float
        Σ_ij α_ij ||Y_j - T(X_i)||², mm² (eq. 19/20 up to the 1/2σ² factor).

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; eq. (17), truncated (ours).
    """
    model_points, data_points, sigma, log_c = check_e_step_inputs(model_points, data_points, sigma, log_c)
    radius = KDTREE_RADIUS_SIGMAS * sigma
    pairs = cKDTree(data_points).sparse_distance_matrix(cKDTree(model_points), radius, output_type="ndarray")
    return statistics_from_pairs(*_pair_arrays(pairs), data_points, len(model_points), sigma, log_c)


def _pair_arrays(pairs: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The fields of ``cKDTree.sparse_distance_matrix(..., output_type="ndarray")`` as contiguous arrays
    (the structured array's strided fields make every later gather several times slower)."""
    return tuple(np.ascontiguousarray(pairs[field]) for field in ("i", "j", "v"))


def statistics_from_pairs(data_index: np.ndarray, model_index: np.ndarray, dist: np.ndarray, data_points: np.ndarray,
                          n_model: int, sigma: float, log_c: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Eq. (17) on the listed (data, model) pairs only: the outputs of :func:`e_step_statistics`.

    The check-free kernel of :func:`e_step_statistics_kdtree`, called by the EM's loop with the
    pairs of :class:`ClosePairs` (not exported).

    Parameters
    ----------
    data_index, model_index : numpy.ndarray of int, shape (P,)
        The data and texture point of each pair.
    dist : numpy.ndarray, shape (P,)
        Their distances, mm.
    data_points : numpy.ndarray, shape (M, 3)
        The data, mm.
    n_model : int
        Number of texture points N.
    sigma, log_c : float
        σ in mm and log c.

    Returns
    -------
    tuple
        weights (N,), weighted_data (N, 3), inlier_prob (M,) and energy, as :func:`e_step_statistics`.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, ECCV 2006, eq. (17), truncated (ours).
    """
    kernel = np.exp(-dist**2 / (2 * sigma**2))
    row_sum = np.bincount(data_index, kernel, minlength=len(data_points)) + np.exp(log_c)
    alpha = kernel / np.take(row_sum, data_index)
    weights = np.bincount(model_index, alpha, minlength=n_model)
    weighted_data = np.stack([np.bincount(model_index, alpha * np.take(column, data_index), minlength=n_model)
                              for column in data_points.T], axis=1)
    inlier_prob = np.bincount(data_index, alpha, minlength=len(data_points))
    return weights, weighted_data, inlier_prob, float(np.dot(alpha, dist**2))


class ClosePairs:
    """The (data, model) pairs closer than a radius, for a model that moves a little per EM iteration.

    A k-d tree query returns every pair within radius + margin, with the model where it is now;
    later calls only re-measure those candidates, and query again when the radius changes or some
    model point has moved so far that a pair from outside the candidates could have come within
    the radius (more than the margin; half of it when the data are the model itself, whose
    unordered pairs are stored once and mirrored). The pairs returned are exactly those a fresh
    query would give: this saves time, not accuracy. A cache for :func:`register_em`'s k-d tree
    E-step, on checked input (not exported).

    Parameters
    ----------
    data_points : numpy.ndarray, shape (M, 3), or None
        The data Y_j, mm; None when the data are the model points themselves.
    margin_ratio : float, default 0.1
        Margin of the candidate query, as a share of the radius.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; eq. (17), truncated (ours).
    """

    def __init__(self, data_points: np.ndarray | None, margin_ratio: float = 0.1) -> None:
        self._data, self._margin_ratio = data_points, margin_ratio
        self._tree = None if data_points is None else cKDTree(data_points)
        self._radius = self._fraction_radius = -1.0
        self._anchor = self._data_index = self._model_index = None
        self._fraction = 0.0

    def pair_fraction(self, model_points: np.ndarray, radius: float, n_samples: int = 64) -> float:
        """Share of all (data, model) pairs closer than ``radius``, estimated from about ``n_samples``
        model points spread through the array; re-estimated only when the radius changes.

        Parameters
        ----------
        model_points : numpy.ndarray, shape (N, 3)
            Moved texture points, mm.
        radius : float
            Pair distance, mm.
        n_samples : int, default 64
            About how many model points the estimate queries.

        Returns
        -------
        float
            The share, in [0, 1].
        """
        if radius != self._fraction_radius:
            sample = model_points[::max(1, len(model_points) // n_samples)]
            tree, n_data = ((cKDTree(model_points), len(model_points)) if self._data is None
                            else (self._tree, len(self._data)))
            self._fraction = float(np.mean(tree.query_ball_point(sample, radius, return_length=True))) / n_data
            self._fraction_radius = radius
        return self._fraction

    def __call__(self, model_points: np.ndarray, radius: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        margin = self._margin_ratio * radius
        allowed = margin / 2 if self._data is None else margin  # a self pair closes in from both ends
        fresh = None
        if (radius != self._radius
                or np.max(np.sum((model_points - self._anchor) ** 2, axis=1)) > allowed**2):
            if self._data is None:  # each unordered pair i < j once
                unique = cKDTree(model_points).query_pairs(radius + margin, output_type="ndarray")
                self._data_index, self._model_index = unique[:, 0].copy(), unique[:, 1].copy()
            else:  # the query measures the distances already: no need to measure them again now
                self._data_index, self._model_index, fresh = _pair_arrays(
                    self._tree.sparse_distance_matrix(cKDTree(model_points), radius + margin, output_type="ndarray"))
            self._radius, self._anchor = radius, model_points.copy()
        data = model_points if self._data is None else self._data
        if fresh is None:
            offset = np.take(data, self._data_index, axis=0) - np.take(model_points, self._model_index, axis=0)
            fresh = np.sqrt(np.einsum("ij,ij->i", offset, offset))
        keep = fresh <= radius
        data_index, model_index, dist = self._data_index[keep], self._model_index[keep], fresh[keep]
        if self._data is None:  # both orders of every unordered pair, and every point with itself
            own = np.arange(len(model_points))
            return (np.concatenate([data_index, model_index, own]), np.concatenate([model_index, data_index, own]),
                    np.concatenate([dist, dist, np.zeros(len(own))]))
        return data_index, model_index, dist
