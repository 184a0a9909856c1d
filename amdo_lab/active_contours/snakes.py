"""Three ways to minimise one snake energy: greedy search, dynamic programming and variational calculus.

The discrete energy of Caro et al. (2004, Sec. 3.1) sums over the snake's points (eq. 4)

    E = sum_i  alpha E_cont(i) + beta E_curv(i) + gamma E_image(i),

with E_cont = | dbar - |v_i - v_{i-1}| | (eq. 5, our reading of the printed ``v_t - v_{t-1}``; dbar
the mean spacing), E_curv = |v_{i-1} - 2 v_i + v_{i+1}|^2 (eq. 6) and E_image (eq. 7), where the edge strength ``e = max(P) - P`` comes from the potential
``P`` of Sec. 3.2 (eq. 7 prints ``|grad I|``; the paper swaps in the potential without saying so).
``e_max``, which the paper leaves undefined, we read as Williams & Shah do: over the point's
neighbourhood, ``E_image = (e_min - e) / max(e_max - e_min, floor)``, from -1 at the neighbourhood's
strongest edge to 0 at its weakest, with ``floor`` a fifteenth of the potential's range (1 px for the
default cap). Printed literally, ``-e / e_max`` (``image_norm="max"``, an ablation) differs by at most
``1 / e_max`` between neighbouring pixels: a 15th of a unit per pixel, less than the curvature a
single point pays to step one pixel out of a circle, so a snake started inside a boundary cannot climb
to it. The paper says every term is normalised without saying how:
E_cont and E_curv are measured in units of ``dbar`` and ``dbar^2`` (dividing them by their
neighbourhood maximum, as Williams & Shah do, lets a tiny curvature outvote the image term).

- :func:`greedy_snake` (Williams & Shah): each point moves to the best of its ``window x window``
  candidates; points are updated in two colours (even, then odd indices), so a colour moves at once
  in numpy; :func:`greedy_snake_loop` is the same search one point at a time, tested equal.
- :func:`dp_snake` (Amini et al.): the optimal candidates of all points at once, by dynamic
  programming over pairs of neighbouring candidates (``n m^3`` energy evaluations per iteration).
- :func:`variational_snake` (Kass et al.): semi-implicit steps ``(A + I/tau) x' = x/tau + gamma f``
  with ``f`` the gradient vector flow at unit length, the matrix factorised once per resampling (LU).

All three keep a variable number of points: after each iteration a gap over ``d_max_px`` gets new
points, and a gap under ``d_min_px`` loses one (Sec. 3.1).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import scipy.linalg
from scipy import ndimage

from amdo_lab.active_contours.potential import _gvf, _image
from amdo_lab.common import MAX_ITERATIONS, as_finite_array, check_bool, check_choice, check_in_range, \
    check_odd_int, check_positive, check_positive_int

__all__ = ["IMAGE_NORMS", "MAX_POINTS", "NORMALISATIONS", "SnakeResult", "SnakeWeights", "TABLE_1", "candidate_offsets",
           "dp_pass", "dp_snake", "greedy_energies", "greedy_snake", "greedy_snake_loop", "respace", "variational_snake"]

#: Most points a snake may hold.
MAX_POINTS = 100_000
#: Largest window side (candidates per point: window^2).
MAX_WINDOW = 15
#: How the greedy snake scales E_cont and E_curv: by dbar and dbar^2 (ours), or by their largest value among
#: each point's candidates (Williams & Shah's normalisation of every term, eq. 7's e_max read for all three).
NORMALISATIONS = ("spacing", "neighbourhood")
#: How E_image is scaled among a point's candidates: over their range (Williams & Shah, ours) or over their
#: largest edge strength (eq. 7 printed literally, an ablation).
IMAGE_NORMS = ("range", "max")
#: The floor of the range, as a share of the potential's overall range (1 px for the default cap of 15 px).
IMAGE_FLOOR_SHARE = 1.0 / 15.0


@dataclass(frozen=True)
class SnakeWeights:
    """The weights alpha, beta, gamma of eq. (4).

    Parameters
    ----------
    alpha, beta, gamma : float
        Continuity, curvature and image weights, non-negative, not all zero.

    References
    ----------
    Caro et al., AMDO 2004, eq. (4) and Table 1.
    """

    alpha: float
    beta: float
    gamma: float


#: Table 1 of the paper: the weights of each method.
TABLE_1 = {"variational": SnakeWeights(0.4, 0.4, 1.2), "dynamic": SnakeWeights(0.4, 0.4, 2.4),
           "greedy": SnakeWeights(0.4, 0.4, 1.2)}


@dataclass(frozen=True)
class SnakeResult:
    """A converged snake.

    Parameters
    ----------
    points : (n, 2) ndarray
        Final (row, col) pixel coordinates, in order round the contour.
    n_iter : int
        Iterations run.
    energy_evaluations : int
        Candidate energies evaluated (greedy: n m per iteration; dynamic programming: about n m^3;
        variational: n force samples).
    seconds : float
        Wall time of the search.

    References
    ----------
    Caro et al., AMDO 2004, Sec. 3.1.
    """

    points: np.ndarray
    n_iter: int
    energy_evaluations: int
    seconds: float


def candidate_offsets(window: int = 3) -> np.ndarray:
    """The ``window^2`` moves of a point, ``(0, 0)`` first (a tie keeps the point where it is).

    Parameters
    ----------
    window : int
        Odd side of the square neighbourhood, 3 to 15.

    Returns
    -------
    (window^2, 2) ndarray of int
        (row, col) offsets.

    References
    ----------
    Caro et al., AMDO 2004, Sec. 3.1 (the "m x m neighbourhood" of the greedy algorithm).
    """
    return _offsets(check_odd_int(window, "window", maximum=MAX_WINDOW))


def _offsets(window: int) -> np.ndarray:
    half = window // 2
    grid = np.array([(r, c) for r in range(-half, half + 1) for c in range(-half, half + 1)])
    return np.concatenate([[[0, 0]], grid[np.any(grid != 0, axis=1)]])


def _weights(alpha: object, beta: object, gamma: object) -> SnakeWeights:
    weights = [check_positive(value, name, allow_zero=True) for value, name in
               ((alpha, "alpha"), (beta, "beta"), (gamma, "gamma"))]
    if max(weights) > 1e6 or sum(weights) == 0:
        raise ValueError(f"alpha, beta and gamma must not all be zero and each at most 1e6, got {weights}")
    return SnakeWeights(*weights)


def _snake_input(field: object, init: object, field_name: str,
                 init_name: str = "init") -> tuple[np.ndarray, np.ndarray]:
    field = _image(field, field_name)
    init = as_finite_array(init, init_name, shape=(None, 2), max_abs=1e9)
    check_positive_int(init.shape[0], f"{init_name} points", minimum=5, maximum=MAX_POINTS)
    if np.any(init < 0) or np.any(init > np.asarray(field.shape) - 1):
        raise ValueError(f"{init_name} must lie inside the {field_name} (rows 0-{field.shape[0] - 1}, "
                         f"columns 0-{field.shape[1] - 1})")
    return field, init


def _spacing(d_min_px: object, d_max_px: object) -> tuple[float, float]:
    d_min = check_positive(d_min_px, "d_min_px")
    d_max = check_positive(d_max_px, "d_max_px")
    if not d_min < d_max / 2 or d_max > 1e4:
        raise ValueError(f"d_min_px must be below half of d_max_px (and d_max_px at most 1e4), "
                         f"got {d_min} and {d_max}")
    return d_min, d_max


def _search_input(potential: object, init: object, alpha: object, beta: object, gamma: object, window: object,
                  d_min_px: object, d_max_px: object, max_iter: object) -> tuple:
    """The checked arguments of a discrete search (greedy or dynamic programming), in the kernels' order."""
    potential, init = _snake_input(potential, init, "potential")
    weights = _weights(alpha, beta, gamma)
    window = check_odd_int(window, "window", maximum=MAX_WINDOW)
    d_min, d_max = _spacing(d_min_px, d_max_px)
    max_iter = check_positive_int(max_iter, "max_iter", maximum=MAX_ITERATIONS)
    return potential, init, weights, window, d_min, d_max, max_iter


