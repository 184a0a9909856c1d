"""Structure cue (eq. 12): a boosted cascade of Haar features trained here, and the stages it passes.

The paper uses a multi-view face detector [14, 15] in two levels: one cascade trained on all views
that most windows fail, then one cascade per view. OpenCV 5 ships no Haar cascades, so ours is
trained in the package on rendered heads (frontal and the two half profiles) against windows of
office clutter and of badly placed boxes around heads, with the negatives mined stage by stage.
The likelihood of a particle is ``exp(-(1 - n_s/N_s)/(2σ_s²))``, ``n_s`` the stages its box passes.
"""

from __future__ import annotations

import functools
import time
from dataclasses import dataclass, field
from pathlib import Path

import cv2
import numpy as np

from amdo_lab.common import MAX_SAMPLES
from amdo_lab.common import as_finite_array, check_bool, check_in_range, check_instance, check_positive_int, make_rng
from amdo_lab.cue_fusion_pf import data as head_data
from amdo_lab.cue_fusion_pf.likelihoods import SIGMA_RANGE, _gaussian_log_likelihood, check_frame
from amdo_lab.cue_fusion_pf.shape import ShapeSpace

__all__ = ["BoostedCascade", "HaarFeatures", "StructureLikelihood", "TrainingSet", "CASCADE_SEED",
           "load_or_train_cascade", "make_training_set", "normalised_patches"]

#: Detector window (width, height) in pixels: the head's bounding box keeps its 20:26 aspect.
WINDOW = (16, 20)
VIEWS = {"frontal": 0.0, "half-left": -0.7, "half-right": 0.7}
CACHE = Path(__file__).resolve().parents[2] / "build" / "cue_fusion_pf"
#: Seed of the package's cascade (the one the tracker and the chapter use).
CASCADE_SEED = 2004
#: Largest value of a patch :meth:`BoostedCascade.stages_passed_patches` accepts: far beyond grey levels
#: (0-255) and normalised patches, and the sums of a stack, kept in float32, stay finite.
MAX_PIXEL_VALUE = 1e6


def _integral_image(images: np.ndarray) -> np.ndarray:
    """Summed-area tables of (..., H, W) images, zero-padded to (..., H+1, W+1).

    ``ii[r, c]`` is the sum of ``image[:r, :c]``, so any rectangle's sum costs four look-ups.
    Check-free: the cascade calls it with checked patches and the training with its own.

    Parameters
    ----------
    images : numpy.ndarray
        (..., H, W) float images.

    Returns
    -------
    numpy.ndarray
        (..., H+1, W+1) tables (float32 for a stack, float64 for one image).

    References
    ----------
    Li & Chaumette, AMDO 2004, Sec. 2.3; Viola & Jones (2001).
    """
    images = np.asarray(images, dtype=float)  # summed in float64, whatever the patches' type
    padded = np.zeros(images.shape[:-2] + (images.shape[-2] + 1, images.shape[-1] + 1), np.float32 if images.ndim > 2 else np.float64)
    padded[..., 1:, 1:] = images.cumsum(axis=-2).cumsum(axis=-1)
    return padded


@dataclass(frozen=True)
class HaarFeatures:
    """Haar-like features as up to four weighted rectangles (inclusive corners, window pixels).

    ``rows0, cols0, rows1, cols1, weights`` are (n_features, 4); an unused rectangle has weight 0.
    The signs follow scikit-image: two rectangles ``second - first``, three ``middle - outer``,
    four ``second + fourth - first - third``.
    """

    rows0: np.ndarray
    cols0: np.ndarray
    rows1: np.ndarray
    cols1: np.ndarray
    weights: np.ndarray
    types: np.ndarray

    def __len__(self) -> int:
        return len(self.weights)

    def subset(self, index: np.ndarray) -> "HaarFeatures":
        return HaarFeatures(*(getattr(self, name)[index] for name in ("rows0", "cols0", "rows1", "cols1", "weights", "types")))

    def values(self, integrals: np.ndarray) -> np.ndarray:
        """(n_windows, n_features) feature values from (n_windows, H+1, W+1) integral images."""
        r0, c0, r1, c1 = self.rows0, self.cols0, self.rows1 + 1, self.cols1 + 1
        sums = (integrals[:, r1, c1] - integrals[:, r0, c1] - integrals[:, r1, c0] + integrals[:, r0, c0])
        return np.einsum("nfk,fk->nf", sums, self.weights)


