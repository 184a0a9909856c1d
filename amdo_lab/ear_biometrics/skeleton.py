"""The thinned contours: Choraś's crossing number (AMDO 2004, Sec. 4, eq. 8), spur pruning, and the
skeleton read as polylines (the contours traced for eq. 9)."""

from __future__ import annotations

import cv2
import numpy as np
from skimage.morphology import skeletonize

from amdo_lab.common import MAX_ITERATIONS, MAX_SIDE, as_finite_array, check_positive_int
from amdo_lab.ear_biometrics.images import as_bool_image, as_contour_image

MAX_NODE_COORDINATE = 1e6
"""Largest pixel coordinate of a polyline node: far beyond any image, and far below the overflow of
the sums that smoothing takes."""

def crossing_number(skeleton: np.ndarray) -> np.ndarray:
    """The 8-connected crossing number N_c of every skeleton pixel (eq. 8, Fig. 7).

    N_c = 1/2 sum_k |p_{k+1} - p_k| over the 8 neighbours p_1..p_8 in cyclic order: 1 at an ending,
    2 along a contour, 3 or more at a bifurcation.

    Parameters
    ----------
    skeleton : array_like, shape (rows, cols), bool
        A thinned contour image, not empty.

    Returns
    -------
    numpy.ndarray, shape (rows, cols), int
        N_c on the skeleton, 0 off it.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 4, eq. (8) and Fig. 7.
    """
    thin = as_bool_image(skeleton, "skeleton")
    return _crossing_number(thin)


def _ring_neighbours(skeleton: np.ndarray) -> np.ndarray:
    """The 8 neighbours p_1..p_8 of every pixel in cyclic order N, NE, E, ..., NW, shape (8, rows, cols), int8."""
    padded = np.pad(skeleton.astype(np.int8), 1)
    h, w = skeleton.shape
    ring = [(0, 1), (0, 2), (1, 2), (2, 2), (2, 1), (2, 0), (1, 0), (0, 0)]  # N, NE, E, SE, S, SW, W, NW
    return np.stack([padded[r:r + h, c:c + w] for r, c in ring])


def _crossing_number(skeleton: np.ndarray) -> np.ndarray:
    """:func:`crossing_number` of a validated skeleton (the spur pruning loop's inner call)."""
    neighbours = _ring_neighbours(skeleton)
    # eq. (8): N_c = 1/2 Σ_k |p_{k+1} - p_k| around the ring, p_9 = p_1
    transitions = np.abs(np.diff(np.concatenate([neighbours, neighbours[:1]]), axis=0)).sum(axis=0) // 2
    return np.where(skeleton, transitions, 0)


EQ8_READINGS = ("crossing", "yokoi")
"""Readings of eq. (8)'s "connected number": Rutovitz's crossing number (:func:`crossing_number`) or
Yokoi's connectivity number (:func:`connectivity_number`)."""


def connectivity_number(skeleton: np.ndarray) -> np.ndarray:
    """Yokoi's 8-connectivity number of every skeleton pixel: the other reading of eq. (8).

    With q_k = 1 - p_k over the 8 neighbours in cyclic order from a 4-neighbour (N, NE, E, ...),
    N = sum over the 4-neighbours k of (q_k - q_k q_{k+1} q_{k+2}): the number of separate groups of
    8-connected neighbours that the pixel joins. Like :func:`crossing_number` it is 1 at an ending
    and 2 along a line; where branches meet it differs, because neighbours that touch diagonally form
    one group: a T of 4-adjacent arms gives 1 (the crossing number 3), a one-pixel "+" gives 0 (4).

    Parameters
    ----------
    skeleton : array_like, shape (rows, cols), bool
        A thinned contour image, not empty.

    Returns
    -------
    numpy.ndarray, shape (rows, cols), int
        N on the skeleton, 0 off it.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 4, eq. (8).
    S. Yokoi, J. Toriwaki, T. Fukumura, "An analysis of topological properties of digitized binary
    pictures using local features", Computer Graphics and Image Processing 4(1), 1975.
    """
    thin = as_bool_image(skeleton, "skeleton")
    q = 1 - _ring_neighbours(thin)  # q_k = 1 - p_k
    # N = Σ_{k = N, E, S, W} (q_k - q_k q_{k+1} q_{k+2}), indices around the ring
    groups = sum(q[k] - q[k] * q[k + 1] * q[(k + 2) % 8] for k in (0, 2, 4, 6))
    return np.where(thin, groups, 0)


def prune_spurs(skeleton: object, length_px: int) -> np.ndarray:
    """Remove side branches shorter than ``length_px`` pixels from a thinned image.

    Spurs are what a ragged contour border leaves after thinning: ``length_px`` rounds of deleting
    end pixels, then the surviving ends regrow along the original skeleton by up to ``length_px``
    pixels, so genuine open contours keep their full length.

    Parameters
    ----------
    skeleton : array_like, shape (rows, cols), bool
        A thinned contour image, not empty.
    length_px : int
        Longest spur removed, pixels, from 0 (the skeleton unchanged) to ``MAX_SIDE`` (4,096).

    Returns
    -------
    numpy.ndarray, shape (rows, cols), bool
        The pruned skeleton.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 4 (beyond the paper: endings of eq. (9) that a ragged contour would add).
    """
    thin = as_bool_image(skeleton, "skeleton")
    length = check_positive_int(length_px, "length_px", minimum=0, maximum=MAX_SIDE)
    kernel = np.ones((3, 3), np.uint8)

    def ends(mask: np.ndarray) -> np.ndarray:  # one branch (N_c = 1) or isolated (N_c = 0)
        return mask & (_crossing_number(mask) <= 1)

    pruned = thin.copy()
    for _ in range(length):
        pruned &= ~ends(pruned)
    grown = ends(pruned) & (_crossing_number(pruned) == 1)  # ends of the pruned skeleton
    front = grown
    for _ in range(length):
        front = cv2.dilate(front.astype(np.uint8), kernel).astype(bool) & thin & ~pruned & ~grown
        grown |= front
    return pruned | grown


