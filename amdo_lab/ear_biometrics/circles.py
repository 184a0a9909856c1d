"""The first feature vector V of Choraś (AMDO 2004), Sec. 4, eq. (7): crossings of the contours with
circles around the centroid, in the frame of eq. (6)."""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from amdo_lab.common import (MAX_ITERATIONS, MAX_SIDE, as_bool_mask, as_finite_array, check_choice, check_in_range,
                             check_positive, check_positive_int)
from amdo_lab.ear_biometrics.images import as_contour_image, check_record
from amdo_lab.ear_biometrics.normalisation import (MAX_COORDINATE, NORMALISATION_MODES, Normalisation,
                                                   normalise_coordinates)
from amdo_lab.ear_biometrics.skeleton import prune_spurs, skeleton_graph, smooth_polylines, thin_contours

CROSSING_READINGS = ("pixels", "polyline")
"""Readings of "the contour crosses a circle": runs of contour pixels, or crossings of the thinned
contours read as polylines (see :func:`circle_features`)."""

MAX_CIRCLES = 64
"""Most circles N_r of eq. (7): the paper draws a handful; each circle is sampled at least twice per
pixel of its circumference."""

READING_RULES = {  # the range of each setting of V's reading (scikit-learn's _parameter_constraints)
    "n_circles": partial(check_positive_int, maximum=MAX_CIRCLES),
    "step": check_positive,
    "mode": partial(check_choice, choices=NORMALISATION_MODES),
    "min_gap_px": partial(check_positive, allow_zero=True),
    "crossings": partial(check_choice, choices=CROSSING_READINGS),
    "polyline_smoothing": partial(check_positive_int, minimum=0, maximum=MAX_ITERATIONS),
    "band_px": partial(check_positive, allow_zero=True),
    "spur_length_px": partial(check_positive_int, minimum=0, maximum=MAX_SIDE),
}
"""How :func:`circle_features`, :func:`~amdo_lab.ear_biometrics.topology.topology_features` and
:class:`~amdo_lab.ear_biometrics.matcher.MatcherSettings` check each setting of V: a function of (value, name)."""


@dataclass(frozen=True)
class CircleFeatures:
    """Eq. (7): V = {[r, l_r, sum d_r]} for the N_r circles, plus what was used to compute it.

    Parameters
    ----------
    radii : numpy.ndarray, shape (N_r,)
        Circle radii r, normalised units.
    counts : numpy.ndarray, shape (N_r,), int
        l_r, the number of intersections of the contours with each circle.
    distance_sums : numpy.ndarray, shape (N_r,)
        sum d_r, the summed distances between neighbouring intersections, normalised units.
    intersections : tuple of numpy.ndarray
        Per circle, the (l_r, 2) intersection points, normalised (x, y), counter-clockwise.
    normalisation : Normalisation
        The frame of eq. (6) the circles are drawn in.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 4, eq. (7) and Figs. 5-6.
    """

    radii: np.ndarray  # (N_r,) normalised radii
    counts: np.ndarray  # (N_r,) l_r, number of intersections
    distance_sums: np.ndarray  # (N_r,) sum of distances between neighbouring intersections
    intersections: tuple[np.ndarray, ...]  # per circle (l_r, 2) normalised (x, y), counter-clockwise
    normalisation: Normalisation

    @property
    def vector(self) -> np.ndarray:
        """V as an (N_r, 3) array of (r, l_r, sum d)."""
        return np.c_[self.radii, self.counts, self.distance_sums]


