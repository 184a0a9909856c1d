"""Seeded generator of 2-D articulated human-pose shapes (stand-in for the paper's marker photos).

A skeleton has 13 limbs, each drawn as a straight stroke of ``landmarks_per_limb`` points from its
proximal to its distal joint. A pose is a vector of 13 absolute limb directions (degrees; 0 points
down the image, +90 points along +x, 180 points up).

Each Table-1 class has two *articulation modes* (``POSE_MODES``): the different ways people perform
the same action (boxing with the left or the right fist forward, a high or a low kick, arms hanging or
hands on hips, picking with one or both arms, stretching straight up or in a V, shooting with the arms
low or spread for balance). An example draws its mode uniformly, then perturbs the mode's directions
(joint jitter, larger for the arms than for the trunk), the limb lengths, adds isotropic landmark
noise and applies a random similarity. The design was fixed before any recogniser was run on it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common import (apply_similarity_2d, as_finite_array, check_in_range, check_names,
                             check_positive_int, make_rng)

__all__ = [
    "LIMB_NAMES",
    "LIMB_PARENTS",
    "POSES",
    "POSE_MODES",
    "JITTER_SCALE",
    "TABLE1_CLASSES",
    "PoseDataset",
    "make_pose_dataset",
]

LIMB_NAMES: tuple[str, ...] = (
    "head", "neck", "torso",
    "left upper arm", "left forearm", "right upper arm", "right forearm",
    "left thigh", "left shin", "left foot", "right thigh", "right shin", "right foot",
)
# Parent limb whose distal joint is this limb's proximal joint (-1: starts at the pelvis).
# The torso runs pelvis -> neck base; arms start at the neck base offset to the shoulders.
LIMB_PARENTS: tuple[int, ...] = (1, 2, -1, 2, 3, 2, 5, -1, 7, 8, -1, 10, 11)
# The figure faces the viewer: its left side is on the image's +x side.
_OFFSETS = {3: (0.12, 0.0), 5: (-0.12, 0.0), 7: (0.08, 0.0), 10: (-0.08, 0.0)}
MEAN_LENGTHS = np.array([0.20, 0.10, 0.50, 0.30, 0.28, 0.30, 0.28, 0.45, 0.42, 0.12, 0.45, 0.42, 0.12])
# Limbs are generated in this order so a parent exists before its children.
_ORDER = (2, 1, 0, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12)

#            head neck torso  LUA  LFA   RUA   RFA  LTH  LSH LFT  RTH  RSH  RFT
POSES: dict[str, tuple[float, ...]] = {
    "boxing":     (175, 175, 175, 60, 150, 80, 90, 15, 10, 90, -15, -10, 90),
    "kicking":    (195, 190, 195, 45, 65, -50, -35, -5, 0, 90, 70, 80, 115),
    "relaxing":   (180, 180, 180, 10, 5, -10, -5, 5, 0, 90, -5, 0, 90),
    "picking":    (130, 140, 150, 25, 30, -50, -35, -5, 0, 90, 45, 25, 105),
    "stretching": (180, 180, 180, 160, 175, -160, -175, 10, 5, 90, -10, -5, 90),
    "shooting":   (190, 188, 190, 45, 65, -50, -35, -5, 0, 90, 50, 45, 110),
    "walking":    (180, 180, 182, 25, 40, -25, -10, 25, 10, 90, -20, -30, 70),
    "waving":     (180, 180, 180, 10, 5, 120, 170, 5, 0, 90, -5, 0, 90),
    "pointing":   (180, 180, 180, 10, 5, 90, 90, 5, 0, 90, -5, 0, 90),
    "jumping":    (180, 180, 180, 135, 160, -135, -160, 30, -10, 90, -30, 10, 90),
    "crouching":  (160, 165, 160, 40, 90, -40, -90, 120, 10, 90, 110, 0, 90),
    "sitting":    (180, 180, 180, 20, 70, -20, -70, 90, 0, 90, 90, 0, 90),
    "bowing":     (100, 105, 110, 60, 50, 65, 55, 5, 0, 90, -5, 0, 90),
    "star":       (180, 180, 180, 100, 100, -100, -100, 30, 30, 90, -30, -30, 90),
}
TABLE1_CLASSES: tuple[str, ...] = ("boxing", "kicking", "relaxing", "picking", "stretching", "shooting")

# Articulation modes of the Table-1 classes; the first mode of each is its ``POSES`` entry.
# Kicking, picking and shooting keep sharing the arms, the support leg and a raised swing leg.
#                                   head neck torso LUA  LFA   RUA   RFA  LTH LSH LFT  RTH  RSH  RFT
POSE_MODES: dict[str, dict[str, tuple[float, ...]]] = {
    "boxing": {
        "right fist forward":       (175, 175, 175, 60, 150, 80, 90, 15, 10, 90, -15, -10, 90),
        "left fist forward":        (185, 185, 185, -80, -90, -60, -150, 15, 10, 90, -15, -10, 90),
    },
    "kicking": {
        "high kick":                (195, 190, 195, 45, 65, -50, -35, -5, 0, 90, 70, 80, 115),
        "low kick":                 (192, 188, 192, 45, 65, -50, -35, -5, 0, 90, 30, 30, 100),
    },
    "relaxing": {
        "arms hanging":             (180, 180, 180, 10, 5, -10, -5, 5, 0, 90, -5, 0, 90),
        "hands on hips":            (180, 180, 180, 35, -35, -35, 35, 5, 0, 90, -5, 0, 90),
    },
    "picking": {
        "one arm reaching":         (130, 140, 150, 25, 30, -50, -35, -5, 0, 90, 45, 25, 105),
        "both arms reaching":       (130, 140, 150, 25, 30, 20, 25, -5, 0, 90, 45, 25, 105),
    },
    "stretching": {
        "arms straight up":         (180, 180, 180, 160, 175, -160, -175, 10, 5, 90, -10, -5, 90),
        "arms in a V":              (180, 180, 180, 135, 145, -135, -145, 10, 5, 90, -10, -5, 90),
    },
    "shooting": {
        "arms low":                 (190, 188, 190, 45, 65, -50, -35, -5, 0, 90, 50, 45, 110),
        "arms spread":              (190, 188, 190, 80, 95, -80, -95, -5, 0, 90, 50, 45, 110),
    },
}
#: Largest number of examples per class and of landmarks per limb (a draw of 10,000 shapes per class
#: at 100 landmarks per limb holds 26 million coordinates per class).
MAX_PER_CLASS = 10_000
MAX_LANDMARKS_PER_LIMB = 100
#: Largest mode separation factor (the chapter uses up to 3).
MAX_MODE_SEPARATION = 100.0
#: Largest landmark noise std and limb length, in skeleton units (a figure is about 1.7 high).
MAX_NOISE = 1e6
# Per-limb multiplier of ``joint_jitter_deg``: arms swing freely, the trunk and head much less.
JITTER_SCALE = np.array([0.8, 0.8, 0.6, 1.4, 1.4, 1.4, 1.4, 1.0, 1.0, 0.8, 1.0, 1.0, 0.8])


def _pose_modes(name: str) -> dict[str, tuple[float, ...]]:
    """Mode name to the 13 limb directions in degrees of a pose from ``POSES`` (checked by the caller):
    its ``POSE_MODES``, or a single mode named after the pose for poses outside ``POSE_MODES``."""
    return POSE_MODES.get(name, {name: POSES[name]})


@dataclass(frozen=True)
class PoseDataset:
    """Generated articulated shapes with their class labels and ground truth.

    Parameters
    ----------
    shapes : (n, 13, m, 2) numpy.ndarray
        Landmark strokes of the 13 limbs, ``m = landmarks_per_limb``, in skeleton units (a figure
        is about 1.7 high before its similarity).
    labels : (n,) numpy.ndarray of str
        Class (pose) name of every shape.
    classes : tuple of str
        The pose names drawn, in order.
    modes : (n,) numpy.ndarray of str
        The articulation-mode name of every shape.
    limb_lengths : (n, 13) numpy.ndarray
        Limb lengths in the output frame (after the similarity), so with ``noise=0`` the distance
        between a stroke's first and last landmarks equals its entry here.
    scales : (n,) numpy.ndarray
        Similarity scale of every shape, in [0.8, 1.25].
    rotations_rad : (n,) numpy.ndarray
        Similarity rotation of every shape, in radians.
    translations : (n, 2) numpy.ndarray
        Similarity translation of every shape, in [-1, 1]^2.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 7 (our synthetic stand-in for its pose photographs).
    """

    shapes: np.ndarray
    labels: np.ndarray
    classes: tuple[str, ...]
    modes: np.ndarray
    limb_lengths: np.ndarray
    scales: np.ndarray
    rotations_rad: np.ndarray
    translations: np.ndarray


def _check_landmarks_per_limb(value: object) -> int:
    """A stroke's landmark count: its two ends at least, ``MAX_LANDMARKS_PER_LIMB`` at most."""
    return check_positive_int(value, "landmarks_per_limb", minimum=2, maximum=MAX_LANDMARKS_PER_LIMB)


