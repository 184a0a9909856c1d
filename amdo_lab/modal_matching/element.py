"""Sclaroff's isoparametric Gaussian element: mass and stiffness of one object in closed form.

Every node of the object carries one Gaussian ``g_k(x) = exp(-|x - X_k|^2 / (2 sigma^2))``; the
interpolation functions are ``H = A g`` with ``A = G^-1``, ``G_ij = g_j(X_i)``, so that each ``h_i``
is 1 at its own node and 0 at the others. Because products of Gaussians are Gaussians, the integrals
over the plane (or space) that give the mass and stiffness matrices have closed forms; this module
writes them out, and the tests compare them with quadrature.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common import MAX_SAMPLES, as_finite_array, check_choice, check_in_range

__all__ = ["GaussianElement", "MAX_CONDITION", "MAX_COORDINATE_MM", "MAX_MATERIAL", "RIGID_MODES", "check_nodes",
           "check_same_dimension", "gaussian_element", "mean_spacing"]

_REFERENCE = ("L. F. Bastos, J. M. R. S. Tavares. Improvement of Modal Matching Image Objects in Dynamic "
              "Pedobarography Using Optimization Techniques. AMDO 2004, LNCS 3179, Sec. 3-4; the element is "
              "Sclaroff & Pentland, IEEE PAMI 17, 1995 (the paper's ref. [1]).")

#: Largest condition number of the Gaussian interpolation matrix G accepted: beyond it A = G^-1 loses
#: most of its digits and M stops being numerically positive definite.
MAX_CONDITION = 1e10
#: Largest Young's modulus or density accepted: K and M scale with them and stay finite below it.
MAX_MATERIAL = 1e100
#: Largest node coordinate (mm): squared distances of nodes this far apart stay far below overflow.
MAX_COORDINATE_MM = 1e100
#: What the first D(D+1)/2 modes are: the element's own lowest modes ("element"), or the exact rigid
#: motions, M-orthonormalised, with the other modes solved in their M-orthogonal complement ("exact").
RIGID_MODES = ("element", "exact")


@dataclass(frozen=True)
class GaussianElement:
    """The mass and stiffness matrices of one object modelled by a single Gaussian element.

    Parameters
    ----------
    nodes : ndarray, shape (m, D)
        The node positions X (mm), D = 2 or 3.
    sigma : float
        Width of the Gaussians (mm).
    mass, stiffness : ndarray, shape (D m, D m)
        M and K, degrees of freedom ordered axis by axis: (u_1 ... u_m, v_1 ... v_m[, w_1 ... w_m]).
    interpolation : ndarray, shape (m, m)
        A = G^-1: ``h(x) = A g(x)``.
    young, poisson, density : float
        The virtual material: Young's modulus E, Poisson's ratio nu, density rho.
    rigid : {"element", "exact"}
        What :func:`~amdo_lab.modal_matching.modal_analysis` puts first (see :data:`RIGID_MODES`).

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 3.1 and 4; Sclaroff & Pentland, IEEE PAMI 17, 1995.
    """

    nodes: np.ndarray
    sigma: float
    mass: np.ndarray
    stiffness: np.ndarray
    interpolation: np.ndarray
    young: float
    poisson: float
    density: float
    rigid: str

    @property
    def dimension(self) -> int:
        """D, the number of coordinates of a node."""
        return int(self.nodes.shape[1])


def mean_spacing(nodes: np.ndarray) -> float:
    """Mean distance from each node to its nearest other node (mm): the spacing h of an object.

    Parameters
    ----------
    nodes : ndarray, shape (m, D)
        Node positions (mm), m ≥ 2.

    Returns
    -------
    float
        The mean nearest-neighbour distance.

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 4 (our choice of sigma = h for the unstated element width).
    """
    X = as_finite_array(nodes, "nodes", ndim=2, max_abs=MAX_COORDINATE_MM)
    if X.shape[0] < 2:
        raise ValueError(f"nodes must hold at least 2 points, got {X.shape[0]}")
    return _mean_spacing(X)


def _mean_spacing(X: np.ndarray) -> float:
    d2 = np.sum((X[:, None] - X[None]) ** 2, axis=-1)
    np.fill_diagonal(d2, np.inf)
    return float(np.mean(np.sqrt(d2.min(axis=1))))


def gaussian_element(
    nodes: np.ndarray,
    *,
    sigma: float,
    young: float = 1.0,
    poisson: float = 0.3,
    density: float = 1.0,
    rigid: str = "element",
) -> GaussianElement:
    """Mass and stiffness of an object modelled as one isoparametric Gaussian element.

    Parameters
    ----------
    nodes : ndarray, shape (m, D)
        Node positions (mm), D = 2 or 3, at least D + 2 distinct nodes and at most 1,000,000.
    sigma : float
        Width of each node's Gaussian (mm), in (0, 1e100]. The interpolation matrix G must stay conditioned
        below :data:`MAX_CONDITION` (about sigma ≤ 2 h for h the node spacing).
    young : float
        Young's modulus E of the virtual material, in (0, 1e100] (only scales the frequencies).
    poisson : float
        Poisson's ratio nu, in (-1, 0.5); in 2-D the plane-stress law is used.
    density : float
        Density rho, in (0, 1e100] (only scales the frequencies).
    rigid : {"element", "exact"}
        "element": the modes are the element's own, whose lowest D(D+1)/2 are only nearly rigid.
        "exact": :func:`~amdo_lab.modal_matching.modal_analysis` replaces them by the exact translations
        and rotation(s) about the centroid, M-orthonormalised, and solves the other modes M-orthogonal to them.

    Returns
    -------
    GaussianElement
        M, K and A = G^-1.

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 3.1 (the element is ref. [1]: Sclaroff & Pentland, 1995).

    Examples
    --------
    >>> import numpy as np
    >>> angle = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    >>> model = gaussian_element(np.c_[np.cos(angle), np.sin(angle)], sigma=0.8)
    >>> model.mass.shape
    (16, 16)
    """
    X = check_nodes(nodes, "nodes")
    sigma = check_in_range(sigma, "sigma", 0.0, MAX_COORDINATE_MM, closed="right")
    young = check_in_range(young, "young", 0.0, MAX_MATERIAL, closed="right")
    poisson = check_in_range(poisson, "poisson", -1.0, 0.5)
    density = check_in_range(density, "density", 0.0, MAX_MATERIAL, closed="right")
    rigid = check_choice(rigid, "rigid", RIGID_MODES)
    _check_condition(X, sigma)
    return _gaussian_element(X, sigma, young, poisson, density, rigid)


def check_same_dimension(X1: np.ndarray, X2: np.ndarray, names: str = "X1 and X2") -> None:
    """Raise, naming both arguments, when two node sets have different numbers of coordinates.

    Parameters
    ----------
    X1, X2 : ndarray, shapes (m1, D1) and (m2, D2)
        Two node sets.
    names : str
        How the error names them.

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 4 (eq. (3) compares 2-D with 2-D, eq. (4) 3-D with 3-D).
    """
    if X1.shape[1] != X2.shape[1]:
        raise ValueError(f"{names} must have the same number of coordinates, got {X1.shape[1]} and {X2.shape[1]}")


def check_nodes(nodes: object, name: str) -> np.ndarray:
    """The node set as a float array, refused, naming the argument, when the element cannot model it.

    Parameters
    ----------
    nodes : array_like, shape (m, D)
        Node positions (mm), finite, each coordinate at most :data:`MAX_COORDINATE_MM` in size.
    name : str
        The argument's name, used in error messages.

    Returns
    -------
    ndarray, shape (m, D)
        The nodes as floats.

    Raises
    ------
    ValueError
        When D is not 2 or 3, when m is below D + 2 or above 1,000,000, or when two nodes coincide.

    References
    ----------
    Sclaroff & Pentland, IEEE PAMI 17, 1995 (G must be invertible), the element of Bastos & Tavares, AMDO 2004.
    """
    X = as_finite_array(nodes, name, ndim=2, max_abs=MAX_COORDINATE_MM)
    m, D = X.shape
    if D not in (2, 3):
        raise ValueError(f"{name} must hold 2-D or 3-D points, got {D} coordinates")
    if not D + 2 <= m <= MAX_SAMPLES:
        raise ValueError(f"{name} must hold between {D + 2} and {MAX_SAMPLES} nodes, got {m}")
    scale = np.max(np.abs(X)) or 1.0
    if len(np.unique(np.round(X / scale, 12), axis=0)) < m:
        raise ValueError(f"{name} holds duplicate nodes")
    return X


def _check_node_pair(X1: object, X2: object) -> tuple[np.ndarray, np.ndarray]:
    """Two objects' node sets X1 and X2, each checked by :func:`check_nodes`, of the same dimension."""
    X1 = check_nodes(X1, "X1")
    X2 = check_nodes(X2, "X2")
    check_same_dimension(X1, X2)
    return X1, X2