_SIGNS = {"type-2-x": (-1, 1), "type-2-y": (-1, 1), "type-3-x": (-1, 1, -1), "type-3-y": (-1, 1, -1),
          "type-4": (-1, 1, -1, 1)}


def _sample_haar_features(features: HaarFeatures, n_features: int, generator: np.random.Generator) -> HaarFeatures:
    """``n_features`` (at most ``len(features)``) of ``features`` drawn without replacement, kept in their order."""
    return features.subset(np.sort(generator.choice(len(features), n_features, replace=False)))


@functools.lru_cache(maxsize=4)
def _all_haar_features(width: int, height: int) -> HaarFeatures:
    """All Haar-like features of a ``width`` × ``height`` window, in scikit-image's enumeration (no draw).

    References
    ----------
    Li & Chaumette, AMDO 2004, Sec. 2.3; Viola & Jones (2001).
    """
    from skimage.feature import haar_like_feature_coord

    rows0, cols0, rows1, cols1, weights, types = [], [], [], [], [], []
    for kind, signs in _SIGNS.items():
        coords, _ = haar_like_feature_coord(width, height, kind)
        for rectangles in coords:
            padded = list(rectangles) + [((0, 0), (0, 0))] * (4 - len(rectangles))
            rows0.append([r[0][0] for r in padded]); cols0.append([r[0][1] for r in padded])
            rows1.append([r[1][0] for r in padded]); cols1.append([r[1][1] for r in padded])
            weights.append(list(signs) + [0] * (4 - len(signs))); types.append(kind)
    return HaarFeatures(*(np.array(v, dtype=int) for v in (rows0, cols0, rows1, cols1)),
                        np.array(weights, float), np.array(types))


def normalised_patches(frame: np.ndarray, boxes: np.ndarray, window: tuple[int, int] = WINDOW) -> np.ndarray:
    """Grey patches (N, h, w) of the boxes ``(x, y, width, height)`` resized to the window, zero mean, unit std.

    Dividing by the standard deviation makes the features blind to a change of gain (lighting).
    """
    grey = frame.astype(np.float32).mean(axis=2) if frame.ndim == 3 else frame.astype(np.float32)
    width, height = window
    patches = np.empty((len(boxes), height, width), np.float32)
    for i, (x, y, w, h) in enumerate(boxes):
        # an affine map from the window to the box: border pixels are repeated off the frame
        matrix = np.array([[w / width, 0.0, x + 0.5 * w / width - 0.5], [0.0, h / height, y + 0.5 * h / height - 0.5]])
        patches[i] = cv2.warpAffine(grey, matrix, (width, height), flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                                    borderMode=cv2.BORDER_REPLICATE)
    patches -= patches.mean(axis=(1, 2), keepdims=True)
    patches /= patches.std(axis=(1, 2), keepdims=True) + 1e-3
    return patches


@dataclass
class TrainingSet:
    """Normalised patches: ``positives`` per view (name -> (n, h, w)), a pool of ``negatives``, and
    ``near_misses``: boxes shifted by 15-35 % of the head's size, the hard negatives of level 2."""

    positives: dict[str, np.ndarray]
    negatives: np.ndarray
    near_misses: np.ndarray


def _head_box(cx: float, cy: float, scale: float) -> np.ndarray:
    a, b = head_data.HEAD_AXES[0] * scale, head_data.HEAD_AXES[1] * scale
    return np.array([cx - a, cy - b, 2 * a, 2 * b])