def skeleton_strokes(directions_deg: np.ndarray, lengths: np.ndarray, landmarks_per_limb: int) -> np.ndarray:
    """Landmark strokes of stick-figure skeletons with given limb directions and lengths.

    Limbs are chained proximal-to-distal (``LIMB_PARENTS``); the pelvis is at the origin.

    Parameters
    ----------
    directions_deg : (n, 13) array_like
        Limb directions in degrees (0 points along -y, down in a plot with y up; 90 along +x).
    lengths : (n, 13) array_like
        Limb lengths, in (0, 1e6] skeleton units (``MAX_NOISE``).
    landmarks_per_limb : int
        Landmarks per stroke, from 2 to ``MAX_LANDMARKS_PER_LIMB``, evenly spaced from the limb's start to its end.

    Returns
    -------
    numpy.ndarray
        Strokes ``(n, 13, m, 2)``.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 3 (shapes as K jointed, non-overlapping limbs of landmarks).
    """
    directions_deg = as_finite_array(directions_deg, "directions_deg", shape=(None, len(LIMB_PARENTS)))
    lengths = as_finite_array(lengths, "lengths", shape=directions_deg.shape, bounds=(0, MAX_NOISE), closed="right")
    landmarks_per_limb = _check_landmarks_per_limb(landmarks_per_limb)
    return _skeleton_strokes(directions_deg, lengths, landmarks_per_limb)


