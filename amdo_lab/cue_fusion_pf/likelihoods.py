"""The image cues as log-likelihoods of particle states: colour (eqs. 7-11) and edges (eqs. 13-14).

Every cue has ``.log_likelihood(frame, states) -> (N,)``; the fusion of eq. (6) is their sum.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from amdo_lab.common import MAX_SAMPLES, MAX_SIDE
from amdo_lab.common import as_finite_array, check_bool, check_choice, check_in_range, check_instance, check_positive, check_positive_int, make_rng
from amdo_lab.cue_fusion_pf.shape import ShapeSpace

__all__ = [
    "COLOR_SPACES", "CalibrationResult", "EDGE_SMOOTHING_PX", "check_cues", "check_frames", "ColorLikelihood", "EdgeLikelihood", "MAX_CLUTTER_DENSITY", "MAX_DISTANCE", "MAX_PIXELS", "PAPER_SIGMAS", "SIGMA_RANGE", "bhattacharyya",
    "calibrate_sigma", "check_frame", "edge_line_likelihood", "fused_log_likelihood",
    "kernel_histogram", "simulate_measurement_lines",
]

#: Table 1's standard deviations of the colour and structure likelihoods.
PAPER_SIGMAS = {"color": 5.0, "structure": float(np.sqrt(15.0))}
#: Largest length or coordinate in pixels the chapter accepts (its frames are a few hundred pixels
#: wide): beyond it squared lengths overflow and pixel indices leave int32 (the overflow policy).
MAX_PIXELS = 1e6
#: Range of the σ of a cue's likelihood ``exp(-d / 2σ²)`` (σ_c, σ_s), with d in [0, 1]: below it every
#: particle but the best gets weight 0, above it the cue is switched off (and σ² leaves float64 far beyond).
SIGMA_RANGE = (1e-6, 1e6)
#: Largest distance :func:`calibrate_sigma` accepts (the cues' distances 1 - ρ and 1 - n_s/N_s are in [0, 1]).
MAX_DISTANCE = 1e6
#: Largest clutter density λ, features per pixel: a 1-D edge detector finds at most one per pixel.
MAX_CLUTTER_DENSITY = 1.0
#: σ of the Gaussian blur of the grey image before the edges' 1-D derivative (the "1-D Canny"), pixels.
EDGE_SMOOTHING_PX = 1.0


# --- colour: eqs. (7)-(11) ----------------------------------------------------------------------

def check_frame(frame: np.ndarray, name: str = "frame") -> np.ndarray:
    """Return ``frame`` as an array after checking it is a non-empty (H, W, 3) uint8 RGB image.

    Parameters
    ----------
    frame : numpy.ndarray
        The user's image.
    name : str
        The argument's name, used in error messages.

    Returns
    -------
    numpy.ndarray
        ``frame`` as an (H, W, 3) uint8 array (not copied).

    References
    ----------
    Li & Chaumette, AMDO 2004, Sec. 2 (every cue reads an RGB frame).
    """
    check_instance(name, "name", str)  # a label (CONTRIBUTING.md's label rule)
    frame = np.asarray(frame)
    if frame.dtype != np.uint8:
        raise TypeError(f"{name} must be uint8 RGB, got dtype {frame.dtype}")
    if frame.ndim != 3 or frame.shape[2] != 3 or frame.size == 0:
        raise ValueError(f"{name} must be a non-empty (H, W, 3) RGB image, got shape {frame.shape}")
    return frame


def check_frames(frames: object) -> np.ndarray:
    """Return ``frames`` as a (T, H, W, 3) uint8 array after checking it is a non-empty RGB sequence.

    Parameters
    ----------
    frames : array_like
        (T, H, W, 3) uint8 RGB, or float RGB in [0, 255] (rounded to whole grey levels).

    Returns
    -------
    numpy.ndarray
        (T, H, W, 3) uint8 frames (not copied when already uint8).

    References
    ----------
    Li & Chaumette, AMDO 2004, Sec. 4 (the tracked sequences).
    """
    array = np.asarray(frames)
    if array.dtype != np.uint8 and not np.issubdtype(array.dtype, np.floating):
        raise TypeError(f"frames must be uint8 or float RGB, got dtype {array.dtype}")
    if array.dtype != np.uint8:  # float RGB: finite, in [0, 255], rounded to whole grey levels
        array = as_finite_array(array, "frames", bounds=(0.0, 255.0))
        array = np.rint(array).astype(np.uint8)
    if array.ndim != 4 or array.shape[-1] != 3 or array.shape[0] == 0:
        raise ValueError(f"frames must be a (T, H, W, 3) RGB array of at least one frame, got shape {array.shape}")
    return array


#: The numbers of bins per channel a histogram can have: the divisors of 256 (a bin is 256 / bins grey levels).
BIN_COUNTS = (2, 4, 8, 16, 32, 64, 128, 256)


def _check_bins(bins: object) -> int:
    bins = check_positive_int(bins, "bins", minimum=2, maximum=MAX_SIDE)
    return check_choice(bins, "bins", BIN_COUNTS)  # a divisor of 256


def bin_index_image(frame: np.ndarray, bins: int) -> np.ndarray:
    """b(z) of eq. (8) for every pixel: the index of its RGB bin in a ``bins³`` histogram."""
    shift = 8 - int(np.log2(bins)) if bins & (bins - 1) == 0 else None
    if shift is not None:
        q = frame.astype(np.int32) >> shift
    else:
        q = frame.astype(np.int32) * bins // 256
    return (q[..., 0] * bins + q[..., 1]) * bins + q[..., 2]


COLOR_SPACES = ("rgb", "hsv")


def _to_color_space(frame: np.ndarray, color_space: str) -> np.ndarray:
    """The frame in the colour space whose channels the histogram bins: RGB as given, or HSV (check-free).

    Parameters
    ----------
    frame : numpy.ndarray
        (H, W, 3) uint8 RGB image.
    color_space : str
        ``"rgb"`` (returned unchanged) or ``"hsv"`` (OpenCV's full-range HSV: hue, saturation and
        value each on 0-255).

    Returns
    -------
    numpy.ndarray
        (H, W, 3) uint8 image.

    References
    ----------
    Li & Chaumette, AMDO 2004, eq. (8) (bins in RGB); Pérez et al., ECCV 2002 (HSV bins), an ablation.
    """
    if color_space == "rgb":
        return frame
    import cv2

    return cv2.cvtColor(np.ascontiguousarray(frame, dtype=np.uint8), cv2.COLOR_RGB2HSV_FULL)


def kernel_histogram(frame: np.ndarray, ellipse: np.ndarray, bins: int = 32) -> np.ndarray:
    """Eq. (8), the plain way: the kernel-weighted RGB histogram of the pixels inside an ellipse.

    Every pixel centre z_i inside the ellipse ``(cx, cy, a, b, angle)`` adds ``K(r²) = 1 - r²`` to
    its bin, r being its normalised elliptical radius (eq. 7 with the profile 1 - r²: eq. 8 feeds
    the squared norm to K, which we read as the Epanechnikov profile, as in Comaniciu et al.).

    Parameters
    ----------
    frame : numpy.ndarray
        (H, W, 3) uint8 RGB image.
    ellipse : numpy.ndarray
        (5,) ellipse ``(cx, cy, a, b, angle)``.
    bins : int
        Bins per channel; must divide 256.

    Returns
    -------
    numpy.ndarray
        (bins³,) histogram summing to 1 (all zeros if no pixel of the ellipse lies in the frame).

    References
    ----------
    Li & Chaumette, AMDO 2004, eqs. (7)-(8); Comaniciu, Ramesh & Meer, CVPR 2000.
    """
    frame = check_frame(frame)
    bins = _check_bins(bins)
    cx, cy, a, b, angle = as_finite_array(ellipse, "ellipse", shape=(5,))
    height, width, _ = frame.shape
    ys, xs = np.mgrid[0:height, 0:width]
    c, s = np.cos(angle), np.sin(angle)
    u = ((xs - cx) * c + (ys - cy) * s) / a
    v = (-(xs - cx) * s + (ys - cy) * c) / b
    r_squared = u**2 + v**2
    inside = r_squared < 1.0
    weights = 1.0 - r_squared[inside]  # eq. (7), constant c cancels in eq. (8)
    # eq. (8): kernel-weighted count of the pixels of each colour bin, normalised by the total weight
    histogram = np.bincount(bin_index_image(frame, bins)[inside], weights=weights, minlength=bins**3).astype(float)
    total = histogram.sum()  # (bincount of no pixel gives int zeros: the astype keeps the dtype float)
    return histogram / total if total > 0 else histogram


def bhattacharyya(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Eq. (10): ρ = Σ_u sqrt(p_u q_u), along the last axis.

    Parameters
    ----------
    p, q : numpy.ndarray
        Histograms (at least 1-D, bins in [0, 1] summing to 1 along the last axis).

    Returns
    -------
    numpy.ndarray or float
        The Bhattacharyya coefficient, in [0, 1].

    References
    ----------
    Li & Chaumette, AMDO 2004, eq. (10).
    """
    p = as_finite_array(p, "p", bounds=(0.0, 1.0))  # bins of a histogram that sums to 1
    q = as_finite_array(q, "q", bounds=(0.0, 1.0))
    if p.ndim == 0 or q.ndim == 0 or p.shape[-1] != q.shape[-1]:  # which one is at fault is unknowable: name both
        raise ValueError(f"p and q must be histograms with the same number of bins, got shapes {p.shape} and {q.shape}")
    return np.sum(np.sqrt(p * q), axis=-1)  # eq. (10): ρ = Σ_u √(p_u q_u)