def _repeats(points: np.ndarray, history: list) -> bool:
    """True if ``points`` is one of the last two states kept in ``history`` (an oscillation); else keep it."""
    if any(np.array_equal(points, old) for old in history):
        return True
    history[:] = [points.copy()] + history[:1]
    return False


def respace(points: np.ndarray, d_min_px: float = 2.0, d_max_px: float = 6.0) -> np.ndarray:
    """Sec. 3.1's variable ``n``: split gaps over ``d_max_px``, drop a point after a gap under ``d_min_px``.

    Parameters
    ----------
    points : (n, 2) ndarray
        A closed contour, n at least 5.
    d_min_px, d_max_px : float
        Smallest and largest spacing, pixels, ``0 < d_min_px < d_max_px / 2``.

    Returns
    -------
    (n', 2) ndarray
        The contour with new points evenly spaced in long gaps and no two consecutive points dropped;
        never fewer than 5 points.

    References
    ----------
    Caro et al., AMDO 2004, Sec. 3.1 (``d_max`` and ``d_min``).
    """
    points = as_finite_array(points, "points", shape=(None, 2), max_abs=1e9)
    check_positive_int(points.shape[0], "points count", minimum=5, maximum=MAX_POINTS)
    return _respace(points, *_spacing(d_min_px, d_max_px))


