"""From snakes to areas and volumes, and a whole study segmented (Caro et al. 2004, Sec. 3.2 and 4).

The area of a final snake is the shoelace formula on its points in millimetres; the volume of a
muscle is the sum of its slice areas times the distance between slices.
"""

from __future__ import annotations

import numpy as np

from amdo_lab.active_contours.phantom import MUSCLES, PIXEL_MM, SLICE_MM, HamStudy, _initial_contour
from amdo_lab.active_contours.potential import _potential_field
from amdo_lab.active_contours.snakes import TABLE_1, SnakeWeights, _dp, _greedy, _variational
from amdo_lab.common import as_finite_array, check_choice, check_in_range, check_positive_int

__all__ = ["METHODS", "polygon_area_mm2", "segment_contour", "segment_study", "volume_mm3"]

#: The three paradigms compared by the paper, and scikit-image's semi-implicit snake as a peer.
METHODS = ("greedy", "dynamic", "variational")
#: Margin (px) of the crop round a starting snake in which the variational snake runs (its GVF costs per pixel;
#: the discrete searches cost per point and run on the whole image).
CROP_MARGIN_PX = 24


def _pixel_size(pixel_mm: object) -> np.ndarray:
    return as_finite_array(pixel_mm, "pixel_mm", shape=(2,), bounds=(1e-6, 1e3))


def polygon_area_mm2(points: np.ndarray, pixel_mm: tuple[float, float] = PIXEL_MM) -> float:
    """Area (mm^2) enclosed by a closed polygon of (row, col) pixel points: the shoelace formula.

    Parameters
    ----------
    points : (n, 2) ndarray
        (row, col) pixel coordinates, n at least 3, magnitudes at most 1e9.
    pixel_mm : (float, float)
        Pixel size along rows and columns, mm, each in [1e-6, 1e3] (Sec. 2: 0.20 x 0.23).

    Returns
    -------
    float
        The enclosed area, mm^2 (orientation does not matter).

    References
    ----------
    Caro et al., AMDO 2004, Sec. 3.2 ("surfaces ... using the classical methods in analytical geometry").

    Examples
    --------
    >>> polygon_area_mm2([[0, 0], [0, 10], [10, 10], [10, 0]], pixel_mm=(1.0, 1.0))
    100.0
    """
    points = as_finite_array(points, "points", shape=(None, 2), max_abs=1e9)
    check_positive_int(points.shape[0], "points count", minimum=3, maximum=10**7)
    return _polygon_area(points, _pixel_size(pixel_mm))


