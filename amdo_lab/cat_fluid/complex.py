"""The CAT image model (Sec. 2): a 2-D cubical complex with chains, boundaries and cochains.

q-pixels of an H x W grid of 0-pixels: vertices (0-pixels), horizontal and vertical edges
(1-pixels, oriented along +axis 1 and +axis 0) and unit squares (2-pixels, oriented
counter-clockwise in the (axis 1, axis 0) plane). A q-chain is an integer vector over the
q-pixels; the boundary operator maps q-chains to (q-1)-chains and the coboundary, its
transpose, maps (q-1)-cochains (values on (q-1)-pixels) to q-cochains.
"""

from __future__ import annotations


import numpy as np
import scipy.sparse as sp

from amdo_lab.common import check_choice, check_image_shape, check_positive_int

__all__ = ["CubicalComplex"]


class CubicalComplex:
    """Cubical complex of an image support with ``shape = (H, W)`` 0-pixels (Sec. 2).

    Numbering: vertex (i, j) -> i*W + j; horizontal edge (i, j)->(i, j+1) -> i*(W-1) + j, then
    vertical edges (i, j)->(i+1, j) -> H*(W-1) + i*W + j; square with lower corner (i, j) ->
    i*(W-1) + j.

    Parameters
    ----------
    shape : tuple of two int
        (H, W), the number of 0-pixels (pixel centres) along array axes 0 and 1; each at least 2.

    References
    ----------
    L. Bentabet, D. Ziou, "Neuroanatomy Registration: An Algebraic-Topology Based Approach",
    AMDO 2004, LNCS 3179, pp. 76-85,
    Sec. 2 (q-pixels, chains, the boundary and coboundary operators) and eq. (7).
    """

    def __init__(self, shape: tuple[int, int]) -> None:
        self.shape = check_image_shape(shape, minimum=2, axes="H, W")

    @property
    def n_pixels(self) -> tuple[int, int, int]:
        """Number of 0-, 1- and 2-pixels."""
        h, w = self.shape
        return h * w, h * (w - 1) + (h - 1) * w, (h - 1) * (w - 1)

    def edges(self) -> tuple[np.ndarray, np.ndarray]:
        """Tail and head vertex numbers of every 1-pixel, in edge-number order (∂γ = head - tail).

        Returns
        -------
        tails, heads : numpy.ndarray of int, shape (n_1,)
            Vertex numbers of each edge's start and end; n_1 = H (W - 1) + (H - 1) W, horizontal edges
            first.
        """
        h, w = self.shape
        vertex = np.arange(h * w).reshape(h, w)
        tails = np.concatenate([vertex[:, :-1].ravel(), vertex[:-1, :].ravel()])
        heads = np.concatenate([vertex[:, 1:].ravel(), vertex[1:, :].ravel()])
        return tails, heads

    def boundary(self, q: int) -> sp.csr_matrix:
        """Boundary operator ∂_q as a sparse (n_{q-1} x n_q) integer matrix, q = 1 or 2.

        Column k is the (q-1)-chain ∂γ_k: head - tail for an edge; for a square, its four edges
        with sign +1 where the edge runs with the square's counter-clockwise orientation.

        Parameters
        ----------
        q : int
            Degree of the chains it acts on: 1 (edges to vertices) or 2 (squares to edges).

        Returns
        -------
        scipy.sparse.csr_matrix of int, shape (n_{q-1}, n_q)
            Entries in {-1, 0, 1}; ``boundary(1) @ boundary(2)`` is zero.
        """
        check_choice(check_positive_int(q, "q", minimum=0), "q", (1, 2))  # an int: True and 1.0 are refused
        h, w = self.shape
        if q == 1:
            # an oriented edge's boundary is head - tail
            tails, heads = self.edges()
            edges = np.arange(len(tails))
            rows = np.concatenate([heads, tails])
            values = np.concatenate([np.ones(len(edges)), -np.ones(len(edges))])
            return sp.csr_matrix((values, (rows, np.concatenate([edges, edges]))), shape=(h * w, len(edges)), dtype=int)
        horizontal = np.arange(h * (w - 1)).reshape(h, w - 1)
        vertical = h * (w - 1) + np.arange((h - 1) * w).reshape(h - 1, w)
        squares = np.arange((h - 1) * (w - 1))
        # counter-clockwise: bottom edge +, right edge +, top edge -, left edge -
        faces = [(horizontal[:-1, :], 1), (vertical[:, 1:], 1), (horizontal[1:, :], -1), (vertical[:, :-1], -1)]
        rows = np.concatenate([edges.ravel() for edges, _ in faces])
        values = np.concatenate([np.full(squares.size, sign) for _, sign in faces])
        cols = np.tile(squares, 4)
        return sp.csr_matrix((values, (rows, cols)), shape=(self.n_pixels[1], squares.size), dtype=int)

    def coboundary(self, q: int) -> sp.csr_matrix:
        """Coboundary δ_q: q-cochains -> (q+1)-cochains, (δ_q f)(γ) = f(∂γ), so δ_q = ∂_{q+1}ᵀ.

        For q = 0 this is eq. (7): the value on an edge is f(head) - f(tail).

        Parameters
        ----------
        q : int
            Degree of the cochains it acts on: 0 (vertex values to edge values) or 1 (edges to squares).

        Returns
        -------
        scipy.sparse.csr_matrix of int, shape (n_{q+1}, n_q)
            The transpose of ``boundary(q + 1)``.
        """
        check_choice(check_positive_int(q, "q", minimum=0), "q", (0, 1))  # an int: True and 0.0 are refused
        # eq. (7) for q = 0: D_1(γ) = Ψ_0(∂γ) = Ψ_0(x_*) - Ψ_0(x_#), the transpose of the boundary map
        return self.boundary(q + 1).T.tocsr()
