"""Peers on the same frames: OpenCV's CamShift (mean shift on a colour back-projection, ref. [13])."""

from __future__ import annotations

import time

import cv2
import numpy as np

from amdo_lab.common import as_finite_array, check_positive_int
from amdo_lab.cue_fusion_pf.tracker import TrackResult, _check_frames

__all__ = ["track_camshift"]


def track_camshift(frames: np.ndarray, init: np.ndarray, *, hue_bins: int = 32) -> TrackResult:
    """Track with ``cv2.CamShift`` on the back-projection of the initial ellipse's hue histogram.

    The usual OpenCV recipe: a hue histogram of the target (pixels with saturation and value above
    a floor), back-projected on each frame, and CamShift's window started from the last one.
    ``states`` holds ``(cx, cy, s)`` with s the relative change of the larger semi-axis.

    Parameters
    ----------
    frames : (T, H, W, 3) uint8 RGB.
    init : initial ellipse ``(cx, cy, a, b, angle)``.
    hue_bins : bins of the hue histogram.
    """
    frames = _check_frames(frames)
    init = as_finite_array(init, "init", shape=(5,))
    if init[2] <= 0 or init[3] <= 0:
        raise ValueError(f"init ellipse axes must be positive, got a={init[2]}, b={init[3]}")
    hue_bins = check_positive_int(hue_bins, "hue_bins", minimum=2)
    began = time.perf_counter()
    height, width = frames.shape[1:3]
    cx, cy, a, b, _ = init
    window = (int(max(cx - a, 0)), int(max(cy - b, 0)), int(2 * a), int(2 * b))
    hsv = cv2.cvtColor(frames[0], cv2.COLOR_RGB2HSV)
    mask = cv2.inRange(hsv, (0, 40, 40), (180, 255, 255))
    x, y, w, h = window
    histogram = cv2.calcHist([hsv[y : y + h, x : x + w]], [0], mask[y : y + h, x : x + w], [hue_bins], [0, 180])
    cv2.normalize(histogram, histogram, 0, 255, cv2.NORM_MINMAX)
    criteria = (cv2.TERM_CRITERIA_EPS | cv2.TERM_CRITERIA_COUNT, 10, 1)
    ellipses = np.empty((len(frames), 5))
    for k, frame in enumerate(frames):
        hsv = cv2.cvtColor(frame, cv2.COLOR_RGB2HSV)
        back = cv2.calcBackProject([hsv], [0], histogram, [0, 180], 1)
        back &= cv2.inRange(hsv, (0, 40, 40), (180, 255, 255))
        box, window = cv2.CamShift(back, window, criteria)
        (bx, by), (bw, bh), angle = box
        if bw <= 0 or bh <= 0 or window[2] <= 0 or window[3] <= 0:  # lost: keep the last ellipse
            ellipses[k] = ellipses[k - 1] if k else init
            window = (int(np.clip(ellipses[k, 0] - a, 0, width - 2)), int(np.clip(ellipses[k, 1] - b, 0, height - 2)),
                      int(2 * a), int(2 * b))
            continue
        ellipses[k] = (bx, by, bw / 2.0, bh / 2.0, np.deg2rad(angle))
    seconds = time.perf_counter() - began
    scale = np.maximum(ellipses[:, 2], ellipses[:, 3]) / max(a, b) - 1.0
    states = np.column_stack([ellipses[:, :2], scale])
    return TrackResult(states, ellipses, ellipses[:, :2].copy(), np.full(len(frames), np.nan), seconds,
                       states[:, None, :], np.ones((len(frames), 1)))