class ColorLikelihood:
    """Colour cue, eqs. (7)-(11): ``log p_c = -(1 - ρ)/(2 σ_c²) - log(√(2π) σ_c)``.

    Parameters
    ----------
    shape_space : ShapeSpace
        Maps states to ellipses.
    reference_frame, reference_state : numpy.ndarray
        The model histogram q̂ is taken from this (H, W, 3) frame inside this (3,) state's ellipse
        (the paper uses a face detector for it; we use the initial state); the state's entries
        within ±:data:`MAX_PIXELS`.
    bins : int
        Bins per channel (32 for the head, Table 1); must divide 256.
    sigma : float
        σ_c, in :data:`SIGMA_RANGE`.
    stride : float
        Spacing of the sample grid in pixels at scale 1 (see Notes), > 0 and small enough to leave
        a grid point inside the template's ellipse (at most about its smaller semi-axis).
    color_space : str
        ``"rgb"`` (the paper) or ``"hsv"`` (the frames converted by :func:`_to_color_space` before
        binning; an ablation).

    Notes
    -----
    The fast path evaluates eq. (8) on a fixed grid of points of the unit disc, scaled to each
    particle's ellipse (``stride`` = 1 is one point per pixel at the template's size), and only over
    the bins where q̂ is non-zero: the other bins add nothing to ρ but still count in the
    normalisation. :func:`kernel_histogram` is the per-pixel reference.

    References
    ----------
    Li & Chaumette, AMDO 2004, eqs. (7)-(11).
    """

    def __init__(self, shape_space: ShapeSpace, reference_frame: np.ndarray, reference_state: np.ndarray, *,
                 bins: int = 32, sigma: float = 5.0, stride: float = 2.0, color_space: str = "rgb"):
        self.shape_space = check_instance(shape_space, "shape_space", ShapeSpace, what="a ShapeSpace")
        self.bins = _check_bins(bins)
        self.sigma = check_in_range(sigma, "sigma", *SIGMA_RANGE, closed="both")
        self.stride = check_positive(stride, "stride")
        self.color_space = check_choice(color_space, "color_space", COLOR_SPACES)
        reference_frame = check_frame(reference_frame, "reference_frame")
        reference_state = as_finite_array(reference_state, "reference_state", shape=(shape_space.state_dim,), max_abs=MAX_PIXELS)
        self.target = kernel_histogram(_to_color_space(reference_frame, self.color_space),
                                       shape_space.ellipses(reference_state)[0], self.bins)
        support = np.flatnonzero(self.target)
        self._sqrt_target = np.sqrt(self.target[support])
        # lookup: bin -> position in the target's support, or len(support) for "any other bin"
        self._lookup = np.full(self.bins**3, support.size, np.int32)
        self._lookup[support] = np.arange(support.size)
        _, _, a, b, _ = shape_space.template_ellipse
        gx, gy = np.meshgrid(np.arange(-a, a + 1e-9, self.stride) / a, np.arange(-b, b + 1e-9, self.stride) / b)
        keep = gx**2 + gy**2 < 1.0
        if not keep.any():  # no sample point: every histogram would be 0/0
            raise ValueError(f"stride must leave a sample point inside the template ellipse ({a:.3g} × {b:.3g} px), "
                             f"got {self.stride:g}")
        self._unit_points = np.stack([gx[keep], gy[keep]], axis=1)  # points of the unit disc
        self._kernel = 1.0 - np.sum(self._unit_points**2, axis=1)  # eq. (7), profile 1 - r²

    def rho(self, frame: np.ndarray, states: np.ndarray) -> np.ndarray:
        """The Bhattacharyya coefficient ρ(q̂, p̂(x)) of eq. (10) for each state, by the fast path.

        :func:`bhattacharyya` is the plain per-histogram formula it is tested against.

        Parameters
        ----------
        frame : numpy.ndarray
            (H, W, 3) uint8 RGB image.
        states : numpy.ndarray
            (N, 3) or (3,) states.

        Returns
        -------
        numpy.ndarray
            (N,) Bhattacharyya coefficients.
        """
        frame = check_frame(frame)
        ellipses = self.shape_space.ellipses(states)
        n = len(ellipses)
        height, width, _ = frame.shape
        cos, sin = np.cos(ellipses[:, 4:5]), np.sin(ellipses[:, 4:5])
        u = self._unit_points[:, 0] * ellipses[:, 2:3]
        v = self._unit_points[:, 1] * ellipses[:, 3:4]
        xs = np.rint(ellipses[:, 0:1] + u * cos - v * sin).astype(np.int32)
        ys = np.rint(ellipses[:, 1:2] + u * sin + v * cos).astype(np.int32)
        on_frame = (xs >= 0) & (xs < width) & (ys >= 0) & (ys < height)
        support = self._sqrt_target.size
        compact = self._lookup[bin_index_image(_to_color_space(frame, self.color_space), self.bins)]
        # off-frame points go to the "other bins" slot: they lower ρ as missing colour would
        slot = np.where(on_frame, compact[np.clip(ys, 0, height - 1), np.clip(xs, 0, width - 1)], support)
        flat = slot + (support + 1) * np.arange(n)[:, None]
        weights = np.broadcast_to(self._kernel, slot.shape)
        histograms = np.bincount(flat.ravel(), weights=weights.ravel(), minlength=n * (support + 1))
        histograms = histograms.reshape(n, support + 1) / self._kernel.sum()  # eq. (8)
        return histograms[:, :support].clip(min=0.0) ** 0.5 @ self._sqrt_target  # eq. (10)

    def distance(self, frame: np.ndarray, states: np.ndarray) -> np.ndarray:
        """1 - ρ, the squared distance of eq. (9), for each state.

        Parameters
        ----------
        frame : numpy.ndarray
            (H, W, 3) uint8 RGB image.
        states : numpy.ndarray
            (N, 3) or (3,) states.

        Returns
        -------
        numpy.ndarray
            (N,) distances in [0, 1].
        """
        return 1.0 - self.rho(frame, states)  # eq. (9) squared: d² = 1 - ρ

    def log_likelihood(self, frame: np.ndarray, states: np.ndarray) -> np.ndarray:
        """Eq. (11) in the log domain, for each state.

        Parameters
        ----------
        frame : numpy.ndarray
            (H, W, 3) uint8 RGB image.
        states : numpy.ndarray
            (N, 3) or (3,) states.

        Returns
        -------
        numpy.ndarray
            (N,) log-likelihoods.
        """
        # ln of eq. (11): p_c = exp(-(1 - ρ)/2σ_c²) / (√(2π) σ_c)
        return _gaussian_log_likelihood(self.distance(frame, states), self.sigma)


