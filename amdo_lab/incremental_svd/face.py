"""A seeded synthetic talking face: the stream of frames the chapter learns from.

A grey face, drawn with soft edges on a dark background, is driven per frame by four latent
trajectories (mouth opening, mouth width, brow raise, blink). The clean frames are kept beside the
noisy ones, so a model's reconstruction can be scored against the truth.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from scipy import ndimage

from amdo_lab.common import (as_finite_array, check_choice, check_image_shape, check_in_range,
                             check_positive_int, make_rng, MAX_ITERATIONS)

__all__ = ["LATENT_NAMES", "MOTIONS", "PAPER_SIZE", "SIMILARITY_BOUNDS", "TalkingFace", "corner_error_less_offset_px",
           "corner_error_px",
           "make_talking_face", "psnr_db", "render_faces", "similarity_points"]

#: The paper's face: 41,205 pixels (Sec. 3.1); 201 x 205 is one factorisation of that number.
PAPER_SIZE = (201, 205)
#: The four latent trajectories, one column each of :attr:`TalkingFace.latent`.
LATENT_NAMES = ("mouth_open", "mouth_width", "brow_raise", "blink")
#: ``"none"``: the face stays still; ``"similarity"``: it moves on a textured canvas.
MOTIONS = ("none", "similarity")
#: Largest shift (px), rotation (rad) and log scale of ``motion="similarity"``: ±6 px, ±4°, ±4 %.
SIMILARITY_BOUNDS = (6.0, 6.0, np.deg2rad(4.0), np.log(1.04))

_REFERENCE = "Melenchón, Meler & Iriondo. On-the-Fly Training. AMDO 2004, LNCS 3179, Sec. 3.1 and Fig. 1."


@dataclass(frozen=True)
class TalkingFace:
    """A sequence of face frames with its truth.

    Parameters
    ----------
    frames : ndarray, shape (n_frames, rows, cols)
        Noisy frames, grey levels in [0, 1] plus noise.
    clean : ndarray, shape (n_frames, rows, cols)
        The same frames without noise.
    latent : ndarray, shape (n_frames, 4)
        Mouth opening and blink in [0, 1], mouth width and brow raise in [-1, 1] (:data:`LATENT_NAMES`).
    masks : dict of str to ndarray of bool, shape (rows, cols)
        Four facial regions: ``left_eye``, ``right_eye``, ``mouth``, ``forehead`` (disjoint).
    noise : float
        Standard deviation of the added noise.
    truth : ndarray, shape (n_frames, 4)
        Placement of the face in each frame, ``(tx, ty, angle, log_scale)`` (px, px, rad, natural log;
        x right, y down, see :func:`similarity_points`); all zero for ``motion="none"``.

    References
    ----------
    Melenchón, Meler & Iriondo, AMDO 2004, Sec. 4 (the sequences it stands in for).
    """

    frames: np.ndarray
    clean: np.ndarray
    latent: np.ndarray
    masks: dict[str, np.ndarray]
    noise: float
    truth: np.ndarray


def _smooth_track(rng: np.random.Generator, n_frames: int, period_frames: float) -> np.ndarray:
    """A smooth random trajectory of unit scale: white noise through a Gaussian filter."""
    width = period_frames / 4
    half = int(np.ceil(4 * width))
    kernel = np.exp(-0.5 * (np.arange(-half, half + 1) / width) ** 2)
    raw = np.convolve(rng.standard_normal(n_frames + 2 * half), kernel / np.sqrt(np.sum(kernel**2)), "valid")
    return raw


def _latent_tracks(rng: np.random.Generator, n_frames: int) -> np.ndarray:
    mouth_open = np.clip(0.45 + 0.35 * _smooth_track(rng, n_frames, 6.0), 0.0, 1.0)  # syllables, ~4 Hz
    mouth_width = np.tanh(0.8 * _smooth_track(rng, n_frames, 30.0))
    brow_raise = np.tanh(0.8 * _smooth_track(rng, n_frames, 40.0))
    blink = np.zeros(n_frames)
    start = int(rng.integers(10, 60))
    while start < n_frames:                       # a blink every 2-5 s at 25 frames/s, 7 frames long
        profile = np.array([0.3, 0.7, 1.0, 1.0, 0.7, 0.4, 0.15])
        stop = min(start + profile.size, n_frames)
        blink[start:stop] = profile[:stop - start]
        start += int(rng.integers(50, 125))
    return np.column_stack([mouth_open, mouth_width, brow_raise, blink])


def similarity_points(params: np.ndarray, points: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """Where the points ``points`` of the face's reference frame appear under the placement ``params``.

    A placement turns the reference frame about its centre ``c`` by ``angle``, scales it by
    ``exp(log_scale)`` and shifts it by ``(tx, ty)``: ``x = c + exp(log_scale) R(angle) (u - c) + t``.

    Parameters
    ----------
    params : ndarray, shape (4,) or (n, 4)
        ``(tx, ty, angle, log_scale)``: px, px, rad, natural log; x right, y down.
    points : ndarray, shape (m, 2)
        Points ``(x, y)`` in pixels of the reference frame.
    size : pair of int
        Frame size (rows, cols); its centre is the centre of the rotation and scaling.

    Returns
    -------
    ndarray, shape (m, 2) or (n, m, 2)
        The placed points.

    References
    ----------
    Melenchón, Meler & Iriondo, AMDO 2004, Sec. 3.2 (the alignment coefficients a_t).

    Examples
    --------
    >>> similarity_points([1.0, 2.0, 0.0, 0.0], [[0.0, 0.0]], (5, 5)).tolist()
    [[1.0, 2.0]]
    """
    params = as_finite_array(params, "params", shape=(4,) if np.ndim(params) == 1 else (None, 4), max_abs=1e6)
    points = as_finite_array(points, "points", shape=(None, 2), max_abs=1e9)
    rows, cols = check_image_shape(size, "size")
    return _place(params, points, rows, cols)


def _place(params: np.ndarray, points: np.ndarray, rows: int, cols: int) -> np.ndarray:
    centre = np.array([(cols - 1) / 2, (rows - 1) / 2])
    tx, ty, angle, log_scale = (params[..., k, None] for k in range(4))
    dx, dy = points[:, 0] - centre[0], points[:, 1] - centre[1]
    scale = np.exp(log_scale)
    x = centre[0] + scale * (np.cos(angle) * dx - np.sin(angle) * dy) + tx
    y = centre[1] + scale * (np.sin(angle) * dx + np.cos(angle) * dy) + ty
    return np.stack([x, y], axis=-1)


def corner_error_px(params: np.ndarray, truth: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """Mean distance, over the four corners of the frame, between two placements of it, per frame.

    Parameters
    ----------
    params, truth : ndarray, shape (n, 4)
        Estimated and true placements ``(tx, ty, angle, log_scale)`` (see :func:`similarity_points`).
    size : pair of int
        Frame size (rows, cols).

    Returns
    -------
    ndarray, shape (n,)
        Pixels.

    References
    ----------
    Melenchón, Meler & Iriondo, AMDO 2004, Fig. 4 (the tracking it scores).

    Examples
    --------
    >>> corner_error_px([[3.0, 4.0, 0.0, 0.0]], [[0.0, 0.0, 0.0, 0.0]], (10, 10)).tolist()
    [5.0]
    """
    params, truth, (rows, cols) = _check_placements(params, truth, size)
    corners = np.array([[0, 0], [cols - 1, 0], [cols - 1, rows - 1], [0, rows - 1]], dtype=float)
    gaps = _place(params, corners, rows, cols) - _place(truth, corners, rows, cols)
    return np.mean(np.linalg.norm(gaps, axis=-1), axis=-1)


def _check_placements(params: object, truth: object, size: object) -> tuple[np.ndarray, np.ndarray, tuple[int, int]]:
    """Estimated and true placements, one row (tx, ty, angle, log_scale) per frame, and the frame size."""
    params = as_finite_array(params, "params", shape=(None, 4), max_abs=1e6)
    truth = as_finite_array(truth, "truth", shape=(params.shape[0], 4), max_abs=1e6)
    return params, truth, check_image_shape(size, "size")


def corner_error_less_offset_px(params: np.ndarray, truth: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """:func:`corner_error_px` after taking out one similarity offset shared by all frames.

    A tracker whose models were learnt at a misplaced region places every frame as the truth composed
    with a constant similarity O of the reference frame: estimate(u) = truth(O(u)). The estimated corners
    are pulled back into the reference frame through the true placement, O is fitted to all frames by
    least squares (a similarity u -> a u + b in complex numbers), and the error left is measured in the
    frame, as :func:`corner_error_px` does. It is zero for a constant offset, whatever its size.

    Parameters
    ----------
    params, truth : ndarray, shape (n, 4)
        Estimated and true placements ``(tx, ty, angle, log_scale)`` (see :func:`similarity_points`),
        entries within ±1e6.
    size : pair of int
        Frame size (rows, cols).

    Returns
    -------
    ndarray, shape (n,)
        Pixels.

    References
    ----------
    Melenchón, Meler & Iriondo, AMDO 2004, Fig. 4 (the tracking it scores).

    Examples
    --------
    >>> offset = [[3.0, 4.0, 0.0, 0.0], [3.0, 4.0, 0.0, 0.0]]     # the same 5-pixel shift on both frames
    >>> corner_error_less_offset_px(offset, [[0.0] * 4, [1.0, 0.0, 0.0, 0.0]], (10, 10)).round(12).tolist()
    [0.0, 0.0]
    """
    params, truth, (rows, cols) = _check_placements(params, truth, size)
    return _error_less_offset(params, truth, rows, cols)


def _error_less_offset(params: np.ndarray, truth: np.ndarray, rows: int, cols: int) -> np.ndarray:
    centre = complex((cols - 1) / 2, (rows - 1) / 2)
    corners = np.array([0, cols - 1, cols - 1 + 1j * (rows - 1), 1j * (rows - 1)])  # x + i y
    # a placement in complex numbers: z = centre + k (u - centre) + t, k = exp(log_scale + i angle)
    k_est, t_est = np.exp(params[:, 3] + 1j * params[:, 2])[:, None], (params[:, 0] + 1j * params[:, 1])[:, None]
    k_true, t_true = np.exp(truth[:, 3] + 1j * truth[:, 2])[:, None], (truth[:, 0] + 1j * truth[:, 1])[:, None]
    placed = centre + k_est * (corners - centre) + t_est
    pulled = centre + (placed - centre - t_true) / k_true      # the estimate's corners in the reference frame
    design = np.column_stack([np.tile(corners, len(params)), np.ones(pulled.size)])
    a, b = np.linalg.lstsq(design, pulled.ravel(), rcond=None)[0]   # the offset O(u) = a u + b
    offset_placed = centre + k_true * (a * corners + b - centre) + t_true
    return np.mean(np.abs(placed - offset_placed), axis=-1)


def _similarity_tracks(rng: np.random.Generator, n_frames: int) -> np.ndarray:
    """Smooth placements starting at zero, each parameter reaching its bound at its largest."""
    tracks = np.column_stack([_smooth_track(rng, n_frames, 80.0) for _ in SIMILARITY_BOUNDS])
    tracks -= tracks[0]
    peak = np.maximum(np.max(np.abs(tracks), axis=0), 1e-12)
    return tracks / peak * np.array(SIMILARITY_BOUNDS)


def _texture(rng: np.random.Generator, rows: int, cols: int) -> np.ndarray:
    """A seeded canvas: smoothed noise about grey level 0.35."""
    raw = ndimage.gaussian_filter(rng.standard_normal((rows, cols)), rows / 60)
    return np.clip(0.35 + 0.12 * raw / raw.std(), 0.0, 1.0)


def _move(clean: np.ndarray, truth: np.ndarray, canvas: np.ndarray) -> np.ndarray:
    """Place each clean face on the canvas: pixel x shows the face at the reference point u, x = S(u)."""
    rows, cols = canvas.shape
    y, x = np.mgrid[0:rows, 0:cols].astype(float)
    head = _head(x / rows, y / rows, cols / rows / 2, 1.5 / rows)
    centre = np.array([(cols - 1) / 2, (rows - 1) / 2])
    moved = np.empty_like(clean)
    for frame, face, (tx, ty, angle, log_scale) in zip(moved, clean, truth):
        dx, dy = (x - centre[0] - tx) / np.exp(log_scale), (y - centre[1] - ty) / np.exp(log_scale)
        ref = [centre[1] - np.sin(angle) * dx + np.cos(angle) * dy, centre[0] + np.cos(angle) * dx + np.sin(angle) * dy]
        cover = ndimage.map_coordinates(head, ref, order=1, cval=0.0)
        frame[:] = cover * ndimage.map_coordinates(face, ref, order=1, mode="nearest") + (1 - cover) * canvas
    return moved


def _head(x: np.ndarray, y: np.ndarray, cx: float, edge: float) -> np.ndarray:
    return _soft_ellipse(x, y, cx, 0.5, 0.36, 0.47, edge)


def _soft_ellipse(x: np.ndarray, y: np.ndarray, cx: float, cy: float, ax: float, ay: float,
                  edge_px: float = 1.5) -> np.ndarray:
    """Coverage in [0, 1] of an axis-aligned ellipse, with a linear ramp about ``edge_px`` wide."""
    radius = np.sqrt(((x - cx) / ax) ** 2 + ((y - cy) / ay) ** 2)
    signed_px = (1.0 - radius) * min(ax, ay)      # roughly the distance inside the rim, in pixels
    return np.clip(0.5 + signed_px / edge_px, 0.0, 1.0)


def render_faces(latent: np.ndarray, *, size: tuple[int, int] = PAPER_SIZE) -> np.ndarray:
    """Draw one clean face per row of ``latent``.

    Parameters
    ----------
    latent : ndarray, shape (n, 4)
        Mouth opening and blink in [0, 1], mouth width and brow raise in [-1, 1], per frame.
    size : pair of int
        Frame size (rows, cols), each at least 32.

    Returns
    -------
    ndarray, shape (n, rows, cols)
        Grey levels in [0, 1].

    References
    ----------
    Melenchón, Meler & Iriondo, AMDO 2004, Fig. 2 (the faces it stands in for).

    Examples
    --------
    >>> render_faces([[0.5, 0.0, 0.0, 0.0]], size=(40, 41)).shape
    (1, 40, 41)
    """
    latent = as_finite_array(latent, "latent", shape=(None, 4), bounds=(-1, 1))  # width and brow raise
    as_finite_array(latent[:, [0, 3]], "latent's mouth opening and blink", bounds=(0, 1))
    rows, cols = check_image_shape(size, "size", minimum=32)
    y, x = np.mgrid[0:rows, 0:cols].astype(float) / rows  # unit: face height; x right, y down
    cx = cols / rows / 2
    head = _head(x, y, cx, 1.5 / rows)
    base = 0.12 + head * (0.62 - 0.18 * (y - 0.3) ** 2 - 0.12 * (x - cx) ** 2)
    base -= 0.10 * _soft_ellipse(x, y, cx, 0.58, 0.035, 0.09, 3.0 / rows)   # the shadow of the nose
    frames = np.empty((latent.shape[0], rows, cols))
    for frame, (mouth_open, mouth_width, brow_raise, blink) in zip(frames, latent):
        face = base.copy()
        for side in (-1, 1):
            ex = cx + side * 0.15
            eye = _soft_ellipse(x, y, ex, 0.42, 0.065, max(0.032 * (1 - blink), 0.003), 1.5 / rows)
            iris = _soft_ellipse(x, y, ex, 0.42, 0.025, 0.025, 1.5 / rows) * eye
            face += 0.28 * eye - 0.75 * iris
            brow = _soft_ellipse(x, y, ex, 0.33 - 0.035 * brow_raise, 0.08, 0.012, 1.5 / rows)
            face -= 0.35 * brow
        mouth = _soft_ellipse(x, y, cx, 0.76, 0.11 * (1 + 0.2 * mouth_width), 0.012 + 0.05 * mouth_open,
                              1.5 / rows)
        teeth = _soft_ellipse(x, y, cx, 0.76 - 0.02 * mouth_open, 0.07, 0.012 * mouth_open + 1e-3, 1.5 / rows)
        frame[:] = np.clip(face - 0.45 * mouth + 0.5 * teeth * mouth, 0.0, 1.0)
    return frames


def _face_masks(rows: int, cols: int) -> dict[str, np.ndarray]:
    """The four facial regions of Fig. 1 on a (rows, cols) frame: two eyes, the mouth and the forehead
    (disjoint boxes; left and right as seen in the image)."""
    y, x = np.mgrid[0:rows, 0:cols].astype(float) / rows
    cx = cols / rows / 2

    def box(x0: float, x1: float, y0: float, y1: float) -> np.ndarray:
        return (x >= cx + x0) & (x < cx + x1) & (y >= y0) & (y < y1)

    return {"left_eye": box(-0.25, -0.03, 0.27, 0.50), "right_eye": box(0.03, 0.25, 0.27, 0.50),
            "mouth": box(-0.17, 0.17, 0.66, 0.87), "forehead": box(-0.22, 0.22, 0.10, 0.27)}


def make_talking_face(n_frames: int, *, rng: int | np.random.Generator, size: tuple[int, int] = PAPER_SIZE,
                      noise: float = 0.01, motion: str = "none") -> TalkingFace:
    """A seeded talking face: smooth mouth and brow motion, blinks, Gaussian pixel noise.

    With ``motion="similarity"`` the face also moves, on a still textured canvas, under a smooth
    similarity of at most ±6 px, ±4° and ±4 % (:data:`SIMILARITY_BOUNDS`) that starts at zero, so the
    masks drawn on the first frame fit it; :attr:`TalkingFace.truth` holds the placements.

    Parameters
    ----------
    n_frames : int
        Number of frames, at least 2.
    rng : int or numpy.random.Generator
        Seed of the trajectories and the noise.
    size : pair of int
        Frame size (rows, cols), each at least 32; the paper's 41,205 pixels by default.
    noise : float
        Standard deviation of the Gaussian noise added to each pixel, non-negative, at most 1.
    motion : {"none", "similarity"}
        Whether the face stays still or moves on a textured canvas.

    Returns
    -------
    TalkingFace
        Noisy and clean frames, the latent trajectories and the four masks.

    References
    ----------
    Melenchón, Meler & Iriondo, AMDO 2004, Sec. 4 (a 316-frame and a 10,000-frame sequence at 25 fps).

    Examples
    --------
    >>> face = make_talking_face(3, rng=0, size=(40, 41))
    >>> face.frames.shape, sorted(face.masks)
    ((3, 40, 41), ['forehead', 'left_eye', 'mouth', 'right_eye'])
    """
    n_frames = check_positive_int(n_frames, "n_frames", minimum=2, maximum=MAX_ITERATIONS)
    generator = make_rng(rng, "rng")
    size = check_image_shape(size, "size", minimum=32)
    noise = check_in_range(noise, "noise", 0, 1, closed="both")  # grey levels are in [0, 1]
    check_choice(motion, "motion", MOTIONS)
    latent = _latent_tracks(generator, n_frames)
    clean = render_faces(latent, size=size)
    truth = np.zeros((n_frames, 4))
    if motion == "similarity":   # drawn after the latent tracks, so the still face's draws are unchanged
        truth = _similarity_tracks(generator, n_frames)
        clean = _move(clean, truth, _texture(generator, *size))
    frames = clean + noise * generator.standard_normal(clean.shape)
    return TalkingFace(frames, clean, latent, _face_masks(*size), noise, truth)


def psnr_db(estimate: np.ndarray, clean: np.ndarray) -> float:
    """Peak signal-to-noise ratio of ``estimate`` against ``clean``, for grey levels in [0, 1].

    Parameters
    ----------
    estimate, clean : ndarray, same shape
        Images or stacks of images.

    Returns
    -------
    float
        ``-10 log10(mean((estimate - clean)^2))`` in dB (a peak of 1); inf for identical input.

    References
    ----------
    Melenchón, Meler & Iriondo, AMDO 2004, Fig. 2 (the quality it shows by eye).

    Examples
    --------
    >>> round(psnr_db(np.full(4, 0.51), np.full(4, 0.5)), 1)
    40.0
    """
    estimate = as_finite_array(estimate, "estimate", max_abs=1e100)
    clean = as_finite_array(clean, "clean (same shape as estimate)", shape=estimate.shape, max_abs=1e100)
    mse = float(np.mean((estimate - clean) ** 2))
    return float("inf") if mse == 0 else float(-10 * np.log10(mse))
