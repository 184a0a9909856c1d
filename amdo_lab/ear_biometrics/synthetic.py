"""Seeded synthetic ear images (stand-in for Choraś's licence-restricted database) and a folder loader.

An ear is a set of parametric curves in a canonical frame (y up, ear height about 2 units): outer
helix, lobule, antihelix with its superior and inferior crus (a Y junction), concha rim, tragus and
antitragus. Per-subject parameters fix the shape; per-capture nuisance moves, tilts, scales, yaws and
lights it. Curves are rendered as shaded grooves (dark line plus a highlight offset towards the light)
on a textured skin silhouette.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, fields
from pathlib import Path

import cv2
import numpy as np

from amdo_lab.common import (MAX_SIDE, as_finite_array, check_bool, check_choice, check_in_range, check_names,
                             check_positive_int, make_rng)
from amdo_lab.ear_biometrics.images import check_record

DIFFICULTIES = ("easy", "difficult")
NUISANCE_FACTORS = ("rotation", "scale", "translation", "yaw", "illumination", "noise", "jitter")
"""Per-capture nuisance factors that :func:`make_ear_database` can switch off (``disable=``):
in-plane rotation, scale, translation, the camera's yaw, illumination (difficult images only: light
direction, groove contrast, background level, gradient and gain; easy images never vary it), sensor noise with
skin texture, and the small per-capture shape jitter. A disabled factor is still drawn (so the
random stream, and hence every other factor, stays the same) and then set to its neutral value."""

FIXED_LIGHT = 0.75 * np.pi  # highlight direction (image angle) when illumination does not vary

MIN_SIZE = 32
"""Smallest image side of a synthetic ear, pixels (the grooves are drawn at least one pixel wide)."""

MAX_SUBJECTS = 10_000
"""Most subjects of one synthetic database (the paper's has 180 images)."""

MAX_IMAGES_PER_SUBJECT = 100
"""Most captures of one subject in a synthetic database (the paper takes two)."""

MAX_YAW_DEG = 30.0
"""Largest yaw of a non-frontal capture, degrees (the paper's second capture is at about 30)."""

MAX_ROTATION_DEG = {"easy": 10.0, "difficult": 20.0}
"""Largest in-plane rotation of a capture, degrees, per difficulty."""

MAX_SHAPE_VALUE = 10.0
"""Largest magnitude of an :class:`EarShape` parameter (units of about half an ear height; a drawn
ear's parameters stay below 2)."""

MAX_POSE_SCALE = 10.0
"""Largest scale of a :class:`CapturePose`: at 10 an ear is several times the image."""

_SHAPE_FIELDS = {"helix_axes": (2,), "helix_harmonics": (3, 2), "antihelix_harmonics": (3, 2),
                 "superior_crus_end": (2,), "inferior_crus_end": (2,), "concha_centre": (2,), "concha_axes": (2,),
                 "tragus_centre": (2,), "antitragus_centre": (2,)}  # the others are numbers, shape ()


def check_disable(disable: object) -> frozenset:
    """Validate a collection of nuisance-factor names (see :data:`NUISANCE_FACTORS`); empty: none.

    Parameters
    ----------
    disable : collection of str
        Names from :data:`NUISANCE_FACTORS`, each at most once, or an empty collection.

    Returns
    -------
    frozenset of str
        The names.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 6 (the captures' nuisance, which the synthetic data can switch off).
    """
    if isinstance(disable, (tuple, list, set, frozenset)) and not disable:
        return frozenset()  # nothing switched off
    return frozenset(check_names(disable, "disable", allowed=NUISANCE_FACTORS))


@dataclass(frozen=True)
class EarShape:
    """Per-subject shape parameters of a synthetic ear (canonical frame, units of about half an ear height).

    Every parameter is finite and at most :data:`MAX_SHAPE_VALUE` in magnitude (checked when the
    record is made).

    Parameters
    ----------
    helix_axes : numpy.ndarray, shape (2,)
        Semi-axes (x, y) of the helix ellipse.
    helix_harmonics : numpy.ndarray, shape (3, 2)
        Cosine and sine amplitudes of harmonics 2-4 of the helix radius.
    antihelix_scale : float
        Antihelix radius relative to the helix radius.
    antihelix_harmonics : numpy.ndarray, shape (3, 2)
        Cosine and sine amplitudes of harmonics 2-4 of the antihelix radius.
    junction_angle : float
        Polar angle of the crura junction, radians.
    superior_crus_end : numpy.ndarray, shape (2,)
        End point (x, y) of the superior crus.
    inferior_crus_end : numpy.ndarray, shape (2,)
        End point (x, y) of the inferior crus.
    concha_centre : numpy.ndarray, shape (2,)
        Centre (x, y) of the concha rim.
    concha_axes : numpy.ndarray, shape (2,)
        Semi-axes (x, y) of the concha rim.
    tragus_centre : numpy.ndarray, shape (2,)
        Centre (x, y) of the tragus.
    antitragus_centre : numpy.ndarray, shape (2,)
        Centre (x, y) of the antitragus.
    lobule_depth : float
        How far the lobule hangs below the helix ellipse.
    helix_start : float
        Polar angle where the helix root starts at the front, radians.
    lobule_width : float
        Horizontal extent of the lobule.
    tragus_size : float
        Relative size of the tragus (1 = average).
    antitragus_size : float
        Relative size of the antitragus (1 = average).

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61. Synthetic data: no equation of the paper; stands in for its database of Sec. 6 (Figs. 1-2).
    """

    helix_axes: np.ndarray  # (2,) semi-axes (x, y) of the helix ellipse
    helix_harmonics: np.ndarray  # (3, 2) cos/sin amplitudes of harmonics 2..4 of the helix radius
    antihelix_scale: float  # antihelix radius relative to the helix
    antihelix_harmonics: np.ndarray  # (3, 2)
    junction_angle: float  # polar angle (rad) of the crura junction
    superior_crus_end: np.ndarray  # (2,) end point of the superior crus
    inferior_crus_end: np.ndarray  # (2,) end point of the inferior crus
    concha_centre: np.ndarray  # (2,)
    concha_axes: np.ndarray  # (2,)
    tragus_centre: np.ndarray  # (2,)
    antitragus_centre: np.ndarray  # (2,)
    lobule_depth: float  # how far the lobule hangs below the helix ellipse
    helix_start: float  # polar angle (rad) where the helix root starts at the front
    lobule_width: float  # horizontal extent of the lobule
    tragus_size: float  # relative size of the tragus
    antitragus_size: float  # relative size of the antitragus

    def __post_init__(self) -> None:
        # a record the user may build: every parameter finite, of its shape, within MAX_SHAPE_VALUE
        for item in fields(self):
            value = as_finite_array(getattr(self, item.name), f"shape.{item.name}",
                                    shape=_SHAPE_FIELDS.get(item.name, ()), max_abs=MAX_SHAPE_VALUE)
            object.__setattr__(self, item.name, value if value.ndim else float(value))


@dataclass(frozen=True)
class CapturePose:
    """Per-capture nuisance of a synthetic ear image: how the camera saw the ear.

    Parameters
    ----------
    rotation : float
        In-plane rotation, radians (counter-clockwise as displayed), in [-2 pi, 2 pi].
    scale : float
        Scale factor, in (0, :data:`MAX_POSE_SCALE`] (1 = an ear about 0.36 x 2.15 of the image side tall).
    translation : numpy.ndarray, shape (2,)
        Shift (columns, rows) of the ear from the image centre, pixels, each within +-4,096.
    yaw : float
        The camera's turn about the head's vertical axis, radians, in (-pi/2, pi/2); it foreshortens
        the ear horizontally by cos(yaw).

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 6: the second capture of every subject at about 30 degrees.
    """

    rotation: float
    scale: float
    translation: np.ndarray
    yaw: float

    def __post_init__(self) -> None:
        # a record the user may build: checked here, once, under the names render_ear reports
        check_in_range(self.rotation, "pose.rotation", -2 * np.pi, 2 * np.pi, closed="both")
        check_in_range(self.scale, "pose.scale", 0, MAX_POSE_SCALE, closed="right")
        object.__setattr__(self, "translation", as_finite_array(self.translation, "pose.translation", shape=(2,),
                                                                max_abs=MAX_SIDE))
        check_in_range(self.yaw, "pose.yaw", -np.pi / 2, np.pi / 2)  # at +-90 degrees the ear is seen edge-on


@dataclass(frozen=True)
class EarDatabase:
    """A synthetic ear database: images with their subject ids, shapes and poses.

    Unpacks as ``images, subject_ids = database``.

    Parameters
    ----------
    images : numpy.ndarray, shape (n, size, size), uint8
        Grey-level images, captures of one subject next to each other.
    subject_ids : numpy.ndarray, shape (n,), int
        Subject of each image (0, 0, 1, 1, ... for two captures per subject).
    shapes : tuple of EarShape
        One shape per subject.
    poses : tuple of CapturePose
        One pose per image.
    difficulty : {"easy", "difficult"}
        Which kind of images were rendered.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 6 and Figs. 1-2 (its "easy" and "difficult" images).
    """

    images: np.ndarray  # (n, size, size) uint8
    subject_ids: np.ndarray  # (n,) int
    shapes: tuple[EarShape, ...]
    poses: tuple[CapturePose, ...]
    difficulty: str

    def __iter__(self):  # allows ``images, ids = make_ear_database(...)``
        return iter((self.images, self.subject_ids))


def draw_ear_shape(*, rng: int | np.random.Generator) -> EarShape:
    """Draw one subject's ear shape parameters.

    The canonical ear is about 2.15 units tall (helix top to lobule tip), so one unit is roughly
    29 mm of a 62 mm adult ear. Between-subject spreads follow the anthropometric literature
    (coefficients of variation, roughly: ear length 7 %, width/length index 9 %, concha 10-12 %,
    lobule 15 %): overall size 7 % and helix width relative to height 9 % (the method normalises
    size away, the baseline does not), concha axes 12 %, lobule width 15 % and depth 0.08 units,
    tragus and antitragus sizes 15 %, their positions 0.06 units (about 2 mm); the antihelix
    (scapha width) 9 %, its shape harmonics and the helix's 0.06, the crura junction angle 15
    degrees. The crura end beneath the helix rim: their end points are drawn as a polar angle
    (standard deviation 9 degrees) and a fraction of the local helix radius (uniform, 0.72-0.90 for
    the superior crus, 0.60-0.78 for the inferior one), so they never leave the ear.

    Parameters
    ----------
    rng : int or numpy.random.Generator
        Seed (non-negative int) or generator of the draw; a generator is advanced.

    Returns
    -------
    EarShape
        The subject's shape parameters.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61. Synthetic data: no equation of the paper; stands in for its database of Sec. 6 (Figs. 1-2).
    """
    rng = make_rng(rng, "rng")
    normal = rng.normal
    size = 1 + 0.07 * normal()
    helix_axes = np.array([0.62 * (1 + 0.09 * normal()), 0.95]) * size
    helix_harmonics = 0.06 * normal(size=(3, 2))

    def under_helix(mean_angle_deg: float, low: float, high: float) -> np.ndarray:
        angle = np.deg2rad(mean_angle_deg + 9 * normal())
        radius = _radius(np.array([angle]), helix_harmonics)[0] * rng.uniform(low, high)
        return np.array([np.cos(angle), np.sin(angle)]) * helix_axes * radius

    return EarShape(
        helix_axes=helix_axes,
        helix_harmonics=helix_harmonics,
        antihelix_scale=float(0.66 + 0.06 * normal()),
        antihelix_harmonics=0.06 * normal(size=(3, 2)),
        junction_angle=float(np.deg2rad(105 + 15 * normal())),
        superior_crus_end=under_helix(76, 0.72, 0.90),
        inferior_crus_end=under_helix(20, 0.60, 0.78),
        concha_centre=np.array([0.12, -0.12]) * size + 0.08 * normal(size=2),
        concha_axes=np.array([0.26, 0.30]) * size * (1 + 0.12 * normal(size=2)),
        tragus_centre=np.array([0.58, -0.22]) * size + 0.06 * normal(size=2),
        antitragus_centre=np.array([0.12, -0.58]) * size + 0.06 * normal(size=2),
        lobule_depth=float(0.25 * size + 0.08 * normal()),
        helix_start=float(np.deg2rad(15 + 12 * normal())),
        lobule_width=float(0.22 * size * (1 + 0.15 * normal())),
        tragus_size=float(size * (1 + 0.15 * normal())),
        antitragus_size=float(size * (1 + 0.15 * normal())),
    )


def _radius(angles: np.ndarray, harmonics: np.ndarray) -> np.ndarray:
    orders = np.arange(2, 2 + len(harmonics))[:, None]
    return 1 + np.sum(harmonics[:, :1] * np.cos(orders * angles) + harmonics[:, 1:] * np.sin(orders * angles), axis=0)


def _bezier(start: np.ndarray, control: np.ndarray, end: np.ndarray, n: int = 40) -> np.ndarray:
    t = np.linspace(0, 1, n)[:, None]
    return (1 - t) ** 2 * start + 2 * (1 - t) * t * control + t**2 * end


def ear_curves(shape: EarShape) -> list[np.ndarray]:
    """Polylines of the ear's anatomical curves in the canonical frame (y up).

    Parameters
    ----------
    shape : EarShape
        A subject's shape, every parameter finite.

    Returns
    -------
    list of numpy.ndarray
        Seven (n_k, 2) arrays of (x, y) points: the outer silhouette (helix and lobule) first, then
        the antihelix, its superior and inferior crus, the concha rim, the tragus and the antitragus.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Fig. 8 (the contours the method traces). Synthetic data: no equation of the paper; stands in for its database of Sec. 6 (Figs. 1-2).
    """
    return _ear_curves(check_record(shape, "shape", EarShape, "draw_ear_shape"))


def _ear_curves(shape: EarShape) -> list[np.ndarray]:
    angles = np.linspace(shape.helix_start, np.deg2rad(268), 160)
    helix = np.c_[np.cos(angles), np.sin(angles)] * shape.helix_axes * _radius(angles, shape.helix_harmonics)[:, None]
    bottom = helix[-1]
    lobule_angles = np.linspace(np.pi, 2 * np.pi, 40)
    lobule = np.c_[bottom[0] + shape.lobule_width * (1 + np.cos(lobule_angles)),
                   bottom[1] + shape.lobule_depth * np.sin(lobule_angles)]
    outer = np.vstack([helix, lobule[1:]])
    anti_angles = np.linspace(shape.junction_angle, np.deg2rad(250), 90)
    anti_r = shape.antihelix_scale * _radius(anti_angles, shape.antihelix_harmonics)[:, None]
    antihelix = np.c_[np.cos(anti_angles), np.sin(anti_angles)] * shape.helix_axes * anti_r
    junction = antihelix[0]
    superior = _bezier(junction, junction + np.array([0.0, 0.18]), shape.superior_crus_end)
    inferior = _bezier(junction, junction + np.array([0.2, -0.05]), shape.inferior_crus_end)
    concha_angles = np.linspace(np.deg2rad(110), np.deg2rad(320), 60)
    concha = shape.concha_centre + np.c_[np.cos(concha_angles), np.sin(concha_angles)] * shape.concha_axes
    tragus_angles = np.linspace(np.deg2rad(-80), np.deg2rad(80), 30)
    tragus = shape.tragus_centre + shape.tragus_size * np.c_[-0.12 * np.cos(tragus_angles), 0.16 * np.sin(tragus_angles)]
    anti_t_angles = np.linspace(np.deg2rad(20), np.deg2rad(160), 30)
    antitragus = shape.antitragus_centre + shape.antitragus_size * np.c_[0.14 * np.cos(anti_t_angles), 0.09 * np.sin(anti_t_angles)]
    return [outer, antihelix, superior, inferior, concha, tragus, antitragus]


def _jitter_shape(shape: EarShape, rng: np.random.Generator, amount: float) -> EarShape:
    """Small per-capture deformation (soft tissue, segmentation of the ear by the photographer)."""
    values = {}
    for name, value in shape.__dict__.items():
        value = np.asarray(value, dtype=float)
        values[name] = value + amount * rng.normal(size=value.shape) * (0.1 if name.endswith("harmonics") else 1.0)
        if value.ndim == 0:
            values[name] = float(values[name])
    return EarShape(**values)


def _to_pixels(points: np.ndarray, pose: CapturePose, size: int) -> np.ndarray:
    # Yaw foreshortens the horizontal axis (camera turned about the head's vertical axis).
    xy = points * np.array([np.cos(pose.yaw), 1.0])
    c, s = np.cos(pose.rotation), np.sin(pose.rotation)
    xy = xy @ np.array([[c, s], [-s, c]])
    unit = 0.36 * size * pose.scale
    cols = size / 2 + unit * xy[:, 0] + pose.translation[0]
    rows = size / 2 - unit * xy[:, 1] + pose.translation[1]
    return np.c_[cols, rows]


def render_ear(
    shape: EarShape,
    pose: CapturePose,
    *,
    rng: int | np.random.Generator,
    difficulty: str = "easy",
    size: int = 256,
    disable: object = (),
) -> np.ndarray:
    """Render one grey-level ear image of ``shape`` seen under ``pose``.

    ``difficulty="easy"``: one fixed, even illumination for every capture (light direction, groove
    contrast and background level do not vary; the paper's easy images have no illumination
    changes), mild noise. ``"difficult"``: a random light direction and groove contrast per capture,
    an illumination gradient, lower contrast and stronger noise, plus hair strands, an earring and a
    straight glasses arm.

    Parameters
    ----------
    shape : EarShape
        The subject's shape (from :func:`draw_ear_shape`).
    pose : CapturePose
        The capture's pose: finite, scale > 0, yaw within (-pi/2, pi/2).
    rng : int or numpy.random.Generator
        Seed or generator of the lighting, texture, noise and occluders; a generator is advanced.
    difficulty : {"easy", "difficult"}
        Kind of image, as above.
    size : int
        Image side in pixels, from 32 to ``MAX_SIDE`` (4,096).
    disable : collection of str
        Nuisance factors switched off: ``"illumination"`` (difficult images only) and ``"noise"``
        (see :data:`NUISANCE_FACTORS`); the random stream is drawn all the same.

    Returns
    -------
    numpy.ndarray, shape (size, size), uint8
        The grey-level image.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 6 and Figs. 1-2 (easy and difficult images). Synthetic data: no equation of the paper; stands in for its database of Sec. 6 (Figs. 1-2).
    """
    check_record(shape, "shape", EarShape, "draw_ear_shape")
    check_record(pose, "pose", CapturePose, "draw_capture_pose")
    rng = make_rng(rng, "rng")
    check_choice(difficulty, "difficulty", DIFFICULTIES)
    size = check_positive_int(size, "size", minimum=MIN_SIZE, maximum=MAX_SIDE)
    disable = check_disable(disable)
    return _render_ear(shape, pose, rng, difficulty=difficulty, size=size, disable=disable)


def _render_ear(shape: EarShape, pose: CapturePose, rng: np.random.Generator, *, difficulty: str, size: int,
                disable: frozenset) -> np.ndarray:
    """:func:`render_ear` on validated input (the database generator's per-image call)."""
    hard = difficulty == "difficult"
    # The paper's easy images were taken "without illumination changes" (Sec. 6): one fixed lighting.
    lit, noisy = hard and "illumination" not in disable, "noise" not in disable
    curves = [_to_pixels(c, pose, size) for c in _ear_curves(shape)]
    shift = 4  # sub-pixel drawing precision (cv2 fixed point)

    def polyline(canvas, pts, thickness, value=1.0, closed=False):
        cv2.polylines(canvas, [np.round(pts * (1 << shift)).astype(np.int32)], closed, value, thickness, cv2.LINE_AA, shift)

    silhouette = np.zeros((size, size), np.float32)
    cv2.fillPoly(silhouette, [np.round(curves[0] * (1 << shift)).astype(np.int32)], 1.0, cv2.LINE_AA, shift)
    silhouette = cv2.GaussianBlur(silhouette, (0, 0), 1.0)
    grooves = np.zeros((size, size), np.float32)
    line_width = max(1, int(round(size / 128)))
    for curve in curves[1:]:
        polyline(grooves, curve, line_width)
    polyline(grooves, curves[0], line_width)
    grooves = cv2.GaussianBlur(grooves, (0, 0), 0.9 * size / 128)
    grooves = np.clip(grooves / max(float(grooves.max()), 1e-6), 0, 1)  # peak darkening = contrast
    light = rng.uniform(0, 2 * np.pi)
    light = light if lit else FIXED_LIGHT
    offset = np.array([np.cos(light), np.sin(light)]) * 1.5 * size / 128
    highlight = cv2.warpAffine(grooves, np.float32([[1, 0, offset[0]], [0, 1, offset[1]]]), (size, size))
    # skin texture is a property of the skin: its grain scales with the ear (2 px at 128 px), so a
    # larger size renders the same scene at a finer sampling; the sensor noise below stays per pixel
    texture = cv2.GaussianBlur(rng.normal(size=(size, size)).astype(np.float32), (0, 0), 2.0 * size / 128)
    texture *= (0.02 if noisy else 0.0) / max(float(texture.std()), 1e-6)
    contrast = rng.uniform(0.35, 0.55) if hard else rng.uniform(0.75, 0.9)
    contrast = contrast if lit else (0.45 if hard else 0.825)
    skin = 0.72 * (1 + texture)
    background = 0.45 + (0.04 if lit else 0.0) * rng.normal()
    image = background + (skin - background) * silhouette
    image = image * (1 - contrast * 0.8 * grooves + contrast * 0.25 * highlight)
    if hard:
        image = _add_occluders(image, curves, rng, size)
        rows, cols = np.mgrid[0:size, 0:size] / size - 0.5
        direction = rng.uniform(0, 2 * np.pi)
        gradient, gain, offset_level = rng.uniform(0.3, 0.6), rng.uniform(0.6, 1.0), rng.uniform(0.0, 0.15)
        if not lit:  # neutral values: mid gradient strength along a fixed direction, mid gain/offset
            direction, gradient, gain, offset_level = 0.0, 0.45, 0.8, 0.075
        image = image * (1 + gradient * (np.cos(direction) * cols + np.sin(direction) * rows))
        image = image * gain + offset_level
    noise = rng.uniform(0.02, 0.035) if hard else 0.01
    image = image + (noise if noisy else 0.0) * rng.normal(size=image.shape)
    return np.clip(np.round(255 * image), 0, 255).astype(np.uint8)


def _add_occluders(image: np.ndarray, curves: list[np.ndarray], rng: np.random.Generator, size: int) -> np.ndarray:
    """Hair strands over the top of the ear, an earring on the lobule and a straight glasses arm."""
    image = image.copy()
    top = curves[0][np.argmin(curves[0][:, 1])]
    hair = np.zeros((size, size), np.float32)
    for _ in range(rng.integers(3, 8)):
        start = top + rng.normal(0, 0.15 * size, 2) + np.array([0, -0.1 * size])
        end = start + np.array([rng.normal(0, 0.2), 1.0]) * rng.uniform(0.2, 0.5) * size
        control = (start + end) / 2 + rng.normal(0, 0.08 * size, 2)
        pts = _bezier(start, control, end, 30)
        cv2.polylines(hair, [np.round(pts * 16).astype(np.int32)], False, 1.0, 1, cv2.LINE_AA, 4)
    image = image * (1 - 0.6 * np.clip(hair, 0, 1))
    lobe = curves[0][-20]
    ring = np.zeros((size, size), np.float32)
    radius = 0.045 * size * rng.uniform(0.8, 1.3)
    centre = lobe + np.array([0.0, radius * 0.8])
    cv2.circle(ring, tuple(int(v) for v in np.round(centre * 16)), int(round(radius * 16)), 1.0, max(1, size // 64), cv2.LINE_AA, 4)
    image = image * (1 - np.clip(ring, 0, 1)) + 0.9 * np.clip(ring, 0, 1)
    arm = np.zeros((size, size), np.float32)
    row = rng.uniform(0.2, 0.4) * size
    slope = rng.normal(0, 0.1)
    cv2.line(arm, (0, int(row * 16)), (size * 16, int((row + slope * size) * 16)), 1.0, max(2, size // 40), cv2.LINE_AA, 4)
    return image * (1 - 0.75 * np.clip(arm, 0, 1)) + 0.08 * np.clip(arm, 0, 1)


def draw_capture_pose(*, rng: int | np.random.Generator, frontal: bool, size: int, difficulty: str) -> CapturePose:
    """Draw one capture's nuisance: rotation, scale, shift and yaw.

    Rotation uniform in +-10 degrees (+-20 for difficult images, :data:`MAX_ROTATION_DEG`), scale
    uniform in 0.85-1.1, shift uniform in +-6 % of the image side per axis, yaw 0 for the
    perpendicular capture, else uniform in [2/3, 1] x :data:`MAX_YAW_DEG`.

    Parameters
    ----------
    rng : int or numpy.random.Generator
        Seed or generator of the draw; a generator is advanced.
    frontal : bool
        True for the capture with the camera perpendicular to the head (yaw 0).
    size : int
        Image side in pixels, from 32 to ``MAX_SIDE`` (4,096) (scales the shift).
    difficulty : {"easy", "difficult"}
        Sets the rotation range.

    Returns
    -------
    CapturePose
        The drawn pose (angles in radians).

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 6: one capture perpendicular to the head, one at 30 degrees.
    """
    rng = make_rng(rng, "rng")
    check_bool(frontal, "frontal")
    size = check_positive_int(size, "size", minimum=MIN_SIZE, maximum=MAX_SIDE)
    check_choice(difficulty, "difficulty", DIFFICULTIES)
    return _draw_capture_pose(rng, frontal=frontal, size=size, difficulty=difficulty)


def _draw_capture_pose(rng: np.random.Generator, *, frontal: bool, size: int, difficulty: str) -> CapturePose:
    """:func:`draw_capture_pose` on validated input."""
    return CapturePose(
        rotation=float(np.deg2rad(rng.uniform(-1, 1) * MAX_ROTATION_DEG[difficulty])),
        scale=float(rng.uniform(0.85, 1.1)),
        translation=rng.uniform(-0.06, 0.06, 2) * size,
        yaw=0.0 if frontal else float(np.deg2rad(rng.uniform(2 / 3, 1) * MAX_YAW_DEG)),
    )


def _neutralise(pose: CapturePose, disable: frozenset) -> CapturePose:
    """Set the disabled pose factors to neutral (no rotation, unit scale, centred, perpendicular)."""
    return CapturePose(
        rotation=0.0 if "rotation" in disable else pose.rotation,
        scale=1.0 if "scale" in disable else pose.scale,
        translation=np.zeros(2) if "translation" in disable else pose.translation,
        yaw=0.0 if "yaw" in disable else pose.yaw,
    )


def make_ear_database(
    n_subjects: int,
    images_per_subject: int = 2,
    difficulty: str = "easy",
    *,
    rng: int | np.random.Generator,
    size: int = 256,
    disable: object = (),
) -> EarDatabase:
    """Seeded synthetic ear database: capture 0 of a subject is perpendicular, the others yawed.

    Images are ``size`` x ``size``, 256 by default: the paper's "very high quality" photographs
    resolve the ear far more finely than 128 px, and at 128 px the contours are only a few pixels
    apart, so the circle features change with the rasterisation of the same ear. Every subject draws
    its shape, then per capture a pose, a small shape jitter and the rendering, all from one stream.

    Parameters
    ----------
    n_subjects : int
        Number of subjects, from 1 to :data:`MAX_SUBJECTS`.
    images_per_subject : int
        Captures per subject, from 1 to :data:`MAX_IMAGES_PER_SUBJECT`.
    difficulty : {"easy", "difficult"}
        Kind of images (see :func:`render_ear`).
    rng : int or numpy.random.Generator
        Seed or generator of the whole database; a generator is advanced.
    size : int
        Image side in pixels, from 32 to ``MAX_SIDE`` (4,096).
    disable : collection of str
        Nuisance factors switched off (names from :data:`NUISANCE_FACTORS`); the random stream is
        unchanged, so a database with a factor disabled differs from the default one only in that
        factor.

    Returns
    -------
    EarDatabase
        Images, subject ids, shapes and poses; unpacks as ``images, subject_ids``.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 6: two captures per subject, perpendicular and at 30 degrees, "easy" and
    "difficult" images.

    Examples
    --------
    >>> from amdo_lab import ear_biometrics as eb
    >>> images, ids = eb.make_ear_database(2, 2, "easy", rng=0, size=128)
    >>> images.shape, images.dtype.name, ids.tolist()
    ((4, 128, 128), 'uint8', [0, 0, 1, 1])
    """
    n_subjects = check_positive_int(n_subjects, "n_subjects", maximum=MAX_SUBJECTS)
    images_per_subject = check_positive_int(images_per_subject, "images_per_subject", maximum=MAX_IMAGES_PER_SUBJECT)
    check_choice(difficulty, "difficulty", DIFFICULTIES)
    size = check_positive_int(size, "size", minimum=MIN_SIZE, maximum=MAX_SIDE)
    disable = check_disable(disable)
    rng = make_rng(rng, "rng")
    shapes, poses, images, ids = [], [], [], []
    for subject in range(n_subjects):
        shape = draw_ear_shape(rng=rng)
        shapes.append(shape)
        for capture in range(images_per_subject):
            pose = _neutralise(_draw_capture_pose(rng, frontal=capture == 0, size=size, difficulty=difficulty), disable)
            jittered = _jitter_shape(shape, rng, 0.005)
            if "jitter" in disable:
                jittered = shape
            images.append(_render_ear(jittered, pose, rng, difficulty=difficulty, size=size, disable=disable))
            poses.append(pose)
            ids.append(subject)
    return EarDatabase(np.stack(images), np.array(ids), tuple(shapes), tuple(poses), difficulty)


IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".pgm")


def load_ear_folder(folder: str | Path, *, size: int | None = None) -> tuple[list[np.ndarray], np.ndarray]:
    """Load a folder of the reader's ear images as grey levels.

    Subject id = the file-name part before the first ``_`` (``017_a.png`` -> ``"017"``); files are
    read in sorted order. Colour images are converted to grey (OpenCV's BGR->GRAY weights).

    Parameters
    ----------
    folder : str or os.PathLike
        An existing directory holding .png, .jpg, .jpeg, .bmp, .tif, .tiff or .pgm files.
    size : int or None
        When given (1 to ``MAX_SIDE``, 4,096), every image is resized to ``size`` x ``size`` (area
        interpolation).

    Returns
    -------
    images : list of numpy.ndarray
        The uint8 grey-level images, in file-name order.
    subject_ids : numpy.ndarray, shape (n,), str
        The subject id of each image.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 6 (a database of two left-ear images per person).
    """
    if not isinstance(folder, (str, os.PathLike)):
        raise TypeError(f"folder must be a path (str or pathlib.Path), got {type(folder).__name__}")
    if size is not None:
        size = check_positive_int(size, "size", maximum=MAX_SIDE)
    folder = Path(folder)
    files = sorted(p for p in folder.iterdir() if p.suffix.lower() in IMAGE_SUFFIXES) if folder.is_dir() else []
    if not files:
        raise ValueError(f"folder must be an existing directory holding image files, got {folder.name!r}")
    images, ids = [], []
    for path in files:
        image = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE)
        if image is None:
            raise ValueError(f"could not read image file {path.name!r}")
        if size is not None:
            image = cv2.resize(image, (size, size), interpolation=cv2.INTER_AREA)
        images.append(image)
        ids.append(path.stem.split("_")[0])
    return images, np.array(ids)