def _gaussian_log_likelihood(distance: np.ndarray, sigma: float) -> np.ndarray:
    """``ln[exp(-d / 2σ²) / (√(2π) σ)]``: the log-likelihood of eqs. (11) and (12) at the distances ``d``."""
    return -distance / (2.0 * sigma**2) - np.log(np.sqrt(2.0 * np.pi) * sigma)


# --- edges: eqs. (13)-(14) ----------------------------------------------------------------------

def edge_line_likelihood(offsets: np.ndarray, p0: float, clutter_density: float, sigma_e: float) -> float:
    """Eq. (13) for one measurement line: ``P0 + (1 - P0)/λ Σ_j N(z_j; 0, σ_e²)``.

    This is the likelihood of the line's features ``z_j`` (distances from the contour, pixels)
    divided by their likelihood when all are clutter, ``exp(-λL) λ^n``: with Poisson clutter of
    density λ uniform on the line, the edge missed with probability P0, and found at a Gaussian
    offset otherwise (see the chapter for the two-line derivation).

    Parameters
    ----------
    offsets : array_like
        Distances z_j of the line's features from the contour, pixels (may be empty), within
        ±:data:`MAX_PIXELS`.
    p0 : float
        P0, in (0, 1).
    clutter_density : float
        λ, clutter features per pixel, > 0.
    sigma_e : float
        σ_e in pixels, in (0, :data:`MAX_PIXELS`].

    Returns
    -------
    float
        The value of eq. (13).

    References
    ----------
    Li & Chaumette, AMDO 2004, eq. (13); MacCormick, PhD thesis, Oxford (2000).
    """
    offsets = as_finite_array(offsets, "offsets", ndim=1, allow_empty=True, max_abs=MAX_PIXELS)
    p0 = check_in_range(p0, "p0", 0.0, 1.0)
    clutter_density = check_positive(clutter_density, "clutter_density")
    sigma_e = check_in_range(sigma_e, "sigma_e", 0.0, MAX_PIXELS, closed="right")
    gauss = np.exp(-offsets**2 / (2.0 * sigma_e**2)) / (np.sqrt(2.0 * np.pi) * sigma_e)
    # eq. (13): p_0 + (1 - p_0)/λ Σ_m N(z_m; 0, σ_e²), the likelihood ratio of one measurement line
    return float(p0 + (1.0 - p0) / clutter_density * gauss.sum())


