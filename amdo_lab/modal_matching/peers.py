"""Peers of modal matching on the same pairs: raw coordinates, and coherent point drift (pycpd).

Both end with the same global search as modal matching (scipy's ``linear_sum_assignment``), so the
comparison is about the features in the cost matrix, not about the search.
"""

from __future__ import annotations

import time

import numpy as np

from amdo_lab.common import check_choice
from amdo_lab.modal_matching.element import _check_node_pair
from amdo_lab.modal_matching.matching import MatchResult, _excess, _global_search

__all__ = ["CPD_KINDS", "match_coordinates", "match_cpd"]

#: pycpd's registrations.
CPD_KINDS = ("rigid", "deformable")


def _squared_distances(X1: np.ndarray, X2: np.ndarray) -> np.ndarray:
    return np.sum((X1[:, None, :] - X2[None, :, :]) ** 2, axis=-1)


def match_coordinates(X1: np.ndarray, X2: np.ndarray) -> MatchResult:
    """Match two objects by the global search on squared distances between their raw coordinates.

    Parameters
    ----------
    X1, X2 : ndarray, shapes (m1, D) and (m2, D)
        The two objects' nodes (mm), in contour order, D = 2 or 3, at least D + 2 distinct nodes.

    Returns
    -------
    MatchResult
        One-to-one pairs, ADCom's pairs for the excess nodes, the cost matrix and the wall time.

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 4 (the same search as the modal method, on coordinates).

    Examples
    --------
    >>> import numpy as np
    >>> square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    >>> match_coordinates(square, square + 0.1).pairs.tolist()
    [[0, 0], [1, 1], [2, 2], [3, 3]]
    """
    X1, X2 = _check_node_pair(X1, X2)
    start = time.perf_counter()
    Z = _squared_distances(X1, X2)
    pairs = _global_search(Z)
    return MatchResult(pairs, _excess(Z, pairs, X1, X2), Z, time.perf_counter() - start)


def match_cpd(X1: np.ndarray, X2: np.ndarray, *, kind: str = "deformable") -> MatchResult:
    """Register object 2 onto object 1 with coherent point drift (pycpd), then the global search.

    Parameters
    ----------
    X1, X2 : ndarray, shapes (m1, D) and (m2, D)
        The two objects' nodes (mm), in contour order, D = 2 or 3, at least D + 2 distinct nodes.
    kind : {"rigid", "deformable"}
        pycpd's ``RigidRegistration`` (rotation, translation, scale) or ``DeformableRegistration``
        (its defaults, alpha = beta = 2, on coordinates scaled to unit spread).

    Returns
    -------
    MatchResult
        One-to-one pairs, ADCom's pairs, the cost matrix (squared distances after registration) and
        the wall time.

    References
    ----------
    Myronenko & Song, Point Set Registration: Coherent Point Drift, IEEE PAMI 32, 2010; compared with
    Bastos & Tavares, AMDO 2004.
    """
    from pycpd import DeformableRegistration, RigidRegistration

    X1, X2 = _check_node_pair(X1, X2)
    kind = check_choice(kind, "kind", CPD_KINDS)
    start = time.perf_counter()
    centre, scale = X1.mean(axis=0), np.sqrt(np.mean(np.sum((X1 - X1.mean(axis=0)) ** 2, axis=1)))
    fixed, moving = (X1 - centre) / scale, (X2 - centre) / scale
    registration = (RigidRegistration if kind == "rigid" else DeformableRegistration)(X=fixed, Y=moving)
    moved, _ = registration.register()
    Z = _squared_distances(fixed, moved)
    pairs = _global_search(Z)
    return MatchResult(pairs, _excess(Z, pairs, X1, X2), Z, time.perf_counter() - start)
