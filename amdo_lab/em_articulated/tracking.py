"""Frame-to-frame tracking with texture refresh (Sec. 3, Sec. 5)."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from amdo_lab.common import MAX_ITERATIONS
from amdo_lab.common import check_positive_int

from amdo_lab.em_articulated.em import OUR_SETTINGS, EMSettings, check_em_settings, register_em
from amdo_lab.em_articulated.hand import HandModel, check_hand, check_points
from amdo_lab.em_articulated.surface import fit_surface

__all__ = ["TrackResult", "track", "TRACKING_SETTINGS"]

#: EM settings of a tracking frame: our debiased EM with the k-d tree E-step, σ from 8 mm (about the
#: motion between frames 50 ms apart) to 3 mm, four σ levels, one EM iteration per level; the surface
#: fit that follows corrects what the EM leaves. Chosen on held-out sequences (seeds 11-14, not the
#: chapter's seed 5): one iteration per level tracked better than two, three or five (lower median
#: error on all four sequences) and is the fastest; 3 or 5 σ levels, or 2 or 4 surface steps, did no
#: better. ``benchmarks/bench_01_em_articulated.py --tracking-ablation`` prints the comparison.
TRACKING_SETTINGS = replace(OUR_SETTINGS, sigma_max=8.0, sigma_min=3.0, n_levels=4, max_iter=1)
#: Texture refresh radius ε around the fitted surface, mm (the paper's 5 mm).
EPSILON_MM = 5.0
#: Most texture points carried to the next frame (evenly subsampled).
MAX_TEXTURE = 500


@dataclass(frozen=True)
class TrackResult:
    """Result of :func:`track`.

    Parameters
    ----------
    poses : numpy.ndarray, shape (F, 27)
        Estimated pose of every frame (the first is the given start pose).
    n_texture : numpy.ndarray of int, shape (F,)
        Texture points kept after each frame (data within ε of the fitted surface).

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591, Sec. 5.
    """

    poses: np.ndarray
    n_texture: np.ndarray


def track(frames: list, hand: HandModel, theta_start: np.ndarray, *, settings: EMSettings = TRACKING_SETTINGS,
          surface_max_iter: int = 3) -> TrackResult:
    """Track a sequence: EM on the previous frame's texture, surface fit, then texture refresh.

    The texture for frame t+1 is the data of frame t within ε = 5 mm of the fitted surface
    (|d| < ε, eq. 2), at most 500 of them (evenly subsampled). ``surface_max_iter``
    Gauss-Newton steps of the surface fit (Sec. 3.4; 0 skips it) on the data within ε of the
    EM's pose correct the drift that frame-to-frame matching alone accumulates.

    Parameters
    ----------
    frames : list of array_like
        Data of every frame, shape (M_f, 3), mm, within ±1e6; at least one frame.
    hand : HandModel
        The hand to track.
    theta_start : array_like, shape (27,)
        Pose at the first frame, inside the joint limits.
    settings : EMSettings, default TRACKING_SETTINGS
        Settings of each frame's EM (:func:`register_em`).
    surface_max_iter : int, default 3
        Most Gauss-Newton steps of the surface fit per frame (≥ 0; 0 skips it).
        At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).

    Returns
    -------
    TrackResult
        Poses and texture sizes per frame.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591, Sec. 3 (texture refresh, eq. 2),
    Sec. 3.4 (surface fit) and Sec. 5.
    """
    if not hasattr(frames, "__len__") or len(frames) == 0:
        raise ValueError("frames must be a non-empty list of (n, 3) point arrays, one per frame")
    frames = [check_points(data, f"frames[{f}]") for f, data in enumerate(frames)]
    check_hand(hand)
    theta = hand.check_theta(theta_start, "theta_start", within_limits=True)
    settings = check_em_settings(settings)
    surface_max_iter = check_positive_int(surface_max_iter, "surface_max_iter", minimum=0, maximum=MAX_ITERATIONS)
    texture = frames[0][np.abs(hand._surface_distance(frames[0], theta)) < EPSILON_MM]
    poses, counts = [theta], [len(texture)]
    for data in frames[1:]:
        texture = texture[:: max(1, int(np.ceil(len(texture) / MAX_TEXTURE)))]
        theta = register_em(texture, data, hand, theta, settings=settings).theta
        if surface_max_iter:
            close = np.abs(hand._surface_distance(data, theta)) < EPSILON_MM
            if np.any(close):
                theta = fit_surface(data[close], hand, theta, max_iter=surface_max_iter).theta
        texture = data[np.abs(hand._surface_distance(data, theta)) < EPSILON_MM]
        poses.append(theta)
        counts.append(len(texture))
    return TrackResult(np.array(poses), np.array(counts))