def _polygon_area(points: np.ndarray, pixel_mm: np.ndarray) -> float:
    y, x = (points * pixel_mm).T
    return float(0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


def volume_mm3(areas_mm2: np.ndarray, slice_mm: float = SLICE_MM) -> float:
    """Volume (mm^3) of a muscle from its slice areas: their sum times the distance between slices.

    Parameters
    ----------
    areas_mm2 : (k,) ndarray
        Areas of consecutive slices, mm^2, each in [0, 1e12].
    slice_mm : float
        Distance between the slices, mm, in (0, 1e3] (Sec. 2: 2 mm).

    Returns
    -------
    float
        ``slice_mm * sum(areas_mm2)``.

    References
    ----------
    Caro et al., AMDO 2004, Sec. 3.2.

    Examples
    --------
    >>> volume_mm3([100.0, 120.0, 100.0], slice_mm=2.0)
    640.0
    """
    areas = as_finite_array(areas_mm2, "areas_mm2", ndim=1, bounds=(0.0, 1e12))
    slice_mm = check_in_range(slice_mm, "slice_mm", 0.0, 1e3, closed="right")
    return float(slice_mm * areas.sum())


def _crop(init: np.ndarray, shape: tuple[int, int]) -> tuple[slice, slice]:
    low = np.maximum(np.floor(init.min(axis=0)) - CROP_MARGIN_PX, 0).astype(int)
    high = np.minimum(np.ceil(init.max(axis=0)) + CROP_MARGIN_PX + 1, shape).astype(int)
    return slice(low[0], high[0]), slice(low[1], high[1])


def _segment(potential: np.ndarray, init: np.ndarray, method: str, weights: SnakeWeights | None = None,
             window: int = 3):
    """Run ``method`` (the variational snake in a crop round ``init``); Table 1's weights unless ``weights`` is given.

    The greedy and dynamic-programming results equal ``greedy_snake(potential, init)`` and
    ``dp_snake(potential, init)`` with Table 1's weights.
    """
    weights = TABLE_1[method] if weights is None else weights
    if method == "greedy":
        result = _greedy(potential, init, weights, window, 2.0, 6.0, 300, vectorised=True)
        return result.points, result
    if method == "dynamic":
        result = _dp(potential, init, weights, window, 2.0, 6.0, 100)
        return result.points, result
    rows, cols = _crop(init, potential.shape)
    local, offset = potential[rows, cols], np.array([rows.start, cols.start])
    result = _variational(local.max() - local, init - offset, weights, 0.5, 2.0, 6.0, 200, 0.2, 80)
    return result.points + offset, result


def segment_contour(potential: np.ndarray, init: np.ndarray, method: str) -> np.ndarray:
    """One muscle's final snake: ``method`` with Table 1's weights (the variational snake in a crop round ``init``).

    ``segment_contour(potential, init, "greedy")`` is ``greedy_snake(potential, init).points`` and
    ``"dynamic"`` is ``dp_snake(potential, init, gamma=2.4).points``; the variational snake runs with
    its GVF computed on a crop 24 px round the start (``variational_snake`` on that crop).

    Parameters
    ----------
    potential : (rows, cols) ndarray
        Sec. 3.2's potential of the slice.
    init : (n, 2) ndarray
        The starting snake, inside the image.
    method : {"greedy", "dynamic", "variational"}
        The paradigm.

    Returns
    -------
    (n', 2) ndarray
        The final snake in the slice's pixel coordinates.

    References
    ----------
    Caro et al., AMDO 2004, Sec. 3.1 and Table 1.
    """
    from amdo_lab.active_contours.snakes import _snake_input
    potential, init = _snake_input(potential, init, "potential")
    method = check_choice(method, "method", METHODS)
    return _segment(potential, init, method)[0]


def segment_study(study: HamStudy, method: str, *, hams: tuple[int, ...], every: int = 1) -> list:
    """Segment both muscles on every ``every``-th slice of the chosen hams: one row per contour.

    Starting snakes are drawn by :func:`~amdo_lab.active_contours.initial_contour` (10-20 % larger)
    from a seed of the slice, so every method starts from the same snakes.

    Parameters
    ----------
    study : HamStudy
        The study.
    method : {"greedy", "dynamic", "variational"}
        The paradigm (Table 1's weights).
    hams : tuple of int
        The hams to segment.
    every : int
        Use slices 0, every, 2 every, ... (1 to 1,000); volumes then use a spacing of ``every`` x 2 mm.

    Returns
    -------
    list of dict
        Keys ``ham``, ``stage``, ``index``, ``muscle``, ``true_mm2``, ``found_mm2``, ``seconds``.

    References
    ----------
    Caro et al., AMDO 2004, Sec. 3.2 and 4.
    """
    if not isinstance(study, HamStudy):
        raise TypeError(f"study must be a HamStudy, got {type(study).__name__}")
    method = check_choice(method, "method", METHODS)
    every = check_positive_int(every, "every", maximum=1000)
    if not isinstance(hams, (tuple, list)):
        raise TypeError(f"hams must be a tuple of ham numbers, got {type(hams).__name__}")
    chosen = [check_positive_int(h, "hams", minimum=0, maximum=study.n_hams - 1) for h in hams]
    rows = []
    for ham in chosen:
        for stage in range(4):
            if ham not in study.hams_at(stage):
                continue
            for index in range(0, len(study._positions(ham, stage)), every):
                ham_slice = study._slice(ham, stage, index)
                potential = _potential_field(ham_slice.image, 0.10, 40, 15.0, "sobel")
                for k, muscle in enumerate(MUSCLES):
                    if muscle not in ham_slice.contours:
                        continue
                    rng = np.random.default_rng([study._seed, ham, stage, index, k, 1])
                    init = _initial_contour(ham_slice.contours[muscle], rng, 0.10, 0.20, 60)
                    points, result = _segment(potential, init, method)
                    rows.append({"ham": ham, "stage": stage, "index": index, "muscle": muscle,
                                 "true_mm2": ham_slice.areas_mm2[muscle],
                                 "found_mm2": _polygon_area(points, np.asarray(PIXEL_MM)),
                                 "seconds": result.seconds})
    return rows
