"""A seeded walker sequence with ground truth, for the paper's person tracking (Sec. 4, Fig. 6).

The paper's second video (a person walking past a shop window, filmed through a wide-angle lens)
is not available, so we render one with the difficulties the paper lists: an articulated walker
(head, torso, swinging arms and legs) whose clothes have the colours of the window behind it,
lettering on the glass in front of the walker, the walker's reflection on the floor, barrel
distortion of the whole image, and a burst of clutter (a bright reflection sweeping across the
glass) around frame 95.

The tracked contour is a B-spline outline of the body standing straight; the ground truth is, per
frame, the true outline (the neutral outline carried along the walk and through the lens
distortion) and the similarity state (eqs. 2-3) that fits it best in the least-squares sense.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import cv2
import numpy as np

from amdo_lab.common import as_finite_array, check_in_range, make_rng
from amdo_lab.cue_fusion_pf.data import SequenceWithTruth
from amdo_lab.cue_fusion_pf.shape import ShapeSpace

__all__ = ["WALKER_SEGMENTS", "WalkerSequence", "box_iou", "make_walker_sequence"]

WIDTH, HEIGHT, N_FRAMES = 640, 240, 130
#: Frame ranges (stop excluded): the clutter burst covers frames 88-102, around the paper's frame 95.
WALKER_SEGMENTS = {"walking": (0, 88), "clutter": (88, 103), "after": (103, N_FRAMES)}
#: Undistorted scene: the floor line, the walker's height and the margin rendered around the frame.
FLOOR_Y, BODY_HEIGHT, MARGIN = 196.0, 140.0, 64
#: Lens centre (px) and focal length used to normalise radii for the barrel distortion.
LENS_CENTRE, LENS_FOCAL = np.array([320.0, 80.0]), 320.0
GLASS = np.array([118.0, 134.0, 150.0])  # the window's tint
FRAME_DARK = np.array([52.0, 58.0, 66.0])  # the sill and the display stands
MULLION = np.array([168.0, 170.0, 174.0])  # aluminium window frames
SHIRT = 0.78 * GLASS  # clothes coloured like the window behind, a shade darker
TROUSERS = FRAME_DARK + np.array([6.0, 4.0, 2.0])
SKIN, HAIR = np.array([205.0, 160.0, 130.0]), np.array([50.0, 38.0, 30.0])
#: The neutral outline (arms at the sides, legs together), x right and y down in body heights,
#: from the top of the head clockwise; the origin is the hips.
_OUTLINE = np.array([
    [0.0, -0.52], [0.05, -0.50], [0.06, -0.44], [0.035, -0.39], [0.12, -0.35], [0.14, -0.22], [0.13, -0.05],
    [0.10, 0.02], [0.085, 0.25], [0.075, 0.46], [0.08, 0.50], [0.02, 0.50], [0.0, 0.10],
    [-0.02, 0.50], [-0.08, 0.50], [-0.075, 0.46], [-0.085, 0.25], [-0.10, 0.02], [-0.13, -0.05], [-0.14, -0.22],
    [-0.12, -0.35], [-0.035, -0.39], [-0.06, -0.44], [-0.05, -0.50]])


@dataclass
class WalkerSequence(SequenceWithTruth):
    """A rendered walker sequence and its ground truth (the interface of ``HeadSequence``).

    Parameters
    ----------
    frames : numpy.ndarray
        (T, 240, 640, 3) uint8 RGB.
    truth : numpy.ndarray
        (T, 4) similarity states ``(t_x, t_y, s_c, s_s)`` of the template (eqs. 2-3) that best fit
        the true outline of each frame.
    true_ellipses : numpy.ndarray
        (T, 5) the template's ellipse at the true states ``(cx, cy, a, b, angle)``.
    true_control_points : numpy.ndarray
        (T, J, 2) the true outline's control points after the lens distortion (not exactly a
        similarity of the template).
    segments : dict
        Ordered ``{name: (start, stop)}`` frame ranges (stop excluded).
    template : numpy.ndarray
        (J, 2) the outline's control points on frame 0: the ``init`` of :func:`track`.
    kind : str
        ``"walker"``.
    oracle_std : tuple of float
        Standard deviations of the oracle likelihood: centre (px) and each of s_c, s_s.

    References
    ----------
    Li & Chaumette, AMDO 2004, Sec. 4 and Fig. 6 (the sequence this one imitates).
    """

    frames: np.ndarray
    truth: np.ndarray
    true_ellipses: np.ndarray
    true_control_points: np.ndarray
    segments: dict[str, tuple[int, int]]
    template: np.ndarray
    kind: str = "walker"
    oracle_std: tuple[float, float] = field(default=(2.0, 0.02))

    def shape_space(self) -> ShapeSpace:
        """The similarity shape space of the template, in which ``truth`` is expressed.

        Returns
        -------
        ShapeSpace
            ``ShapeSpace(template, "similarity")``.
        """
        return ShapeSpace(self.template, "similarity")


def _fit_similarity(template: np.ndarray, points: np.ndarray) -> np.ndarray:
    """The similarity state ``(t_x, t_y, s_c, s_s)`` whose eq. (2) best fits ``points`` (least squares).

    With the template centred, ``t`` is the mean of ``points`` and, writing points as complex
    numbers, ``(1 + s_c) + i s_s = Σ conj(q̄_j) p_j / Σ |q̄_j|²`` (p centred): the linear
    least-squares solution of ``W X + Q̄ = P`` for the four columns of W (eq. 3, right).

    Check-free: :func:`make_walker_sequence` calls it with its own outlines (a template of distinct points).

    Parameters
    ----------
    template : numpy.ndarray
        (J, 2) template control points (centred here on their mean).
    points : numpy.ndarray
        (J, 2) or (T, J, 2) control points to fit.

    Returns
    -------
    numpy.ndarray
        (4,) or (T, 4) states; exact when ``points`` is a similarity of the template.

    References
    ----------
    Li & Chaumette, AMDO 2004, eqs. (2)-(3); Blake & Isard, Active Contours (1998), ch. 4.
    """
    centred = template - template.mean(axis=0)
    q = centred[:, 0] + 1j * centred[:, 1]
    centre = points.mean(axis=-2)
    p = (points[..., 0] - centre[..., None, 0]) + 1j * (points[..., 1] - centre[..., None, 1])
    a = (p @ np.conj(q)) / np.sum(np.abs(q) ** 2)
    return np.concatenate([centre, np.stack([a.real - 1.0, a.imag], axis=-1)], axis=-1)


# --- the lens --------------------------------------------------------------------------------

def _undistort(points: np.ndarray, k: float) -> np.ndarray:
    """Scene position seen at image position ``points``: ``u = c + (d - c)(1 + k r_d²)`` (barrel for k > 0)."""
    offset = (points - LENS_CENTRE) / LENS_FOCAL
    return LENS_CENTRE + LENS_FOCAL * offset * (1.0 + k * np.sum(offset**2, axis=-1, keepdims=True))


def _distort(points: np.ndarray, k: float) -> np.ndarray:
    """Image position of scene ``points``: inverts :func:`_undistort` (Newton on the radius)."""
    offset = (points - LENS_CENTRE) / LENS_FOCAL
    radius_u = np.linalg.norm(offset, axis=-1, keepdims=True)
    radius_d = radius_u.copy()
    for _ in range(20):  # r_d (1 + k r_d²) = r_u is increasing in r_d: Newton converges from r_u
        radius_d -= (radius_d * (1.0 + k * radius_d**2) - radius_u) / (1.0 + 3.0 * k * radius_d**2)
    ratio = np.divide(radius_d, radius_u, out=np.ones_like(radius_u), where=radius_u > 0)
    return LENS_CENTRE + LENS_FOCAL * offset * ratio


# --- the scene -------------------------------------------------------------------------------

def _shop_window(rng: np.random.Generator) -> np.ndarray:
    """The undistorted background (with a margin): wall, glass with displays and mullions, sill, floor."""
    height, width = HEIGHT + 2 * MARGIN, WIDTH + 2 * MARGIN
    top, sill = int(MARGIN + 22), int(MARGIN + FLOOR_Y - 8)
    image = np.empty((height, width, 3), np.float32)
    image[:] = (196.0, 186.0, 168.0)  # the wall above
    image[top:sill] = GLASS
    for _ in range(9):  # displays behind the glass, some in the clothes' colours
        w, h = int(rng.integers(30, 90)), int(rng.integers(30, 110))
        x, y = int(rng.integers(0, width - w)), int(rng.integers(top + 10, sill - h))
        colour = [SHIRT, TROUSERS, GLASS * 0.8, np.array([150.0, 160.0, 170.0])][int(rng.integers(4))]
        image[y : y + h, x : x + w] = colour + rng.normal(0.0, 4.0, 3)
    ys, xs = np.mgrid[top:sill, 0:width]  # a soft diagonal reflection of the street across the glass
    image[top:sill] += (10.0 * np.sin((xs + 0.6 * ys) / 23.0))[..., None].astype(np.float32)
    for x in range(MARGIN - 4, width, 160):  # mullions
        image[top - 4 : sill, x : x + 6] = MULLION
    image[top - 6 : top] = MULLION
    image[sill : sill + 8] = FRAME_DARK  # the sill, just above the floor line
    image[sill + 8 :] = (112.0, 108.0, 104.0)  # the floor
    for x in range(0, width, 70):  # tile joints converge a little: they cross the reflection
        cv2.line(image, (x, sill + 8), (x - 20, height), (96.0, 92.0, 90.0), 2, cv2.LINE_AA)
    return image


def _lettering() -> tuple[np.ndarray, np.ndarray]:
    """Lettering on the glass, drawn in front of the walker: its coverage and colour (undistorted, with margin)."""
    height, width = HEIGHT + 2 * MARGIN, WIDTH + 2 * MARGIN
    mask = np.zeros((height, width), np.uint8)
    for x, y, text in ((MARGIN + 20, MARGIN + 132, "SALE -50%"), (MARGIN + 330, MARGIN + 132, "NEW SEASON"),
                       (MARGIN + 200, MARGIN + 62, "OPEN")):
        cv2.putText(mask, text, (x, y), cv2.FONT_HERSHEY_DUPLEX, 1.3, 255, 3, cv2.LINE_AA)
    return mask.astype(np.float32) / 255.0, np.array([238.0, 238.0, 232.0], np.float32)


def _limb(origin: np.ndarray, angle: float, length: float) -> np.ndarray:
    """The end of a limb of ``length`` px hanging from ``origin`` turned by ``angle`` (0: straight down)."""
    return origin + length * np.array([np.sin(angle), np.cos(angle)])


def _body_parts(hips: np.ndarray, phase: float) -> list[tuple[str, list[np.ndarray], float, np.ndarray]]:
    """Capsules (name, polyline, thickness px, colour) of the walker at gait ``phase``, back to front."""
    h = BODY_HEIGHT
    swing = 0.42 * np.sin(phase)  # thighs swing opposite to each other, arms opposite to the legs
    shoulders = hips + np.array([0.0, -0.33 * h])
    parts = []
    for side, sign in (("back", -1.0), ("front", 1.0)):
        thigh = sign * swing
        knee = _limb(hips, thigh, 0.25 * h)
        bend = 0.5 * max(0.0, np.sin(phase * sign + 0.8))  # the knee bends on the forward swing
        ankle = _limb(knee, thigh - bend, 0.24 * h)
        foot = ankle + np.array([0.07 * h, 0.0])
        arm = -0.8 * sign * swing
        elbow = _limb(shoulders + np.array([0.0, 0.02 * h]), arm, 0.18 * h)
        wrist = _limb(elbow, arm + 0.25, 0.16 * h)
        shade = 0.85 if side == "back" else 1.0
        parts.append((f"{side} leg", [hips, knee, ankle, foot], 0.085 * h, TROUSERS * shade))
        parts.append((f"{side} arm", [shoulders + np.array([0.0, 0.02 * h]), elbow, wrist], 0.06 * h, SHIRT * shade))
        parts.append((f"{side} hand", [wrist, wrist + np.array([0.0, 0.02 * h])], 0.045 * h, SKIN * shade))
    # draw order: back limbs, torso, head, front limbs
    order = [parts[0], parts[1], parts[2],
             ("torso", [shoulders + np.array([0.0, 0.03 * h]), hips - np.array([0.0, 0.02 * h])], 0.2 * h, SHIRT),
             ("neck", [shoulders, shoulders - np.array([0.0, 0.06 * h])], 0.06 * h, SKIN),
             ("head", [shoulders - np.array([0.0, 0.12 * h])], 0.105 * h, SKIN),
             ("hair", [shoulders - np.array([0.0, 0.16 * h])], 0.085 * h, HAIR),  # a cap: the face stays skin
             parts[3], parts[4], parts[5]]
    return order


def _draw_walker(height: int, hips: np.ndarray, phase: float) -> tuple[int, int, np.ndarray, np.ndarray]:
    """The walker in a box of the undistorted scene reaching its bottom: top row, left column, colour, coverage."""
    left, top = int(hips[0] + MARGIN - 0.4 * BODY_HEIGHT), int(hips[1] + MARGIN - 0.7 * BODY_HEIGHT)
    width, height = int(0.8 * BODY_HEIGHT), height - top
    colour = np.zeros((height, width, 3), np.float32)
    coverage = np.zeros((height, width), np.float32)
    origin = np.array([left - MARGIN, top - MARGIN], float)
    for _name, polyline, thickness, part_colour in _body_parts(hips - origin, phase):
        # draw each part only in its own bounding box (a tenth of the walker's box)
        corner = np.floor(np.min(polyline, axis=0) - thickness - 2).astype(int).clip(0)
        end = np.ceil(np.max(polyline, axis=0) + thickness + 2).astype(int)
        mask = np.zeros((max(end[1] - corner[1], 1), max(end[0] - corner[0], 1)), np.uint8)
        points = [tuple(int(v) for v in np.rint((p - corner) * 16)) for p in polyline]  # 4 fractional bits (shift=4)
        if len(points) == 1:
            cv2.circle(mask, points[0], int(thickness * 16), 255, -1, cv2.LINE_AA, shift=4)
        for start, stop in zip(points[:-1], points[1:]):
            cv2.line(mask, start, stop, 255, max(int(round(thickness)), 1), cv2.LINE_AA, shift=4)
        rows, columns = slice(corner[1], end[1]), slice(corner[0], end[0])
        part, covered = colour[rows, columns], coverage[rows, columns]  # views, clipped to the box
        alpha = mask[: part.shape[0], : part.shape[1]].astype(np.float32) / 255.0
        part += alpha[..., None] * (part_colour.astype(np.float32) - part)
        covered += alpha * (1.0 - covered)
    return top, left, colour, coverage


def _paint_clutter(scene: np.ndarray, t: int, centre_x: float, strength: float) -> None:
    """The burst around frame 95: bars of a passing reflection (white and shirt-coloured) sweeping over the glass."""
    start, stop = WALKER_SEGMENTS["clutter"]
    ramp = strength * float(np.clip(min(t - start + 1, stop - t) / 3.0, 0.0, 1.0))
    if ramp <= 0:
        return
    sweep = centre_x + MARGIN + 6.0 * (t - (start + stop) / 2.0)  # the reflection slides with the walk, faster
    xs = np.arange(scene.shape[1], dtype=np.float32) - sweep
    bar_index = np.floor(xs / 13.0)
    on_bar = (np.abs(xs) < 130) & (bar_index % 2 == 0)  # 13 px bars every 26 px over 260 px
    colours = np.where((bar_index // 2 % 2 == 0)[:, None], np.float32(240.0), SHIRT.astype(np.float32))
    band = scene[int(MARGIN + 30) : int(MARGIN + FLOOR_Y - 10)]
    band += (ramp * on_bar)[None, :, None].astype(np.float32) * (colours[None] - band)


def make_walker_sequence(*, rng: int | np.random.Generator, noise_std: float = 4.0, distortion: float = 0.12,
                         clutter_strength: float = 0.85) -> WalkerSequence:
    """A seeded 640×240 RGB walker sequence at 25 fps (130 frames) with its ground truth.

    A person walks from left to right past a shop window: arms and legs swing (a gait cycle of
    about one second), the shirt has the glass's tint and the trousers the mullions' grey, the
    lettering on the glass passes in front of the body, the floor mirrors the legs, the whole
    image goes through a barrel distortion (so the body shrinks and leans near the sides), and on
    frames 88-102 a bright striped reflection sweeps across the glass around the walker.

    Parameters
    ----------
    rng : int or numpy.random.Generator
        Source of the displays in the window, the gait's phase and pace, and the camera noise.
    noise_std : float
        Standard deviation of the camera noise, grey levels, in [0, 255].
    distortion : float
        Barrel coefficient k in [0, 0.5]: the scene point seen at normalised radius r lies at
        ``r (1 + k r²)`` (0: a pinhole camera).
    clutter_strength : float
        Opacity of the burst's bars, in [0, 1] (0: no burst).

    Returns
    -------
    WalkerSequence
        Frames, truth (similarity states), ellipses, true outlines, segments and the template.

    References
    ----------
    Li & Chaumette, AMDO 2004, Sec. 4 and Fig. 6.
    """
    generator = make_rng(rng, "rng")
    noise_std = check_in_range(noise_std, "noise_std", 0.0, 255.0, closed="both")
    distortion = check_in_range(distortion, "distortion", 0.0, 0.5, closed="both")
    clutter_strength = check_in_range(clutter_strength, "clutter_strength", 0.0, 1.0, closed="both")
    background = _shop_window(generator)
    letters, letter_colour = _lettering()
    letters_at = np.nonzero(letters)
    letter_alpha = (0.92 * letters[letters_at])[:, None]
    # camera noise: windows of 8 noise fields at random offsets (drawing 460k normals per frame is slow)
    noise_bank = noise_std * generator.standard_normal((8, HEIGHT + 16, WIDTH + 16, 3), dtype=np.float32)
    shape = background.shape[:2]
    # the image pixel (x, y) shows the scene at undistort(x, y): one remap table for the whole sequence
    grid = np.stack(np.meshgrid(np.arange(WIDTH, dtype=float), np.arange(HEIGHT, dtype=float)), axis=-1)
    source = (_undistort(grid, distortion) + MARGIN).astype(np.float32)
    t = np.arange(N_FRAMES, dtype=float)
    pace = generator.uniform(3.7, 4.1)  # px per frame: across the frame in about five seconds
    phase = generator.uniform(0.0, 2.0 * np.pi) + 2.0 * np.pi * t / generator.uniform(24.0, 28.0)
    hips = np.stack([70.0 + pace * t, FLOOR_Y - 0.5 * BODY_HEIGHT - 1.5 * np.abs(np.cos(phase))], axis=1)
    outline = BODY_HEIGHT * _OUTLINE
    true_control_points = _distort(hips[:, None, :] + outline[None], distortion)
    frames = np.empty((N_FRAMES, HEIGHT, WIDTH, 3), np.uint8)
    for k in range(N_FRAMES):
        scene = background.copy()
        _paint_clutter(scene, k, hips[k, 0], clutter_strength)
        top, left, colour, coverage = _draw_walker(shape[0], hips[k], phase[k])
        box = scene[top:, left : left + coverage.shape[1]]  # a view: the walker is painted in place
        box += coverage[..., None] * (colour - box)
        # the floor mirrors the walker about the floor line, dimmed
        floor = int(MARGIN + FLOOR_Y) - top
        depth = len(box) - floor
        mirrored = coverage[floor - depth : floor][::-1, :, None] * 0.35
        box[floor:] += mirrored * (colour[floor - depth : floor][::-1] - box[floor:])
        letter_pixels = scene[letters_at]  # lettering in front of everything
        scene[letters_at] = letter_pixels + letter_alpha * (letter_colour - letter_pixels)
        image = cv2.remap(scene, source[..., 0], source[..., 1], cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
        dy, dx = generator.integers(0, 16, size=2)
        image += noise_bank[generator.integers(len(noise_bank)), dy : dy + HEIGHT, dx : dx + WIDTH]
        frames[k] = np.clip(image + 0.5, 0, 255).astype(np.uint8)
    template = true_control_points[0]
    truth = _fit_similarity(template, true_control_points)
    space = ShapeSpace(template, "similarity")
    return WalkerSequence(frames, truth, space.ellipses(truth), true_control_points, dict(WALKER_SEGMENTS), template)


def box_iou(first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """Intersection over union of the axis-aligned bounding boxes of two outlines, frame by frame.

    Parameters
    ----------
    first, second : numpy.ndarray
        (J, 2) or (T, J, 2) points (x, y) in pixels, e.g. B-spline control points; the two may
        have different numbers of points J.

    Returns
    -------
    float or numpy.ndarray
        IoU in [0, 1], one per frame.

    References
    ----------
    Wu, Lim & Yang, "Online object tracking: a benchmark", CVPR 2013 (the success criterion
    box IoU >= 0.5); Li & Chaumette, AMDO 2004, Fig. 6.
    """
    first = as_finite_array(first, "first", max_abs=1e6)
    if first.ndim not in (2, 3) or first.shape[-1] != 2:
        raise ValueError(f"first must have shape (J, 2) or (T, J, 2), got {first.shape}")
    second = as_finite_array(second, "second", max_abs=1e6)
    if second.ndim not in (2, 3) or second.shape[-1] != 2:
        raise ValueError(f"second must have shape (J, 2) or (T, J, 2), got {second.shape}")
    if second.shape[:-2] != first.shape[:-2]:  # a mismatch: either may be at fault, so both are named
        raise ValueError(f"first and second disagree: first has shape {first.shape}, second {second.shape}; both "
                         "must be (J, 2), or (T, J, 2) with the same T")
    single = first.ndim == 2
    low = np.maximum(first.min(axis=-2), second.min(axis=-2))
    high = np.minimum(first.max(axis=-2), second.max(axis=-2))
    intersection = np.prod(np.clip(high - low, 0.0, None), axis=-1)
    areas = [np.prod(points.max(axis=-2) - points.min(axis=-2), axis=-1) for points in (first, second)]
    union = areas[0] + areas[1] - intersection
    iou = np.divide(intersection, union, out=np.zeros_like(union), where=union > 0)
    return float(iou) if single else iou
