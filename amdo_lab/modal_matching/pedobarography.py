"""A seeded synthetic dynamic pedobarography sequence, with the truth of every node's partner.

Twelve anisotropic Gaussian loads (heel, lateral midfoot, the five metatarsal heads, hallux and four
lesser toes) rise and fall on a stance schedule; each frame is the pressure on a pixel grid plus
noise, with the pixels under a calibration floor set to zero and a Gaussian filter applied (Sec. 3.2,
step 1). The pressure is also available as an analytic field, which the filter only widens: from it,
a node's partner on another contour is where the field's gradient flow carries it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage
from skimage import measure

from amdo_lab.common import (MAX_SAMPLES, MAX_SIDE, as_finite_array, check_choice, check_in_range, check_instance,
                             check_positive, check_positive_int, make_rng)
from amdo_lab.modal_matching.element import MAX_COORDINATE_MM, check_nodes, check_same_dimension, mean_spacing
from amdo_lab.modal_matching.matching import _check_index_pairs

__all__ = ["LOAD_NAMES", "ObjectPair", "PAPER_PAIRS", "PedobarographySequence", "SURFACE_BOX_MM", "correct_share",
           "frame_pair",
           "make_pedobarography_sequence", "move_object", "paper_pair"]

_REFERENCE = ("Bastos & Tavares. Improvement of Modal Matching Image Objects in Dynamic Pedobarography Using "
              "Optimization Techniques. AMDO 2004, LNCS 3179, Sec. 2-3.")

#: The twelve loads, heel to toes.
LOAD_NAMES = ("heel", "lateral midfoot", "M1", "M2", "M3", "M4", "M5", "hallux", "toe 2", "toe 3", "toe 4", "toe 5")
# per load: centre x, y (mm), standard deviations along x, y (mm), tilt (rad), peak (kPa),
# time of the peak and its spread (fractions of the stance)
_LOADS = np.array([
    [80, 62, 17, 21, 0.00, 260, 0.22, 0.20],
    [108, 125, 13, 34, 0.10, 90, 0.45, 0.25],
    [58, 205, 11, 11, 0.00, 230, 0.68, 0.20],
    [74, 212, 9, 10, 0.00, 200, 0.66, 0.20],
    [89, 210, 9, 10, 0.00, 170, 0.64, 0.20],
    [103, 203, 9, 10, 0.00, 140, 0.62, 0.20],
    [117, 190, 10, 11, 0.20, 120, 0.60, 0.20],
    [57, 262, 11, 13, 0.00, 200, 0.82, 0.14],
    [80, 258, 6, 7, 0.00, 90, 0.80, 0.14],
    [93, 252, 6, 7, 0.00, 80, 0.79, 0.14],
    [105, 245, 6, 6, 0.00, 70, 0.78, 0.14],
    [116, 236, 6, 6, 0.00, 60, 0.77, 0.14],
])
#: The pairs of Tables 1-3, as (frame, level in kPa, nodes) of object 1 and of object 2: the foot's
#: outline at the calibration level in two consecutive frames (64 and 58 nodes, as printed), two
#: isobars of the heel in the second frame (54 and 46 nodes), and the heel's pressure surface in the
#: two frames (every 3rd pixel). The frames and levels are our choice.
PAPER_PAIRS = {"contours": ((4, 15.0, 64), (5, 15.0, 58)), "isobars": ((5, 100.0, 54), (5, 120.0, 46)),
               "surfaces": ((4, 50.0, 3), (5, 50.0, 3))}
#: Table 3's surfaces: the heel's circumscribing rectangle (x0, x1, y0, y1 in mm) sampled every
#: ``nodes`` pixels (the third entry of the "surfaces" pair) where the pressure reaches the level.
SURFACE_BOX_MM = (30.0, 130.0, 0.0, 110.0)
#: The plate: rows (heel to toes) and columns of a frame, and the pixel size (mm).
PLATE_SHAPE_PX = (150, 80)
MM_PER_PX = 2.0
#: The sensor: standard deviation of the pixel noise (kPa), calibration floor (kPa), and standard
#: deviation of the Gaussian filter applied after the floor (pixels).
NOISE_KPA = 3.0
FLOOR_KPA = 8.0
FILTER_PX = 1.0
#: Sub-steps of the field's gradient flow between the start and the end isobar.
FOLLOW_STEPS = 16
#: Largest pressure (kPa) accepted as a level: a thousand times a foot's peak.
MAX_PRESSURE_KPA = 1e6
#: Latest time (frames) the field is evaluated at: far beyond any step, and (t - t_k)^2 stays finite.
MAX_TIME_FRAMES = 1e6
#: Longest Newton step (mm) of the field's gradient flow, so flat regions do not throw a point away.
_MAX_NEWTON_STEP_MM = 2.0
#: Standard deviations of the seeded perturbations: centres (mm), log peaks, peak times (stance).
_JITTER = (3.0, 0.10, 0.02)


@dataclass(frozen=True)
class PedobarographySequence:
    """Pressure images of one step, and the analytic field behind them.

    Parameters
    ----------
    frames : ndarray, shape (n_frames, rows, cols)
        Pressure (kPa) per pixel after the calibration floor and the Gaussian filter.
    mm_per_px : float
        Pixel size (mm); pixel (r, c) is at x = c mm_per_px, y = r mm_per_px.
    centres, covariances, peaks, peak_times, spreads : ndarray
        The loads: centres (12, 2) in mm, covariances (12, 2, 2) in mm^2 including the filter's
        widening, peaks (12,) in kPa after it, times of the peaks and their spreads in frames.
    floor : float
        The calibration floor (kPa).

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 2 and 3.2 (step 1).
    """

    frames: np.ndarray
    mm_per_px: float
    centres: np.ndarray
    covariances: np.ndarray
    peaks: np.ndarray
    peak_times: np.ndarray
    spreads: np.ndarray
    floor: float

    def pressure(self, xy_mm: np.ndarray, t: float) -> np.ndarray:
        """The analytic pressure at some points and time, the filter's widening included.

        Parameters
        ----------
        xy_mm : ndarray, shape (p, 2)
            Points (mm).
        t : float
            Time (frames), in [0, 1e6].

        Returns
        -------
        ndarray, shape (p,)
            Pressure (kPa).
        """
        xy = as_finite_array(xy_mm, "xy_mm", ndim=2, shape=(None, 2), max_abs=MAX_COORDINATE_MM)
        value, _ = self._field(xy, check_in_range(t, "t", 0.0, MAX_TIME_FRAMES, closed="both"))
        return value

    def _field(self, xy: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray]:
        """Pressure and its gradient (kPa/mm) at points xy (p, 2) and time t."""
        weights = self.peaks * np.exp(-0.5 * ((t - self.peak_times) / self.spreads) ** 2)
        precision = np.linalg.inv(self.covariances)
        d = xy[:, None, :] - self.centres[None]
        Pd = np.einsum("kab,pkb->pka", precision, d)
        loads = weights * np.exp(-0.5 * np.einsum("pka,pka->pk", d, Pd))
        return loads.sum(axis=1), -np.einsum("pk,pka->pa", loads, Pd)

    def contour(self, frame: int, level: float, n_nodes: int) -> np.ndarray:
        """The longest closed isobar of a frame at ``level`` kPa, resampled to ``n_nodes`` nodes.

        Parameters
        ----------
        frame : int
            Index of the frame.
        level : float
            Pressure (kPa), above the calibration floor.
        n_nodes : int
            Nodes of the resampled contour, at least 4 and at most 1,000,000.

        Returns
        -------
        ndarray, shape (n_nodes, 2)
            Nodes (mm), counter-clockwise, equally spaced along the contour, the first the lowest
            (smallest y) point.
        """
        frame = check_positive_int(frame, "frame", minimum=0, maximum=self.frames.shape[0] - 1)
        level = check_positive(level, "level")
        n_nodes = check_positive_int(n_nodes, "n_nodes", minimum=4, maximum=MAX_SAMPLES)
        # a zero border closes the isobars that leave the plate
        padded = np.pad(self.frames[frame], 1)
        curves = [c - 1 for c in measure.find_contours(padded, level) if np.allclose(c[0], c[-1])]
        if not curves:
            raise ValueError(f"no closed contour at level {level:g} kPa in frame {frame}")
        longest = max(curves, key=len)
        return _resample_closed_curve(longest[:, ::-1] * self.mm_per_px, n_nodes)

    def _surface(self, frame: int, level: float, stride: int, z_scale: float = 1.0) -> np.ndarray:
        """The pressure surface of a frame as 3-D nodes (x, y, z) in mm, row by row: every ``stride``-th pixel
        inside the heel's rectangle :data:`SURFACE_BOX_MM` where the pressure reaches ``level`` kPa, with the
        pressure times ``z_scale`` (mm per kPa) as third coordinate (Sec. 3.2, steps 2-6)."""
        x0, x1, y0, y1 = SURFACE_BOX_MM
        image = self.frames[frame]
        rows, cols = np.mgrid[0:image.shape[0]:stride, 0:image.shape[1]:stride]
        x, y, p = cols * self.mm_per_px, rows * self.mm_per_px, image[rows, cols]
        inside = (x >= x0) & (x <= x1) & (y >= y0) & (y <= y1) & (p >= level)
        return np.c_[x[inside], y[inside], z_scale * p[inside]]

    def _follow(self, P: np.ndarray, t_from: float, level_from: float, t_to: float, level_to: float) -> np.ndarray:
        """Where the field's gradient flow carries points P (p, 2) from the isobar ``level_from`` at time
        ``t_from`` to the isobar ``level_to`` at ``t_to``: each of :data:`FOLLOW_STEPS` sub-steps moves the time
        and the level a little and projects every point back onto the current isobar along the gradient
        (Newton steps); between frames this is the isobar's normal motion, between levels the steepest ascent."""
        for fraction in np.linspace(0, 1, FOLLOW_STEPS + 1):
            t = t_from + fraction * (t_to - t_from)
            level = level_from + fraction * (level_to - level_from)
            for _ in range(4):
                value, grad = self._field(P, t)
                move = ((level - value) / np.maximum(np.sum(grad**2, axis=1), 1e-12))[:, None] * grad
                length = np.linalg.norm(move, axis=1, keepdims=True)  # damped where the field is flat
                P = P + move * np.minimum(1.0, _MAX_NEWTON_STEP_MM / np.maximum(length, 1e-300))
        return P