def simulate_measurement_lines(n_lines: int, *, half_length: float, p0: float, clutter_density: float,
                               sigma_e: float, rng: int | np.random.Generator) -> list[np.ndarray]:
    """Feature offsets on ``n_lines`` lines drawn from the assumptions of eq. (13).

    Each line spans ``[-half_length, half_length]``; clutter is Poisson with density λ per pixel,
    uniform; the true edge (at offset 0) is detected with probability 1 - P0, at a N(0, σ_e²) offset.

    Parameters
    ----------
    n_lines : int
        Number of lines. At most :data:`amdo_lab.common.MAX_SAMPLES` (1,000,000).
    half_length : float
        L/2 in pixels, in (0, :data:`MAX_PIXELS`].
    p0 : float
        P0, the probability that the edge is missed, in (0, 1).
    clutter_density : float
        λ, clutter features per pixel, in [0, :data:`MAX_CLUTTER_DENSITY`] (at most one per pixel).
    sigma_e : float
        σ_e in pixels, in (0, :data:`MAX_PIXELS`].
    rng : int or numpy.random.Generator
        Source of the draws.

    Returns
    -------
    list of numpy.ndarray
        For each line, the offsets of its features (clutter, then the edge when detected).

    References
    ----------
    Li & Chaumette, AMDO 2004, the assumptions above eq. (13); MacCormick (2000).
    """
    generator = make_rng(rng, "rng")
    n_lines = check_positive_int(n_lines, "n_lines", maximum=MAX_SAMPLES)
    half_length = check_in_range(half_length, "half_length", 0.0, MAX_PIXELS, closed="right")
    p0 = check_in_range(p0, "p0", 0.0, 1.0)
    clutter_density = check_in_range(clutter_density, "clutter_density", 0.0, MAX_CLUTTER_DENSITY, closed="both")
    sigma_e = check_in_range(sigma_e, "sigma_e", 0.0, MAX_PIXELS, closed="right")
    counts = generator.poisson(clutter_density * 2.0 * half_length, n_lines)
    clutter = generator.uniform(-half_length, half_length, counts.sum())
    edges = generator.normal(0.0, sigma_e, n_lines)
    # the edge is kept when detected (probability 1 - P0) and on the line
    found = (generator.random(n_lines) > p0) & (np.abs(edges) <= half_length)
    lines = np.split(clutter, np.cumsum(counts)[:-1])
    return [np.append(line, edge) if keep else line for line, edge, keep in zip(lines, edges, found)]


