"""Seeded synthetic sequences with the true pose of every frame: a frontal upper body and a jump.

They stand in for the paper's recordings (Figs. 5 and 8), whose truth was digitised by hand: our truth
is exact, so the errors of Table 2 can be measured against it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common import as_finite_array, check_bool, check_image_shape, check_positive_int, make_rng
from amdo_lab.path_relinking_pf.body import BodyModel

__all__ = ["MAX_FRAMES", "MAX_RATE_DEG", "BodySequence", "make_jump_sequence", "make_upper_body_sequence"]

#: Most frames a sequence may have.
MAX_FRAMES = 10_000
#: Fastest change of a true angle at ``speed=1``, degrees a frame.
MAX_RATE_DEG = 11.0
#: Largest speed factor of :func:`make_upper_body_sequence`.
MAX_SPEED = 4.0


@dataclass(frozen=True)
class BodySequence:
    """A synthetic recording: grey frames, the known background, the body model and the true poses.

    Parameters
    ----------
    frames : numpy.ndarray
        ``(T, rows, cols)`` uint8 frames.
    background : numpy.ndarray
        ``(rows, cols)`` uint8 background without the subject.
    model : BodyModel
        The body model the subject was drawn with.
    truth : numpy.ndarray
        ``(T, n_pose)`` true poses ``[x1, y1, theta_1, ...]`` (px, rad).

    References
    ----------
    Pantrigo et al., AMDO 2004, Sec. 6 (the sequences of Figs. 5 and 8).
    """

    frames: np.ndarray
    background: np.ndarray
    model: BodyModel
    truth: np.ndarray


def _background(shape: tuple[int, int], rng: np.random.Generator) -> np.ndarray:
    """A dark gradient with clutter blocks: edges that background subtraction removes."""
    rows, cols = shape
    background = 30.0 + 15.0 * np.linspace(0.0, 1.0, cols)[None, :] + np.zeros((rows, 1))
    for _ in range(14):
        r, c = rng.integers(0, rows - 8), rng.integers(0, cols - 8)
        h, w = rng.integers(6, max(7, rows // 4)), rng.integers(6, max(7, cols // 4))
        background[r:r + h, c:c + w] = rng.uniform(45.0, 80.0)
    return background


def _draw(model: BodyModel, truth: np.ndarray, background: np.ndarray, noise: float,
          rng: np.random.Generator) -> np.ndarray:
    greys = np.array([0.0] + [limb.grey for limb in model.limbs])
    frames = np.empty((len(truth),) + background.shape, np.uint8)
    labels = np.zeros(background.shape, np.uint8)
    for t, pose in enumerate(truth):
        labels[:] = 0
        model._render_into(labels, model._polygons(pose))
        image = np.where(labels > 0, greys[labels], background) + noise * rng.standard_normal(background.shape)
        frames[t] = np.clip(np.round(image), 0, 255).astype(np.uint8)
    return frames


def _wave(t: np.ndarray, low_deg: float, high_deg: float, rate_deg: float, rng: np.random.Generator) -> np.ndarray:
    """A sinusoid between two angles whose speed never exceeds ``rate_deg`` a frame, in radians."""
    centre, amplitude = (low_deg + high_deg) / 2, (high_deg - low_deg) / 2
    omega = rng.uniform(0.6, 1.0) * np.deg2rad(rate_deg) / np.deg2rad(amplitude)
    return np.deg2rad(centre + amplitude * np.sin(omega * t + rng.uniform(0, 2 * np.pi)))


def make_upper_body_sequence(*, rng: int | np.random.Generator, n_frames: int = 50,
                             size: tuple[int, int] = (160, 160), noise: float = 8.0,
                             speed: float = 1.0, cross: bool = False) -> BodySequence:
    """A frontal upper body waving its arms (Fig. 5): shoulders 25-135 deg, elbows 0-100 deg.

    With ``cross`` the forearms stay folded over the chest instead: shoulders 10-30 deg, elbows bent
    100-150 deg towards the midline, so the forearms hide the trunk and cross each other.

    Every angle follows a sinusoid with a seeded phase and frequency; no angle turns faster than
    ``11 * speed`` degrees a frame. The trunk sways by a few pixels and degrees, the head and hands
    by up to 15 degrees.

    Parameters
    ----------
    rng : int or numpy.random.Generator
        Seed of the motion, the clutter and the pixel noise.
    n_frames : int
        Frames, 2 to 10,000.
    size : tuple of int
        ``(rows, cols)``, each 120 to 4,096 (the body spans about 110 pixels).
    noise : float
        Standard deviation of the pixel noise, grey levels, in [0, 50].
    speed : float
        Factor on every angular speed, in (0, 4].
    cross : bool
        Whether the forearms are folded over the chest (occlusion of the trunk by the arms).

    Returns
    -------
    BodySequence
        Frames, background, ``BodyModel.upper_body()`` and the true poses.

    References
    ----------
    Pantrigo et al., AMDO 2004, Sec. 6 and Fig. 5.

    Examples
    --------
    >>> seq = make_upper_body_sequence(rng=0, n_frames=3)
    >>> seq.frames.shape, seq.truth.shape
    ((3, 160, 160), (3, 10))
    """
    generator = make_rng(rng, "rng")
    n_frames = check_positive_int(n_frames, "n_frames", minimum=2, maximum=MAX_FRAMES)
    size = check_image_shape(size, "size", minimum=120)
    noise = float(as_finite_array(noise, "noise", shape=(), bounds=(0.0, 50.0)))
    speed = float(as_finite_array(speed, "speed", shape=(), bounds=(0.0, MAX_SPEED), closed="right"))
    cross = check_bool(cross, "cross")
    model = BodyModel.upper_body()
    rows, cols = size
    t = np.arange(n_frames, dtype=float)
    rate = MAX_RATE_DEG * speed
    truth = np.empty((n_frames, model.n_pose))
    truth[:, 0] = cols / 2 + 3.0 * np.sin(0.05 * t + generator.uniform(0, 2 * np.pi))
    truth[:, 1] = rows / 2 + 45.0 + 2.0 * np.sin(0.07 * t + generator.uniform(0, 2 * np.pi))
    truth[:, 2] = -np.pi / 2 + _wave(t, -4.0, 4.0, 1.0, generator)  # trunk, upright
    truth[:, 3] = _wave(t, -15.0, 15.0, rate / 2, generator)  # head
    shoulders, elbows = ((10.0, 30.0), (-150.0, -100.0)) if cross else ((25.0, 135.0), (0.0, 100.0))
    truth[:, 4] = np.pi + _wave(t, *shoulders, rate, generator)  # R. shoulder: abduction to the image left
    truth[:, 5] = np.pi - _wave(t, *shoulders, rate, generator)  # L. shoulder
    truth[:, 6] = _wave(t, *elbows, rate, generator)  # R. elbow (negative: towards the midline)
    truth[:, 7] = -_wave(t, *elbows, rate, generator)  # L. elbow
    truth[:, 8] = _wave(t, -15.0, 15.0, rate / 2, generator)  # hands
    truth[:, 9] = _wave(t, -15.0, 15.0, rate / 2, generator)
    background = _background(size, generator)
    frames = _draw(model, truth, background, noise, generator)
    return BodySequence(frames, np.clip(np.round(background), 0, 255).astype(np.uint8), model, truth)


def make_jump_sequence(*, rng: int | np.random.Generator, n_frames: int = 60,
                       size: tuple[int, int] = (160, 160), noise: float = 8.0) -> BodySequence:
    """A countermovement jump seen from the side (Fig. 8): stand, squat, push off, fly 27 px, land.

    The foot stays pinned to the ground while it touches it (the hip is placed so that the ankle does not
    move); knee flexion reaches 90 deg and hip flexion 65 deg at the bottom of the squat.

    Parameters
    ----------
    rng : int or numpy.random.Generator
        Seed of the squat depth, the clutter and the pixel noise.
    n_frames : int
        Frames, 2 to 10,000; at 60 no angle turns faster than about 11 degrees a frame.
    size : tuple of int
        ``(rows, cols)``, each 150 to 4,096 (the jumper is 115 pixels tall and flies 27).
    noise : float
        Standard deviation of the pixel noise, grey levels, in [0, 50].

    Returns
    -------
    BodySequence
        Frames, background, ``BodyModel.jumper()`` and the true poses.

    References
    ----------
    Pantrigo et al., AMDO 2004, Sec. 6 and Fig. 8.

    Examples
    --------
    >>> make_jump_sequence(rng=0, n_frames=4).truth.shape
    (4, 7)
    """
    generator = make_rng(rng, "rng")
    n_frames = check_positive_int(n_frames, "n_frames", minimum=2, maximum=MAX_FRAMES)
    size = check_image_shape(size, "size", minimum=150)
    noise = float(as_finite_array(noise, "noise", shape=(), bounds=(0.0, 50.0)))
    model = BodyModel.jumper()
    s = np.linspace(0.0, 1.0, n_frames)
    depth_scale = generator.uniform(0.85, 1.0)

    def ramp(a, b):  # 0 before a, 1 after b, a half cosine between
        x = np.clip((s - a) / (b - a), 0.0, 1.0)
        return (1 - np.cos(np.pi * x)) / 2

    depth = depth_scale * (ramp(0.15, 0.42) - ramp(0.42, 0.64) + 0.5 * ramp(0.8, 0.9) - 0.5 * ramp(0.9, 1.0))
    flight = np.where((s > 0.64) & (s < 0.8), np.sin(np.pi * np.clip((s - 0.64) / 0.16, 0, 1)), 0.0)
    knee, hip, lean = np.deg2rad(90.0) * depth, np.deg2rad(65.0) * depth, np.deg2rad(25.0) * depth
    truth = np.zeros((n_frames, model.n_pose))
    truth[:, 2] = -np.pi / 2 + lean  # trunk leans forward (+x) in the squat
    truth[:, 3] = np.deg2rad(5.0) * depth  # head
    truth[:, 4] = np.pi - hip - lean  # thigh relative to the trunk: the hip angle
    truth[:, 5] = knee  # shank relative to the thigh: the knee angle
    shank = truth[:, 2] + truth[:, 4] + truth[:, 5]
    truth[:, 6] = -shank + np.deg2rad(30.0) * flight  # foot flat on the ground, pointed in flight
    ankle = model._forward(truth)[0][:, 4]  # foot joint with the hip at the origin
    ground = np.array([size[1] * 0.45, size[0] - 12.0])
    truth[:, :2] = ground - ankle
    truth[:, 1] -= 27.0 * flight
    background = _background(size, generator)
    frames = _draw(model, truth, background, noise, generator)
    return BodySequence(frames, np.clip(np.round(background), 0, 255).astype(np.uint8), model, truth)