def make_training_set(*, rng: int | np.random.Generator, n_scenes: int = 40, per_scene: int = 8,
                      negatives_per_scene: int = 300) -> TrainingSet:
    """Rendered heads (three views, random lighting and noise) and negative windows around them.

    Positives: the head's bounding box jittered by ±2 px and ±5 % in size. Negatives: boxes of
    the same aspect anywhere in the scene, plus boxes displaced from the head by 40 % or more of
    its size or scaled by 0.6 or 1.6 (a detector of "a head here", not "a head somewhere").

    Parameters
    ----------
    rng : int or numpy.random.Generator
        Source of the scenes.
    n_scenes : int
        Scenes per view. At most :data:`amdo_lab.common.MAX_SAMPLES` (1,000,000).
    per_scene : int
        Positive windows per head. At most :data:`amdo_lab.common.MAX_SAMPLES` (1,000,000).
    negatives_per_scene : int
        Negative windows per scene, at least 3.

    Returns
    -------
    TrainingSet
        Normalised patches.

    References
    ----------
    Li & Chaumette, AMDO 2004, Sec. 2.3; Viola & Jones (2001).
    """
    generator = make_rng(rng, "rng")
    n_scenes = check_positive_int(n_scenes, "n_scenes", maximum=MAX_SAMPLES)
    per_scene = check_positive_int(per_scene, "per_scene", maximum=MAX_SAMPLES)
    negatives_per_scene = check_positive_int(negatives_per_scene, "negatives_per_scene", minimum=3, maximum=MAX_SAMPLES)
    height, width = 192, 256
    positives = {view: [] for view in VIEWS}
    negatives, near_misses = [], []
    for _ in range(n_scenes):
        background = head_data.office_background(generator, height, width)
        for view, yaw in VIEWS.items():
            scene = background.copy()
            cx, cy, scale = generator.uniform(50, 206), generator.uniform(60, 120), generator.uniform(0.85, 1.2)
            head_data.draw_head(scene, cx, cy, scale, yaw + generator.normal(0, 0.1))
            scene *= generator.uniform(0.45, 1.25, 3).astype(np.float32)  # lighting gain and colour cast
            scene += generator.normal(0, 5, scene.shape).astype(np.float32)
            frame = np.clip(scene, 0, 255).astype(np.uint8)
            box = _head_box(cx, cy, scale)
            jitter = box + np.concatenate([generator.uniform(-2, 2, (per_scene, 2)), np.zeros((per_scene, 2))], axis=1)
            jitter[:, 2:] *= generator.uniform(0.95, 1.05, (per_scene, 1))
            positives[view].append(normalised_patches(frame, jitter))
            n_near = negatives_per_scene // 2
            shift = generator.uniform(0.4, 1.2, (n_near, 2)) * generator.choice([-1, 1], (n_near, 2)) * box[2:]
            near = np.tile(box, (n_near, 1)); near[:, :2] += shift
            resized = np.tile(box, (4, 1)); resized[:, 2:] *= np.array([[0.6], [0.6], [1.6], [1.6]])
            resized[:, :2] += box[2:] / 2 - resized[:, 2:] / 2
            size = generator.uniform(25, 70, negatives_per_scene // 3)
            anywhere = np.column_stack([generator.uniform(0, width - size), generator.uniform(0, height - 1.3 * size),
                                        size, 1.3 * size])
            negatives.append(normalised_patches(frame, np.vstack([near, resized, anywhere])))
            n_miss = 4 * per_scene
            miss = np.tile(box, (n_miss, 1))
            miss[:, :2] += generator.uniform(0.15, 0.35, (n_miss, 2)) * generator.choice([-1, 1], (n_miss, 2)) * box[2:]
            miss[:, 2:] *= generator.uniform(0.8, 1.25, (n_miss, 1))
            near_misses.append(normalised_patches(frame, miss))
    return TrainingSet({view: np.concatenate(p) for view, p in positives.items()}, np.concatenate(negatives),
                       np.concatenate(near_misses))


# --- AdaBoost with decision stumps ----------------------------------------------------------------

@dataclass
class _Stage:
    features: HaarFeatures
    thresholds: np.ndarray
    polarities: np.ndarray
    alphas: np.ndarray
    threshold: float

    def scores(self, integrals: np.ndarray) -> np.ndarray:
        votes = np.where(self.polarities * self.features.values(integrals) < self.polarities * self.thresholds, 1.0, -1.0)
        return votes @ self.alphas


def _best_stumps(values: np.ndarray, labels: np.ndarray, weights: np.ndarray):
    """For every feature, the threshold and polarity with the least weighted error (labels ±1)."""
    order = np.argsort(values, axis=0)
    sorted_values = np.take_along_axis(values, order, axis=0)
    w_pos = np.where(labels[order] > 0, weights[order], 0.0)
    w_neg = np.where(labels[order] < 0, weights[order], 0.0)
    below_pos, below_neg = np.cumsum(w_pos, axis=0), np.cumsum(w_neg, axis=0)
    total_pos, total_neg = below_pos[-1], below_neg[-1]
    # polarity +1: "positive if value < threshold" errs on positives above and negatives below
    error_plus = (total_pos - below_pos) + below_neg
    error_minus = below_pos + (total_neg - below_neg)
    errors = np.minimum(error_plus, error_minus)
    row = np.argmin(errors, axis=0)
    cols = np.arange(values.shape[1])
    threshold = 0.5 * (sorted_values[row, cols] + sorted_values[np.minimum(row + 1, len(values) - 1), cols])
    polarity = np.where(error_plus[row, cols] <= error_minus[row, cols], 1.0, -1.0)
    return errors[row, cols], threshold, polarity


def _train_stage(features, pos_values, neg_values, *, max_stumps, min_detection, max_false_positive):
    values = np.vstack([pos_values, neg_values])
    labels = np.concatenate([np.ones(len(pos_values)), -np.ones(len(neg_values))])
    weights = np.where(labels > 0, 0.5 / len(pos_values), 0.5 / len(neg_values))
    chosen, thresholds, polarities, alphas = [], [], [], []
    for _ in range(max_stumps):
        errors, threshold, polarity = _best_stumps(values, labels, weights)
        best = int(np.argmin(errors))
        error = float(np.clip(errors[best], 1e-10, 1 - 1e-10))
        alpha = 0.5 * np.log((1 - error) / error)
        prediction = np.where(polarity[best] * values[:, best] < polarity[best] * threshold[best], 1.0, -1.0)
        weights = weights * np.exp(-alpha * labels * prediction)
        weights /= weights.sum()
        chosen.append(best); thresholds.append(threshold[best]); polarities.append(polarity[best]); alphas.append(alpha)
        votes = np.where(np.array(polarities) * values[:, chosen] < np.array(polarities) * np.array(thresholds), 1.0, -1.0)
        scores = votes @ np.array(alphas)
        # the stage threshold keeps min_detection of the positives
        stage_threshold = np.quantile(scores[labels > 0], 1 - min_detection) - 1e-9
        false_positive = np.mean(scores[labels < 0] >= stage_threshold)
        if false_positive <= max_false_positive:
            break
    stage = _Stage(features.subset(np.array(chosen)), np.array(thresholds), np.array(polarities), np.array(alphas),
                   float(stage_threshold))
    return stage, scores[labels < 0] >= stage_threshold


@dataclass
class BoostedCascade:
    """Two levels of cascades (Sec. 2.3): a first cascade for all views, then one cascade per view.

    ``n_stages`` is N_s: the first level's stages plus the longest second-level cascade's. A window
    that passes level 1 counts the stages of its best view, scaled to that longest cascade, so
    passing a whole shorter view cascade also gives n_s = N_s.

    Parameters
    ----------
    first_level : list
        Stages of level 1.
    second_level : dict
        View name -> list of stages.
    window : tuple of int
        Detector window (width, height).
    training_seconds : float
        Training time.
    report : dict
        Free-form training notes.

    References
    ----------
    Li & Chaumette, AMDO 2004, Sec. 2.3; Viola & Jones (2001).
    """

    first_level: list
    second_level: dict[str, list]
    window: tuple[int, int] = WINDOW
    training_seconds: float = 0.0
    report: dict = field(default_factory=dict)

    @property
    def n_stages(self) -> int:
        """N_s of eq. (12)."""
        return len(self.first_level) + max(len(c) for c in self.second_level.values())

    def stages_passed_patches(self, patches: np.ndarray) -> np.ndarray:
        """n_s for normalised patches: first-level stages passed in order, then the best view's.

        Parameters
        ----------
        patches : numpy.ndarray
            (N, h, w) patches from :func:`normalised_patches`, values within ±:data:`MAX_PIXEL_VALUE`.

        Returns
        -------
        numpy.ndarray
            (N,) stages passed, in [0, N_s].
        """
        patches = as_finite_array(patches, "patches", shape=(None, self.window[1], self.window[0]), allow_empty=True,
                                  max_abs=MAX_PIXEL_VALUE)
        integrals = _integral_image(patches)
        passed = np.zeros(len(patches))
        alive = np.arange(len(patches))
        for stage in self.first_level:
            if alive.size == 0:
                break
            ok = stage.scores(integrals[alive]) >= stage.threshold
            alive = alive[ok]
            passed[alive] += 1
        best = np.zeros(len(patches))
        longest = max(len(c) for c in self.second_level.values())
        for cascade in self.second_level.values():
            count = np.zeros(alive.size)
            still = np.arange(alive.size)
            for stage in cascade:
                if still.size == 0:
                    break
                still = still[stage.scores(integrals[alive[still]]) >= stage.threshold]
                count[still] += 1
            best[alive] = np.maximum(best[alive], count * longest / max(len(cascade), 1))
        return passed + best

    def _stages_passed(self, image: np.ndarray, boxes: np.ndarray) -> np.ndarray:
        """n_s of eq. (12) for each box ``(x, y, width, height)`` (N, 4) of an (H, W, 3) or (H, W) image (check-free)."""
        return self.stages_passed_patches(normalised_patches(image, boxes, self.window))


def _train_cascade_level(features, positives, negative_pool, *, n_stages, n_negatives,
                         max_stumps, min_detection, max_false_positive, rng):
    """Stages trained one after the other; each stage's negatives are pool windows the cascade still accepts."""
    pos_integrals = _integral_image(positives)
    pos_values = features.values(pos_integrals)
    pool_integrals = _integral_image(negative_pool)
    stages = []
    accepted = np.arange(len(negative_pool))
    alive_pos = np.arange(len(positives))
    for _ in range(n_stages):
        if accepted.size < 20:  # the pool is exhausted: the cascade stops here
            break
        chosen = rng.choice(accepted, min(n_negatives, accepted.size), replace=False)
        stage, _ = _train_stage(features, pos_values[alive_pos], features.values(pool_integrals[chosen]),
                                max_stumps=max_stumps, min_detection=min_detection,
                                max_false_positive=max_false_positive)
        stages.append(stage)
        accepted = accepted[stage.scores(pool_integrals[accepted]) >= stage.threshold]
        alive_pos = alive_pos[stage.scores(pos_integrals[alive_pos]) >= stage.threshold]
    return stages


def _train_cascade(training: TrainingSet, *, rng: int | np.random.Generator, first_stages: int = 4,
                   second_stages: int = 21, n_features: int = 1500, n_negatives: int = 600, max_stumps: int = 12,
                   min_detection: float = 0.997, max_false_positive: float = 0.6) -> BoostedCascade:
    """Train the two-level cascade of Sec. 2.3 on ``training`` (see :func:`make_training_set`).

    Check-free: :func:`load_or_train_cascade` calls it with the defaults, the tests with small settings.

    Level 1: ``first_stages`` stages on all views' positives. Level 2: ``second_stages`` stages per
    view, trained on the pool windows that pass level 1, on boxes shifted by 15-35 % of the head's
    size, and on the other views' heads. N_s = first_stages + second_stages (25 by
    default, as Table 1) unless the negative pool runs out first.

    Parameters
    ----------
    training : TrainingSet
        Positives per view and negatives.
    rng : int or numpy.random.Generator
        Source of the feature subset and of the negatives drawn per stage.
    first_stages, second_stages : int
        Stages of level 1 and of each level-2 cascade (at most).
    n_features : int
        Haar features drawn from all those of the window.
    n_negatives : int
        Negatives per stage.
    max_stumps : int
        Most decision stumps per stage.
    min_detection : float
        Share of the positives each stage keeps, in (0, 1].
    max_false_positive : float
        A stage stops adding stumps once it passes at most this share of its negatives, in [0, 1].

    Returns
    -------
    BoostedCascade
        The two-level cascade and its training time.

    References
    ----------
    Li & Chaumette, AMDO 2004, Sec. 2.3; Viola & Jones (2001).
    """
    generator = make_rng(rng, "rng")
    began = time.perf_counter()
    features = _sample_haar_features(_all_haar_features(*WINDOW), n_features, generator)
    everyone = np.concatenate(list(training.positives.values()))
    options = dict(n_negatives=n_negatives, max_stumps=max_stumps, min_detection=min_detection,
                   max_false_positive=max_false_positive, rng=generator)
    first = _train_cascade_level(features, everyone, training.negatives, n_stages=first_stages, **options)
    # the negatives that reach level 2
    pool = training.negatives
    integrals = _integral_image(pool)
    keep = np.ones(len(pool), bool)
    for stage in first:
        keep &= stage.scores(integrals) >= stage.threshold
    # level 2, one cascade per view: against what passed level 1, the near misses and the other views
    second = {}
    for view, positives in training.positives.items():
        others = [p for name, p in training.positives.items() if name != view]
        hard = np.concatenate([pool[keep], training.near_misses, *others])
        second[view] = _train_cascade_level(features, positives, hard, n_stages=second_stages, **options)
    return BoostedCascade(first, second, WINDOW, time.perf_counter() - began)


def load_or_train_cascade(*, rng: int, cache: bool = True) -> BoostedCascade:
    """The cascade trained from the integer seed ``rng``, read from (or written to) a cache under build/.

    Parameters
    ----------
    rng : int
        Seed of the training set (``rng``) and of the training (``rng + 1``); an int, because it
        names the cache file. The package's cascade is ``CASCADE_SEED``.
    cache : bool
        Read and write ``build/cue_fusion_pf/cascade_<rng>.pkl``.

    Returns
    -------
    BoostedCascade
        The trained two-level cascade (the same for the same seed: training is deterministic).

    References
    ----------
    Li & Chaumette, AMDO 2004, Sec. 2.3; Viola & Jones (2001).
    """
    import pickle

    if isinstance(rng, bool) or not isinstance(rng, (int, np.integer)) or rng < 0:
        raise TypeError(f"rng must be a non-negative int (it names the cache file), got {rng!r}")
    cache = check_bool(cache, "cache")
    seed = int(rng)
    path = CACHE / f"cascade_{seed}.pkl"
    if cache and path.exists():
        with open(path, "rb") as handle:
            return pickle.load(handle)
    cascade = _train_cascade(make_training_set(rng=seed), rng=seed + 1)
    if cache:
        path.parent.mkdir(parents=True, exist_ok=True)
        with open(path, "wb") as handle:
            pickle.dump(cascade, handle)
    return cascade


class StructureLikelihood:
    """Structure cue, eq. (12): ``log p_s = -(1 - n_s/N_s)/(2σ_s²) - log(√(2π) σ_s)``.

    The cascade is run on each particle's circumscribed rectangle (the ellipse's bounding box).

    Parameters
    ----------
    shape_space : ShapeSpace
        Maps states to ellipses.
    cascade : BoostedCascade
        The detector.
    sigma : float
        σ_s, in :data:`~amdo_lab.cue_fusion_pf.likelihoods.SIGMA_RANGE`.

    References
    ----------
    Li & Chaumette, AMDO 2004, eq. (12); Viola & Jones (2001).
    """

    def __init__(self, shape_space: ShapeSpace, cascade: BoostedCascade, *, sigma: float = float(np.sqrt(15.0))):
        self.shape_space = check_instance(shape_space, "shape_space", ShapeSpace, what="a ShapeSpace")
        check_instance(cascade, "cascade", BoostedCascade, what="a BoostedCascade (see load_or_train_cascade)")
        self.cascade = cascade
        self.sigma = check_in_range(sigma, "sigma", *SIGMA_RANGE, closed="both")

    def boxes(self, states: np.ndarray) -> np.ndarray:
        """The circumscribed rectangles of the states' ellipses.

        Parameters
        ----------
        states : numpy.ndarray
            (N, 3) or (3,) states.

        Returns
        -------
        numpy.ndarray
            (N, 4) boxes ``(x, y, width, height)``.
        """
        ellipses = self.shape_space.ellipses(states)
        c, s = np.abs(np.cos(ellipses[:, 4])), np.abs(np.sin(ellipses[:, 4]))
        half_w = ellipses[:, 2] * c + ellipses[:, 3] * s
        half_h = ellipses[:, 2] * s + ellipses[:, 3] * c
        return np.column_stack([ellipses[:, 0] - half_w, ellipses[:, 1] - half_h, 2 * half_w, 2 * half_h])

    def distance(self, frame: np.ndarray, states: np.ndarray) -> np.ndarray:
        """1 - n_s/N_s for each state.

        Parameters
        ----------
        frame : numpy.ndarray
            (H, W, 3) uint8 RGB image.
        states : numpy.ndarray
            (N, 3) or (3,) states.

        Returns
        -------
        numpy.ndarray
            (N,) distances in [0, 1].
        """
        frame = check_frame(frame)
        return 1.0 - self.cascade._stages_passed(frame, self.boxes(states)) / self.cascade.n_stages

    def log_likelihood(self, frame: np.ndarray, states: np.ndarray) -> np.ndarray:
        """Eq. (12) in the log domain.

        Parameters
        ----------
        frame : numpy.ndarray
            (H, W, 3) uint8 RGB image.
        states : numpy.ndarray
            (N, 3) or (3,) states.

        Returns
        -------
        numpy.ndarray
            (N,) log-likelihoods.
        """
        # ln of eq. (12): p_s = exp(-(1 - n_s/N_s)/2σ_s²) / (√(2π) σ_s), distance = 1 - n_s/N_s
        return _gaussian_log_likelihood(self.distance(frame, states), self.sigma)
