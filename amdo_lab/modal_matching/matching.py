"""Modal matching: the affinity matrix of eq. (3), the local and global searches, and ADCom.

Two objects are compared node by node in their modal coordinates: node i of object 1 and node j
of object 2 are alike when their rows of the shape matrices are close. The local search keeps the
pairs that are each other's best; the global search solves the assignment problem on the whole
matrix (scipy's ``linear_sum_assignment``), with zero-cost fictitious nodes when the counts differ;
ADCom then gives every excess node the partner of a matched neighbour.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

import numpy as np
from scipy import stats
from scipy.optimize import linear_sum_assignment
from scipy.spatial import Delaunay

from amdo_lab.common import (as_finite_array, check_bool, check_choice, check_in_range, check_instance,
                             check_positive_int)
from amdo_lab.modal_matching.axial import _axial_element
from amdo_lab.modal_matching.element import (MAX_COORDINATE_MM, RIGID_MODES, GaussianElement, _check_condition,
                                             _check_node_pair, _gaussian_element, _interpolate_field, _mean_spacing,
                                             check_same_dimension)
from amdo_lab.modal_matching.modes import ModalBasis, _modal_analysis

__all__ = ["ALIGNMENTS", "CONTOUR_BAR_REACH", "ELEMENTS", "MatchResult", "SEARCHES", "adcom", "affinity_matrix",
           "global_search", "local_search",
           "match_objects", "mode_features", "procrustes_alignment"]

#: How object 2's modes are put in object 1's frame before eq. (3): not at all, by a sign per mode,
#: or by the orthogonal map that best matches object 1's modes interpolated at object 2's nodes.
ALIGNMENTS = ("none", "sign", "procrustes")
#: The paper's two searches.
SEARCHES = ("local", "global")
#: The paper's two models of an object: one Gaussian (Sclaroff) element, or linear axial bars between neighbours.
ELEMENTS = ("gaussian", "axial")
#: Axial bars of a contour tie node i to nodes i +- 1 ... i +- CONTOUR_BAR_REACH along it.
CONTOUR_BAR_REACH = 3
#: Largest magnitude of an affinity entry: sums of a million of them stay finite.
MAX_AFFINITY = 1e300


@dataclass(frozen=True)
class MatchResult:
    """The matches between two objects.

    Parameters
    ----------
    pairs : ndarray of int, shape (k, 2)
        One-to-one pairs (i in object 1, j in object 2) from the search.
    excess_pairs : ndarray of int, shape (e, 2)
        Pairs that ADCom added for the nodes the search left unmatched (empty when not asked).
    Z : ndarray, shape (m1, m2)
        The affinity matrix of eq. (3).
    seconds : float
        Wall time of the whole match (modes, affinity, search).

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 4.
    """

    pairs: np.ndarray
    excess_pairs: np.ndarray
    Z: np.ndarray
    seconds: float

    @property
    def all_pairs(self) -> np.ndarray:
        """The search's pairs followed by ADCom's."""
        return np.concatenate([self.pairs, self.excess_pairs], axis=0)


def mode_features(modes1: ModalBasis, modes2: ModalBasis, *, n_modes: int = 16,
                  align: str = "procrustes") -> tuple[np.ndarray, np.ndarray]:
    """Each node's modal coordinates in the first ``n_modes`` modes, object 2 aligned to object 1.

    Each mode is scaled to a root-mean-square entry of 1 over the degrees of freedom, so objects
    with different node counts compare on one scale.

    Parameters
    ----------
    modes1, modes2 : ModalBasis
        The two objects' modes (same D).
    n_modes : int
        Modes kept, from 1 to D min(m1, m2); the near-rigid ones are kept.
    align : {"none", "sign", "procrustes"}
        ``"sign"``: flip each mode of object 2 whose entries' distribution is closer (Wasserstein-1)
        to that of object 1's mode negated; ``"procrustes"``: rotate object 2's kept modes by the
        orthogonal matrix that best matches object 1's modes interpolated at object 2's nodes
        (the objects must overlap in space).

    Returns
    -------
    features1 : ndarray, shape (m1, D, n_modes)
    features2 : ndarray, shape (m2, D, n_modes)

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 4 (signs and degenerate modes are not discussed there).
    """
    _check_pair(modes1, modes2)
    n = check_positive_int(n_modes, "n_modes", maximum=modes1.model.dimension * min(len(modes1.model.nodes),
                                                                                   len(modes2.model.nodes)))
    align = check_choice(align, "align", ALIGNMENTS)
    return _mode_features(modes1, modes2, n, align)


def _check_pair(modes1: object, modes2: object) -> None:
    check_instance(modes1, "modes1", ModalBasis)
    check_instance(modes2, "modes2", ModalBasis)
    check_same_dimension(modes1.model.nodes, modes2.model.nodes, "modes1 and modes2")


def _unit_rms(shapes: np.ndarray) -> np.ndarray:
    return shapes / np.sqrt(np.mean(shapes**2, axis=0))


def _sign_alignment(Phi1: np.ndarray, Phi2: np.ndarray) -> np.ndarray:
    """+1 or -1 per mode: the sign that brings object 2's value distribution closer to object 1's."""
    signs = np.ones(Phi2.shape[1])
    for k in range(Phi2.shape[1]):
        plus = stats.wasserstein_distance(Phi1[:, k], Phi2[:, k])
        minus = stats.wasserstein_distance(Phi1[:, k], -Phi2[:, k])
        signs[k] = -1.0 if minus < plus else 1.0
    return signs


def _procrustes_alignment(modes1: ModalBasis, Phi1: np.ndarray, modes2: ModalBasis, Phi2: np.ndarray) -> np.ndarray:
    """The orthogonal R minimising |Phi2 R - P|, P = object 1's modes interpolated at object 2's nodes."""
    P = _interpolate_field(modes1.model, Phi1, modes2.model.nodes)
    U, _, Vt = np.linalg.svd(Phi2.T @ P)
    return U @ Vt


def procrustes_alignment(modes1: ModalBasis, modes2: ModalBasis, *, n_modes: int = 16) -> np.ndarray:
    """The orthogonal matrix that puts object 2's first ``n_modes`` modes in object 1's frame (``align="procrustes"``).

    Each mode is scaled to a root-mean-square entry of 1 (as in :func:`mode_features`). Object 1's kept
    modes, read as displacement fields u(x) = sum_i h_i(x) U_i of its element, are evaluated at object 2's
    nodes, giving P; R minimises |Phi2 R - P| over orthogonal matrices: R = U V^T from the SVD
    Phi2^T P = U S V^T. It undoes flipped signs and modes of close frequency rotated into each other, and
    needs the two objects to overlap in space.

    Parameters
    ----------
    modes1, modes2 : ModalBasis
        The two objects' modes (same D); object 1's must come from a Gaussian element.
    n_modes : int
        Modes kept, from 1 to D min(m1, m2).

    Returns
    -------
    ndarray, shape (n_modes, n_modes)
        R, orthogonal: object 2's aligned modes are ``Phi2 @ R``.

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 4 (the paper does not align modes); Schönemann, Psychometrika 31,
    1966 (the orthogonal Procrustes problem).

    Examples
    --------
    >>> import numpy as np
    >>> from amdo_lab.modal_matching import gaussian_element, modal_analysis
    >>> angle = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    >>> basis = modal_analysis(gaussian_element(np.c_[np.cos(angle), np.sin(angle)], sigma=0.8))
    >>> R = procrustes_alignment(basis, basis, n_modes=6)
    >>> bool(np.allclose(R @ R.T, np.eye(6)))
    True
    """
    _check_pair(modes1, modes2)
    check_instance(modes1.model, "modes1.model", GaussianElement)
    n = check_positive_int(n_modes, "n_modes", maximum=modes1.model.dimension * min(len(modes1.model.nodes),
                                                                                   len(modes2.model.nodes)))
    Phi1, Phi2 = _unit_rms(modes1.shapes[:, :n]), _unit_rms(modes2.shapes[:, :n])
    return _procrustes_alignment(modes1, Phi1, modes2, Phi2)


def _mode_features(modes1: ModalBasis, modes2: ModalBasis, n: int, align: str) -> tuple[np.ndarray, np.ndarray]:
    Phi1, Phi2 = _unit_rms(modes1.shapes[:, :n]), _unit_rms(modes2.shapes[:, :n])
    if align == "sign":
        Phi2 = Phi2 * _sign_alignment(Phi1, Phi2)
    elif align == "procrustes":
        Phi2 = Phi2 @ _procrustes_alignment(modes1, Phi1, modes2, Phi2)
    D = modes1.model.dimension
    return (Phi1.reshape(D, -1, n).transpose(1, 0, 2), Phi2.reshape(D, -1, n).transpose(1, 0, 2))


def affinity_matrix(modes1: ModalBasis, modes2: ModalBasis, *, n_modes: int = 16,
                    align: str = "procrustes") -> np.ndarray:
    """The affinity matrix Z of eqs. (3)-(4): squared distances between the nodes' modal coordinates.

    Parameters
    ----------
    modes1, modes2 : ModalBasis
        The two objects' modes (same D).
    n_modes : int
        Modes kept, from 1 to D min(m1, m2) (rigid ones included).
    align : {"none", "sign", "procrustes"}
        How object 2's modes are aligned with object 1's (see :func:`mode_features`).

    Returns
    -------
    ndarray, shape (m1, m2)
        Z_ij = |u_1,i - u_2,j|^2 + |v_1,i - v_2,j|^2 (+ |w_1,i - w_2,j|^2 in 3-D).

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 4, eqs. (3) (2-D) and (4) (3-D).

    Examples
    --------
    >>> import numpy as np
    >>> from amdo_lab.modal_matching import gaussian_element, modal_analysis
    >>> angle = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    >>> basis = modal_analysis(gaussian_element(np.c_[np.cos(angle), np.sin(angle)], sigma=0.8))
    >>> affinity_matrix(basis, basis, n_modes=6).shape
    (8, 8)
    """
    features1, features2 = mode_features(modes1, modes2, n_modes=n_modes, align=align)
    return _affinity(features1, features2)


def _affinity(features1: np.ndarray, features2: np.ndarray) -> np.ndarray:
    # eqs. (3)-(4): Z_ij = sum over axes (u, v[, w]) of |row of node i - row of node j|^2
    Z = np.zeros((features1.shape[0], features2.shape[0]))
    for a in range(features1.shape[1]):
        u1, u2 = features1[:, a, :], features2[:, a, :]
        Z += np.sum((u1[:, None, :] - u2[None, :, :]) ** 2, axis=-1)
    return Z


def local_search(Z: np.ndarray) -> np.ndarray:
    """The local search: keep (i, j) when Z_ij is the lowest of its row and of its column.

    Parameters
    ----------
    Z : ndarray, shape (m1, m2)
        An affinity (cost) matrix.

    Returns
    -------
    ndarray of int, shape (k, 2)
        The mutual-best pairs, by row.

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 4 (the search of their refs. [1], [2], [13]).
    """
    return _local_search(as_finite_array(Z, "Z", ndim=2, max_abs=MAX_AFFINITY))


def _local_search(Z: np.ndarray) -> np.ndarray:
    best_in_row, best_in_column = np.argmin(Z, axis=1), np.argmin(Z, axis=0)
    rows = np.flatnonzero(best_in_column[best_in_row] == np.arange(Z.shape[0]))
    return np.stack([rows, best_in_row[rows]], axis=1).astype(int)


def global_search(Z: np.ndarray, *, pad: bool = False) -> np.ndarray:
    """The global search: the one-to-one assignment of least total cost (Hungarian-type solver).

    Parameters
    ----------
    Z : ndarray, shape (m1, m2)
        An affinity (cost) matrix.
    pad : bool
        Add zero-cost fictitious nodes to the smaller object so the matrix is square, as the paper
        does; the pairs and the cost are the same as the rectangular solution's.

    Returns
    -------
    ndarray of int, shape (min(m1, m2), 2)
        The pairs between real nodes, by row.

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 4 (the assignment problem, refs. [18]-[22]).
    """
    return _global_search(as_finite_array(Z, "Z", ndim=2, max_abs=MAX_AFFINITY), check_bool(pad, "pad"))


def _global_search(Z: np.ndarray, pad: bool = False) -> np.ndarray:
    m1, m2 = Z.shape
    if pad:  # fictitious nodes: zero-cost rows or columns that make the problem square
        size = max(m1, m2)
        square = np.zeros((size, size))
        square[:m1, :m2] = Z
        rows, columns = linear_sum_assignment(square)
        real = (rows < m1) & (columns < m2)
        rows, columns = rows[real], columns[real]
    else:
        rows, columns = linear_sum_assignment(Z)
    return np.stack([rows, columns], axis=1).astype(int)


def adcom(Z: np.ndarray, pairs: np.ndarray, *, X1: np.ndarray | None = None,
          X2: np.ndarray | None = None) -> np.ndarray:
    """ADCom: give each node the one-to-one search left unmatched the partner of a matched neighbour.

    For an unmatched node, two matched nodes of its own object are its neighbours: without node
    positions, the nearest matched node on each side along a closed contour (nodes in contour order);
    with them (surfaces), the two matched nodes nearest in space, its mesh neighbours on a sampled grid.
    Of the two neighbours' partners, the one with the lower Z to the unmatched node is taken. The
    unmatched nodes may belong to either object.

    Parameters
    ----------
    Z : ndarray, shape (m1, m2)
        The affinity matrix.
    pairs : ndarray of int, shape (k, 2)
        One-to-one pairs (i, j), e.g. from :func:`global_search`.
    X1, X2 : ndarray, shapes (m1, D) and (m2, D), optional
        The two objects' nodes (mm), both or neither: neighbours by distance instead of contour order.

    Returns
    -------
    ndarray of int, shape (e, 2)
        The added pairs (i, j), one per unmatched node of either object.

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 4 (one sentence: "a neighbourhood criterion"; our reading).
    """
    Z = as_finite_array(Z, "Z", ndim=2, max_abs=MAX_AFFINITY)
    pairs = _check_index_pairs(pairs, Z.shape, f"Z's shape {Z.shape}")
    if (X1 is None) != (X2 is None):
        raise ValueError("X1 and X2 must be given together (neighbours in space) or not at all (contour order)")
    if X1 is None:
        return _adcom(Z, pairs, None)
    X1 = as_finite_array(X1, "X1 (one row per row of Z)", shape=(Z.shape[0], None), max_abs=MAX_COORDINATE_MM)
    X2 = as_finite_array(X2, "X2 (one row per column of Z)", shape=(Z.shape[1], None), max_abs=MAX_COORDINATE_MM)
    return _adcom(Z, pairs, (X1, X2))


def _check_index_pairs(pairs: object, sizes: tuple[int, int], what: str) -> np.ndarray:
    """Rows (i, j) of node indices, i below sizes[0] and j below sizes[1]; ``what`` names the two sizes."""
    pairs = as_finite_array(pairs, "pairs", ndim=2, shape=(None, 2), dtype=int, bounds=(0, max(sizes) - 1))
    if np.any(pairs >= np.array(sizes)):
        raise ValueError(f"pairs name a node outside {what}")
    return pairs


def _two_neighbours(node: int, matched: np.ndarray, m: int, X: np.ndarray | None) -> np.ndarray:
    """The two matched nodes next to ``node``: along the closed contour of m nodes, or nearest in space (X)."""
    if X is None:
        return np.array([matched[np.argmin((matched - node) % m)], matched[np.argmin((node - matched) % m)]])
    return matched[np.argsort(np.sum((X[matched] - X[node]) ** 2, axis=1), kind="stable")[:2]]


def _adcom(Z: np.ndarray, pairs: np.ndarray, nodes: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
    added = []
    for side, cost in ((0, Z), (1, Z.T)):
        partner = np.full(cost.shape[0], -1)
        partner[pairs[:, side]] = pairs[:, 1 - side]
        matched = np.flatnonzero(partner >= 0)
        if matched.size == 0:
            continue
        for node in np.flatnonzero(partner < 0):
            near = _two_neighbours(node, matched, cost.shape[0], None if nodes is None else nodes[side])
            best = min(partner[near], key=lambda j: (cost[node, j], j))
            added.append((node, best) if side == 0 else (best, node))
    return np.array(added, dtype=int).reshape(-1, 2)


def _excess(Z: np.ndarray, pairs: np.ndarray, X1: np.ndarray, X2: np.ndarray) -> np.ndarray:
    """ADCom for two checked objects: contour order in 2-D, neighbours in space on 3-D surfaces."""
    return _adcom(Z, pairs, None if X1.shape[1] == 2 else (X1, X2))


def _object_bars(X: np.ndarray) -> np.ndarray:
    """The axial bars of an object (Sec. 3.1-3.2, Fig. 5: each node tied to its neighbours): along a contour
    (2-D, contour order) node i to nodes i +- 1 ... i +- CONTOUR_BAR_REACH; on a surface (3-D) the edges of
    the Delaunay triangulation of the plate positions (x, y)."""
    m = len(X)
    if X.shape[1] == 2:
        return np.array([(i, (i + step) % m) for step in range(1, CONTOUR_BAR_REACH + 1) for i in range(m)])
    triangles = Delaunay(X[:, :2]).simplices
    edges = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    return np.unique(edges, axis=0)


def match_objects(X1: np.ndarray, X2: np.ndarray, *, sigma: float | None = None, n_modes: int = 16,
                  align: str = "procrustes", search: str = "global", excess: bool = True, element: str = "gaussian",
                  rigid: str = "element") -> MatchResult:
    """Match the nodes of two objects in modal space: an element, its modes, eq. (3) or (4), a search, ADCom.

    Parameters
    ----------
    X1, X2 : ndarray, shapes (m1, D) and (m2, D)
        The two objects' nodes (mm), D = 2 (contours, in contour order) or 3 (surfaces, the pressure as
        third coordinate), at least D + 2 distinct nodes each.
    sigma : float, optional
        Width of the Gaussians (mm) for both objects, in (0, 1e100]; default: object 1's mean node
        spacing h. Gaussian element only (the bars interpolate with each object's own h).
    n_modes : int
        Modes compared, from 1 to D min(m1, m2).
    align : {"none", "sign", "procrustes"}
        How object 2's modes are aligned with object 1's (see :func:`mode_features`).
    search : {"local", "global"}
        Mutual best matches, or the assignment of least total cost.
    excess : bool
        Match the nodes left over by the search with ADCom (global search only); its neighbours are
        taken along the contour in 2-D and in space on 3-D surfaces (see :func:`adcom`).
    element : {"gaussian", "axial"}
        One Gaussian (Sclaroff) element per object, or linear axial bars (lumped mass) tying each node
        to its neighbours: :data:`CONTOUR_BAR_REACH` on either side along a contour, the Delaunay
        triangulation of (x, y) on a surface (a sheet of bars: its out-of-plane mechanisms cost no energy,
        so its lowest modes are an arbitrary basis of them).
    rigid : {"element", "exact"}
        The element's own first D(D+1)/2 modes, or the exact rigid motions in their place
        (see :func:`~amdo_lab.modal_matching.gaussian_element`).

    Returns
    -------
    MatchResult
        The pairs, ADCom's pairs, Z and the wall time.

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 3-4 and Fig. 8.

    Examples
    --------
    >>> import numpy as np
    >>> angle = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    >>> X1 = np.c_[3 * np.cos(angle), 2 * np.sin(angle)]
    >>> match_objects(X1, X1[:11], n_modes=6).pairs.shape
    (11, 2)
    """
    X1, X2 = _check_node_pair(X1, X2)
    if sigma is not None:
        sigma = check_in_range(sigma, "sigma", 0.0, MAX_COORDINATE_MM, closed="right")
    n_modes = check_positive_int(n_modes, "n_modes", maximum=X1.shape[1] * min(len(X1), len(X2)))
    align = check_choice(align, "align", ALIGNMENTS)
    search = check_choice(search, "search", SEARCHES)
    excess = check_bool(excess, "excess")
    element = check_choice(element, "element", ELEMENTS)
    rigid = check_choice(rigid, "rigid", RIGID_MODES)
    sigma = _mean_spacing(X1) if sigma is None else sigma
    bars = element == "axial"
    for X in (X1, X2):   # G of width sigma (Gaussian) or of each object's own h (bars) must be invertible
        _check_condition(X, _mean_spacing(X) if bars else sigma, sigma_is_spacing=bars)
    return _match_objects(X1, X2, sigma, n_modes, align, search, excess, element, rigid)


def _object_model(X: np.ndarray, element: str, sigma: float, rigid: str) -> GaussianElement:
    """The paper's model of one checked object: a Gaussian element of width sigma, or axial bars."""
    if element == "axial":
        return replace(_axial_element(X, _object_bars(X), 1.0, 1.0), rigid=rigid)
    return _gaussian_element(X, sigma, 1.0, 0.3, 1.0, rigid)


def _match_objects(X1: np.ndarray, X2: np.ndarray, sigma: float, n_modes: int, align: str, search: str,
                   excess: bool, element: str = "gaussian", rigid: str = "element") -> MatchResult:
    start = time.perf_counter()
    modes1, modes2 = (_modal_analysis(_object_model(X, element, sigma, rigid)) for X in (X1, X2))
    Z = _affinity(*_mode_features(modes1, modes2, n_modes, align))
    pairs = _global_search(Z) if search == "global" else _local_search(Z)
    extra = _excess(Z, pairs, X1, X2) if excess and search == "global" else np.zeros((0, 2), dtype=int)
    return MatchResult(pairs, extra, Z, time.perf_counter() - start)
