"""Modal analysis of an element: the generalised eigenproblem K phi = omega^2 M phi.

The eigenvectors (shape vectors) are an object's own coordinates, ordered from the lowest frequency
(global motion) to the highest (local wiggles). Their signs are arbitrary for the eigensolver; we fix
them by one rule so that every machine returns the same vectors.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import linalg

from amdo_lab.common import check_instance, check_positive_int
from amdo_lab.modal_matching.element import GaussianElement

__all__ = ["ModalBasis", "modal_analysis"]


@dataclass(frozen=True)
class ModalBasis:
    """The modes of one object: frequencies and shape vectors, lowest frequency first.

    Parameters
    ----------
    omega : ndarray, shape (D m,)
        Natural frequencies omega (rad per unit time of the virtual material), ascending; with
        ``model.rigid == "exact"``, the D(D+1)/2 exact rigid modes come first (their omega is the
        element's Rayleigh quotient, not 0), then the other modes ascending.
    shapes : ndarray, shape (D m, D m)
        Phi: column i is the shape vector phi_i, M-orthonormal (Phi^T M Phi = I), degrees of freedom
        ordered axis by axis (u_1 ... u_m, v_1 ... v_m[, w ...]), the sign fixed so that the entry
        of largest magnitude is positive.
    model : GaussianElement
        The element the modes belong to.

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 4, eqs. (1)-(2) (lost in our copy of the text).
    """

    omega: np.ndarray
    shapes: np.ndarray
    model: GaussianElement

    def node_vectors(self, n_modes: int) -> np.ndarray:
        """Each node's displacement in the first ``n_modes`` modes: rows u_i, v_i (, w_i) of Phi.

        Parameters
        ----------
        n_modes : int
            How many modes, from 1 to D m.

        Returns
        -------
        ndarray, shape (m, D, n_modes)
            ``[i, a, k]``: displacement of node i along axis a in mode k.
        """
        m, D = self.model.nodes.shape
        n = check_positive_int(n_modes, "n_modes", maximum=D * m)
        return self.shapes[:, :n].reshape(D, m, n).transpose(1, 0, 2)

    def rigid_cosines(self) -> np.ndarray:
        """How rigid the first D(D+1)/2 modes are: for each exact rigid motion, the cosine of its
        angle to their span.

        Returns
        -------
        ndarray, shape (D (D + 1) / 2,)
            Translations along each axis, then rotations; 1 means the motion lies in the span.
        """
        rigid = _exact_rigid_motions(self.model.nodes)
        basis, _ = np.linalg.qr(self.shapes[:, :rigid.shape[1]])
        rigid = rigid / np.linalg.norm(rigid, axis=0)
        return np.linalg.norm(basis.T @ rigid, axis=0)


def _exact_rigid_motions(X: np.ndarray) -> np.ndarray:
    """The exact rigid motions of nodes X (m, D): unit translations, then small rotations about the centroid,
    as columns of nodal displacements (D m, D (D + 1) / 2), degrees of freedom axis by axis (Sec. 4: "the first
    three (six) modes are rigid")."""
    m, D = X.shape
    centred = X - X.mean(axis=0)
    columns = [np.kron(np.eye(D)[a], np.ones(m)) for a in range(D)]
    for a, b in ([(0, 1)] if D == 2 else [(1, 2), (2, 0), (0, 1)]):
        rotation = np.zeros((D, m))  # an infinitesimal rotation in the (a, b) plane
        rotation[a], rotation[b] = -centred[:, b], centred[:, a]
        columns.append(rotation.ravel())
    return np.stack(columns, axis=1)


def modal_analysis(model: GaussianElement) -> ModalBasis:
    """Solve K phi = omega^2 M phi for every mode of an element.

    Parameters
    ----------
    model : GaussianElement
        From :func:`~amdo_lab.modal_matching.gaussian_element`.

    Returns
    -------
    ModalBasis
        Frequencies ascending, M-orthonormal shape vectors with deterministic signs.

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 4, eqs. (1)-(2): Phi = [phi_1 ... phi_Dm], Omega = diag(omega^2).

    Examples
    --------
    >>> import numpy as np
    >>> from amdo_lab.modal_matching import gaussian_element
    >>> angle = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    >>> basis = modal_analysis(gaussian_element(np.c_[np.cos(angle), np.sin(angle)], sigma=0.8))
    >>> basis.shapes.shape
    (16, 16)
    """
    check_instance(model, "model", GaussianElement)
    return _modal_analysis(model)


def _modal_analysis(model: GaussianElement) -> ModalBasis:
    if model.rigid == "exact":
        omega_sq, shapes = _exact_rigid_eigenproblem(model)
    else:  # eqs. (1)-(2): K Phi = M Phi Omega, Omega = diag(omega_i^2), Phi^T M Phi = I
        omega_sq, shapes = linalg.eigh(model.stiffness, model.mass)
    # the eigensolver may return -phi as well as phi: make each vector's largest entry positive
    largest = shapes[np.argmax(np.abs(shapes), axis=0), np.arange(shapes.shape[1])]
    shapes = shapes * np.sign(largest)
    return ModalBasis(np.sqrt(np.clip(omega_sq, 0.0, None)), shapes, model)


def _exact_rigid_eigenproblem(model: GaussianElement) -> tuple[np.ndarray, np.ndarray]:
    """Eqs. (1)-(2) with the exact rigid motions first: Rayleigh-Ritz in their span, then in its M-complement."""
    M, K = model.mass, model.stiffness
    R = _exact_rigid_motions(model.nodes)
    # the rigid block: M-orthonormal combinations of the exact motions that diagonalise K in their span
    rigid_sq, rigid = linalg.eigh(R.T @ K @ R, R.T @ M @ R)
    # the rest: an orthonormal basis C of the vectors M-orthogonal to every rigid motion (R^T M C = 0)
    C = linalg.null_space((M @ R).T)
    rest_sq, rest = linalg.eigh(C.T @ K @ C, C.T @ M @ C)
    return np.concatenate([rigid_sq, rest_sq]), np.concatenate([R @ rigid, C @ rest], axis=1)