def _respace(points: np.ndarray, d_min: float, d_max: float) -> np.ndarray:
    gaps = np.linalg.norm(np.roll(points, -1, axis=0) - points, axis=1)
    short = gaps < d_min                                     # drop the point after a short gap ...
    short[1:] &= ~short[:-1]                                 # ... never two in a row
    drop = np.roll(short, 1)
    if points.shape[0] - drop.sum() >= 5:
        points = points[~drop]
    following = np.roll(points, -1, axis=0)
    gaps = np.linalg.norm(following - points, axis=1)
    extra = np.maximum(np.ceil(gaps / d_max).astype(int) - 1, 0)
    if not extra.any():
        return points
    pieces = []
    for start, end, k in zip(points, following, extra):
        pieces.append(start[None])
        if k:
            pieces.append(start + np.outer(np.arange(1, k + 1) / (k + 1), end - start))
    return np.concatenate(pieces)[:MAX_POINTS]


def _edge_of(potential: np.ndarray) -> np.ndarray:
    return potential.max() - potential                       # e: high on edges


def _image_term(e: np.ndarray, floor: float, image_norm: str = "range") -> np.ndarray:
    """Eq. (7) for each row of candidates' edge strengths ``e``: over their range (floored) or their maximum."""
    high = e.max(axis=-1, keepdims=True)
    if image_norm == "max":
        return -e / _positive(high)                                          # -e / e_max, printed literally
    low = e.min(axis=-1, keepdims=True)
    return (low - e) / np.maximum(high - low, floor)                         # Williams & Shah: -1 .. 0


def _floor(edge: np.ndarray) -> float:
    span = float(edge.max() - edge.min())
    return IMAGE_FLOOR_SHARE * span if span > 0 else 1.0


def _greedy_energies(points: np.ndarray, movers: np.ndarray, edge: np.ndarray, weights: SnakeWeights,
                     d_bar: float, offsets: np.ndarray, normalise: str = "spacing",
                     image_norm: str = "range", floor: float | None = None) -> np.ndarray:
    """Eq. (4) for each candidate of each mover: E_image over its neighbourhood's range, the others over dbar."""
    n = points.shape[0]
    candidates = points[movers, None, :] + offsets[None]                     # (k, m, 2)
    previous, following = points[(movers - 1) % n, None, :], points[(movers + 1) % n, None, :]
    e_cont = np.abs(d_bar - np.linalg.norm(candidates - previous, axis=2))   # eq. (5)
    e_curv = np.sum((previous - 2 * candidates + following) ** 2, axis=2)    # eq. (6)
    rows = np.clip(candidates[..., 0], 0, edge.shape[0] - 1).astype(int)
    cols = np.clip(candidates[..., 1], 0, edge.shape[1] - 1).astype(int)
    e_image = _image_term(edge[rows, cols], _floor(edge) if floor is None else floor, image_norm)   # eq. (7)
    if normalise == "neighbourhood":                                         # Williams & Shah: every term over
        e_cont = e_cont / _positive(e_cont.max(axis=1, keepdims=True))       # its neighbourhood maximum
        e_curv, d_bar = e_curv / _positive(e_curv.max(axis=1, keepdims=True)), 1.0
    scale = max(d_bar, 1.0)                                                  # E_cont, E_curv in units of dbar
    energy = weights.alpha * e_cont / scale + weights.beta * e_curv / scale ** 2 + weights.gamma * e_image  # eq. (4)
    outside = ((candidates < 0) | (candidates > np.asarray(edge.shape) - 1)).any(axis=2)
    return np.where(outside, np.inf, energy)


