"""Classification (Sec. 5, steps 1-9) and a HOG nearest-neighbour baseline."""

from __future__ import annotations

from dataclasses import dataclass, field

import cv2
import numpy as np
from skimage.feature import hog

from amdo_lab.common import check_positive_int
from amdo_lab.ear_biometrics.features import (
    CircleFeatures,
    TopologyFeatures,
    as_grey_image,
    clean_contours,
    detect_contours,
    topology_features,
)


@dataclass(frozen=True)
class EarTemplate:
    """Both feature vectors of one image: V (eq. 7) and F (eq. 9)."""

    circles: CircleFeatures
    topology: TopologyFeatures


@dataclass(frozen=True)
class IdentificationResult:
    """Outcome of :meth:`EarMatcher.identify`.

    ``subject_id`` is None for a rejection. ``candidate_ids``/``candidate_scores`` are the enrolled
    templates that passed steps 2-4 (count gate and distance-sum threshold), best first; ``scores``
    holds the ranking score of every enrolled template (lower is better; used for CMC curves).
    """

    subject_id: object
    candidate_ids: tuple
    candidate_scores: np.ndarray
    scores: np.ndarray
    reason: str = ""


def topology_similarity(query: TopologyFeatures, reference: TopologyFeatures, coordinate_tolerance: float = 0.2) -> float:
    """Steps 7-9: fraction of contours (of the larger set) whose triple (N_E, N_B, N_I) equals that of
    an unused contour of the other image *and* whose characteristic points lie within
    ``coordinate_tolerance`` (normalised units, mean nearest-point distance) of it. Greedy, outermost
    contour first (the paper's tracing order)."""
    used = np.zeros(len(reference.contours), bool)
    matched = 0
    for contour in query.contours:
        for index, other in enumerate(reference.contours):
            if used[index] or other.triple != contour.triple:
                continue
            a, b = contour.points, other.points
            if len(a):
                gaps = np.linalg.norm(a[:, None] - b[None], axis=2).min(axis=1).mean()
                if gaps > coordinate_tolerance:
                    continue
            used[index] = True
            matched += 1
            break
    return matched / max(len(query.contours), len(reference.contours), 1)