def circle_features(contours: object, n_circles: int = 8, step: float = 0.25, *, mode: str = "principal",
                    min_gap_px: float = 0.0, crossings: str = "pixels", polyline_smoothing: int = 2,
                    band_px: float = 0.0, spur_length_px: int = 0, skeleton: np.ndarray | None = None,
                    normalisation: Normalisation | None = None) -> CircleFeatures:
    """First feature vector V, eq. (7).

    Circles of radius r_m = m * step (m = 1..n_circles) in *normalised* units (eq. 6) are centred on
    the centroid; our reading of "alpha pixels apart" uses normalised units so that V is scale
    invariant. Two readings of "the contour crosses the circle":

    ``crossings="pixels"`` (the literal one)
        All circles are sampled at the same angles, at least two samples per pixel of the largest
        one; a run of consecutive samples on contour pixels is one intersection (l_r counts runs, so
        a 2-pixel-thick contour crossing the circle counts once). ``min_gap_px`` > 0 first merges
        runs separated by a shorter gap (a ragged contour grazing the circle).
    ``crossings="polyline"`` (sub-pixel)
        The contours are thinned, the skeleton is read as polylines (:func:`skeleton_graph`),
        smoothed (:func:`smooth_polylines`) and intersected with each circle analytically: one
        crossing per sign change of r(s) - R along a contour, so a contour that crosses a circle once
        counts once however ragged its pixels are.

    sum d is the perimeter of the polygon through the intersections taken counter-clockwise, closed
    so that it does not depend on a start angle (0 for fewer than two intersections).

    Parameters
    ----------
    contours : array_like, shape (rows, cols), bool
        Contour image with at least one contour pixel.
    n_circles : int
        Number of circles N_r, from 1 to :data:`MAX_CIRCLES`.
    step : float
        Radius step alpha between circles, normalised units, > 0; the first circle must reach into
        the image (step times the larger normalisation spread at most the image diagonal).
    mode : {"principal", "axes", "isotropic"}
        Reading of eq. (6) (see :func:`normalise_coordinates`); unused with ``normalisation``.
    min_gap_px : float
        ``"pixels"`` only: runs closer than this arc length, pixels, are merged; >= 0 (0 is the
        literal count).
    crossings : {"pixels", "polyline"}
        Reading of "the contour crosses the circle", as above.
    polyline_smoothing : int
        ``"polyline"`` only: rounds of :func:`smooth_polylines`, from 0 to ``MAX_ITERATIONS`` (100,000).
    band_px : float
        ``"polyline"`` only: half-width of the dead band around each circle, pixels, >= 0; a crossing
        must go from below R - band to above R + band, so a graze is not counted.
    spur_length_px : int
        ``"polyline"`` only: spurs shorter than this, pixels, are pruned first (:func:`prune_spurs`); from
        0 to ``MAX_SIDE`` (4,096).
    skeleton : numpy.ndarray or None
        ``"polyline"`` only: an already thinned image of the contours' shape (saves the thinning).
    normalisation : Normalisation or None
        A given frame in place of eq. (6) on the contour pixels (for instance the silhouette's,
        :func:`~amdo_lab.ear_biometrics.frame.frame_normalisation`).

    Returns
    -------
    CircleFeatures
        V: radii, counts l_r, distance sums, the intersections and the frame.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 3, eq. (6) and Sec. 4, eq. (7), Figs. 5-6.

    Examples
    --------
    A '+' of two one-pixel lines crosses every circle around its centre four times.

    >>> import numpy as np
    >>> from amdo_lab import ear_biometrics as eb
    >>> plus = np.zeros((64, 64), bool)
    >>> plus[32, 8:56] = True
    >>> plus[8:56, 32] = True
    >>> eb.circle_features(plus, n_circles=2, step=0.5, mode="isotropic").counts.tolist()
    [4, 4]
    """
    array = as_contour_image(contours)
    skeleton = None if skeleton is None else as_bool_mask(skeleton, "skeleton", shape=array.shape)
    reading = dict(n_circles=n_circles, mode=mode, min_gap_px=min_gap_px, crossings=crossings,
                   polyline_smoothing=polyline_smoothing, band_px=band_px, spur_length_px=spur_length_px)
    for name, value in reading.items():
        READING_RULES[name](value, name)
    if normalisation is None:
        norm = normalise_coordinates(array, mode)
    else:
        norm = check_record(normalisation, "normalisation", Normalisation, "normalise_coordinates")
    # the first circle must reach into the image (beyond it every count is 0 and the sampling grows without bound)
    check_in_range(step, "step", 0, np.hypot(*array.shape) / norm.spread.max(), closed="right")
    radii = step * np.arange(1, n_circles + 1)
    if crossings == "pixels":
        rows, theta = _pixel_crossings(array, norm, radii, min_gap_px)
    else:
        thin = thin_contours(array) if skeleton is None else skeleton
        rows, theta = _polyline_crossings(prune_spurs(thin, spur_length_px), norm, radii, polyline_smoothing, band_px)
    counts, sums, points = _circle_polygons(rows, theta, radii)
    return CircleFeatures(radii, counts, sums, points, norm)