def _positive(values: np.ndarray) -> np.ndarray:
    return np.where(values > 0, values, 1.0)


def greedy_energies(potential: np.ndarray, points: np.ndarray, *, alpha: float = 0.4, beta: float = 0.4,
                    gamma: float = 1.2, window: int = 3, image_norm: str = "range") -> np.ndarray:
    """Eq. (4)'s energy of every candidate of every point (E_image per neighbourhood, the others per dbar).

    Parameters
    ----------
    potential : (rows, cols) ndarray
        Sec. 3.2's potential (low on edges).
    points : (n, 2) ndarray
        The snake, whole pixels inside the image, n at least 5.
    alpha, beta, gamma : float
        Weights of eq. (4), non-negative, not all zero, each at most 1e6.
    window : int
        Odd side of the neighbourhood, 3 to 15.
    image_norm : {"range", "max"}
        E_image over the candidates' range of edge strength (Williams & Shah, ours) or over their
        largest (eq. 7 printed literally, an ablation).

    Returns
    -------
    (n, window^2) ndarray
        Energies, candidate 0 the point itself (``inf`` off the image).

    References
    ----------
    Caro et al., AMDO 2004, eqs. (4)-(7); D.J. Williams, M. Shah, A fast algorithm for active contours
    and curvature estimation, CVGIP: Image Understanding 55, 1992.
    """
    potential, points = _snake_input(potential, points, "potential", "points")
    weights = _weights(alpha, beta, gamma)
    offsets = _offsets(check_odd_int(window, "window", maximum=MAX_WINDOW))
    image_norm = str(check_choice(image_norm, "image_norm", IMAGE_NORMS))
    d_bar = float(np.mean(np.linalg.norm(np.roll(points, -1, axis=0) - points, axis=1)))
    return _greedy_energies(points, np.arange(points.shape[0]), _edge_of(potential), weights, d_bar, offsets,
                            image_norm=image_norm)


def _colours(n: int) -> list[np.ndarray]:
    """Even indices, then odd ones; with n odd the last point (next to point 0) moves on its own."""
    indices = np.arange(n)
    if n % 2 == 0:
        return [indices[0::2], indices[1::2]]
    return [indices[0:n - 1:2], indices[1::2], indices[n - 1:]]


def _greedy(potential: np.ndarray, init: np.ndarray, weights: SnakeWeights, window: int, d_min: float,
            d_max: float, max_iter: int, vectorised: bool, normalise: str = "spacing",
            image_norm: str = "range") -> SnakeResult:
    start = time.perf_counter()
    edge, offsets = _edge_of(potential), _offsets(window)
    floor = _floor(edge)
    points = np.rint(init)
    history, evaluations, iteration = [], 0, 0
    for iteration in range(1, max_iter + 1):
        d_bar = float(np.mean(np.linalg.norm(np.roll(points, -1, axis=0) - points, axis=1)))
        moved = 0
        for colour in _colours(points.shape[0]):
            if vectorised:
                energy = _greedy_energies(points, colour, edge, weights, d_bar, offsets, normalise,
                                          image_norm, floor)
                best = np.argmin(energy, axis=1)
                points[colour] += offsets[best]
                moved += int(np.count_nonzero(best))
            else:
                for i in colour:   # the plain loop of Williams & Shah, one point at a time
                    energy = _greedy_energies(points, np.array([i]), edge, weights, d_bar, offsets,
                                              normalise, image_norm, floor)[0]
                    best = int(np.argmin(energy))
                    points[i] += offsets[best]
                    moved += best != 0
        evaluations += points.shape[0] * offsets.shape[0]
        points = np.rint(_respace(points, d_min, d_max))
        if moved == 0 or _repeats(points, history):
            break                                             # converged, or cycling between two states
    return SnakeResult(points, iteration, evaluations, time.perf_counter() - start)