class EdgeLikelihood:
    """Edge cue, eqs. (13)-(14), on ``n_lines`` normals to the contour.

    Parameters
    ----------
    shape_space : ShapeSpace
        Gives each particle's contour points and normals.
    n_lines : int
        N_e (40 for the head, Table 1), 3 to :data:`amdo_lab.common.MAX_SAMPLES` (1,000,000).
    half_length : int
        L/2 in pixels (not given by the paper; ours: 12), 2 to :data:`amdo_lab.common.MAX_SIDE` (4,096).
    p0 : float
        P0, probability that the edge is not detected, in (0, 1) (0.2).
    sigma_e : float
        σ_e in pixels, in (0, :data:`MAX_PIXELS`] (√2).
    threshold : float
        Smallest gradient magnitude of a feature, grey levels per pixel, in (0, 255] (the central
        difference of grey levels never exceeds 127.5 per pixel).
    exponent : float
        α in (0, 1]: the log-likelihood of eq. (14) is multiplied by α (the product of the lines
        raised to the power α, a *tempered* likelihood). 1 is the paper's eq. (14); α < 1 counts the
        N_e lines as α·N_e independent pieces of evidence, for lines that share their edges and clutter.

    Notes
    -----
    A "1-D Canny" on each line: the grey image is smoothed once per frame (σ =
    :data:`EDGE_SMOOTHING_PX`), sampled along the line at 1 px steps (bilinear), differentiated with a central difference, and the local maxima of
    the magnitude above ``threshold`` are the features. λ, the clutter density, is not given by
    the paper: we estimate it per frame as the mean number of features per line divided by L.

    References
    ----------
    Li & Chaumette, AMDO 2004, eqs. (13)-(14); MacCormick (2000).
    """

    def __init__(self, shape_space: ShapeSpace, *, n_lines: int = 40, half_length: int = 12, p0: float = 0.2,
                 sigma_e: float = float(np.sqrt(2.0)), threshold: float = 6.0, exponent: float = 1.0):
        self.shape_space = check_instance(shape_space, "shape_space", ShapeSpace, what="a ShapeSpace")
        self.n_lines = check_positive_int(n_lines, "n_lines", minimum=3, maximum=MAX_SAMPLES)
        self.half_length = check_positive_int(half_length, "half_length", minimum=2, maximum=MAX_SIDE)
        self.p0 = check_in_range(p0, "p0", 0.0, 1.0)
        self.sigma_e = check_in_range(sigma_e, "sigma_e", 0.0, MAX_PIXELS, closed="right")
        self.threshold = check_in_range(threshold, "threshold", 0.0, 255.0, closed="right")
        self.exponent = check_in_range(exponent, "exponent", 0.0, 1.0, closed="right")
        self._points, self._normals = shape_space.template_normals(self.n_lines)
        self.offsets = np.arange(-self.half_length, self.half_length + 1, dtype=float)
        self.clutter_density = float("nan")  # λ of the last frame seen

    def grey(self, frame: np.ndarray) -> np.ndarray:
        """The smoothed grey image the lines are read from.

        Parameters
        ----------
        frame : numpy.ndarray
            (H, W, 3) uint8 RGB image.

        Returns
        -------
        numpy.ndarray
            (H, W) float32 grey levels.
        """
        grey = check_frame(frame).astype(np.float32).mean(axis=2)
        return cv2.GaussianBlur(grey, (0, 0), EDGE_SMOOTHING_PX)

    def profiles(self, frame: np.ndarray, states: np.ndarray, *, reference: bool = False) -> np.ndarray:
        """Grey levels (N, N_e, 2L+1) along every measurement line of every state.

        ``reference=True`` samples with the plain-numpy :func:`_bilinear`; the default uses
        ``cv2.remap`` (the same bilinear interpolation, several times faster).

        Parameters
        ----------
        frame : numpy.ndarray
            (H, W, 3) uint8 RGB image.
        states : numpy.ndarray
            (N, 3) or (3,) states.
        reference : bool
            Use the plain-numpy reference path.

        Returns
        -------
        numpy.ndarray
            (N, N_e, 2L+1) grey levels.
        """
        grey = self.grey(frame)
        states = np.atleast_2d(self.shape_space.check_states(states))
        reference = check_bool(reference, "reference")
        if len(states) == 0:  # no particles: no lines to read (cv2.remap refuses an empty map)
            return np.empty((0, self.n_lines, self.offsets.size), np.float32)
        if reference:  # contour point t + k R p and normal R n of each line (eqs. 2-3: k, R of the state)
            scale, rotation = self.shape_space.similarity_parts(states)
            centres = states[:, None, :2] + scale[:, None, None] * np.einsum("nij,lj->nli", rotation, self._points)
            normals = np.einsum("nij,lj->nli", rotation, self._normals)  # (N, N_e, 2)
            samples = centres[:, :, None, :] + self.offsets[:, None] * normals[:, :, None, :]  # (N, N_e, 2L+1, 2)
            return _bilinear(grey, samples[..., 0], samples[..., 1])
        # the same sample positions, built axis by axis in single precision
        states32 = states.astype(np.float32)
        scale, rotation = (part.astype(np.float32) for part in self.shape_space.similarity_parts(states32))
        scale = scale[:, None, None]
        (r00, r01), (r10, r11) = rotation.transpose(1, 2, 0)[..., None, None]  # each (N, 1, 1)
        offsets = self.offsets.astype(np.float32)[None, None, :]
        (px, py), (nx, ny) = (part.astype(np.float32).T[:, None, :, None] for part in (self._points, self._normals))
        map_x = states32[:, 0, None, None] + scale * (r00 * px + r01 * py) + offsets * (r00 * nx + r01 * ny)
        map_y = states32[:, 1, None, None] + scale * (r10 * px + r11 * py) + offsets * (r10 * nx + r11 * ny)
        n, n_lines, n_offsets = map_x.shape
        sampled = cv2.remap(grey, map_x.reshape(n * n_lines, n_offsets), map_y.reshape(n * n_lines, n_offsets),
                            cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
        return sampled.reshape(n, n_lines, n_offsets)

    def features(self, frame: np.ndarray, states: np.ndarray, *, reference: bool = False):
        """The features of every line: (state, line) indices and sub-pixel offsets z_j, pixels.

        A feature is a local maximum of the magnitude of the central difference along the line,
        above ``threshold``, its position refined by a parabola through the three samples.

        Parameters
        ----------
        frame : numpy.ndarray
            (H, W, 3) uint8 RGB image.
        states : numpy.ndarray
            (N, 3) or (3,) states.
        reference : bool
            Use the plain-numpy reference path.

        Returns
        -------
        tuple of numpy.ndarray
            State indices, line indices and offsets z_j (pixels) of every feature found.
        """
        profile = self.profiles(frame, states, reference=reference)
        gradient = 0.5 * np.abs(profile[..., 2:] - profile[..., :-2])  # at offsets[1:-1]
        middle, left, right = gradient[..., 1:-1], gradient[..., :-2], gradient[..., 2:]
        state_index, line_index, position = np.nonzero((middle >= left) & (middle > right) & (middle > self.threshold))
        g0 = left[state_index, line_index, position]
        g1 = middle[state_index, line_index, position]
        g2 = right[state_index, line_index, position]
        curvature = g0 - 2.0 * g1 + g2
        shift = np.where(curvature < 0, 0.5 * (g0 - g2) / np.where(curvature < 0, curvature, -1.0), 0.0)
        return state_index, line_index, self.offsets[2:-2][position] + shift

    def log_likelihood(self, frame: np.ndarray, states: np.ndarray, *, reference: bool = False) -> np.ndarray:
        """Eq. (14) in the log domain: the sum over lines of log eq. (13).

        Parameters
        ----------
        frame : numpy.ndarray
            (H, W, 3) uint8 RGB image.
        states : numpy.ndarray
            (N, 3) or (3,) states.
        reference : bool
            Use the plain-numpy reference path.

        Returns
        -------
        numpy.ndarray
            (N,) log-likelihoods, times ``exponent`` (λ of this frame is kept in ``clutter_density``).
        """
        states = np.atleast_2d(self.shape_space.check_states(states))
        n = len(states)
        state_index, line_index, offsets = self.features(frame, states, reference=reference)
        if n == 0:  # no particles (λ of this frame is left as it was)
            return np.empty(0)
        length = 2.0 * self.half_length
        self.clutter_density = max(len(offsets) / (n * self.n_lines), 0.5) / length  # λ per pixel, this frame
        gauss = np.exp(-offsets**2 / (2.0 * self.sigma_e**2)) / (np.sqrt(2.0 * np.pi) * self.sigma_e)
        sums = np.bincount(state_index * self.n_lines + line_index, weights=gauss, minlength=n * self.n_lines)
        line = self.p0 + (1.0 - self.p0) / self.clutter_density * sums  # eq. (13)
        return self.exponent * np.log(line).reshape(n, self.n_lines).sum(axis=1)  # eq. (14), tempered by α


def _bilinear(image: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Bilinear samples of ``image`` at (x, y), clamped to the border."""
    height, width = image.shape
    x = np.clip(x, 0.0, width - 1.001)
    y = np.clip(y, 0.0, height - 1.001)
    x0, y0 = x.astype(np.int32), y.astype(np.int32)
    fx, fy = x - x0, y - y0
    top = image[y0, x0] * (1 - fx) + image[y0, x0 + 1] * fx
    bottom = image[y0 + 1, x0] * (1 - fx) + image[y0 + 1, x0 + 1] * fx
    return top * (1 - fy) + bottom * fy


# --- fusion: eq. (6) ----------------------------------------------------------------------------

def check_cues(cues: object) -> dict:
    """Return ``cues`` after checking it is a dict of likelihood objects (each with ``.log_likelihood``).

    Parameters
    ----------
    cues : dict
        Name -> likelihood object (:class:`ColorLikelihood`, :class:`EdgeLikelihood`, ...), at least one;
        each has ``.log_likelihood(frame, states)`` and ``.shape_space``.

    Returns
    -------
    dict
        ``cues``.

    References
    ----------
    Li & Chaumette, AMDO 2004, eq. (6) (the cues fused).
    """
    if not isinstance(cues, dict) or not cues or not all(isinstance(getattr(cue, "shape_space", None), ShapeSpace)
                                                          and hasattr(cue, "log_likelihood") for cue in cues.values()):
        raise TypeError(f"cues must be a non-empty dict of likelihood objects (with .log_likelihood and .shape_space), "
                        f"got {type(cues).__name__}")
    return cues


def fused_log_likelihood(cues: dict, frame: np.ndarray, states: np.ndarray) -> np.ndarray:
    """Eq. (6) in the log domain: the sum of the cues' log-likelihoods (independent cues).

    Parameters
    ----------
    cues : dict
        Name -> likelihood object with ``.log_likelihood(frame, states)``.
    frame : numpy.ndarray
        (H, W, 3) uint8 RGB image.
    states : numpy.ndarray
        (N, 3) states.

    Returns
    -------
    numpy.ndarray
        (N,) fused log-likelihoods.

    References
    ----------
    Li & Chaumette, AMDO 2004, eq. (6).
    """
    cues = check_cues(cues)
    # eq. (6) in the log domain: the product of the cues' likelihoods is a sum (each cue checks the frame and the states)
    return sum(cue.log_likelihood(frame, states) for cue in cues.values())


# --- calibration of σ ---------------------------------------------------------------------------

@dataclass(frozen=True)
class CalibrationResult:
    """The σ with the best mean log score, the grid searched and the score at each σ.

    Parameters
    ----------
    sigma : float
        The chosen σ.
    grid : numpy.ndarray
        The σ values tried.
    scores : numpy.ndarray
        Mean log score at each σ.

    References
    ----------
    Li & Chaumette, AMDO 2004, Table 1 (σ_c, σ_s set "empirically").
    """

    sigma: float
    grid: np.ndarray
    scores: np.ndarray


def calibrate_sigma(distances_true: np.ndarray, distances_prior: np.ndarray, grid: np.ndarray | None = None) -> CalibrationResult:
    """Choose σ in ``exp(-d / (2σ²))`` by the log score of the true state against prior samples.

    For each calibration frame ``t`` we have the cue's distance ``d*_t`` at the true state and
    ``d_{t,i}`` at N states drawn from the dynamics around the truth. The score of σ is the mean
    over frames of ``log w*`` with ``w* = exp(-d*/2σ²) / mean_i exp(-d_i/2σ²)``: the weight the filter
    would give the truth relative to an average particle. Too large a σ makes every weight 1 (score
    0); too small a σ punishes every frame where a prior sample looks better than the truth.

    Parameters
    ----------
    distances_true : numpy.ndarray
        (T,) distances at the true states, within ±:data:`MAX_DISTANCE` (the cues' distances lie
        in [0, 1]).
    distances_prior : numpy.ndarray
        (T, N) distances at the prior samples, likewise bounded.
    grid : numpy.ndarray, optional
        σ values to try, in :data:`SIGMA_RANGE` (default: 60 log-spaced values from 0.005 to 10).

    Returns
    -------
    CalibrationResult
        The best σ, the grid and the scores.

    References
    ----------
    Li & Chaumette, AMDO 2004, eqs. (11)-(12) and Table 1.
    """
    distances_prior = as_finite_array(distances_prior, "distances_prior", ndim=2, max_abs=MAX_DISTANCE)
    # one distance at the truth per frame, i.e. per row of distances_prior
    distances_true = as_finite_array(distances_true, "distances_true", shape=(len(distances_prior),), max_abs=MAX_DISTANCE)
    grid = np.geomspace(0.005, 10.0, 60) if grid is None else as_finite_array(grid, "grid", ndim=1, bounds=SIGMA_RANGE)
    scores = []
    for sigma in grid:
        log_prior = -distances_prior / (2.0 * sigma**2)
        peak = log_prior.max(axis=1)
        log_mean = peak + np.log(np.mean(np.exp(log_prior - peak[:, None]), axis=1))
        scores.append(np.mean(-distances_true / (2.0 * sigma**2) - log_mean))
    scores = np.array(scores)
    return CalibrationResult(float(grid[np.argmax(scores)]), grid, scores)