@dataclass
class EarMatcher:
    """Choraś's classifier (Sec. 5).

    Steps: (2-3) a reference is a candidate when |l_r - l_r,ref| <= ``count_tolerance`` on every
    radius, except at most ``max_count_violations`` radii (0 = the paper's rule); (4) its mean
    absolute difference of the distance sums must be below ``distance_threshold``; (5) no candidate
    -> rejection (``subject_id=None``); (6-9) candidates are ranked by the distance-sum difference
    minus ``topology_weight`` times the topology similarity (exact triples + close coordinates).
    ``smoothing`` > 0 applies a Gaussian blur (that sigma, pixels) before contour detection; the
    default 0 follows the paper. Step 1's contours are cleaned by :func:`clean_contours` (a
    (2 ``closing`` + 1)^2 closing, fragments under ``min_component_size`` pixels dropped).
    ``mode`` is the reading of eq. 6 (see :func:`normalise_coordinates`; default the principal-axis
    one). ``crossings`` is the reading of "the contour crosses a circle" (see :func:`circle_features`):
    the default ``"polyline"`` intersects the thinned contours, pruned of spurs shorter than
    ``spur_length`` pixels and smoothed by ``polyline_smoothing`` rounds, with each circle, with a
    dead band of ``band`` pixels; ``"pixels"`` counts runs of contour pixels along the sampled circle,
    merging runs less than ``min_gap`` pixels of arc apart (``min_gap=0`` is the literal count).
    Pixel settings are for 256 x 256 images (the database default); they were chosen on development
    seeds, not on the notebook's data.
    """

    k: float = 8.0
    window: int = 3
    smoothing: float = 0.0
    n_circles: int = 8
    step: float = 0.25
    min_component_size: int = 40
    closing: int = 2
    count_tolerance: int = 1
    max_count_violations: int = 0
    distance_threshold: float = np.inf
    topology_weight: float = 1.0
    mode: str = "principal"
    min_gap: float = 6.0
    crossings: str = "polyline"
    polyline_smoothing: int = 4
    band: float = 6.0
    spur_length: int = 8
    _ids: list = field(default_factory=list, init=False, repr=False)
    _templates: list = field(default_factory=list, init=False, repr=False)

    def extract(self, image: object) -> EarTemplate:
        """Features of one image: contours (eqs. 1-5), clean-up, V and F."""
        grey = as_grey_image(image)  # validates; 8-bit input keeps the detector's fast uint8 path
        if self.smoothing > 0:  # image normalisation step before contour detection (Fig. 3)
            grey = cv2.GaussianBlur(grey, (0, 0), self.smoothing)
        elif np.asarray(image).dtype == np.uint8:
            grey = np.asarray(image)
        contours = clean_contours(detect_contours(grey, self.k, self.window), self.min_component_size, self.closing)
        if not contours.any():
            raise ValueError("image has no contour (blank, constant or too smooth image)")
        topology = topology_features(contours, self.n_circles, self.step, mode=self.mode, min_gap=self.min_gap,
                                     crossings=self.crossings, polyline_smoothing=self.polyline_smoothing,
                                     band=self.band, spur_length=self.spur_length)
        return EarTemplate(topology.circles, topology)

    def enroll(self, subject_id: object, image: object) -> EarTemplate:
        """Add one reference image; raises ValueError when it has no contour."""
        if subject_id is None:
            raise ValueError("subject_id must not be None (None means rejection)")
        return self.enroll_template(subject_id, self.extract(image))

    def enroll_template(self, subject_id: object, template: EarTemplate) -> EarTemplate:
        """Add already extracted features (from :meth:`extract` with the same settings)."""
        if subject_id is None:
            raise ValueError("subject_id must not be None (None means rejection)")
        if not isinstance(template, EarTemplate):
            raise TypeError(f"template must be an EarTemplate, got {type(template).__name__}")
        if len(template.circles.counts) != self.n_circles:
            raise ValueError(f"template has {len(template.circles.counts)} circles, matcher expects {self.n_circles}")
        self._ids.append(subject_id)
        self._templates.append(template)
        self._counts = np.array([t.circles.counts for t in self._templates])
        self._sums = np.array([t.circles.distance_sums for t in self._templates])
        return template

    @property
    def n_enrolled(self) -> int:
        return len(self._ids)

    def identify(self, image: object, *, shortlist: int = 10) -> IdentificationResult:
        """Identify one query image (steps 1-9); a blank/constant image is rejected, not an error."""
        if not self._ids:
            raise ValueError("no subject enrolled: call enroll() first")
        as_grey_image(image)  # bad dtype/shape/NaN -> TypeError/ValueError
        try:
            query = self.extract(image)
        except ValueError as error:
            if "no contour" in str(error):
                return IdentificationResult(None, (), np.zeros(0), np.full(self.n_enrolled, np.inf), "no contour")
            raise
        return self.identify_template(query, shortlist=shortlist)

    def identify_template(self, query: EarTemplate, *, shortlist: int = 10) -> IdentificationResult:
        """Steps 2-9 on already extracted features."""
        shortlist = check_positive_int(shortlist, "shortlist")
        count_gap = np.abs(self._counts - query.circles.counts)
        violations = np.sum(count_gap > self.count_tolerance, axis=1)
        sum_gap = np.abs(self._sums - query.circles.distance_sums).mean(axis=1)
        scores = sum_gap + violations.astype(float)  # ranking for CMC: count violations cost 1 each
        gate = (violations <= self.max_count_violations) & (sum_gap < self.distance_threshold)
        candidates = np.flatnonzero(gate)
        if len(candidates) == 0:
            return IdentificationResult(None, (), np.zeros(0), scores, "no reference passed steps 2-4")
        candidates = candidates[np.argsort(sum_gap[candidates])][:shortlist]
        topo = np.array([topology_similarity(query.topology, self._templates[i].topology) for i in candidates])
        final = sum_gap[candidates] - self.topology_weight * topo
        order = np.argsort(final, kind="stable")
        candidates, final = candidates[order], final[order]
        scores = scores.copy()
        scores[candidates] = final - 10.0  # gated candidates rank ahead of all others
        return IdentificationResult(self._ids[candidates[0]], tuple(self._ids[i] for i in candidates), final, scores)