def greedy_snake(
    potential: np.ndarray,
    init: np.ndarray,
    *,
    alpha: float = 0.4,
    beta: float = 0.4,
    gamma: float = 1.2,
    window: int = 3,
    d_min_px: float = 2.0,
    d_max_px: float = 6.0,
    max_iter: int = 300,
    normalise: str = "spacing",
    image_norm: str = "range",
) -> SnakeResult:
    """Williams & Shah's greedy snake on Sec. 3.2's potential, points moved in two colours at once.

    Each iteration computes the mean spacing ``dbar``, moves the even points to their best candidate
    (eq. 4), then the odd ones, then respaces. It stops when no
    point moves, when the snake returns to one of its last two states (an oscillation), or after
    ``max_iter`` iterations. Points on the same colour do not see each other's moves, so a colour
    can move at once: :func:`greedy_snake_loop` moves them one at a time and gives the same snake.

    Parameters
    ----------
    potential : (rows, cols) ndarray
        Sec. 3.2's potential (low on edges), at least 7 x 7.
    init : (n, 2) ndarray
        Starting (row, col) points inside the image, n from 5 to 100,000; rounded to whole pixels.
    alpha, beta, gamma : float
        Weights of eq. (4) (Table 1: 0.4, 0.4, 1.2), non-negative, not all zero, each at most 1e6.
    window : int
        Odd side of each point's neighbourhood, 3 to 15 (m = window^2 candidates).
    d_min_px, d_max_px : float
        Spacing limits of the variable ``n`` (pixels), ``0 < d_min_px < d_max_px / 2``.
    max_iter : int
        Most iterations, 1 to 100,000.
    normalise : {"spacing", "neighbourhood"}
        ``E_cont`` and ``E_curv`` over ``dbar`` and ``dbar^2`` (ours), or each over its largest value
        among the point's candidates, as Williams & Shah normalise every term (an ablation: a tiny
        curvature then counts as much as a strong edge).
    image_norm : {"range", "max"}
        ``E_image`` over the candidates' range of edge strength (Williams & Shah, ours) or over their
        largest, ``-e / e_max`` (eq. 7 printed literally, an ablation: too weak a pull to bring a
        snake started inside an edge out to it).

    Returns
    -------
    SnakeResult
        Final points, iterations, ``n m`` energy evaluations per iteration, seconds.

    References
    ----------
    Caro et al., AMDO 2004, eqs. (4)-(7), Sec. 3.1; Williams & Shah, CVGIP: IU 55, 1992.

    Examples
    --------
    >>> import numpy as np
    >>> from amdo_lab.active_contours import potential_field
    >>> disc = (np.hypot(*np.mgrid[-31:33, -31:33]) < 16).astype(float)
    >>> theta = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    >>> start = 31 + 24 * np.column_stack([np.sin(theta), np.cos(theta)])
    >>> snake = greedy_snake(potential_field(disc), start)
    >>> bool(np.abs(np.hypot(*(snake.points - 31).T) - 16).max() < 3)
    True
    """
    search = _search_input(potential, init, alpha, beta, gamma, window, d_min_px, d_max_px, max_iter)
    normalise = str(check_choice(normalise, "normalise", NORMALISATIONS))
    image_norm = str(check_choice(image_norm, "image_norm", IMAGE_NORMS))
    return _greedy(*search, vectorised=True, normalise=normalise, image_norm=image_norm)


def greedy_snake_loop(
    potential: np.ndarray,
    init: np.ndarray,
    *,
    alpha: float = 0.4,
    beta: float = 0.4,
    gamma: float = 1.2,
    window: int = 3,
    d_min_px: float = 2.0,
    d_max_px: float = 6.0,
    max_iter: int = 300,
) -> SnakeResult:
    """The reference path of :func:`greedy_snake`: the same search, one point at a time.

    Parameters
    ----------
    potential, init, alpha, beta, gamma, window, d_min_px, d_max_px, max_iter
        As in :func:`greedy_snake`.

    Returns
    -------
    SnakeResult
        The same snake as :func:`greedy_snake` (tested), in more time.

    References
    ----------
    Caro et al., AMDO 2004, eqs. (4)-(7); Williams & Shah, CVGIP: IU 55, 1992.
    """
    search = _search_input(potential, init, alpha, beta, gamma, window, d_min_px, d_max_px, max_iter)
    return _greedy(*search, vectorised=False)