def circle_features_reference(contours: object, n_circles: int = 8, step: float = 0.25) -> CircleFeatures:
    """Eqs. (6)-(7) written out in plain numpy, one circle at a time: the reading to open beside the paper.

    Literal eq. 6 (the image axes, ``mode="axes"``) and the literal count (every run of contour
    pixels met along a sampled circle is one intersection, ``crossings="pixels"``,
    ``min_gap_px=0``); :func:`circle_features` with those settings is the vectorised path and is
    tested equal to this.

    Parameters
    ----------
    contours : array_like, shape (rows, cols), bool
        Contour image with at least one contour pixel.
    n_circles : int
        Number of circles N_r, from 1 to :data:`MAX_CIRCLES`.
    step : float
        Radius step alpha between circles, normalised units, > 0; the first circle must reach into
        the image (step times the larger normalisation spread at most the image diagonal).

    Returns
    -------
    CircleFeatures
        V: radii, counts l_r, distance sums, the intersections and the frame of eq. (6).

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 3, eq. (6) and Sec. 4, eq. (7).
    """
    array = as_contour_image(contours)
    n_circles = check_positive_int(n_circles, "n_circles", maximum=MAX_CIRCLES)
    rows_cols = np.argwhere(array).astype(float)
    # eq. 6: the centroid (I, J) becomes the origin; each axis is divided by its standard deviation
    centroid = rows_cols.mean(axis=0)  # (I, J)
    sigma = rows_cols.std(axis=0)  # (sigma_i, sigma_j)
    matrix = np.array([[0.0, 1.0 / sigma[1]], [-1.0 / sigma[0], 0.0]])  # x = (j - J)/sigma_j, y = -(i - I)/sigma_i
    norm = Normalisation(centroid, sigma, matrix)
    check_in_range(step, "step", 0, np.hypot(*array.shape) / sigma.max(), closed="right")  # as in circle_features
    radii = step * np.arange(1, n_circles + 1)  # r_m = m * alpha, normalised units
    n_samples = int(8 * np.ceil(4 * np.pi * radii[-1] * sigma.max() / 8)) + 8  # >= 2 samples per pixel
    angles = 2 * np.pi * np.arange(n_samples) / n_samples
    counts, sums, points = [], [], []
    for r in radii:
        # the circle of radius r around the centroid, back in pixels (inverse of eq. 6)
        circle_xy = r * np.c_[np.cos(angles), np.sin(angles)]
        pixel = np.round(norm.to_pixels(circle_xy)).astype(int)
        inside = np.all((pixel >= 0) & (pixel < array.shape), axis=1)
        on_contour = np.zeros(n_samples, bool)
        on_contour[inside] = array[pixel[inside, 0], pixel[inside, 1]]
        # l_r (eq. 7): runs of consecutive samples on contour pixels, the circle read as closed
        if on_contour.all():
            middles = np.array([0.0])
        else:
            start = np.argmin(on_contour)  # begin on a sample off the contour: no run wraps around
            rolled = np.roll(on_contour, -start)
            edges = np.diff(np.r_[0, rolled.astype(int), 0])
            first, last = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1
            middles = ((first + last) / 2 + start) % n_samples
        middles = np.sort(middles)
        crossing_xy = r * np.c_[np.cos(2 * np.pi * middles / n_samples), np.sin(2 * np.pi * middles / n_samples)]
        # sum d (eq. 7): distances between neighbouring intersections, counter-clockwise, closed
        if len(crossing_xy) > 1:
            chords = np.linalg.norm(np.roll(crossing_xy, -1, axis=0) - crossing_xy, axis=1)
            sums.append(chords.sum())
        else:
            sums.append(0.0)
        counts.append(len(crossing_xy))
        points.append(crossing_xy)
    return CircleFeatures(radii, np.array(counts), np.array(sums), tuple(points), norm)