def _skeleton_strokes(directions_deg: np.ndarray, lengths: np.ndarray, landmarks_per_limb: int) -> np.ndarray:
    """:func:`skeleton_strokes` on validated input."""
    angles = np.deg2rad(directions_deg)
    vectors = lengths[..., None] * np.stack([np.sin(angles), -np.cos(angles)], axis=-1)  # (n,13,2)
    starts = np.zeros_like(vectors)
    for limb in _ORDER:  # 13 limbs: a loop over the kinematic tree, vectorised over examples
        parent = LIMB_PARENTS[limb]
        base = np.zeros_like(vectors[:, 0]) if parent < 0 else starts[:, parent] + vectors[:, parent]
        starts[:, limb] = base + np.asarray(_OFFSETS.get(limb, (0.0, 0.0)))
    fractions = np.linspace(0.0, 1.0, landmarks_per_limb)
    return starts[:, :, None, :] + fractions[None, None, :, None] * vectors[:, :, None, :]


def make_pose_dataset(
    classes: tuple[str, ...] | list[str],
    n_per_class: int,
    *,
    rng: int | np.random.Generator,
    noise: float = 0.01,
    joint_jitter_deg: float = 10.0,
    length_jitter: float = 0.06,
    landmarks_per_limb: int = 6,
    max_rotation_deg: float = 15.0,
    mode_separation: float = 1.0,
) -> PoseDataset:
    """Draw ``n_per_class`` articulated shapes of each pose in ``classes``.

    Parameters
    ----------
    classes : sequence of str
        Pose names from ``POSES`` (``TABLE1_CLASSES`` are the six of the paper's Table 1).
    n_per_class : int
        Examples per class, from 1 to ``MAX_PER_CLASS``.
    rng : int or numpy.random.Generator
        Seed or generator of every draw (keyword-only, no default; via ``make_rng``).
    noise : float
        Std of isotropic landmark noise, in units of the skeleton (height about 1.7) before scaling,
        in [0, 1e6] (``MAX_NOISE``).
    joint_jitter_deg : float
        Std (degrees, in [0, 360]) of the Gaussian perturbation of a limb direction, times
        ``JITTER_SCALE`` per limb (arms 1.4x, torso 0.6x); with the modes it sets the class overlap.
    length_jitter : float
        Relative std of each limb length, in [0, 1] (lengths are drawn log-normally).
    landmarks_per_limb : int
        Landmarks per stroke, from 2 to ``MAX_LANDMARKS_PER_LIMB``.
    max_rotation_deg : float
        Global rotation drawn uniformly in +-this, in [0, 180] (180 covers every rotation); scale in [0.8, 1.25]; translation in [-1, 1]^2.
    mode_separation : float
        Factor in [0, 100] (``MAX_MODE_SEPARATION``) on each class's articulation modes about their mean direction vector:
        0 merges a class's modes into one, 1 (default) keeps ``POSE_MODES`` as written, 2 doubles
        the angular distance between the modes. Classes with one mode are unaffected.

    Returns
    -------
    PoseDataset
        ``n_per_class * len(classes)`` shapes, grouped by class in the order of ``classes``.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 7 (its 14 pose classes photographed; we draw seeded stick figures instead).

    Examples
    --------
    >>> data = make_pose_dataset(("boxing", "kicking"), 3, rng=0)
    >>> data.shapes.shape
    (6, 13, 6, 2)
    >>> data.labels.tolist()
    ['boxing', 'boxing', 'boxing', 'kicking', 'kicking', 'kicking']
    """
    names = check_names(classes, "classes", allowed=POSES)
    n_per_class = check_positive_int(n_per_class, "n_per_class", maximum=MAX_PER_CLASS)
    landmarks_per_limb = _check_landmarks_per_limb(landmarks_per_limb)
    noise = check_in_range(noise, "noise", 0, MAX_NOISE, closed="both")
    joint_jitter_deg = check_in_range(joint_jitter_deg, "joint_jitter_deg", 0, 360, closed="both")
    length_jitter = check_in_range(length_jitter, "length_jitter", 0, 1, closed="both")
    max_rotation_deg = check_in_range(max_rotation_deg, "max_rotation_deg", 0, 180, closed="both")
    mode_separation = check_in_range(mode_separation, "mode_separation", 0, MAX_MODE_SEPARATION, closed="both")
    generator = make_rng(rng, "rng")
    n = n_per_class * len(names)
    labels = np.repeat(np.array(names), n_per_class)
    # Every example picks one of its class's articulation modes with equal probability.
    modes = np.empty(n, dtype=object)
    base = np.empty((n, 13))
    for c in names:
        rows = np.flatnonzero(labels == c)
        options = _pose_modes(c)
        picks = generator.integers(0, len(options), len(rows))
        modes[rows] = np.array(list(options), dtype=object)[picks]
        mode_directions = np.array(list(options.values()), dtype=float)  # (n_modes, 13)
        # mode + (s - 1)(mode - centre) = centre + s (mode - centre); exactly the mode when s = 1
        mode_directions = mode_directions + (mode_separation - 1.0) * (mode_directions - mode_directions.mean(axis=0))
        base[rows] = mode_directions[picks]
    directions = base + joint_jitter_deg * JITTER_SCALE * generator.standard_normal((n, 13))
    lengths = MEAN_LENGTHS * np.exp(length_jitter * generator.standard_normal((n, 13)))
    strokes = _skeleton_strokes(directions, lengths, landmarks_per_limb)
    strokes = strokes + noise * generator.standard_normal(strokes.shape)
    scales = generator.uniform(0.8, 1.25, n)
    rotations = np.deg2rad(generator.uniform(-max_rotation_deg, max_rotation_deg, n))
    translations = generator.uniform(-1.0, 1.0, (n, 2))
    shapes = np.empty_like(strokes)
    for i in range(n):  # one similarity per example
        shapes[i] = apply_similarity_2d(strokes[i].reshape(-1, 2), scales[i], rotations[i], translations[i]).reshape(
            strokes.shape[1:]
        )
    return PoseDataset(shapes, labels, names, modes.astype(str), lengths * scales[:, None], scales, rotations, translations)