def _dp_iteration(points: np.ndarray, edge: np.ndarray, weights: SnakeWeights, offsets: np.ndarray,
                  fixed: int, floor: float | None = None, image_norm: str = "range") -> tuple[np.ndarray, int]:
    """One Amini step: the best candidates of every point but ``fixed``, by dynamic programming.

    State ``(j_{i-1}, j_i)``: candidates of two neighbours; the transition adds eq. (6)'s curvature
    of the triple, eq. (5)'s continuity of the pair and eq. (7)'s image term. E_cont and E_curv are
    scaled by ``dbar`` and ``dbar^2`` (a neighbourhood maximum is not defined before the choice).
    The curvature at the fixed point itself is left out, so the chain stays a chain; the fixed
    point rotates each iteration. Returns the new points and the energy evaluations (about n m^3).
    """
    q = np.roll(points, -fixed, axis=0)
    n, m = q.shape[0], offsets.shape[0]
    d_bar = float(np.mean(np.linalg.norm(np.roll(q, -1, axis=0) - q, axis=1)))
    scale = max(d_bar, 1.0)
    cands = q[:, None, :] + offsets[None]                                     # (n, m, 2)
    cands[0] = q[0]                                                           # the fixed point
    rows = np.clip(cands[..., 0], 0, edge.shape[0] - 1).astype(int)
    cols = np.clip(cands[..., 1], 0, edge.shape[1] - 1).astype(int)
    e_image = _image_term(edge[rows, cols], _floor(edge) if floor is None else floor, image_norm)   # eq. (7)
    outside = ((cands < 0) | (cands > np.asarray(edge.shape) - 1)).any(axis=2)
    e_image = np.where(outside, np.inf, e_image)

    def cont(a, b):                                                           # eq. (5), a (.., 2), b (.., 2)
        return np.abs(d_bar - np.linalg.norm(b - a, axis=-1)) / scale

    def curv(a, b, c):                                                        # eq. (6)
        return np.sum((a - 2 * b + c) ** 2, axis=-1) / scale ** 2

    a, b, g = weights.alpha, weights.beta, weights.gamma
    cost = a * cont(q[0], cands[1]) + g * e_image[1]                          # point 1, (m,)
    cost = (cost[:, None] + a * cont(cands[1][:, None], cands[2][None])       # points 1, 2: (m, m)
            + b * curv(q[0], cands[1][:, None], cands[2][None]) + g * e_image[2][None])
    evaluations = m + m * m
    back = []
    for i in range(3, n):                                                     # (j_{i-2}, j_{i-1}) -> (j_{i-1}, j_i)
        triple = (cost[:, :, None]
                  + b * curv(cands[i - 2][:, None, None], cands[i - 1][None, :, None], cands[i][None, None]))
        best = np.argmin(triple, axis=0)                                      # (m, m): best j_{i-2}
        cost = (np.take_along_axis(triple, best[None], axis=0)[0]
                + a * cont(cands[i - 1][:, None], cands[i][None]) + g * e_image[i][None])   # eq. (4)
        back.append(best)
        evaluations += m ** 3
    closing = cost + a * cont(cands[n - 1][None], q[0]) + b * curv(cands[n - 2][:, None], cands[n - 1][None], q[0])
    evaluations += m * m
    j_prev, j_last = np.unravel_index(int(np.argmin(closing)), closing.shape)
    choice = np.zeros(n, dtype=int)
    choice[n - 1], choice[n - 2] = j_last, j_prev
    for i in range(n - 1, 2, -1):
        choice[i - 2] = back[i - 3][choice[i - 1], choice[i]]
    choice[0] = 0
    moved = q + offsets[choice]
    return np.roll(moved, fixed, axis=0), evaluations


def dp_pass(potential: np.ndarray, points: np.ndarray, *, fixed: int = 0, alpha: float = 0.4, beta: float = 0.4,
            gamma: float = 2.4, window: int = 3, image_norm: str = "range") -> np.ndarray:
    """One pass of Amini's dynamic programming: the jointly best candidates of every point but ``fixed``.

    The table's state is the pair ``(j_{i-1}, j_i)`` of two neighbours' candidates; each step adds
    eq. (6)'s curvature of a triple, eq. (5)'s continuity of a pair and eq. (7)'s image term of the
    new point (as :func:`greedy_energies`: E_image over each point's candidates' range, E_cont and
    E_curv over ``dbar`` and ``dbar^2``, ``dbar`` the mean spacing before the pass). Point ``fixed``
    keeps its place and its own curvature is left out, so the closed snake becomes a chain from
    ``fixed + 1`` round to ``fixed - 1``, closed by the last point's continuity and curvature to it.
    No point is added or dropped (:func:`dp_snake` respaces between passes).

    Parameters
    ----------
    potential : (rows, cols) ndarray
        Sec. 3.2's potential (low on edges), at least 7 x 7.
    points : (n, 2) ndarray
        The snake, (row, col) inside the image, n from 5 to 100,000; rounded to whole pixels.
    fixed : int
        Index of the point that stays, 0 to n - 1.
    alpha, beta, gamma : float
        Weights of eq. (4) (Table 1's dynamic programming: 0.4, 0.4, 2.4).
    window : int
        Odd side of each point's neighbourhood, 3 to 15.
    image_norm : {"range", "max"}
        As in :func:`greedy_snake`.

    Returns
    -------
    (n, 2) ndarray
        The moved points, in the same order.

    References
    ----------
    Caro et al., AMDO 2004, eqs. (4)-(7), Sec. 3.1; Amini, Weymouth & Jain, IEEE PAMI 12, 1990.
    """
    potential, points = _snake_input(potential, points, "potential", "points")
    weights = _weights(alpha, beta, gamma)
    window = check_odd_int(window, "window", maximum=MAX_WINDOW)
    fixed = check_positive_int(fixed, "fixed", minimum=0, maximum=points.shape[0] - 1)
    image_norm = str(check_choice(image_norm, "image_norm", IMAGE_NORMS))
    return _dp_iteration(np.rint(points), _edge_of(potential), weights, _offsets(window), fixed,
                         image_norm=image_norm)[0]


