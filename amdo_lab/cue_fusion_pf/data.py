"""Synthetic head sequences with ground truth, and the overlap of two ellipses.

The paper's videos are not available, so each figure gets a seeded sequence built to show one
difficulty: an office-like background with strong edges, a head (skin ellipse, hair, eyes, mouth)
over a shirt, camera noise, and, for the "fusion" kind, a colour cast on frames 29-80, a
skin-coloured hand crossing in front of the face, the head turning its back to the camera, and fast
jumps at the end; the "lighting" and "turn" kinds isolate the lighting change and the head's pose.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from amdo_lab.common import as_finite_array, check_bool, check_choice, check_in_range, check_same_shape, check_positive_int, make_rng
from amdo_lab.cue_fusion_pf.likelihoods import MAX_PIXELS, check_frames
from amdo_lab.cue_fusion_pf.shape import as_states

__all__ = ["HEAD_AXES", "HeadSequence", "SEQUENCE_KINDS", "SequenceWithTruth", "as_ellipse", "ellipse_iou", "head_views", "make_head_sequence"]

#: Semi-axes (a along x, b along y) of the head at scale s = 0, in pixels.
HEAD_AXES = (20.0, 26.0)
SEQUENCE_KINDS = ("fusion", "edges", "twin", "lighting", "turn")
FRAME_RATE = 25.0
SKIN = np.array([214.0, 158.0, 126.0])
HAIR = np.array([62.0, 42.0, 30.0])
SHIRT = np.array([70.0, 95.0, 140.0])
_CLUTTER_COLOURS = np.array([[40, 60, 110], [150, 150, 160], [30, 90, 60], [190, 190, 80], [110, 40, 50],
                             [20, 20, 25], [230, 230, 235], [90, 120, 150], [60, 130, 140]], float)


class SequenceWithTruth:
    """What a rendered sequence with ground truth offers (shared by :class:`HeadSequence` and the walker's).

    A subclass holds ``frames`` (T, H, W, 3), ``truth`` (T, d) true states, ``segments``
    ``{name: (start, stop)}`` and ``oracle_std`` (centre std in pixels, std of each shape entry).

    References
    ----------
    Li & Chaumette, AMDO 2004, Sec. 4 (the sequences and their ground truth).
    """

    def oracle_log_likelihood(self, t: int, states: np.ndarray) -> np.ndarray:
        """A likelihood that knows the truth: Gaussian on the centre and on each shape entry.

        Parameters
        ----------
        t : int
            Frame index, in [0, T).
        states : numpy.ndarray
            (N, d) or (d,) states, entries within ±:data:`~amdo_lab.cue_fusion_pf.shape.MAX_STATE_ENTRY`.

        Returns
        -------
        numpy.ndarray
            (N,) log-likelihoods (0 at the truth).
        """
        t = check_positive_int(t, "t", minimum=0, maximum=len(self.truth) - 1)
        states = np.atleast_2d(as_states(states, self.truth.shape[1]))
        centre_sd, shape_sd = self.oracle_std
        squared = np.sum((states[:, :2] - self.truth[t, :2]) ** 2, axis=1) / centre_sd**2
        return -0.5 * (squared + np.sum((states[:, 2:] - self.truth[t, 2:]) ** 2, axis=1) / shape_sd**2)

    def segment_of_frames(self) -> np.ndarray:
        """The name of the segment each frame belongs to.

        Returns
        -------
        numpy.ndarray
            (T,) segment names (object array).
        """
        names = np.empty(len(self.frames), dtype=object)
        for name, (start, stop) in self.segments.items():
            names[start:stop] = name
        return names


@dataclass
class HeadSequence(SequenceWithTruth):
    """A rendered sequence and its ground truth.

    Parameters
    ----------
    frames : numpy.ndarray
        (T, H, W, 3) uint8 RGB.
    truth : numpy.ndarray
        (T, 3) true states ``(cx, cy, s)``: centre in pixels, relative scale.
    true_ellipses : numpy.ndarray
        (T, 5) ``(cx, cy, a, b, angle)``.
    segments : dict
        Ordered ``{name: (start, stop)}`` frame ranges (stop excluded).
    kind : str
        The generator's kind.
    oracle_std : tuple of float
        Standard deviations of the oracle likelihood: centre (px) and scale, each in (0, 1e6].

    References
    ----------
    Li & Chaumette, AMDO 2004, Sec. 4 (the head sequences this one imitates).
    """

    frames: np.ndarray
    truth: np.ndarray
    true_ellipses: np.ndarray
    segments: dict[str, tuple[int, int]]
    kind: str
    oracle_std: tuple[float, float] = field(default=(2.0, 0.02))

    def __post_init__(self) -> None:
        self.frames = check_frames(self.frames)
        self.truth = as_finite_array(self.truth, "truth", shape=(len(self.frames), 3), max_abs=1e6)
        self.true_ellipses = as_finite_array(self.true_ellipses, "true_ellipses", shape=(len(self.truth), 5), max_abs=1e6)
        _check_segments(self.segments, len(self.frames))
        self.kind = check_choice(self.kind, "kind", SEQUENCE_KINDS)
        self.oracle_std = tuple(as_finite_array(self.oracle_std, "oracle_std", shape=(2,), bounds=(0.0, 1e6), closed="right"))


def _check_segments(segments: object, n_frames: int) -> dict[str, tuple[int, int]]:
    """``segments`` after checking it maps str names to int frame ranges ``(start, stop)`` within ``n_frames``."""
    if not isinstance(segments, dict) or not all(
            isinstance(name, str) and isinstance(span, tuple) and len(span) == 2
            and all(isinstance(i, int) and not isinstance(i, bool) for i in span) and 0 <= span[0] < span[1] <= n_frames
            for name, span in segments.items()):
        raise TypeError(f"segments must be a dict of name -> (start, stop) frame ranges within {n_frames} frames")
    return segments


def office_background(rng: np.random.Generator, height: int, width: int) -> np.ndarray:
    """An office-like wall: a shelf of books, framed pictures, a window, a desk; no skin colours.

    Shared by the head sequences and the cascade's training scenes (:mod:`.structure`).

    Parameters
    ----------
    rng : numpy.random.Generator
        Source of the books, pictures and their colours (already made by the caller).
    height, width : int
        Image size in pixels.

    Returns
    -------
    numpy.ndarray
        (height, width, 3) float32 RGB grey levels in [0, 255].

    References
    ----------
    Li & Chaumette, AMDO 2004, Sec. 4 (heads tracked over office clutter).
    """
    ys, xs = np.mgrid[0:height, 0:width]
    image = np.empty((height, width, 3), np.float32)
    image[:] = np.array([150.0, 155.0, 150.0]) + 0.15 * (ys[..., None] - height / 2)
    del xs
    shelf_top = int(rng.integers(20, 40))
    x = 0
    while x < width:  # a shelf of books: many vertical edges of varying contrast
        book = int(rng.integers(5, 13))
        colour = _CLUTTER_COLOURS[rng.integers(len(_CLUTTER_COLOURS))]
        top = shelf_top + int(rng.integers(0, 12))
        if rng.random() < 0.7:
            image[top : shelf_top + 45, x : x + book - 1] = colour
        x += book
    image[shelf_top + 45 : shelf_top + 49] = (95.0, 80.0, 70.0)  # the shelf board
    for _ in range(4):  # pictures and a monitor: rectangles with frames
        h, w = int(rng.integers(25, 50)), int(rng.integers(25, 60))
        top, left = int(rng.integers(shelf_top + 55, height - h)), int(rng.integers(0, width - w))
        image[top : top + h, left : left + w] = _CLUTTER_COLOURS[rng.integers(len(_CLUTTER_COLOURS))]
        image[top + 3 : top + h - 3, left + 3 : left + w - 3] = _CLUTTER_COLOURS[rng.integers(len(_CLUTTER_COLOURS))]
    image[height - 22 :] = (85.0, 85.0, 95.0)  # desk edge
    return image


def _coverage(dx: np.ndarray, dy: np.ndarray, a: float, b: float, softness: float = 1.0) -> np.ndarray:
    """Fraction of each pixel inside the ellipse (a linear ramp of ``softness`` pixels at the border)."""
    radius = np.sqrt((dx / a) ** 2 + (dy / b) ** 2)
    return np.clip((1.0 - radius) * min(a, b) / softness + 0.5, 0.0, 1.0)


def _paint(image: np.ndarray, alpha: np.ndarray, colour: np.ndarray) -> None:
    alpha = alpha.astype(np.float32)[..., None]
    image += alpha * (np.asarray(colour, np.float32) - image)


def _window(image: np.ndarray, cx: float, cy: float, half_width: float, top: float, bottom: float):
    """The sub-image (a view) and its pixel offsets from (cx, cy) where a shape is drawn: only there."""
    height, width, _ = image.shape
    x0, x1 = max(int(cx - half_width), 0), min(int(cx + half_width) + 2, width)
    y0, y1 = max(int(cy + top), 0), min(int(cy + bottom) + 2, height)
    ys, xs = np.mgrid[y0:y1, x0:x1]
    return image[y0:y1, x0:x1], xs - cx, ys - cy


def draw_head(image: np.ndarray, cx: float, cy: float, scale: float, yaw: float = 0.0, tilt: float = 0.0) -> None:
    """Paint a head over shoulders into ``image``, in place.

    Shared by the head sequences and the cascade's training scenes (:mod:`.structure`).

    Parameters
    ----------
    image : numpy.ndarray
        (H, W, 3) float32 RGB, modified in place.
    cx, cy : float
        Centre of the head ellipse, pixels.
    scale : float
        Size relative to ``HEAD_AXES``.
    yaw : float
        Turn in radians: 0 frontal, ±π/4 half profiles, π the back of the head.
    tilt : float
        Roll in the image plane, radians, clockwise on screen for positive values.

    References
    ----------
    Li & Chaumette, AMDO 2004, Sec. 4 and Figs. 4-5 (heads seen from the front, the side and the back).
    """
    a, b = HEAD_AXES[0] * scale, HEAD_AXES[1] * scale
    window, dx, dy = _window(image, cx, cy, 2.2 * a, -1.1 * b, 4.0 * b)
    # shirt and shoulders below the chin
    shoulders = _coverage(dx, dy - 2.5 * b, 2.0 * a, 1.4 * b) * (dy > 0.85 * b)
    _paint(window, shoulders, SHIRT)
    if tilt:  # the head's own axes: (dx, dy) rotated by -tilt
        dx, dy = np.cos(tilt) * dx + np.sin(tilt) * dy, -np.sin(tilt) * dx + np.cos(tilt) * dy
    head = _coverage(dx, dy, a, b)
    radius = np.sqrt((dx / a) ** 2 + (dy / b) ** 2)
    shading = 1.0 - 0.18 * np.clip(radius, 0, 1) ** 2  # brighter in the middle of the face
    window += (head * shading)[..., None].astype(np.float32) * SKIN.astype(np.float32) - head[..., None].astype(np.float32) * window
    facing = np.cos(yaw)
    # hair on the top, and on the side turned away (all of the head seen from the back)
    side = np.sin(yaw) * dx / a
    hair_line = -0.35 + 1.6 * np.clip(-side - 0.2 * facing, 0.0, None) + 1.4 * np.clip(-facing, 0.0, None)
    hair = head * np.clip((-dy / b - 0.35 + hair_line + 0.35) * 6.0, 0.0, 1.0) if yaw else head * np.clip((-dy / b - 0.35) * 6.0, 0.0, 1.0)
    _paint(window, hair, HAIR)
    if facing <= 0.2:
        return
    shift = np.sin(yaw) * 0.45
    features = [(-0.38 * facing + shift, -0.05, 0.12 * max(facing, 0.3), 0.07, (40, 30, 30)),
                (0.38 * facing + shift, -0.05, 0.12 * max(facing, 0.3), 0.07, (40, 30, 30)),
                (shift, 0.5, 0.3 * facing, 0.06, (140, 60, 60))]  # eyes and mouth
    for ex, ey, ea, eb, colour in features:
        # the feature's centre in image offsets (rotated by the tilt; the small features themselves are not)
        ox, oy = ex * a, ey * b
        if tilt:
            ox, oy = np.cos(tilt) * ox - np.sin(tilt) * oy, np.sin(tilt) * ox + np.cos(tilt) * oy
        feature, fx, fy = _window(image, cx + ox, cy + oy, ea * a + 2, -eb * b - 2, eb * b + 2)
        _paint(feature, _coverage(fx, fy, ea * a, eb * b), np.array(colour, np.float32))


#: Frame counts and sizes (width, height) of each kind.
_LAYOUT = {"fusion": (164, 256, 192), "edges": (100, 256, 192), "twin": (80, 256, 192),
           "lighting": (100, 320, 240), "turn": (120, 256, 192)}
#: Frames of the "fusion" kind's three jumps (each about 30 px in two frames).
_JUMP_STARTS = (144, 151, 158)


def _segments(kind: str, n_frames: int) -> dict[str, tuple[int, int]]:
    """The named frame ranges of each kind: what each stretch of the sequence is built to test."""
    return {"fusion": {"calm": (0, 29), "lighting": (29, 81), "distractor": (81, 104), "turned away": (104, 140),
                       "agile": (140, n_frames)},
            "edges": {"sharp": (0, 40), "weak edges": (40, 80), "sharp again": (80, n_frames)},
            "twin": {"apart": (0, 30), "crossing": (30, 50), "after": (50, n_frames)},
            "lighting": {"normal": (0, 20), "mild change": (20, 60), "strong change": (60, n_frames)},
            "turn": {"frontal": (0, 15), "pose": (15, 55), "tilt": (55, 80), "turning away": (80, 90),
                     "back": (90, n_frames)}}[kind]


def _ramp(t: np.ndarray, start: float, stop: float) -> np.ndarray:
    """0 before ``start``, 1 after ``stop``, a smooth (half-cosine) rise in between."""
    return 0.5 - 0.5 * np.cos(np.pi * np.clip((t - start) / (stop - start), 0.0, 1.0))


def _trajectory(kind: str, rng: np.random.Generator, n_frames: int, width: int, height: int) -> np.ndarray:
    t = np.arange(n_frames, dtype=float)
    phase = rng.uniform(0, 2 * np.pi, size=3)
    cx = width / 2 + 0.16 * width * np.sin(2 * np.pi * t / 120 + phase[0]) + 3 * np.sin(2 * np.pi * t / 17 + phase[1])
    cy = height / 2 + 8 * np.sin(2 * np.pi * t / 70 + phase[2])
    scale = 0.07 * np.sin(2 * np.pi * t / 90 + phase[1])
    if kind == "twin":  # straight across the frame, meeting a twin coming the other way
        cx = np.linspace(0.27 * width, 0.73 * width, n_frames)
        cy = np.full(n_frames, height / 2.0)
        scale = np.zeros(n_frames)
    if kind == "fusion":  # agile jumps: 14 to 18 px per frame for two frames, back and forth
        jumps = np.zeros((n_frames, 2))
        direction = rng.choice([-1.0, 1.0])
        for start in _JUMP_STARTS:
            if start + 2 <= n_frames:
                step = np.array([direction * rng.uniform(28, 36), rng.uniform(-10, 10)])
                jumps[start : start + 2] += np.outer([0.5, 1.0], step)
                jumps[start + 2 :] += step
                direction = -direction
        cx, cy = cx + jumps[:, 0], cy + jumps[:, 1]
    return np.stack([cx, cy, scale], axis=1)


def _pose_and_light(kind: str, rng: np.random.Generator, n_frames: int, cast_strength: float):
    """Per frame: head yaw and tilt (radians) and the size of the lighting change (0 none, 1 full cast)."""
    t = np.arange(n_frames, dtype=float)
    yaw, tilt, cast = np.zeros(n_frames), np.zeros(n_frames), np.zeros(n_frames)
    if kind == "fusion":
        # the cast ramps in over 29-33 and out over 77-80; the head turns its back on 104-139
        cast = np.clip(np.minimum(t - 28, 81 - t) / 4.0, 0.0, 1.0)
        turn = rng.choice([-1.0, 1.0])
        yaw = turn * np.pi * (_ramp(t, 104, 112) + _ramp(t, 130, 138))  # frontal, back (112-129), frontal
    elif kind == "lighting":  # a quarter of the cast on 20-59, the full cast from frame 60 (4-frame ramps)
        cast = 0.25 * _ramp(t, 18, 22) + 0.75 * _ramp(t, 58, 62)
    elif kind == "turn":
        side = rng.choice([-1.0, 1.0])
        pose = (t >= 15) & (t < 55)
        yaw[pose] = side * np.pi / 3 * np.sin(2 * np.pi * (t[pose] - 15) / 40)  # half profiles, ±60°
        rolling = (t >= 55) & (t < 80)
        tilt[rolling] = np.radians(15.0) * np.sin(2 * np.pi * (t[rolling] - 55) / 25)  # ±15° in the image plane
        yaw += side * np.pi * _ramp(t, 80, 90)  # turns away: profile near frame 85, the back from 90
    return yaw, tilt, cast_strength * cast


def make_head_sequence(kind: str, *, rng: int | np.random.Generator, noise_std: float = 5.0,
                       cast_strength: float = 1.0) -> HeadSequence:
    """A seeded RGB head sequence at 25 fps with its ground truth; each kind tests one difficulty per segment.

    Parameters
    ----------
    kind : str
        One of :data:`SEQUENCE_KINDS`; segments are listed in ``.segments``:

        - ``"fusion"`` (256×192, 164 frames), a stretch that defeats each cue: calm 0-28; colour
          cast and darkening on 29-80 (colour); a skin-coloured hand crossing the face on 81-103;
          the head turning its back to the camera on 104-139, the back shown on 112-129
          (structure); three jumps of about 30 px in two frames on 140-163 (edges).
        - ``"edges"`` (256×192, 100 frames): the camera loses focus and contrast on 40-79, so
          edges vanish.
        - ``"twin"`` (256×192, 80 frames): the head crosses an identical head walking the other
          way, in front of it, on frames 30-49.
        - ``"lighting"`` (320×240, 100 frames): normal light on 0-19, a quarter of the colour cast
          on 20-59, the full cast from frame 60.
        - ``"turn"`` (256×192, 120 frames): frontal on 0-14, half profiles (yaw ±60°) on 15-54,
          in-plane tilt of ±15° on 55-79, turning away on 80-89, the back of the head on 90-119.
    rng : int or numpy.random.Generator
        Source of the background, the motion and the noise.
    noise_std : float
        Standard deviation of the camera noise, grey levels, in [0, 255].
    cast_strength : float
        Size of the lighting change, 0 (none) to 1.5; at 1 the full cast has channel gains 0.45,
        0.62, 1.05, and values in between scale the gains' departure from 1 ("fusion" and
        "lighting" kinds).

    Returns
    -------
    HeadSequence
        Frames, truth, ellipses (their angle is the head's tilt) and segments.

    References
    ----------
    Li & Chaumette, AMDO 2004, Sec. 4 and Figs. 2-5.
    """
    kind = check_choice(kind, "kind", SEQUENCE_KINDS)
    generator = make_rng(rng, "rng")
    noise_std = check_in_range(noise_std, "noise_std", 0.0, 255.0, closed="both")  # grey levels of uint8
    cast_strength = check_in_range(cast_strength, "cast_strength", 0.0, 1.5, closed="both")
    n_frames, width, height = _LAYOUT[kind]
    background = office_background(generator, height, width)
    truth = _trajectory(kind, generator, n_frames, width, height)
    yaw, tilt, cast = _pose_and_light(kind, generator, n_frames, cast_strength)
    segments = _segments(kind, n_frames)
    frames = np.empty((n_frames, height, width, 3), np.uint8)
    hand_start, hand_stop = segments["distractor"] if kind == "fusion" else (0, 0)
    for t in range(n_frames):
        image = background.copy()
        cx, cy, s = truth[t]
        draw_head(image, cx, cy, 1.0 + s, yaw[t], tilt[t])
        if kind == "twin":  # the twin walks the other way, in front
            draw_head(image, width - cx, cy, 1.0 + s)
        if hand_start <= t < hand_stop:  # a hand crosses in front of the face
            progress = (t - hand_start) / (hand_stop - hand_start - 1)
            hx = cx - 70 + 140 * progress
            window, dx, dy = _window(image, hx, cy + 10, 16.0, -20.0, 20.0)
            _paint(window, _coverage(dx, dy, 13.0, 17.0, softness=5.0), SKIN * 0.97)
        if cast[t] > 0:  # colour cast and darkening
            gain = 1.0 + cast[t] * (np.array([0.45, 0.62, 1.05]) - 1.0)
            image *= gain.astype(np.float32)
        elif kind == "edges" and 40 <= t < 80:  # defocus and low contrast: the edges fade
            import cv2
            image = cv2.GaussianBlur(image.astype(np.float32), (0, 0), 3.5)
            image = 0.45 * image + 0.55 * image.mean(axis=(0, 1))
        image += noise_std * generator.standard_normal(image.shape, dtype=np.float32)
        np.clip(image, 0, 255, out=image)
        frames[t] = (image + 0.5).astype(np.uint8)
    axes = np.outer(1.0 + truth[:, 2], HEAD_AXES)
    true_ellipses = np.column_stack([truth[:, :2], axes, tilt])
    return HeadSequence(frames, truth, true_ellipses, segments, kind)


def as_ellipse(ellipse: object, name: str, *, allow_stack: bool = False) -> np.ndarray:
    """Return ``ellipse`` as a float array ``(cx, cy, a, b, angle)`` after checking it.

    Parameters
    ----------
    ellipse : array_like
        (5,), or (T, 5) when ``allow_stack``: centre and semi-axes in pixels (axes > 0), angle in
        radians; every entry within ±:data:`~amdo_lab.cue_fusion_pf.likelihoods.MAX_PIXELS`.
    name : str
        The argument's name, used in error messages.
    allow_stack : bool
        Whether a (T, 5) stack of ellipses is accepted (a flag of the package's own calls).

    Returns
    -------
    numpy.ndarray
        The ellipse(s), shape as given.

    References
    ----------
    Li & Chaumette, AMDO 2004, Sec. 2.1 (the ellipse of a contour).
    """
    ellipse = as_finite_array(ellipse, name, max_abs=MAX_PIXELS)
    allow_stack = check_bool(allow_stack, "allow_stack")
    shapes, ndims = ("(5,) or (T, 5)", (1, 2)) if allow_stack else ("(5,)", (1,))
    if ellipse.ndim not in ndims or ellipse.shape[-1] != 5 or np.any(ellipse[..., 2:4] <= 0):
        raise ValueError(f"{name} must be an ellipse (cx, cy, a, b, angle) with positive axes, of shape {shapes}, "
                         f"got {ellipse.shape}")
    return ellipse


def ellipse_iou(first: np.ndarray, second: np.ndarray, *, step: float = 0.5) -> np.ndarray:
    """Intersection over union of ellipses ``(cx, cy, a, b, angle)``, row by row, on a grid of ``step`` px.

    Parameters
    ----------
    first, second : numpy.ndarray
        (5,) or (T, 5) ellipses (semi-axes a along x at angle 0, angle in radians), entries
        within ±1e6.
    step : float
        Grid spacing in pixels for counting the intersection (its error is about step / min axis),
        in (0, 1e6].

    Returns
    -------
    float or numpy.ndarray
        IoU in [0, 1], one per row.

    References
    ----------
    The success criterion of this chapter (IoU >= 0.5); the paper shows its results as figures.
    """
    first, second = as_ellipse(first, "first", allow_stack=True), as_ellipse(second, "second", allow_stack=True)
    step = check_in_range(step, "step", 0.0, 1e6, closed="right")
    check_same_shape(first, second, "first", "second")  # which one is at fault is unknowable: name both
    single = first.ndim == 1
    first, second = np.atleast_2d(first), np.atleast_2d(second)
    scores = np.empty(len(first))
    for row, (e1, e2) in enumerate(zip(first, second)):
        # count grid points inside both ellipses over the overlap of their bounding boxes only; the
        # union's area follows from the exact areas π a b (so a huge ellipse costs no memory)
        lo = np.maximum(e1[:2] - max(e1[2], e1[3]), e2[:2] - max(e2[2], e2[3]))
        hi = np.minimum(e1[:2] + max(e1[2], e1[3]), e2[:2] + max(e2[2], e2[3]))
        if np.any(hi <= lo):
            scores[row] = 0.0
            continue
        gx, gy = np.meshgrid(np.arange(lo[0], hi[0], step) + step / 2, np.arange(lo[1], hi[1], step) + step / 2)
        intersection = np.count_nonzero(_inside(e1, gx, gy) & _inside(e2, gx, gy)) * step**2
        union = np.pi * (e1[2] * e1[3] + e2[2] * e2[3]) - intersection
        scores[row] = float(np.clip(intersection / union, 0.0, 1.0))
    return float(scores[0]) if single else scores


def _inside(ellipse: np.ndarray, gx: np.ndarray, gy: np.ndarray) -> np.ndarray:
    cx, cy, a, b, angle = ellipse
    c, s = np.cos(angle), np.sin(angle)
    u = (gx - cx) * c + (gy - cy) * s
    v = -(gx - cx) * s + (gy - cy) * c
    return (u / a) ** 2 + (v / b) ** 2 <= 1.0


def head_views(yaws: np.ndarray, *, rng: int | np.random.Generator, noise_std: float = 5.0) -> tuple[np.ndarray, np.ndarray]:
    """One 256×192 frame per yaw (radians; 0 frontal, ±π/4 half profiles, π the back) and the true states.

    Each frame has its own office background and a head at a random place and scale.

    Parameters
    ----------
    yaws : array_like
        (n,) head yaw angles in radians.
    rng : int or numpy.random.Generator
        Source of the backgrounds, positions and noise.
    noise_std : float
        Camera noise, grey levels, in [0, 255].

    Returns
    -------
    tuple of numpy.ndarray
        (n, 192, 256, 3) uint8 frames and (n, 3) true states ``(cx, cy, s)``.

    References
    ----------
    Li & Chaumette, AMDO 2004, Fig. 4 (the structure cue as the head turns).
    """
    yaws = as_finite_array(yaws, "yaws", ndim=1)
    noise_std = check_in_range(noise_std, "noise_std", 0.0, 255.0, closed="both")  # grey levels of uint8
    generator = make_rng(rng, "rng")
    frames, states = [], []
    for yaw in yaws:
        image = office_background(generator, 192, 256)
        state = np.array([generator.uniform(70, 186), generator.uniform(70, 110), generator.uniform(-0.1, 0.1)])
        draw_head(image, state[0], state[1], 1.0 + state[2], float(yaw))
        image += noise_std * generator.standard_normal(image.shape, dtype=np.float32)
        frames.append(np.clip(image + 0.5, 0, 255).astype(np.uint8))
        states.append(state)
    return np.array(frames), np.array(states)