@dataclass(frozen=True)
class ObjectPair:
    """Two objects to match and where each node of the first truly goes.

    Parameters
    ----------
    X1, X2 : ndarray, shapes (m1, D) and (m2, D)
        The nodes (mm) of the two contours (D = 2, counter-clockwise) or surfaces (D = 3).
    truth : ndarray, shape (m1, D)
        Each node of ``X1`` carried by the pressure field's gradient flow onto ``X2``'s isobar, or,
        for surfaces, kept at its plate position with the pressure of object 2's frame.

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 5.
    """

    X1: np.ndarray
    X2: np.ndarray
    truth: np.ndarray


def check_pedobarography_sequence(sequence: object, name: str = "sequence") -> PedobarographySequence:
    """Return ``sequence`` after checking its fields' documented rules, or raise naming the field.

    ``frames`` finite (n_frames, rows, cols) pressures >= 0; ``mm_per_px`` > 0; the loads finite,
    ``centres`` (k, 2), ``covariances`` (k, 2, 2), ``peaks``, ``peak_times`` and ``spreads`` (k,),
    the peaks >= 0 and the spreads > 0; ``floor`` finite and >= 0. A sequence edited with
    ``dataclasses.replace`` is checked here, where :func:`paper_pair` receives it.

    Parameters
    ----------
    sequence : PedobarographySequence
        From :func:`make_pedobarography_sequence`.
    name : str
        The caller's argument, for the messages.

    Returns
    -------
    PedobarographySequence
        ``sequence``.
    """
    check_instance(sequence, name, PedobarographySequence)
    as_finite_array(sequence.frames, f"{name}.frames", ndim=3, bounds=(0.0, np.inf))
    check_positive(sequence.mm_per_px, f"{name}.mm_per_px")
    k = len(as_finite_array(sequence.centres, f"{name}.centres", shape=(None, 2)))
    as_finite_array(sequence.covariances, f"{name}.covariances", shape=(k, 2, 2))
    as_finite_array(sequence.peaks, f"{name}.peaks", shape=(k,), bounds=(0.0, np.inf))
    as_finite_array(sequence.peak_times, f"{name}.peak_times", shape=(k,))
    spreads = as_finite_array(sequence.spreads, f"{name}.spreads", shape=(k,))
    if np.any(spreads <= 0):
        raise ValueError(f"{name}.spreads must be positive")
    check_positive(sequence.floor, f"{name}.floor", allow_zero=True)
    return sequence


