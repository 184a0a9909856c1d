"""The external energy of the snakes: Sec. 3.2's potential field and the gradient vector flow.

:func:`potential_field` is the pre-processing of Caro et al. (2004, Sec. 3.2): a 7 x 7 Gaussian,
a 3 x 3 Sobel operator, histogram equalisation, a binary edge map cleaned of specks, thinned to its
centre line, and a "diffusion" of that map, which we read as the distance to the nearest edge pixel
capped at ``cap_px``. Low values lie on edges. The thinning is ours: the binary map keeps a fixed share
of the image's pixels, so its bands are several pixels wide (about ``edge_share * area / edge length``)
and, unthinned, the potential is zero across a whole band; a snake has no image force there and its
internal energy pulls it to the band's inner rim (a disc of radius 40 px on 128 x 128 pixels ends at
radius 37, -15 % in area). :func:`gradient_vector_flow` is Xu & Prince's diffusion of an
edge map's gradient (the external force of the variational snake).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from amdo_lab.common import MAX_ITERATIONS, MAX_SIDE, as_finite_array, check_bool, check_choice, check_in_range, \
    check_positive_int

__all__ = ["EDGE_MODES", "GAUSSIAN_7", "edge_strength", "equalise_histogram", "gradient_vector_flow",
           "potential_field", "smooth_7x7"]

#: OpenCV's 7-tap Gaussian for a 7 x 7 kernel with no sigma given: [1, 3.5, 7, 9, 7, 3.5, 1] / 32.
GAUSSIAN_7 = np.array([1.0, 3.5, 7.0, 9.0, 7.0, 3.5, 1.0]) / 32.0
#: Edge detectors: the paper's Sobel magnitude, or a bright-ridge filter (Sato).
EDGE_MODES = ("sobel", "ridge")
#: Largest accepted image magnitude (a Sobel sum of squares stays finite).
MAX_INTENSITY = 1e100


def _image(image: object, name: str = "image") -> np.ndarray:
    image = as_finite_array(image, name, ndim=2, max_abs=MAX_INTENSITY)
    check_positive_int(max(image.shape), f"{name} side", maximum=MAX_SIDE)
    if min(image.shape) < 7:
        raise ValueError(f"{name} must be at least 7 x 7 pixels (the Gaussian's size), got {image.shape}")
    return image


def smooth_7x7(image: np.ndarray) -> np.ndarray:
    """The 7 x 7 Gaussian of Sec. 3.2 (separable, borders mirrored as OpenCV's ``BORDER_REFLECT_101``).

    Parameters
    ----------
    image : (rows, cols) ndarray
        Intensities, finite, at least 7 x 7, each side at most 4,096.

    Returns
    -------
    (rows, cols) ndarray
        The smoothed image, equal to ``cv2.GaussianBlur(image, (7, 7), 0)``.

    References
    ----------
    Caro et al., AMDO 2004, Sec. 3.2.
    """
    return _smooth(_image(image))


def _smooth(image: np.ndarray) -> np.ndarray:
    once = ndimage.correlate1d(image, GAUSSIAN_7, axis=0, mode="mirror")
    return ndimage.correlate1d(once, GAUSSIAN_7, axis=1, mode="mirror")


def edge_strength(image: np.ndarray, edges: str = "sobel") -> np.ndarray:
    """Edge strength of a smoothed image: Sobel magnitude (Sec. 3.2) or a bright-ridge response.

    Parameters
    ----------
    image : (rows, cols) ndarray
        Intensities (already smoothed by :func:`smooth_7x7` in the pipeline).
    edges : {"sobel", "ridge"}
        ``"sobel"``: ``hypot`` of the two 3 x 3 Sobel derivatives (a bright line gives two edges, one
        on each flank); ``"ridge"``: scikit-image's Sato filter for bright ridges (one response on
        the line's centre).

    Returns
    -------
    (rows, cols) ndarray
        Non-negative strengths.

    References
    ----------
    Caro et al., AMDO 2004, Sec. 3.2; Y. Sato et al., Three-dimensional multi-scale line filter, 1998.
    """
    return _edge_strength(_image(image), check_choice(edges, "edges", EDGE_MODES))


def _edge_strength(smooth: np.ndarray, edges: str) -> np.ndarray:
    if edges == "sobel":
        return np.hypot(ndimage.sobel(smooth, axis=0, mode="mirror"), ndimage.sobel(smooth, axis=1, mode="mirror"))
    from skimage.filters import sato
    return sato(smooth, sigmas=(1.0, 2.0), black_ridges=False, mode="reflect")


def equalise_histogram(image: np.ndarray) -> np.ndarray:
    """Histogram equalisation of an 8-bit image, as ``cv2.equalizeHist``.

    Parameters
    ----------
    image : (rows, cols) ndarray of integers in [0, 255]
        The image.

    Returns
    -------
    (rows, cols) ndarray of uint8
        ``lut[image]`` with ``lut[j] = round(255 (cdf[j] - cdf[first]) / (N - cdf[first]))``.

    References
    ----------
    Caro et al., AMDO 2004, Sec. 3.2 ("the resulting images were equalized").
    """
    image = as_finite_array(image, "image", ndim=2, bounds=(0, 255), dtype=np.int64)
    return _equalise(image.astype(np.uint8))


def _equalise(image: np.ndarray) -> np.ndarray:
    histogram = np.bincount(image.ravel(), minlength=256)
    first = int(np.flatnonzero(histogram)[0])
    cdf = np.cumsum(histogram)
    if cdf[first] == image.size:               # a constant image stays as it is
        return image.copy()
    lut = np.rint((cdf - cdf[first]) * (255.0 / (image.size - cdf[first])))
    return np.clip(lut, 0, 255).astype(np.uint8)[image]


def potential_field(
    image: np.ndarray,
    *,
    edge_share: float = 0.10,
    min_object_px: int = 40,
    cap_px: float = 15.0,
    edges: str = "sobel",
    thin: bool = True,
) -> np.ndarray:
    """Sec. 3.2's potential: distance (px) to the nearest edge of a cleaned binary edge map, capped.

    Steps: 7 x 7 Gaussian; edge strength (3 x 3 Sobel magnitude, or a bright ridge);
    scale to 8 bits and equalise; keep the strongest ``edge_share`` of the pixels; drop
    8-connected specks under ``min_object_px`` pixels; thin each band to its centre line
    (skeletonise); distance transform, capped at ``cap_px``.
    The paper gives neither the threshold, the thinning nor the diffusion: these are our readings.

    Parameters
    ----------
    image : (rows, cols) ndarray
        Intensities, at least 7 x 7, each side at most 4,096.
    edge_share : float
        Share of pixels kept as edges, in (0, 1).
    min_object_px : int
        Smallest edge component kept, in pixels (1 to 4,096).
    cap_px : float
        Largest potential, in pixels, in (0, 4096].
    edges : {"sobel", "ridge"}
        Edge detector (see :func:`edge_strength`).
    thin : bool
        Thin the binary edge map to one-pixel centre lines before the distance (ours, the default);
        ``False`` keeps the whole band at zero potential (an ablation: snakes then stop on the
        band's inner or outer rim, not on its centre).

    Returns
    -------
    (rows, cols) ndarray
        The potential: 0 on edge pixels, growing with the distance to them, at most ``cap_px``.

    References
    ----------
    Caro et al., AMDO 2004, Sec. 3.2 (the potential replaces ``|grad I|`` of eqs. 3 and 7).

    Examples
    --------
    >>> import numpy as np
    >>> disc = (np.hypot(*np.mgrid[-20:21, -20:21]) < 10).astype(float)
    >>> field = potential_field(disc, edge_share=0.1)
    >>> float(field[20, 20]) > 5 and float(field[20, 10]) < 2
    True
    """
    image = _image(image)
    edge_share = check_in_range(edge_share, "edge_share", 0.0, 1.0)
    min_object_px = check_positive_int(min_object_px, "min_object_px", maximum=MAX_SIDE)
    cap_px = check_in_range(cap_px, "cap_px", 0.0, float(MAX_SIDE), closed="right")
    edges = check_choice(edges, "edges", EDGE_MODES)
    thin = check_bool(thin, "thin")
    return _potential_field(image, edge_share, min_object_px, cap_px, edges, thin)


def _binary_edges(image: np.ndarray, edge_share: float, min_object_px: int, edges: str,
                  thin: bool = True) -> np.ndarray:
    strength = _edge_strength(_smooth(image), edges)
    top = strength.max()
    eight_bit = np.rint(255 * strength / top).astype(np.uint8) if top > 0 else np.zeros(image.shape, np.uint8)
    equalised = _equalise(eight_bit)
    binary = equalised > np.quantile(equalised, 1 - edge_share)
    labels, count = ndimage.label(binary, structure=np.ones((3, 3)))
    sizes = np.bincount(labels.ravel(), minlength=count + 1)
    binary = (sizes >= min_object_px)[labels] & binary            # drop the specks
    if thin:                                                      # the band's centre line
        from skimage.morphology import skeletonize
        binary = skeletonize(binary)
    return binary


def _potential_field(image: np.ndarray, edge_share: float, min_object_px: int, cap_px: float,
                     edges: str, thin: bool = True) -> np.ndarray:
    binary = _binary_edges(image, edge_share, min_object_px, edges, thin)
    if not binary.any():
        return np.full(image.shape, float(cap_px))
    return np.minimum(ndimage.distance_transform_edt(~binary), cap_px)


def gradient_vector_flow(edge_map: np.ndarray, *, mu: float = 0.2, n_iter: int = 80) -> np.ndarray:
    """Xu & Prince's gradient vector flow of an edge map, by explicit diffusion.

    Iterates ``u <- u + mu lap(u) - (u - f_x)(f_x^2 + f_y^2)`` (and the same for ``v`` with
    ``f_y``) from ``(u, v) = grad f``, with ``f`` the edge map scaled to [0, 1]. The explicit
    scheme is stable for ``mu <= 0.25`` on a unit grid.

    Parameters
    ----------
    edge_map : (rows, cols) ndarray
        High on edges (for our potential ``P``: ``cap - P``), at least 7 x 7.
    mu : float
        Diffusion weight, in (0, 0.25].
    n_iter : int
        Diffusion steps, 1 to 100,000.

    Returns
    -------
    (2, rows, cols) ndarray
        The flow's row and column components.

    References
    ----------
    C. Xu, J.L. Prince, Gradient Vector Flow: A New External Force for Snakes, CVPR 1997; used as
    the variational snake's force by Caro et al., AMDO 2004, Sec. 3.1.
    """
    edge_map = _image(edge_map, "edge_map")
    mu = check_in_range(mu, "mu", 0.0, 0.25, closed="right")
    n_iter = check_positive_int(n_iter, "n_iter", maximum=MAX_ITERATIONS)
    return _gvf(edge_map, mu, n_iter)


def _gvf(edge_map: np.ndarray, mu: float, n_iter: int) -> np.ndarray:
    span = edge_map.max() - edge_map.min()
    f = (edge_map - edge_map.min()) / span if span > 0 else np.zeros_like(edge_map)
    fy, fx = np.gradient(f)
    b = fx ** 2 + fy ** 2
    flow = np.stack([fy, fx])
    target = flow.copy()
    for _ in range(n_iter):
        padded = np.pad(flow, ((0, 0), (1, 1), (1, 1)), mode="edge")
        laplacian = (padded[:, :-2, 1:-1] + padded[:, 2:, 1:-1] + padded[:, 1:-1, :-2] + padded[:, 1:-1, 2:]
                     - 4 * flow)
        flow = flow + mu * laplacian - b * (flow - target)
    return flow