def _dp(potential: np.ndarray, init: np.ndarray, weights: SnakeWeights, window: int, d_min: float, d_max: float,
        max_iter: int) -> SnakeResult:
    start = time.perf_counter()
    edge, offsets = _edge_of(potential), _offsets(window)
    floor = _floor(edge)
    points = np.rint(init)
    history, evaluations, still, iteration = [], 0, 0, 0
    for iteration in range(1, max_iter + 1):
        moved, count = _dp_iteration(points, edge, weights, offsets, (iteration - 1) % points.shape[0], floor)
        evaluations += count
        still = still + 1 if np.array_equal(moved, points) else 0
        points = np.rint(_respace(moved, d_min, d_max))
        if still >= 2 or _repeats(points, history):
            break                                             # two still iterations, or an oscillation
    return SnakeResult(points, iteration, evaluations, time.perf_counter() - start)


def dp_snake(
    potential: np.ndarray,
    init: np.ndarray,
    *,
    alpha: float = 0.4,
    beta: float = 0.4,
    gamma: float = 2.4,
    window: int = 3,
    d_min_px: float = 2.0,
    d_max_px: float = 6.0,
    max_iter: int = 100,
) -> SnakeResult:
    """Amini's dynamic-programming snake on Sec. 3.2's potential (closed: one point fixed per iteration).

    Each iteration finds the jointly best candidates of all points but one (the start point, which
    rotates round the contour from one iteration to the next), by dynamic programming over pairs
    of neighbouring candidates: ``(n - 3) m^3 + 2 m^2 + m`` energy evaluations. It stops after two
    iterations without a move, on an oscillation, or after ``max_iter``.

    Parameters
    ----------
    potential : (rows, cols) ndarray
        Sec. 3.2's potential (low on edges), at least 7 x 7.
    init : (n, 2) ndarray
        Starting (row, col) points inside the image, n from 5 to 100,000.
    alpha, beta, gamma : float
        Weights of eq. (4) (Table 1: 0.4, 0.4, 2.4), non-negative, not all zero, each at most 1e6.
    window : int
        Odd side of each point's neighbourhood, 3 to 15.
    d_min_px, d_max_px : float
        Spacing limits of the variable ``n`` (pixels), ``0 < d_min_px < d_max_px / 2``.
    max_iter : int
        Most iterations, 1 to 100,000.

    Returns
    -------
    SnakeResult
        Final points, iterations, energy evaluations, seconds.

    References
    ----------
    Caro et al., AMDO 2004, eqs. (4)-(7), Sec. 3.1; A.A. Amini, T.E. Weymouth, R.C. Jain, Using dynamic
    programming for solving variational problems in vision, IEEE PAMI 12, 1990.
    """
    return _dp(*_search_input(potential, init, alpha, beta, gamma, window, d_min_px, d_max_px, max_iter))


def _internal_matrix(n: int, alpha: float, beta: float) -> np.ndarray:
    """Kass's pentadiagonal circulant ``A``: ``alpha`` times minus the second difference plus ``beta`` times the fourth."""
    row = np.zeros(n)
    row[[0, 1, 2, -2, -1]] = [2 * alpha + 6 * beta, -alpha - 4 * beta, beta, beta, -alpha - 4 * beta]
    return scipy.linalg.circulant(row)