def paper_pair(sequence: PedobarographySequence, which: str) -> ObjectPair:
    """The contour pair of Table 1, the isobar pair of Table 2 or the surface pair of Table 3, with its truth.

    Parameters
    ----------
    sequence : PedobarographySequence
        From :func:`make_pedobarography_sequence` (15 frames).
    which : {"contours", "isobars", "surfaces"}
        Which pair of :data:`PAPER_PAIRS`.

    Returns
    -------
    ObjectPair
        Object 1, object 2 and the truth.

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 5, Tables 1 and 2.
    """
    check_pedobarography_sequence(sequence)
    which = check_choice(which, "which", tuple(PAPER_PAIRS))
    (t1, level1, n1), (t2, level2, n2) = PAPER_PAIRS[which]
    if sequence.frames.shape[0] <= max(t1, t2):
        raise ValueError(f"sequence must hold at least {max(t1, t2) + 1} frames")
    if which == "surfaces":  # the plate position is the truth: a node keeps its x and y
        x0, x1 = SURFACE_BOX_MM[:2]
        S1 = sequence._surface(t1, level1, n1)
        scale = (x1 - x0) / S1[:, 2].max()  # z spans the same range as x (Sec. 3.2, step 6)
        S1[:, 2] *= scale
        truth = np.c_[S1[:, :2], scale * sequence.pressure(S1[:, :2], t2)]
        return ObjectPair(S1, sequence._surface(t2, level2, n2, scale), truth)
    X1 = sequence.contour(t1, level1, n1)
    return ObjectPair(X1, sequence.contour(t2, level2, n2), sequence._follow(X1, t1, level1, t2, level2))