def contour_crossings(points: object, radii: object, band: float = 0.0) -> np.ndarray:
    """How often one contour, read as a polyline, crosses each circle around the origin (eq. 7's l_r).

    The readable path of the ``crossings="polyline"`` reading of :func:`circle_features` for one
    open contour: walk along the points and note on which side of the circle each lies, -1 inside
    (r < R - band), +1 outside (r >= R + band), 0 in the dead band between. Skipping the band, every
    change of side is one crossing, so a stretch that enters the band and turns back (a graze) is not
    counted, and one that passes through it is, once.

    Parameters
    ----------
    points : array_like, shape (n, 2)
        The contour's points in order, normalised (x, y) (eq. 6), at least two, within +-1e6.
    radii : array_like, shape (m,)
        Circle radii R, normalised units, > 0 and at most 1e6.
    band : float
        Half-width of the dead band, normalised units, >= 0 (0: every sign change of r - R counts).

    Returns
    -------
    numpy.ndarray of int, shape (m,)
        The number of crossings with each circle.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 4, eq. (7).

    Examples
    --------
    >>> from amdo_lab.ear_biometrics import contour_crossings
    >>> line = [(0.5, 0.0), (1.5, 0.0), (0.98, 0.05), (1.5, 0.2)]  # out, back in to r = 0.98, out again
    >>> contour_crossings(line, [1.0]).tolist(), contour_crossings(line, [1.0], band=0.05).tolist()
    ([3], [1])
    """
    xy = as_finite_array(points, "points", shape=(None, 2), max_abs=MAX_COORDINATE)
    if len(xy) < 2:
        raise ValueError(f"points must hold at least two points of the contour, got {len(xy)}")
    radii = as_finite_array(radii, "radii", ndim=1, bounds=(0.0, MAX_COORDINATE), closed="right")
    band = check_in_range(band, "band", 0.0, MAX_COORDINATE, closed="both")
    radius = np.linalg.norm(xy, axis=1)  # r(s) along the contour
    counts = np.zeros(len(radii), int)
    for m, circle in enumerate(radii):
        side = np.where(radius < circle - band, -1, np.where(radius >= circle + band, 1, 0))
        settled = side[side != 0]  # the sides visited in order, the dead band skipped
        counts[m] = np.count_nonzero(settled[1:] != settled[:-1])  # eq. (7): one crossing per change of side
    return counts


def _roll_rows(values: np.ndarray, shifts: np.ndarray) -> np.ndarray:
    """Row r rolled left by shifts[r] (row r starts at its element shifts[r])."""
    n = values.shape[1]
    return values[np.arange(len(values))[:, None], (np.arange(n) + shifts[:, None]) % n]