def thin_contours(contours: object) -> np.ndarray:
    """Thin a contour image to one-pixel-wide lines (``skimage.morphology.skeletonize``).

    Thinned inside the contours' bounding box plus a 1-pixel margin: the same result as thinning the
    whole image, with less to scan.

    Parameters
    ----------
    contours : array_like, shape (rows, cols), bool
        Contour image with at least one contour pixel.

    Returns
    -------
    numpy.ndarray, shape (rows, cols), bool
        The skeleton.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 4 (the contours are traced on their thinned form, Figs. 7-8).
    """
    array = as_contour_image(contours)
    rows, cols = np.flatnonzero(array.any(axis=1)), np.flatnonzero(array.any(axis=0))
    top, left = max(rows[0] - 1, 0), max(cols[0] - 1, 0)
    thin = np.zeros_like(array)
    thin[top:rows[-1] + 2, left:cols[-1] + 2] = skeletonize(array[top:rows[-1] + 2, left:cols[-1] + 2])
    return thin


def skeleton_graph(skeleton: object) -> tuple[np.ndarray, np.ndarray]:
    """The contour polylines of a thinned contour image as a graph.

    Nodes are the skeleton pixels (row, col); edges join 4-adjacent pixels, and diagonal pixels only
    when no 4-adjacent pixel of the skeleton already links them (a staircase corner is one path, not
    a triangle, so a circle passing the corner is crossed once).

    Parameters
    ----------
    skeleton : array_like, shape (rows, cols), bool
        A thinned contour image (one pixel wide), not empty.

    Returns
    -------
    nodes : numpy.ndarray, shape (n, 2), float
        Pixel positions (row, col) of the skeleton pixels.
    edges : numpy.ndarray, shape (m, 2), int
        Pairs of node indices joined by the contour.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 4 (the contours traced for eq. (9), read here as polylines).
    """
    thin = as_bool_image(skeleton, "skeleton")
    h, w = thin.shape
    index = np.full((h + 2, w + 2), -1, np.int64)
    nodes = np.argwhere(thin)
    index[nodes[:, 0] + 1, nodes[:, 1] + 1] = np.arange(len(nodes))
    on = index >= 0

    def at(d_row: int, d_col: int, array: np.ndarray) -> np.ndarray:
        return array[1 + d_row:1 + d_row + h, 1 + d_col:1 + d_col + w]

    here = at(0, 0, index)
    pairs = []
    for d_row, d_col, keep in [(0, 1, None), (1, 0, None), (1, 1, (0, 1, 1, 0)), (1, -1, (0, -1, 1, 0))]:
        linked = thin & at(d_row, d_col, on)
        if keep is not None:  # diagonal: only if neither shared 4-neighbour is on the skeleton
            linked &= ~at(keep[0], keep[1], on) & ~at(keep[2], keep[3], on)
        pairs.append(np.c_[here[linked], at(d_row, d_col, index)[linked]])
    return nodes.astype(float), np.vstack(pairs)


def smooth_polylines(nodes: np.ndarray, edges: np.ndarray, n_iter: int) -> np.ndarray:
    """Light smoothing along the contours, endings and bifurcations held fixed.

    Each of ``n_iter`` rounds replaces every node of degree 2 (an interior polyline point) by the
    mean of itself and its two neighbours. Endings and bifurcations stay put, so contours neither
    shrink nor come apart.

    Parameters
    ----------
    nodes : array_like, shape (n, 2)
        Node positions (from :func:`skeleton_graph`), pixels, not empty, each within
        +-:data:`MAX_NODE_COORDINATE`.
    edges : array_like, shape (m, 2), int
        Pairs of node indices, each in 0..n-1.
    n_iter : int
        Number of smoothing rounds, from 0 to ``MAX_ITERATIONS`` (100,000).

    Returns
    -------
    numpy.ndarray, shape (n, 2)
        The smoothed node positions (a new array).

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 4 (beyond the paper: sub-pixel crossings of the circles of eq. (7)).
    """
    n_iter = check_positive_int(n_iter, "n_iter", minimum=0, maximum=MAX_ITERATIONS)
    positions = as_finite_array(nodes, "nodes", shape=(None, 2), max_abs=MAX_NODE_COORDINATE)
    edges = as_finite_array(edges, "edges", shape=(None, 2), dtype=int, allow_empty=True,
                            bounds=(0, len(positions) - 1))
    degree = np.bincount(edges.ravel(), minlength=len(positions))
    interior = degree == 2
    for _ in range(n_iter):
        totals = positions.copy()
        np.add.at(totals, edges[:, 0], positions[edges[:, 1]])
        np.add.at(totals, edges[:, 1], positions[edges[:, 0]])
        positions[interior] = totals[interior] / 3.0
    return positions