def frame_pair(sequence: PedobarographySequence, frame1: int, frame2: int, *, level: float = 15.0,
               nodes: tuple[int, int] = (64, 58)) -> ObjectPair:
    """The isobar at ``level`` in two frames, any gap apart, with its truth: a harder Table 1 pair.

    Parameters
    ----------
    sequence : PedobarographySequence
        From :func:`make_pedobarography_sequence`.
    frame1, frame2 : int
        The frames of object 1 and object 2 (indices into ``sequence.frames``).
    level : float
        The isobar's pressure (kPa); 15 kPa is the foot's outline of Table 1.
    nodes : tuple of int
        Nodes of object 1 and object 2, each 4 to 1,000,000 (Table 1's 64 and 58 by default).

    Returns
    -------
    ObjectPair
        Object 1, object 2 and the truth: object 1's nodes carried by the field's gradient flow from
        ``frame1`` to ``frame2``.

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 5 (consecutive frames only).
    """
    check_instance(sequence, "sequence", PedobarographySequence)
    if not isinstance(nodes, tuple) or len(nodes) != 2:
        raise TypeError(f"nodes must be a tuple of two counts, got {nodes!r}")
    X1 = sequence.contour(frame1, level, nodes[0])
    X2 = sequence.contour(frame2, level, nodes[1])
    return ObjectPair(X1, X2, sequence._follow(X1, float(frame1), float(level), float(frame2), float(level)))


