"""A seeded synthetic talking face: the stream of frames the chapter learns from.

A grey face, drawn with soft edges on a dark background, is driven per frame by four latent
trajectories (mouth opening, mouth width, brow raise, blink). The clean frames are kept beside the
noisy ones, so a model's reconstruction can be scored against the truth.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common import as_finite_array, check_image_shape, check_positive, check_positive_int, make_rng

__all__ = ["LATENT_NAMES", "PAPER_SIZE", "TalkingFace", "face_masks", "make_talking_face", "psnr_db",
           "render_faces"]

#: The paper's face: 41,205 pixels (Sec. 3.1); 201 x 205 is one factorisation of that number.
PAPER_SIZE = (201, 205)
#: The four latent trajectories, one column each of :attr:`TalkingFace.latent`.
LATENT_NAMES = ("mouth_open", "mouth_width", "brow_raise", "blink")

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

    References
    ----------
    Melenchón, Meler & Iriondo, AMDO 2004, Sec. 4 (the sequences it stands in for).
    """

    frames: np.ndarray
    clean: np.ndarray
    latent: np.ndarray
    masks: dict[str, np.ndarray]
    noise: float


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
    latent = as_finite_array(latent, "latent", shape=(None, 4))
    if np.any(latent[:, [0, 3]] < 0) or np.any(latent[:, [0, 3]] > 1) or np.any(np.abs(latent[:, 1:3]) > 1):
        raise ValueError("latent must hold mouth opening and blink in [0, 1], width and brow raise in [-1, 1]")
    rows, cols = check_image_shape(size, "size", minimum=32)
    y, x = np.mgrid[0:rows, 0:cols].astype(float) / rows  # unit: face height; x right, y down
    cx = cols / rows / 2
    head = _soft_ellipse(x, y, cx, 0.5, 0.36, 0.47, 1.5 / rows)
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


def face_masks(size: tuple[int, int] = PAPER_SIZE) -> dict[str, np.ndarray]:
    """The four facial regions of Fig. 1: two eyes, the mouth and the forehead (disjoint boxes).

    Parameters
    ----------
    size : pair of int
        Frame size (rows, cols), each at least 32.

    Returns
    -------
    dict of str to ndarray of bool, shape (rows, cols)
        ``left_eye``, ``right_eye``, ``mouth``, ``forehead`` (left and right as seen in the image).

    References
    ----------
    Melenchón, Meler & Iriondo, AMDO 2004, Sec. 3.1 and Fig. 1(a).
    """
    rows, cols = check_image_shape(size, "size", minimum=32)
    y, x = np.mgrid[0:rows, 0:cols].astype(float) / rows
    cx = cols / rows / 2

    def box(x0: float, x1: float, y0: float, y1: float) -> np.ndarray:
        return (x >= cx + x0) & (x < cx + x1) & (y >= y0) & (y < y1)

    return {"left_eye": box(-0.25, -0.03, 0.27, 0.50), "right_eye": box(0.03, 0.25, 0.27, 0.50),
            "mouth": box(-0.17, 0.17, 0.66, 0.87), "forehead": box(-0.22, 0.22, 0.10, 0.27)}


def make_talking_face(n_frames: int, *, rng: int | np.random.Generator, size: tuple[int, int] = PAPER_SIZE,
                      noise: float = 0.01) -> TalkingFace:
    """A seeded talking face: smooth mouth and brow motion, blinks, Gaussian pixel noise.

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
    n_frames = check_positive_int(n_frames, "n_frames", minimum=2)
    generator = make_rng(rng, "rng")
    size = check_image_shape(size, "size", minimum=32)
    noise = check_positive(noise, "noise", allow_zero=True)
    if noise > 1:
        raise ValueError(f"noise must be at most 1 (grey levels are in [0, 1]), got {noise}")
    latent = _latent_tracks(generator, n_frames)
    clean = render_faces(latent, size=size)
    frames = clean + noise * generator.standard_normal(clean.shape)
    return TalkingFace(frames, clean, latent, face_masks(size), noise)


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
    clean = as_finite_array(clean, "clean", max_abs=1e100)
    if clean.shape != estimate.shape:
        raise ValueError(f"estimate and clean must have the same shape, got {estimate.shape} and {clean.shape}")
    mse = float(np.mean((estimate - clean) ** 2))
    return float("inf") if mse == 0 else float(-10 * np.log10(mse))