def _check_condition(X: np.ndarray, sigma: float, *, sigma_is_spacing: bool = False) -> None:
    """Refuse Gaussians of width sigma whose interpolation matrix G is numerically singular at the nodes X.

    With ``sigma_is_spacing`` the width is not an argument but the mean node spacing h (axial bars), so
    the message blames the nodes: too unevenly spaced for one common width.
    """
    condition = np.linalg.cond(_gaussians(X, X, sigma))
    cure = ("nodes are too unevenly spaced for Gaussians as wide as their mean spacing h = {:g}: spread them "
            "more evenly" if sigma_is_spacing else "sigma = {:g} is too wide: take a smaller sigma").format(sigma)
    if not condition <= MAX_CONDITION:
        raise ValueError(f"{cure} (the interpolation matrix has condition {condition:.1e} > {MAX_CONDITION:.0e})")


def _gaussians(points: np.ndarray, centres: np.ndarray, sigma: float) -> np.ndarray:
    """g_k(x) = exp(-|x - X_k|^2 / (2 sigma^2)) for every point (rows) and centre (columns)."""
    d2 = np.sum((points[:, None, :] - centres[None, :, :]) ** 2, axis=-1)
    return np.exp(-d2 / (2 * sigma**2))


def _gaussian_overlaps(X: np.ndarray, sigma: float) -> tuple[np.ndarray, np.ndarray]:
    """The integrals of products of the nodes' Gaussians and of their derivatives, in closed form.

    Parameters
    ----------
    X : ndarray, shape (m, D)
        Node positions (mm).
    sigma : float
        Width of the Gaussians (mm).

    Returns
    -------
    overlap : ndarray, shape (m, m)
        Gbar_kl = integral of g_k g_l = (pi sigma^2)^(D/2) exp(-|X_k - X_l|^2 / (4 sigma^2)).
    gradient_overlap : ndarray, shape (D, D, m, m)
        I[a, b, k, l] = integral of (d g_k / d x_a)(d g_l / d x_b)
        = Gbar_kl (delta_ab sigma^2 / 2 - d_a d_b / 4) / sigma^4 with d = X_k - X_l.

    References
    ----------
    Sclaroff & Pentland, IEEE PAMI 17, 1995, the element of Bastos & Tavares, AMDO 2004, Sec. 3.1.
    """
    m, D = X.shape
    d = X[:, None, :] - X[None, :, :]  # d_kl = X_k - X_l
    overlap = (np.pi * sigma**2) ** (D / 2) * np.exp(-np.sum(d**2, axis=-1) / (4 * sigma**2))
    moments = 0.5 * sigma**2 * np.eye(D)[:, :, None, None] - 0.25 * np.einsum("kla,klb->abkl", d, d)
    return overlap, overlap[None, None] * moments / sigma**4