def move_object(pair: ObjectPair, *, angle_deg: float, shift_mm: float) -> ObjectPair:
    """Turn object 2 (and the truth with it) about its centroid, then shift it along x.

    Parameters
    ----------
    pair : ObjectPair
        The objects and the truth.
    angle_deg : float
        Counter-clockwise turn (degrees), in [-360, 360].
    shift_mm : float
        Shift along x (mm), in [-1e6, 1e6].

    Returns
    -------
    ObjectPair
        Object 1 unchanged; object 2 and the truth moved rigidly.

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 4 (the modes are claimed to be close "even in the presence of an
    affine transformation").
    """
    check_instance(pair, "pair", ObjectPair)
    angle = np.deg2rad(check_in_range(angle_deg, "angle_deg", -360.0, 360.0, closed="both"))
    shift = check_in_range(shift_mm, "shift_mm", -MAX_PRESSURE_KPA, MAX_PRESSURE_KPA, closed="both")
    centre = pair.X2.mean(axis=0)
    R = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])

    def move(points: np.ndarray) -> np.ndarray:
        return (points - centre) @ R.T + centre + np.array([shift, 0.0])

    return ObjectPair(pair.X1, move(pair.X2), move(pair.truth))


def _resample_closed_curve(curve: np.ndarray, n: int) -> np.ndarray:
    """A closed polyline (p, 2), the last vertex may repeat the first, resampled to n nodes equally spaced along
    its length, counter-clockwise, the first at the lowest (smallest y) vertex (Sec. 5: 64 and 58 nodes)."""
    if np.allclose(curve[0], curve[-1]):
        curve = curve[:-1]
    x, y = curve[:, 0], curve[:, 1]
    if np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) < 0:  # signed area: make it counter-clockwise
        curve = curve[::-1]
    curve = np.roll(curve, -int(np.argmin(curve[:, 1])), axis=0)
    closed = np.vstack([curve, curve[:1]])
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(closed, axis=0), axis=1))])
    s = np.linspace(0, arc[-1], n, endpoint=False)
    return np.c_[np.interp(s, arc, closed[:, 0]), np.interp(s, arc, closed[:, 1])]


def make_pedobarography_sequence(*, rng: int | np.random.Generator, n_frames: int = 15) -> PedobarographySequence:
    """A seeded pressure sequence of one step on the plate: 12 loads on a stance schedule.

    The plate and its sensor are fixed: :data:`PLATE_SHAPE_PX` pixels of :data:`MM_PER_PX` mm, pixel
    noise :data:`NOISE_KPA`, calibration floor :data:`FLOOR_KPA` (pixels below it are set to zero
    before the filter) and a Gaussian filter of :data:`FILTER_PX` pixels.

    Parameters
    ----------
    rng : int or numpy.random.Generator
        Seed of the loads' perturbations and of the pixel noise.
    n_frames : int
        Frames over the stance, at least 2 and at most 4,096.

    Returns
    -------
    PedobarographySequence
        The frames and the analytic field (the filter's widening included).

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 2 and 3.2 (step 1); the loads are our choice.

    Examples
    --------
    >>> step = make_pedobarography_sequence(rng=0, n_frames=4)
    >>> step.frames.shape
    (4, 150, 80)
    """
    generator = make_rng(rng, "rng")
    n_frames = check_positive_int(n_frames, "n_frames", minimum=2, maximum=MAX_SIDE)
    return _make_sequence(generator, n_frames, *PLATE_SHAPE_PX, MM_PER_PX, NOISE_KPA, FLOOR_KPA, FILTER_PX)


