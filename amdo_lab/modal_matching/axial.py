"""Linear axial bars: the paper's second way to model a contour or surface, beside the Gaussian element.

Each edge (i, j) of the object is a pin-jointed bar of unit cross-section that resists only a change
of its length: its stiffness is E / L along its own direction, nothing across it. The mass is lumped:
each bar puts half its mass rho L on each end node, on every axis, so M is diagonal. To carry modes to
other points (the Procrustes alignment), the model keeps the Gaussian interpolation of its nodal
values with sigma = the node spacing h; it plays no part in M or K.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common import as_finite_array, check_in_range
from amdo_lab.modal_matching.element import (MAX_MATERIAL, GaussianElement, _check_condition, _gaussians,
                                             _mean_spacing, check_nodes)

__all__ = ["AxialElement", "axial_element"]


@dataclass(frozen=True)
class AxialElement(GaussianElement):
    """The mass and stiffness of an object modelled as a network of linear axial bars.

    Parameters
    ----------
    nodes : ndarray, shape (m, D)
        The node positions X (mm), D = 2 or 3.
    sigma : float
        The node spacing h (mm): the width of the Gaussians that interpolate nodal values between nodes.
    mass : ndarray, shape (D m, D m)
        Lumped M: diagonal, half of each bar's mass on each of its end nodes, on every axis.
    stiffness : ndarray, shape (D m, D m)
        K, degrees of freedom ordered axis by axis like the Gaussian element's.
    interpolation : ndarray, shape (m, m)
        A = G^-1 of the Gaussians of width h; it carries modes to other points and plays no part in M, K.
    young, density : float
        Young's modulus times cross-section, and mass per unit length.
    poisson : float
        0: a bar has no lateral strain law.
    rigid : str
        "element": translations and small rotations already cost no energy.
    edges : ndarray, shape (b, 2)
        The bars, as pairs of node indices.

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 3.1-3.3 (contours and surfaces built of linear axial 2-D or 3-D
    elements; their matrices are the paper's ref. [16]: K.-J. Bathe, Finite Element Procedures, 1996).
    """

    edges: np.ndarray


def axial_element(nodes: np.ndarray, edges: np.ndarray, *, young: float = 1.0, density: float = 1.0) -> AxialElement:
    """Mass and stiffness of an object modelled as linear axial bars between its nodes.

    Parameters
    ----------
    nodes : ndarray, shape (m, D)
        Node positions (mm), D = 2 or 3, at least D + 2 distinct nodes and at most 1,000,000.
    edges : ndarray of int, shape (b, 2)
        The bars: indices of their two end nodes, each in [0, m - 1]; every node must end a bar,
        and no bar may join a node to itself. The nodes must be spaced evenly enough that the Gaussians
        of width h (their mean spacing) that carry modes to other points keep the interpolation matrix
        conditioned below :data:`~amdo_lab.modal_matching.MAX_CONDITION`.
    young : float
        Young's modulus E times the cross-section, in (0, 1e100] (only scales the frequencies).
    density : float
        Mass per unit length rho, in (0, 1e100] (only scales the frequencies).

    Returns
    -------
    AxialElement
        Lumped (diagonal) M and K, usable by :func:`~amdo_lab.modal_matching.modal_analysis`.

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 3.1-3.3 (contours and surfaces built of linear axial 2-D or 3-D
    elements; their matrices are the paper's ref. [16]: K.-J. Bathe, Finite Element Procedures, 1996).

    Examples
    --------
    >>> import numpy as np
    >>> square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    >>> model = axial_element(square, [[0, 1], [1, 2], [2, 3], [3, 0], [0, 2]])
    >>> model.stiffness.shape
    (8, 8)
    """
    X = check_nodes(nodes, "nodes")
    bars = as_finite_array(edges, "edges", shape=(None, 2), dtype=int, bounds=(0, len(X) - 1))
    _check_edges(bars, len(X))
    young = check_in_range(young, "young", 0.0, MAX_MATERIAL, closed="right")
    density = check_in_range(density, "density", 0.0, MAX_MATERIAL, closed="right")
    _check_condition(X, _mean_spacing(X), sigma_is_spacing=True)
    return _axial_element(X, bars, young, density)


def _check_edges(bars: np.ndarray, m: int) -> None:
    if np.any(bars[:, 0] == bars[:, 1]):
        raise ValueError("edges must join two different nodes, got a bar from a node to itself")
    if len(np.unique(bars)) < m:
        raise ValueError(f"edges must reach every one of the {m} nodes, got {len(np.unique(bars))}")


def _axial_element(X: np.ndarray, bars: np.ndarray, young: float, density: float) -> AxialElement:
    m, D = X.shape
    stiffness = np.zeros((D * m, D * m))
    lumped = np.zeros(m)
    for i, j in bars:
        d = X[j] - X[i]
        length = float(np.linalg.norm(d))
        n = d / length
        # bar stiffness in node-major order: (E / L) [[n n^T, -n n^T], [-n n^T, n n^T]]
        block = young / length * np.outer(n, n)
        dofs_i, dofs_j = np.arange(D) * m + i, np.arange(D) * m + j  # axis-by-axis ordering
        for rows, cols, sign in ((dofs_i, dofs_i, 1), (dofs_j, dofs_j, 1), (dofs_i, dofs_j, -1),
                                 (dofs_j, dofs_i, -1)):
            stiffness[np.ix_(rows, cols)] += sign * block
        lumped[[i, j]] += density * length / 2  # half the bar's mass on each end node
    mass = np.diag(np.tile(lumped, D))
    h = _mean_spacing(X)
    A = np.linalg.inv(_gaussians(X, X, h))
    return AxialElement(X, h, mass, stiffness, (A + A.T) / 2, young, 0.0, density, "element", bars)