def _gaussian_element(X: np.ndarray, sigma: float, young: float, poisson: float, density: float,
                      rigid: str = "element") -> GaussianElement:
    m, D = X.shape
    G = _gaussians(X, X, sigma)
    A = np.linalg.inv(G)
    A = (A + A.T) / 2  # G is symmetric; keep its inverse exactly so
    overlap, grad = _gaussian_overlaps(X, sigma)
    # mass, per axis: M_axis = rho A Gbar A (integral of rho H^T H), the same block on every axis
    mass_block = density * A @ overlap @ A
    mass = np.kron(np.eye(D), mass_block)
    # stiffness, isotropic material: strain energy density lambda (div u)^2 / 2 + mu eps:eps gives
    # K_ab = A (lambda I_ab + mu I_ba + mu delta_ab sum_c I_cc) A (2-D: plane stress lambda)
    mu = young / (2 * (1 + poisson))
    lam = young * poisson / (1 - poisson**2) if D == 2 else young * poisson / ((1 + poisson) * (1 - 2 * poisson))
    trace = sum(grad[c, c] for c in range(D))
    stiffness = np.zeros((D * m, D * m))
    for a in range(D):
        for b in range(D):
            block = lam * grad[a, b] + mu * grad[b, a] + (mu * trace if a == b else 0.0)
            stiffness[a * m:(a + 1) * m, b * m:(b + 1) * m] = A @ block @ A
    stiffness = (stiffness + stiffness.T) / 2
    return GaussianElement(X, sigma, mass, stiffness, A, young, poisson, density, rigid)


def _interpolate_field(model: GaussianElement, U: np.ndarray, P: np.ndarray) -> np.ndarray:
    """The element's displacement field u(x) = sum_i h_i(x) U_i (H = A g) at points P (p, D), for nodal
    displacements U (D m, n) ordered axis by axis; returns (D p, n), ordered axis by axis."""
    m, D = model.nodes.shape
    H = _gaussians(P, model.nodes, model.sigma) @ model.interpolation  # (p, m): h_i(x_p)
    return np.concatenate([H @ U[a * m:(a + 1) * m] for a in range(D)], axis=0)