def _variational(edge_map: np.ndarray, init: np.ndarray, weights: SnakeWeights, tau: float, d_min: float,
                 d_max: float, max_iter: int, mu: float, gvf_iter: int,
                 unit_flow: bool = True) -> SnakeResult:
    start = time.perf_counter()
    flow = _gvf(edge_map, mu, gvf_iter)
    if unit_flow:
        length = np.hypot(flow[0], flow[1])
        flow = np.where(length > 1e-12, flow / np.where(length > 1e-12, length, 1.0), 0.0)   # unit length
    points, evaluations, factor, iteration = init.astype(float), 0, None, 0
    limit = np.asarray(edge_map.shape) - 1.0
    for iteration in range(1, max_iter + 1):
        if factor is None or iteration % 10 == 0:             # respace, then refactor A + I/tau (LU)
            points = _respace(points, d_min, d_max)
            n = points.shape[0]
            factor = scipy.linalg.lu_factor(_internal_matrix(n, weights.alpha, weights.beta) + np.eye(n) / tau)
        force = np.stack([ndimage.map_coordinates(component, points.T, order=1, mode="nearest")
                          for component in flow], axis=1)
        evaluations += points.shape[0]
        # eq. (1) by finite differences, semi-implicit: (A + I/tau) x_{t+1} = x_t / tau + gamma f(x_t);
        # A holds eq. (2)'s alpha |v_s|^2 + beta |v_ss|^2, f replaces eq. (3)'s -grad E_image by the unit GVF
        new = scipy.linalg.lu_solve(factor, points / tau + weights.gamma * force)
        points = np.clip(new, 0, limit)
    return SnakeResult(points, iteration, evaluations, time.perf_counter() - start)


def variational_snake(
    edge_map: np.ndarray,
    init: np.ndarray,
    *,
    alpha: float = 0.4,
    beta: float = 0.4,
    gamma: float = 1.2,
    tau: float = 0.5,
    d_min_px: float = 2.0,
    d_max_px: float = 6.0,
    max_iter: int = 200,
    mu: float = 0.2,
    gvf_iter: int = 80,
    unit_flow: bool = True,
) -> SnakeResult:
    """Kass's snake solved semi-implicitly with an LU factorisation, pushed by the unit-length GVF.

    Parameters
    ----------
    edge_map : (rows, cols) ndarray
        High on edges (``cap - P`` for Sec. 3.2's potential ``P``), at least 7 x 7.
    init : (n, 2) ndarray
        Starting (row, col) points inside the map, n from 5 to 100,000.
    alpha, beta, gamma : float
        Tension, rigidity and force weights (Table 1: 0.4, 0.4, 1.2), non-negative, not all zero.
    tau : float
        Time step, in (0, 100].
    d_min_px, d_max_px : float
        Spacing limits of the variable ``n`` (applied every 10 iterations).
    max_iter : int
        Iterations, 1 to 100,000 (the snake runs all of them).
    mu, gvf_iter : float, int
        Diffusion weight in (0, 0.25] and steps of the gradient vector flow.
    unit_flow : bool
        Scale the flow to unit length (ours); ``False`` keeps the raw GVF, whose size follows the edge
        map's units and is small far from edges (an ablation).

    Returns
    -------
    SnakeResult
        Final points (sub-pixel), iterations, ``n`` force samples per iteration, seconds (GVF included).

    References
    ----------
    Caro et al., AMDO 2004, eqs. (1)-(3), Sec. 3.1; M. Kass, A. Witkin, D. Terzopoulos, Snakes: active
    contour models, ICCV 1987; C. Xu, J.L. Prince, Gradient vector flow, CVPR 1997.
    """
    edge_map, init = _snake_input(edge_map, init, "edge_map")
    weights = _weights(alpha, beta, gamma)
    tau = check_in_range(tau, "tau", 0.0, 100.0, closed="right")
    d_min, d_max = _spacing(d_min_px, d_max_px)
    max_iter = check_positive_int(max_iter, "max_iter", maximum=MAX_ITERATIONS)
    mu = float(as_finite_array(mu, "mu", bounds=(0.0, 0.25), closed="right"))
    gvf_iter = check_positive_int(gvf_iter, "gvf_iter", maximum=MAX_ITERATIONS)
    unit_flow = check_bool(unit_flow, "unit_flow")
    return _variational(edge_map, init, weights, tau, d_min, d_max, max_iter, mu, gvf_iter, unit_flow)