def _runs(rolled: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(row, start, end exclusive) of every run of True in each row (rows need not be circular)."""
    edges = np.diff(np.pad(rolled.astype(np.int8), ((0, 0), (1, 1))), axis=1)
    rows, starts = np.nonzero(edges == 1)
    _, ends = np.nonzero(edges == -1)  # row-major order pairs each start with its end
    return rows, starts, ends


def _fill_short_gaps(hits: np.ndarray, arc: np.ndarray, min_gap_px: float) -> np.ndarray:
    """Close runs of False on closed rows whose arc length (sum of ``arc``) is below ``min_gap_px``."""
    partial = hits.any(axis=1) & ~hits.all(axis=1)
    if min_gap_px <= 0 or not partial.any():
        return hits
    sub, sub_arc = hits[partial], arc[partial]
    shifts = np.argmax(sub, axis=1)  # start every row on a True, so no gap wraps around
    rolled, rolled_arc = _roll_rows(sub, shifts), _roll_rows(sub_arc, shifts)
    rows, starts, ends = _runs(~rolled)
    cumulative = np.pad(np.cumsum(rolled_arc, axis=1), ((0, 0), (1, 0)))
    short = cumulative[rows, ends] - cumulative[rows, starts] < min_gap_px
    fill = np.zeros(rolled.shape[1] + 1, np.int32)[None].repeat(len(rolled), axis=0)
    np.add.at(fill, (rows[short], starts[short]), 1)
    np.add.at(fill, (rows[short], ends[short]), -1)
    rolled = rolled | (np.cumsum(fill, axis=1)[:, :-1] > 0)
    filled = hits.copy()
    filled[partial] = _roll_rows(rolled, (-shifts) % hits.shape[1])
    return filled


def _circle_crossings(hits: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Row and midpoint sample index (float) of every run of True on closed (circular) rows,
    sorted by row, then counter-clockwise. A fully covered row counts as one crossing at index 0."""
    n = hits.shape[1]
    full = hits.all(axis=1)
    shifts = np.argmin(hits, axis=1)  # start every row on a False, so no run wraps around
    rows, starts, ends = _runs(_roll_rows(hits & ~full[:, None], shifts))
    mids = ((starts + ends - 1) / 2 + shifts[rows]) % n
    rows, mids = np.r_[rows, np.flatnonzero(full)], np.r_[mids, np.zeros(full.sum())]
    order = np.lexsort((mids, rows))
    return rows[order], mids[order]


def _pixel_crossings(array: np.ndarray, norm: Normalisation, radii: np.ndarray,
                     min_gap_px: float) -> tuple[np.ndarray, np.ndarray]:
    """Literal reading: circle index and angle of every run of contour pixels met along each circle."""
    n_samples = int(8 * np.ceil(4 * np.pi * radii[-1] * norm.spread.max() / 8)) + 8
    angles = 2 * np.pi * np.arange(n_samples) / n_samples
    unit = np.c_[np.cos(angles), np.sin(angles)]
    pixels = norm.to_pixels((radii[:, None, None] * unit).reshape(-1, 2)).reshape(len(radii), n_samples, 2)
    rc = np.round(pixels).astype(int)
    inside = (rc[..., 0] >= 0) & (rc[..., 0] < array.shape[0]) & (rc[..., 1] >= 0) & (rc[..., 1] < array.shape[1])
    hits = np.zeros((len(radii), n_samples), bool)
    hits[inside] = array[rc[inside][:, 0], rc[inside][:, 1]]
    arc = np.linalg.norm(np.roll(pixels, -1, axis=1) - pixels, axis=2)  # pixel length of each sample step
    rows, mids = _circle_crossings(_fill_short_gaps(hits, arc, min_gap_px))
    return rows, 2 * np.pi * mids / n_samples


def _polyline_crossings(skeleton: np.ndarray, norm: Normalisation, radii: np.ndarray, smoothing: int,
                        band_px: float) -> tuple[np.ndarray, np.ndarray]:
    """Sub-pixel reading: circle index and angle of every crossing of the (lightly smoothed) skeleton
    polylines with each circle.

    With ``band_px`` = 0 a crossing is a sign change of r(s) - R along an edge, located by linear
    interpolation. With ``band_px`` = h > 0 (pixels) the sign change must go from below R - h to above
    R + h (a dead band, as in a Schmitt trigger): a stretch of contour inside the band counts once if
    it enters from one side and leaves on the other, and not at all if it touches the circle and turns
    back (a graze), so sub-pixel wobble near a tangent point cannot add or remove crossings.
    """
    nodes, edges = skeleton_graph(skeleton)
    xy = norm.to_normalised(smooth_polylines(nodes, edges, smoothing))
    h = band_px / np.sqrt(np.prod(norm.spread))  # pixels -> normalised units (geometric-mean spread)
    return _graph_crossings(xy, edges, radii, h)


def _graph_crossings(xy: np.ndarray, edges: np.ndarray, radii: np.ndarray, h: float
                     ) -> tuple[np.ndarray, np.ndarray]:
    """Circle index and angle of every crossing of a polyline graph (normalised nodes ``xy``, ``edges``)
    with each circle, dead band ``h`` in normalised units; :func:`contour_crossings` is the same count
    for one path, written out."""
    radius = np.linalg.norm(xy, axis=1)
    n_nodes, n_circles = len(xy), len(radii)
    side = np.where(radius[:, None] < radii - h, -1, np.where(radius[:, None] >= radii + h, 1, 0))
    a, b = edges[:, 0], edges[:, 1]
    # direct jumps over the whole band (always the case for h = 0)
    edge_index, rows = np.nonzero(side[a] * side[b] == -1)
    ea, eb = a[edge_index], b[edge_index]
    t = (radii[rows] - radius[ea]) / (radius[eb] - radius[ea])
    points = xy[ea] + t[:, None] * (xy[eb] - xy[ea])
    rows_out, theta_out = [rows], [np.arctan2(points[:, 1], points[:, 0])]
    if h > 0:
        # stretches inside the band: connected components of band nodes, one graph per circle
        in_band = side == 0  # (n_nodes, n_circles)
        key = lambda node, circle: circle * n_nodes + node  # noqa: E731
        e_idx, c_idx = np.nonzero(in_band[a] & in_band[b])
        graph = coo_matrix((np.ones(len(e_idx)), (key(a[e_idx], c_idx), key(b[e_idx], c_idx))),
                           shape=(n_nodes * n_circles,) * 2)
        _, component = connected_components(graph, directed=False)
        # edges leaving a band stretch to the inside (-1) or the outside (+1)
        both = np.r_[a, b], np.r_[b, a]
        e_idx, c_idx = np.nonzero(in_band[both[0]] & (side[both[1]] != 0))
        stretch = component[key(both[0][e_idx], c_idx)]
        exits = side[both[1][e_idx], c_idx]
        n_comp = component.max() + 1
        inward = np.bincount(stretch, exits < 0, minlength=n_comp)
        outward = np.bincount(stretch, exits > 0, minlength=n_comp)
        crossing_stretches = np.flatnonzero(np.minimum(inward, outward) > 0)
        count = np.minimum(inward, outward)[crossing_stretches].astype(int)
        band_nodes, band_circles = np.nonzero(in_band)
        band_component = component[key(band_nodes, band_circles)]
        size = np.bincount(band_component, minlength=n_comp)
        centre = np.c_[np.bincount(band_component, xy[band_nodes, 0], n_comp),
                       np.bincount(band_component, xy[band_nodes, 1], n_comp)] / np.maximum(size, 1)[:, None]
        circle_of = np.zeros(n_comp, int)
        circle_of[band_component] = band_circles
        centre = np.repeat(centre[crossing_stretches], count, axis=0)
        rows_out.append(np.repeat(circle_of[crossing_stretches], count))
        theta_out.append(np.arctan2(centre[:, 1], centre[:, 0]))
    return np.concatenate(rows_out), np.concatenate(theta_out) % (2 * np.pi)


def _circle_polygons(rows: np.ndarray, theta: np.ndarray, radii: np.ndarray
                     ) -> tuple[np.ndarray, np.ndarray, tuple[np.ndarray, ...]]:
    """Counts l_r, closed counter-clockwise polygon perimeters sum d and crossing points per circle."""
    order = np.lexsort((theta, rows))
    rows, theta = rows[order], theta[order]
    n_circles = len(radii)
    crossings = radii[rows, None] * np.c_[np.cos(theta), np.sin(theta)]
    counts = np.bincount(rows, minlength=n_circles)
    # closed polygon per circle: each crossing joined to the next one of the same circle (cyclically)
    first = np.cumsum(counts) - counts
    position = np.arange(len(rows)) - first[rows]
    following = first[rows] + (position + 1) % np.maximum(counts[rows], 1)
    chords = np.linalg.norm(crossings[following] - crossings, axis=1)
    sums = np.where(counts > 1, np.bincount(rows, chords, minlength=n_circles), 0.0)
    return counts, sums, tuple(np.split(crossings, np.cumsum(counts)[:-1]))