def _make_sequence(rng: np.random.Generator, n_frames: int, rows: int, cols: int, mm_per_px: float,
                   noise: float, floor: float, filter_px: float) -> PedobarographySequence:
    loads = _LOADS.copy()
    n = len(loads)
    loads[:, :2] += rng.normal(0.0, _JITTER[0], (n, 2))
    loads[:, 5] *= np.exp(rng.normal(0.0, _JITTER[1], n))
    loads[:, 6] += rng.normal(0.0, _JITTER[2], n)
    # the foot's layout is given for a 160 x 300 mm plate: scale it to this one
    scale = np.array([cols, rows]) * mm_per_px / np.array([160.0, 300.0])
    centres = loads[:, :2] * scale
    c, s = np.cos(loads[:, 4]), np.sin(loads[:, 4])
    R = np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)
    covariances = R @ (np.eye(2) * (loads[:, 2:4] * scale) [:, None, :] ** 2) @ R.transpose(0, 2, 1)
    # the filter widens each Gaussian load by its own covariance and lowers its peak by the same factor
    widened = covariances + (filter_px * mm_per_px) ** 2 * np.eye(2)
    ratio = np.sqrt(np.linalg.det(covariances) / np.linalg.det(widened))
    raw = PedobarographySequence(np.zeros(0), mm_per_px, centres, covariances, loads[:, 5],
                                 loads[:, 6] * (n_frames - 1), loads[:, 7] * (n_frames - 1), floor)
    ys, xs = np.mgrid[0:rows, 0:cols] * mm_per_px
    grid = np.c_[xs.ravel(), ys.ravel()]
    frames = np.empty((n_frames, rows, cols))
    for t in range(n_frames):
        image = raw.pressure(grid, t).reshape(rows, cols) + rng.normal(0.0, noise, (rows, cols))
        image[image < floor] = 0.0  # the calibration floor
        frames[t] = ndimage.gaussian_filter(image, filter_px)
    return PedobarographySequence(frames, mm_per_px, centres, widened, loads[:, 5] * ratio,
                                  raw.peak_times, raw.spreads, floor)


def correct_share(pairs: np.ndarray, truth: np.ndarray, X2: np.ndarray) -> float:
    """Share of pairs whose partner lies within one node spacing of the true partner position.

    Parameters
    ----------
    pairs : ndarray of int, shape (k, 2)
        Pairs (i in object 1, j in object 2), k ≥ 1.
    truth : ndarray, shape (m1, D)
        Where each node of object 1 truly goes (mm), e.g. from the field's gradient flow.
    X2 : ndarray, shape (m2, D)
        Object 2's nodes (mm), D = 2 or 3, at least D + 2 distinct nodes.

    Returns
    -------
    float
        In [0, 1]; the tolerance is object 2's mean nearest-neighbour spacing.

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 5 (the paper counts "satisfactory" matches by eye).
    """
    truth = as_finite_array(truth, "truth", ndim=2, max_abs=MAX_COORDINATE_MM)
    X2 = check_nodes(X2, "X2")   # an object's nodes, as everywhere: D = 2 or 3, D + 2 distinct nodes at least
    check_same_dimension(truth, X2, "truth and X2")
    pairs = _check_index_pairs(pairs, (len(truth), len(X2)), f"truth's {len(truth)} or X2's {len(X2)} nodes")
    return _correct_share(pairs, truth, X2)


def _correct_share(pairs: np.ndarray, truth: np.ndarray, X2: np.ndarray) -> float:
    distance = np.linalg.norm(X2[pairs[:, 1]] - truth[pairs[:, 0]], axis=1)
    return float(np.mean(distance <= mean_spacing(X2)))