class HogNearestNeighbour:
    """Baseline: HOG (skimage.feature.hog, 9 orientations, 16x16 cells, 2x2 blocks) + 1-NN (L2)."""

    def __init__(self, pixels_per_cell: int = 16) -> None:
        self.pixels_per_cell = check_positive_int(pixels_per_cell, "pixels_per_cell", minimum=2)
        self._ids: list = []
        self._features: list = []

    def describe(self, image: object) -> np.ndarray:
        grey = as_grey_image(image)
        cell = (self.pixels_per_cell, self.pixels_per_cell)
        return hog(grey, orientations=9, pixels_per_cell=cell, cells_per_block=(2, 2), feature_vector=True)

    def enroll(self, subject_id: object, image: object) -> None:
        self._ids.append(subject_id)
        self._features.append(self.describe(image))
        self._matrix = np.array(self._features)

    def distances(self, image: object) -> np.ndarray:
        """L2 distance from the query's HOG to every enrolled HOG (lower is better)."""
        if not self._ids:
            raise ValueError("no subject enrolled: call enroll() first")
        return np.linalg.norm(self._matrix - self.describe(image), axis=1)

    def identify(self, image: object) -> object:
        return self._ids[int(np.argmin(self.distances(image)))]


@dataclass(frozen=True)
class OpenSetRates:
    """False accept / false reject / misidentification rates per distance threshold."""

    thresholds: np.ndarray
    false_accept: np.ndarray  # impostor queries (never enrolled) that were given an identity
    false_reject: np.ndarray  # genuine queries rejected
    misidentified: np.ndarray  # genuine queries accepted as the wrong subject


def open_set_rates(matcher: EarMatcher, genuine: list, genuine_ids: list, impostors: list,
                   thresholds: np.ndarray) -> OpenSetRates:
    """Sweep ``matcher.distance_threshold`` (step 4) over ``thresholds`` on extracted templates;
    the matcher's threshold is restored afterwards."""
    thresholds = np.asarray(thresholds, float)
    saved = matcher.distance_threshold
    far, frr, mis = [], [], []
    try:
        for threshold in thresholds:
            matcher.distance_threshold = float(threshold)
            g = [matcher.identify_template(t).subject_id for t in genuine]
            far.append(np.mean([matcher.identify_template(t).subject_id is not None for t in impostors]))
            frr.append(np.mean([s is None for s in g]))
            mis.append(np.mean([s is not None and s != truth for s, truth in zip(g, genuine_ids)]))
    finally:
        matcher.distance_threshold = saved
    return OpenSetRates(thresholds, np.array(far), np.array(frr), np.array(mis))


def rank_of_truth(scores: np.ndarray, enrolled_ids: np.ndarray, true_id: object) -> int:
    """1-based rank of the best-scoring template of ``true_id`` when templates are sorted by score."""
    scores = np.asarray(scores, float)
    best_true = scores[np.asarray(enrolled_ids) == true_id].min()
    return int(np.sum(scores < best_true) + 1)


def cumulative_match(ranks: np.ndarray, max_rank: int) -> np.ndarray:
    """CMC: fraction of queries whose true subject is within rank 1..max_rank."""
    ranks = np.asarray(ranks)
    return np.array([np.mean(ranks <= r) for r in range(1, check_positive_int(max_rank, "max_rank") + 1)])
