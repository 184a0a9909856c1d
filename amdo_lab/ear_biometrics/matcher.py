"""Classification (Sec. 5, steps 1-9) and two nearest-neighbour baselines (HOG, LBP histograms)."""

from __future__ import annotations

import numbers
from dataclasses import dataclass, field

import cv2
import numpy as np
from skimage.feature import hog, local_binary_pattern

from amdo_lab.common import (MAX_SIDE, as_finite_array, check_choice, check_fitted, check_in_range,
                             check_positive, check_positive_int)
from amdo_lab.ear_biometrics.features import (
    CROSSING_READINGS,
    NORMALISATION_MODES,
    CircleFeatures,
    Normalisation,
    TopologyFeatures,
    as_grey_image,
    clean_contours,
    detect_contours,
    topology_features,
)
from amdo_lab.ear_biometrics.frame import (
    CANONICAL_SPREAD,
    CanonicalFrame,
    check_frame_source,
    check_spread_fraction,
    frame_normalisation,
    moment_frame_fast,
    silhouette,
    to_canonical,
)


@dataclass(frozen=True)
class EarTemplate:
    """Both feature vectors of one image: V (eq. 7) and F (eq. 9).

    Parameters
    ----------
    circles : CircleFeatures
        V, eq. (7).
    topology : TopologyFeatures
        F, eq. (9).

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 4, eqs. (7) and (9); Sec. 5 (the stored F_ref and V_ref).
    """

    circles: CircleFeatures
    topology: TopologyFeatures


@dataclass(frozen=True)
class IdentificationResult:
    """Outcome of :meth:`EarMatcher.identify`.

    Parameters
    ----------
    subject_id : object
        The identified subject, or None for a rejection (step 5).
    candidate_ids : tuple
        Subjects of the enrolled templates that passed steps 2-4, best first (at most ``shortlist``).
    candidate_scores : numpy.ndarray, shape (n_candidates,)
        Their ranking scores, lower is better.
    scores : numpy.ndarray, shape (n_enrolled,)
        The ranking score of every enrolled template, lower is better (for CMC curves).
    reason : str
        Why the query was rejected ("" when it was not).

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 5, steps 1-9.
    """

    subject_id: object
    candidate_ids: tuple
    candidate_scores: np.ndarray
    scores: np.ndarray
    reason: str = ""


# Default of topology_similarity(coordinate_tolerance=...), also what EarMatcher ranks with.
_COORDINATE_TOLERANCE = 0.2


def topology_similarity(query: TopologyFeatures, reference: TopologyFeatures,
                        coordinate_tolerance: float = _COORDINATE_TOLERANCE) -> float:
    """Steps 7-9 read literally: the share of contours whose triple and points match.

    A contour counts as matched when its triple (N_E, N_B, N_I) equals that of an unused contour of
    the other image *and* its characteristic points lie within ``coordinate_tolerance`` (mean
    nearest-point distance) of that contour's. Greedy, outermost contour first (the paper's tracing
    order); the count is divided by the larger number of contours.

    Parameters
    ----------
    query : TopologyFeatures
        F of the query image.
    reference : TopologyFeatures
        F of an enrolled image.
    coordinate_tolerance : float
        Largest mean point distance of a match, normalised units, >= 0.

    Returns
    -------
    float
        Similarity in [0, 1]; 1 when every contour has a matching partner.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 5, steps 7-9, on F of eq. (9).
    """
    for features, name in ((query, "query"), (reference, "reference")):
        if not isinstance(features, TopologyFeatures):
            raise TypeError(f"{name} must be TopologyFeatures (from topology_features), got {type(features).__name__}")
    tolerance = check_positive(coordinate_tolerance, "coordinate_tolerance", allow_zero=True)
    return _topology_similarity(query, reference, tolerance)


def _topology_similarity(query: TopologyFeatures, reference: TopologyFeatures, coordinate_tolerance: float) -> float:
    """:func:`topology_similarity` on validated input (called for every shortlisted candidate)."""
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


POINT_DISTANCE_CAP = 0.5
"""Largest distance (normalised units) one characteristic point can add to :func:`point_distance`:
a point with no partner nearby (a contour break, a spur) costs at most this much."""

RANKINGS = ("points", "triples")
#: Most LBP neighbours :class:`LbpNearestNeighbour` samples on its circle.
MAX_LBP_POINTS = 32


def characteristic_points(features: TopologyFeatures) -> np.ndarray:
    """All characteristic points of F (eq. 9) as one array.

    Parameters
    ----------
    features : TopologyFeatures
        F of one image.

    Returns
    -------
    numpy.ndarray, shape (n, 2)
        Endings, bifurcations and circle crossings of every contour, normalised (x, y).

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 4, eq. (9).
    """
    if not isinstance(features, TopologyFeatures):
        raise TypeError(f"features must be TopologyFeatures (from topology_features), got {type(features).__name__}")
    return _points(features)


def _points(features: TopologyFeatures) -> np.ndarray:
    parts = [c.points for c in features.contours]
    return np.vstack(parts) if parts else np.zeros((0, 2))


def point_distance(query: TopologyFeatures, reference: TopologyFeatures, cap: float = POINT_DISTANCE_CAP) -> float:
    """Steps 8-9 read as a distance: do the stored points of F lie at the same coordinates?

    Plain-numpy reference: for every characteristic point (eq. 9) of one image, the distance to
    the nearest one of the other image, capped at ``cap``; the mean over the query's points and the
    mean over the reference's points are averaged (symmetric, a chamfer distance). Unlike steps 7-8
    read literally (the triples (N_E, N_B, N_I) must match exactly before coordinates are compared),
    one extra or missing point changes the distance by at most ``cap`` / n.

    Parameters
    ----------
    query : TopologyFeatures
        F of the query image.
    reference : TopologyFeatures
        F of an enrolled image.
    cap : float
        Largest distance one point can add, normalised units, > 0.

    Returns
    -------
    float
        Distance in [0, ``cap``]: 0 for the same points, ``cap`` when one image has no point.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 5, steps 8-9, on the points of eq. (9).
    """
    for features, name in ((query, "query"), (reference, "reference")):
        if not isinstance(features, TopologyFeatures):
            raise TypeError(f"{name} must be TopologyFeatures (from topology_features), got {type(features).__name__}")
    cap = check_positive(cap, "cap")
    a, b = _points(query), _points(reference)
    if len(a) == 0 or len(b) == 0:
        return cap
    gaps = np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2)  # (n_query, n_reference)
    return 0.5 * (np.minimum(gaps.min(axis=1), cap).mean() + np.minimum(gaps.min(axis=0), cap).mean())


def _point_distances(query: np.ndarray, stacked: np.ndarray, starts: np.ndarray, cap: float) -> np.ndarray:
    """:func:`point_distance` from one query's points to every enrolled template at once.

    ``stacked`` holds the points of all templates one after the other, template t from row
    ``starts[t]`` (every template has at least one point); the per-template minima and means are
    segment reductions (``np.minimum.reduceat`` / ``np.add.reduceat``) over the same gap matrix."""
    n_templates = len(starts)
    if len(query) == 0:
        return np.full(n_templates, cap)
    # squared gaps: the square root is monotone, so it is taken after the minima (fewer roots)
    squared = ((query[:, None, :] - stacked[None, :, :]) ** 2).sum(axis=2)
    counts = np.diff(np.r_[starts, len(stacked)])
    nearest_to_query = np.sqrt(np.minimum.reduceat(squared, starts, axis=1))  # (n_query, n_templates)
    query_side = np.minimum(nearest_to_query, cap).mean(axis=0)
    reference_side = np.add.reduceat(np.minimum(np.sqrt(squared.min(axis=0)), cap), starts) / counts
    return 0.5 * (query_side + reference_side)


@dataclass
class EarMatcher:
    """Choraś's classifier (Sec. 5): features of enrolled images, identification of a query.

    Steps: (2-3) a reference is a candidate when |l_r - l_r,ref| <= ``count_tolerance`` on every
    radius, except at most ``max_count_violations`` radii (0 = the paper's rule); (4) its mean
    absolute difference of the distance sums must be below ``distance_threshold``; (5) no candidate
    -> rejection (``subject_id=None``); (6-9) candidates are ranked (``ranking``). Pixel settings are
    for 256 x 256 images (the database default); they were chosen on development seeds, not on the
    notebook's data. The decision (``subject_id``) is the best-ranked template among those that pass
    steps 2-4.

    Invariance (beyond the paper's text): with a canonical frame (``frame``) the image is resampled
    into the frame of its silhouette (:func:`~amdo_lab.ear_biometrics.frame.moment_frame`) *before*
    step 1, so a rotated, rescaled or shifted copy is detected at the same place, orientation and
    size; the ``smoothing`` blur then makes detection indifferent to the copy's extra resampling.
    Both need the whole ear inside the image: an ear cut by the image border has a different
    silhouette in every copy, hence a different frame.

    Parameters
    ----------
    k : float
        Sensitivity of the contour detector, eq. (4), >= 0 (12 with the default smoothing: the blur
        lowers the local contrast sigma / mu, so the detector is made more sensitive; the paper's
        figures use 6-10 on unblurred images).
    window : int
        Window side of eqs. (1)-(3), odd, >= 3.
    smoothing : float
        Gaussian blur before contour detection, sigma in pixels, >= 0 (0 follows the paper) and at
        most the image's larger side (checked when an image is processed). The default 1.5 makes
        the contours indifferent to one more interpolation of the image: a rotated or rescaled copy
        has been resampled once more than the original, which blurs it by about 0.4 pixel and drops
        weak contour pixels; after a 1.5-pixel blur that extra blur hardly changes the image.
    n_circles : int
        Number of circles N_r of eq. (7), >= 1.
    step : float
        Radius step between circles, normalised units, > 0.
    min_component_size : int
        Contour fragments with fewer pixels are dropped (:func:`clean_contours`), >= 1.
    closing : int
        Half-width of the closing square of :func:`clean_contours`, pixels, >= 0.
    count_tolerance : int
        Steps 2-3: allowed |l_r - l_r,ref| per radius, >= 0 (the paper's 1).
    max_count_violations : int
        Radii that may break the count rule, >= 0 (0 = the paper's rule).
    distance_threshold : float
        Step 4: largest mean |sum d - sum d_ref|, >= 0, or inf for no threshold.
    topology_weight : float
        ``ranking="triples"``: candidates are ordered by their distance-sum gap minus this weight
        times :func:`topology_similarity`; >= 0.
    mode : {"principal", "axes", "isotropic"}
        Reading of eq. (6) (see :func:`normalise_coordinates`).
    min_gap_px : float
        ``crossings="pixels"``: runs of contour pixels closer than this arc length, pixels, are one
        crossing; >= 0 (0 is the literal count).
    crossings : {"polyline", "pixels"}
        Reading of "the contour crosses a circle" (see :func:`circle_features`).
    polyline_smoothing : int
        ``crossings="polyline"``: smoothing rounds of the thinned contours, >= 0.
    band_px : float
        ``crossings="polyline"``: dead band around each circle, pixels, >= 0.
    spur_length_px : int
        ``crossings="polyline"``: skeleton spurs shorter than this, pixels, are pruned, >= 0.
    frame : {"silhouette", "contours", "image"}
        Where the canonical frame comes from: the silhouette's moments, the contour pixels detected in
        the given image, or none (the image as given, the paper's pipeline).
    canonical_spread : float
        Spread of the silhouette in the canonical image, fraction of the side, in (0, 0.5).
    origin : {"frame", "contours"}
        With a canonical frame: eq. (6)'s centroid and spreads from the silhouette's moments
        (``"frame"``) or from the contour pixels (eq. 6 as printed, in the reading ``mode``).
    ranking : {"points", "triples"}
        Steps 6-9: :func:`point_distance` between the characteristic points of F (``"points"``), or
        the literal exact triples then coordinates (:func:`topology_similarity`), combined with the
        distance-sum gap (``"triples"``).

    Attributes
    ----------
    subject_ids_ : list or None
        Subject of each enrolled template, in enrolment order (None before :meth:`fit` or
        :meth:`enroll`).
    templates_ : list of EarTemplate or None
        The enrolled features V and F.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 2 (eqs. 1-5), Sec. 3 (eq. 6), Sec. 4 (eqs. 7-9) and Sec. 5 (steps 1-9).

    Examples
    --------
    Enrol the perpendicular capture of three subjects and identify the 30-degree capture of the
    first one.

    >>> from amdo_lab import ear_biometrics as eb
    >>> images, ids = eb.generate_ear_database(3, 2, "easy", rng=1)
    >>> matcher = eb.EarMatcher()
    >>> for subject, image in zip(ids[0::2], images[0::2]):
    ...     _ = matcher.enroll(subject, image)
    >>> int(matcher.identify(images[1]).subject_id)
    0
    """

    k: float = 12.0
    window: int = 3
    smoothing: float = 1.5
    n_circles: int = 8
    step: float = 0.25
    min_component_size: int = 40
    closing: int = 2
    count_tolerance: int = 1
    max_count_violations: int = 0
    distance_threshold: float = np.inf
    topology_weight: float = 1.0
    mode: str = "principal"
    min_gap_px: float = 6.0
    crossings: str = "polyline"
    polyline_smoothing: int = 4
    band_px: float = 6.0
    spur_length_px: int = 8
    frame: str = "silhouette"
    canonical_spread: float = CANONICAL_SPREAD
    origin: str = "frame"
    ranking: str = "points"
    # learned from the enrolled images (scikit-learn's trailing underscore); None until the first one
    subject_ids_: list | None = field(default=None, init=False, repr=False)
    templates_: list | None = field(default=None, init=False, repr=False)

    def __post_init__(self) -> None:
        # Checked once here, under the matcher's own names; several settings (the step 2-4 rule and
        # the ranking weight) are not used by any function that would check them later.
        check_positive(self.k, "k", allow_zero=True)
        if check_positive_int(self.window, "window", minimum=3) % 2 == 0:
            raise ValueError(f"window must be odd, got {self.window}")
        check_positive(self.smoothing, "smoothing", allow_zero=True)
        check_positive_int(self.n_circles, "n_circles")
        check_positive(self.step, "step")
        check_positive_int(self.min_component_size, "min_component_size")
        check_positive_int(self.closing, "closing", minimum=0)
        check_positive_int(self.count_tolerance, "count_tolerance", minimum=0)
        check_positive_int(self.max_count_violations, "max_count_violations", minimum=0)
        _check_distance_threshold(self.distance_threshold, "distance_threshold")
        check_positive(self.topology_weight, "topology_weight", allow_zero=True)
        check_choice(self.mode, "mode", NORMALISATION_MODES)
        check_positive(self.min_gap_px, "min_gap_px", allow_zero=True)
        check_choice(self.crossings, "crossings", CROSSING_READINGS)
        check_positive_int(self.polyline_smoothing, "polyline_smoothing", minimum=0)
        check_positive(self.band_px, "band_px", allow_zero=True)
        check_positive_int(self.spur_length_px, "spur_length_px", minimum=0)
        check_frame_source(self.frame, "frame")
        check_spread_fraction(self.canonical_spread, "canonical_spread")
        check_choice(self.origin, "origin", ("frame", "contours"))
        check_choice(self.ranking, "ranking", RANKINGS)

    def canonical_frame(self, image: object) -> CanonicalFrame | None:
        """The similarity that brings ``image`` into its canonical frame.

        Parameters
        ----------
        image : array_like, shape (rows, cols)
            Grey levels (8-bit or float).

        Returns
        -------
        CanonicalFrame or None
            From the silhouette's or the cleaned contours' moments (``frame``); None for
            ``frame="image"``.
        """
        grey = as_grey_image(image)
        return None if self.frame == "image" else self._frame_of(self._input(image, grey))

    def _frame_of(self, work: np.ndarray) -> CanonicalFrame:
        """:meth:`canonical_frame` of validated input (8-bit or float)."""
        mask = silhouette(work) if self.frame == "silhouette" else self._contours(work)
        if np.count_nonzero(mask) < 3:
            raise ValueError("image has no contour (blank, constant or too smooth image): no ear silhouette")
        return moment_frame_fast(mask, work.shape, self.canonical_spread)

    def _input(self, image: object, grey: np.ndarray) -> np.ndarray:
        """8-bit input keeps the detector's fast uint8 path; anything else is used as float."""
        return np.asarray(image) if np.asarray(image).dtype == np.uint8 else grey

    def _contours(self, image: np.ndarray) -> np.ndarray:
        """Step 1: optional smoothing, contours (eqs. 1-5) and the clean-up."""
        if self.smoothing > 0:  # image normalisation step before contour detection (Fig. 3)
            check_in_range(self.smoothing, "smoothing", 0, max(image.shape), closed="right")  # a wider blur is flat
            image = cv2.GaussianBlur(np.asarray(image, float), (0, 0), self.smoothing)
        contours = clean_contours(detect_contours(image, self.k, self.window), self.min_component_size, self.closing)
        if not contours.any():
            raise ValueError("image has no contour (blank, constant or too smooth image)")
        return contours

    def canonical_image(self, image: object) -> np.ndarray:
        """The image that step 1 sees: resampled into the canonical frame, or as given for ``frame="image"``.

        Parameters
        ----------
        image : array_like, shape (rows, cols)
            Grey levels (8-bit or float).

        Returns
        -------
        numpy.ndarray, shape (rows, cols)
            The canonical image (8-bit input stays 8-bit).
        """
        return self._prepare(image)[0]

    def contour_image(self, image: object) -> np.ndarray:
        """Step 1 as the matcher runs it: the cleaned contours that V and F are computed from.

        Parameters
        ----------
        image : array_like, shape (rows, cols)
            Grey levels (8-bit or float).

        Returns
        -------
        numpy.ndarray, shape (rows, cols), bool
            The cleaned contours, in the canonical image unless ``frame="image"``.
        """
        return self._contours(self._prepare(image)[0])

    def _prepare(self, image: object) -> tuple[np.ndarray, Normalisation | None]:
        """Validated input, in the canonical frame when asked, and the frame's eq. 6 (or None)."""
        grey = as_grey_image(image)  # validates
        work, normalisation = self._input(image, grey), None
        if self.frame != "image":
            frame = self._frame_of(work)
            work = to_canonical(work, frame)
            if self.origin == "frame":
                normalisation = frame_normalisation(frame, grey.shape, self.mode, self.canonical_spread)
        return work, normalisation

    def extract(self, image: object) -> EarTemplate:
        """Features of one image: canonical frame, contours (eqs. 1-5), clean-up, V and F.

        Parameters
        ----------
        image : array_like, shape (rows, cols)
            Grey levels (8-bit or float) holding an ear.

        Returns
        -------
        EarTemplate
            V (eq. 7) and F (eq. 9).
        """
        work, normalisation = self._prepare(image)
        topology = topology_features(self._contours(work), self.n_circles, self.step, mode=self.mode,
                                     min_gap_px=self.min_gap_px, crossings=self.crossings,
                                     polyline_smoothing=self.polyline_smoothing, band_px=self.band_px,
                                     spur_length_px=self.spur_length_px, normalisation=normalisation)
        return EarTemplate(topology.circles, topology)

    def enroll(self, subject_id: object, image: object) -> EarTemplate:
        """Add one reference image of ``subject_id``.

        Parameters
        ----------
        subject_id : object
            The subject's id: a str or a real number within +-2**53 (not None, which means rejection, nor a bool).
        image : array_like, shape (rows, cols)
            Grey levels holding the subject's ear; an image without contours raises ValueError.

        Returns
        -------
        EarTemplate
            The enrolled features.
        """
        check_subject_id(subject_id, "subject_id")
        return self.enroll_template(subject_id, self.extract(image))

    def enroll_template(self, subject_id: object, template: EarTemplate) -> EarTemplate:
        """Add already extracted features (from :meth:`extract` with the same settings).

        Parameters
        ----------
        subject_id : object
            The subject's id: a str or a real number within +-2**53 (not None nor a bool).
        template : EarTemplate
            Features with ``n_circles`` circles.

        Returns
        -------
        EarTemplate
            ``template``, now enrolled.
        """
        check_subject_id(subject_id, "subject_id")
        if not isinstance(template, EarTemplate):
            raise TypeError(f"template must be an EarTemplate, got {type(template).__name__}")
        if len(template.circles.counts) != self.n_circles:
            raise ValueError(f"template has {len(template.circles.counts)} circles, matcher expects {self.n_circles}")
        if self.templates_ is None:
            self.subject_ids_, self.templates_ = [], []
        self.subject_ids_.append(subject_id)
        self.templates_.append(template)
        # caches of the enrolled features for steps 2-9, stacked once per enrolment
        self._counts = np.array([t.circles.counts for t in self.templates_])
        self._sums = np.array([t.circles.distance_sums for t in self.templates_])
        points = [_points(t.topology) for t in self.templates_]
        # a template without points gets one far away (at distance >= cap from everything)
        points = [p if len(p) else np.full((1, 2), 1e6) for p in points]
        self._points = np.vstack(points)
        self._point_starts = np.cumsum([0] + [len(p) for p in points[:-1]])
        return template

    @property
    def n_enrolled(self) -> int:
        """Number of enrolled templates (0 before the first enrolment)."""
        return 0 if self.templates_ is None else len(self.templates_)

    def fit(self, images: object, subject_ids: object) -> EarMatcher:
        """Enrol one reference image per subject id, forgetting any earlier enrolment.

        Parameters
        ----------
        images : sequence of array_like
            Grey-level images (8-bit or float), each holding an ear.
        subject_ids : sequence
            The subject of each image (ids as for :meth:`enroll`), as many as ``images``.

        Returns
        -------
        EarMatcher
            ``self``, with ``subject_ids_`` and ``templates_`` learned.
        """
        check_images(images)
        if len(check_subject_ids(subject_ids, "subject_ids")) != len(images):
            raise ValueError(f"subject_ids must give one subject per image ({len(images)}), got {len(subject_ids)}")
        self.subject_ids_, self.templates_ = None, None
        for index, (subject_id, image) in enumerate(zip(subject_ids, images)):
            try:
                self.enroll(subject_id, image)
            except ValueError as error:  # name the image at fault (its features could not be extracted)
                raise ValueError(f"images[{index}]: {error}") from error
        return self

    def identify(self, image: object, *, shortlist: int = 10) -> IdentificationResult:
        """Identify one query image (steps 1-9); a blank or constant image is rejected, not an error.

        Parameters
        ----------
        image : array_like, shape (rows, cols)
            Grey levels of the query.
        shortlist : int
            Largest number of candidates kept and ranked, >= 1.

        Returns
        -------
        IdentificationResult
            The decision, the candidates and every enrolled template's score.
        """
        check_fitted(self, "templates_")  # NotFittedError (a ValueError) before any enrolment
        as_grey_image(image)  # bad dtype/shape/NaN -> TypeError/ValueError
        try:
            query = self.extract(image)
        except ValueError as error:
            if "no contour" in str(error):
                return IdentificationResult(None, (), np.zeros(0), np.full(self.n_enrolled, np.inf), "no contour")
            raise
        return self.identify_template(query, shortlist=shortlist)

    def identify_template(self, query: EarTemplate, *, shortlist: int = 10) -> IdentificationResult:
        """Steps 2-9 on already extracted features.

        Parameters
        ----------
        query : EarTemplate
            The query's features (from :meth:`extract` with the same settings).
        shortlist : int
            Largest number of candidates kept and ranked, >= 1.

        Returns
        -------
        IdentificationResult
            The decision, the candidates and every enrolled template's score.
        """
        shortlist = check_positive_int(shortlist, "shortlist")
        check_fitted(self, "templates_")
        if not isinstance(query, EarTemplate):
            raise TypeError(f"query must be an EarTemplate, got {type(query).__name__}")
        if len(query.circles.counts) != self.n_circles:
            raise ValueError(f"query has {len(query.circles.counts)} circles, matcher expects {self.n_circles}")
        count_gap = np.abs(self._counts - query.circles.counts)
        violations = np.sum(count_gap > self.count_tolerance, axis=1)
        sum_gap = np.abs(self._sums - query.circles.distance_sums).mean(axis=1)
        scores = sum_gap + violations.astype(float)  # ranking for CMC: count violations cost 1 each
        gate = (violations <= self.max_count_violations) & (sum_gap < self.distance_threshold)
        if self.ranking == "points":  # steps 6-9 as a distance between the points of F
            scores = _point_distances(_points(query.topology), self._points, self._point_starts, POINT_DISTANCE_CAP)
        candidates = np.flatnonzero(gate)
        if len(candidates) == 0:
            return IdentificationResult(None, (), np.zeros(0), scores, "no reference passed steps 2-4")
        if self.ranking == "points":
            candidates = candidates[np.argsort(scores[candidates], kind="stable")][:shortlist]
            return IdentificationResult(self.subject_ids_[candidates[0]], tuple(self.subject_ids_[i] for i in candidates),
                                        scores[candidates], scores)
        candidates = candidates[np.argsort(sum_gap[candidates])][:shortlist]
        topo = np.array([_topology_similarity(query.topology, self.templates_[i].topology, _COORDINATE_TOLERANCE)
                         for i in candidates])
        final = sum_gap[candidates] - self.topology_weight * topo
        order = np.argsort(final, kind="stable")
        candidates, final = candidates[order], final[order]
        scores = scores.copy()
        scores[candidates] = final - 10.0  # gated candidates rank ahead of all others
        return IdentificationResult(self.subject_ids_[candidates[0]], tuple(self.subject_ids_[i] for i in candidates), final, scores)


class HogNearestNeighbour:
    """Baseline: HOG descriptors (9 orientations, square cells, 2x2 blocks) and 1-nearest neighbour (L2).

    Parameters
    ----------
    pixels_per_cell : int
        Side of a HOG cell, pixels, >= 2 (checked when a descriptor is computed).

    Attributes
    ----------
    subject_ids_ : list or None
        Subject of each enrolled image (None before :meth:`fit` or :meth:`enroll`).
    descriptors_ : numpy.ndarray or None
        The enrolled HOG descriptors, shape (n_enrolled, n_features).
    image_shape_ : tuple or None
        Shape of the enrolled images (queries must have it).

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 6 (the task; this baseline is ours).
    N. Dalal, B. Triggs, "Histograms of Oriented Gradients for Human Detection", CVPR 2005.
    """

    def __init__(self, pixels_per_cell: int = 16) -> None:
        self.pixels_per_cell = pixels_per_cell  # stored as given, checked where it is used (describe)
        self.subject_ids_: list | None = None  # learned: None until the first enrolment
        self.descriptors_: np.ndarray | None = None  # (n_enrolled, n_features)
        self.image_shape_: tuple | None = None

    def describe(self, image: object) -> np.ndarray:
        """The HOG descriptor of one image.

        Parameters
        ----------
        image : array_like, shape (rows, cols)
            Grey levels.

        Returns
        -------
        numpy.ndarray, shape (n_features,)
            The descriptor (its length depends on the image size).
        """
        grey = as_grey_image(image)
        cell = (check_positive_int(self.pixels_per_cell, "pixels_per_cell", minimum=2),) * 2
        return hog(grey, orientations=9, pixels_per_cell=cell, cells_per_block=(2, 2), feature_vector=True)

    def _check_size(self, image: object) -> None:
        """Descriptors are only comparable between images of one size (the HOG grid depends on it)."""
        if self.image_shape_ is not None and np.shape(image) != self.image_shape_:
            raise ValueError(f"image must have the enrolled images' shape {self.image_shape_}, got {np.shape(image)}")

    def enroll(self, subject_id: object, image: object) -> None:
        """Add one reference image of ``subject_id``.

        Parameters
        ----------
        subject_id : object
            The subject's id: a str or a real number within +-2**53 (not None nor a bool).
        image : array_like, shape (rows, cols)
            Grey levels, of the shape of the images enrolled before.
        """
        check_subject_id(subject_id, "subject_id")
        self._check_size(image)
        descriptor = self.describe(image)[None]
        if self.descriptors_ is None:
            self.subject_ids_, self.descriptors_ = [], np.zeros((0, descriptor.shape[1]))
        self.descriptors_ = np.vstack([self.descriptors_, descriptor])
        self.subject_ids_.append(subject_id)
        self.image_shape_ = np.shape(image)

    def fit(self, images: object, subject_ids: object) -> HogNearestNeighbour:
        """Enrol one reference image per subject id, forgetting any earlier enrolment.

        Parameters
        ----------
        images : sequence of array_like
            Grey-level images, all of one shape.
        subject_ids : sequence
            The subject of each image (str or finite real ids), as many as ``images``.

        Returns
        -------
        HogNearestNeighbour
            ``self``, with ``subject_ids_``, ``descriptors_`` and ``image_shape_`` learned.
        """
        check_images(images)
        if len(check_subject_ids(subject_ids, "subject_ids")) != len(images):
            raise ValueError(f"subject_ids must give one subject per image ({len(images)}), got {len(subject_ids)}")
        self.subject_ids_, self.descriptors_, self.image_shape_ = None, None, None
        for index, (subject_id, image) in enumerate(zip(subject_ids, images)):
            try:
                self.enroll(subject_id, image)
            except ValueError as error:  # name the image at fault (its features could not be extracted)
                raise ValueError(f"images[{index}]: {error}") from error
        return self

    def distances(self, image: object) -> np.ndarray:
        """L2 distance from the query's HOG to every enrolled HOG (lower is better).

        Parameters
        ----------
        image : array_like, shape (rows, cols)
            Grey levels, of the enrolled images' shape.

        Returns
        -------
        numpy.ndarray, shape (n_enrolled,)
            The distances, in enrolment order.
        """
        check_fitted(self, "descriptors_")  # NotFittedError (a ValueError) before any enrolment
        self._check_size(image)
        return np.linalg.norm(self.descriptors_ - self.describe(image), axis=1)

    def identify(self, image: object) -> object:
        """The subject of the nearest enrolled descriptor.

        Parameters
        ----------
        image : array_like, shape (rows, cols)
            Grey levels, of the enrolled images' shape.

        Returns
        -------
        object
            The subject id of the nearest enrolled image.
        """
        return self.subject_ids_[int(np.argmin(self.distances(image)))]


class LbpNearestNeighbour(HogNearestNeighbour):
    """Baseline: histograms of uniform local binary patterns on a grid of cells, and 1-nearest neighbour (L2).

    The image is blurred (Gaussian, ``blur_sigma`` pixels) and rounded to 8 bits, each pixel coded by
    the uniform LBP of its ``n_points`` neighbours at ``radius`` pixels (``n_points + 2`` codes), and
    the image cut into ``cells_per_side`` x ``cells_per_side`` cells; the descriptor is the
    concatenation of the cells' normalised code histograms. The defaults were chosen on a development
    database (seed 77, 60 easy subjects, in the canonical frame), not on the chapter's images: without
    the blur the codes follow the sensor noise.

    Parameters
    ----------
    cells_per_side : int
        Cells along each image side, >= 1 (checked when a descriptor is computed; each cell must hold
        at least one pixel).
    radius : int
        Radius of the LBP neighbourhood, pixels, from 1 to ``MAX_SIDE``.
    n_points : int
        Neighbours sampled on the circle, from 4 to :data:`MAX_LBP_POINTS` (uniform codes of more
        neighbours than that are too rare to fill a histogram).
    blur_sigma : float
        Standard deviation of the Gaussian blur before coding, pixels, >= 0 (0: none).

    Attributes
    ----------
    subject_ids_, descriptors_, image_shape_
        As in :class:`HogNearestNeighbour`.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 6 (the task; this baseline is ours).
    T. Ojala, M. Pietikäinen, T. Mäenpää, "Multiresolution Gray-Scale and Rotation Invariant Texture
    Classification with Local Binary Patterns", IEEE TPAMI 24(7), 2002.
    """

    def __init__(self, cells_per_side: int = 8, radius: int = 1, n_points: int = 8, blur_sigma: float = 3.0) -> None:
        super().__init__()
        self.cells_per_side = cells_per_side  # stored as given, checked where they are used (describe)
        self.radius = radius
        self.n_points = n_points
        self.blur_sigma = blur_sigma

    def describe(self, image: object) -> np.ndarray:
        """The concatenated LBP histograms of one image.

        Parameters
        ----------
        image : array_like, shape (rows, cols)
            Grey levels.

        Returns
        -------
        numpy.ndarray, shape (cells_per_side**2 * (n_points + 2),)
            The descriptor; each cell's histogram sums to 1.
        """
        grey = np.asarray(as_grey_image(image), float)
        cells = check_positive_int(self.cells_per_side, "cells_per_side", minimum=1)
        check_in_range(cells, "cells_per_side", 1, min(grey.shape))
        radius = check_positive_int(self.radius, "radius", minimum=1, maximum=MAX_SIDE)
        n_points = check_positive_int(self.n_points, "n_points", minimum=4, maximum=MAX_LBP_POINTS)
        sigma = check_positive(self.blur_sigma, "blur_sigma", allow_zero=True)
        check_in_range(sigma, "blur_sigma", 0, max(grey.shape))
        if sigma > 0:
            grey = cv2.GaussianBlur(grey, (0, 0), sigma)
        codes = local_binary_pattern(np.clip(np.round(grey), 0, 255).astype(np.uint8), n_points, radius, "uniform")
        row_edges = np.linspace(0, grey.shape[0], cells + 1).astype(int)
        col_edges = np.linspace(0, grey.shape[1], cells + 1).astype(int)
        histograms = []
        for top, bottom in zip(row_edges[:-1], row_edges[1:]):
            for left, right in zip(col_edges[:-1], col_edges[1:]):
                counts = np.bincount(codes[top:bottom, left:right].astype(int).ravel(), minlength=n_points + 2)
                histograms.append(counts / counts.sum())
        return np.concatenate(histograms)


@dataclass(frozen=True)
class OpenSetRates:
    """False accept, false reject and misidentification rates per distance threshold.

    Parameters
    ----------
    thresholds : numpy.ndarray, shape (n,)
        The step-4 thresholds swept.
    false_accept : numpy.ndarray, shape (n,)
        Share of impostor queries (never enrolled) that were given an identity.
    false_reject : numpy.ndarray, shape (n,)
        Share of genuine queries rejected.
    misidentified : numpy.ndarray, shape (n,)
        Share of genuine queries accepted as the wrong subject.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 5, steps 4-5 (the threshold and the rejection).
    """

    thresholds: np.ndarray
    false_accept: np.ndarray  # impostor queries (never enrolled) that were given an identity
    false_reject: np.ndarray  # genuine queries rejected
    misidentified: np.ndarray  # genuine queries accepted as the wrong subject


def open_set_rates(matcher: EarMatcher, genuine: list, genuine_ids: list, impostors: list,
                   thresholds: np.ndarray) -> OpenSetRates:
    """Sweep the matcher's step-4 threshold over ``thresholds`` on extracted templates.

    The matcher's ``distance_threshold`` is restored afterwards.

    Parameters
    ----------
    matcher : EarMatcher
        A matcher with enrolled subjects.
    genuine : list of EarTemplate
        Non-empty: templates of enrolled subjects.
    genuine_ids : sequence
        The subject of each genuine template (str or finite real ids).
    impostors : list of EarTemplate
        Non-empty: templates of subjects never enrolled.
    thresholds : sequence of float
        Non-empty, 1-D: thresholds >= 0 (``inf``: no threshold).

    Returns
    -------
    OpenSetRates
        The three rates per threshold.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 5, steps 4-5.
    """
    if not isinstance(matcher, EarMatcher):
        raise TypeError(f"matcher must be an EarMatcher, got {type(matcher).__name__}")
    check_fitted(matcher, "templates_")
    for templates, name in ((genuine, "genuine"), (impostors, "impostors")):
        check_templates(templates, name)
    if len(check_subject_ids(genuine_ids, "genuine_ids")) != len(genuine):
        raise ValueError(f"genuine_ids must give one subject per genuine template ({len(genuine)}), "
                         f"got {len(genuine_ids)}")
    values = np.asarray(thresholds, dtype=object)
    if values.ndim != 1 or values.size == 0:
        raise ValueError(f"thresholds must be a non-empty 1-D sequence, got shape {values.shape}")
    thresholds = np.array([_check_distance_threshold(t, "thresholds") for t in values.tolist()])
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
    """1-based rank of the best-scoring template of ``true_id`` when templates are sorted by score.

    Parameters
    ----------
    scores : array_like, shape (n,)
        Finite scores, lower is better (a NaN would compare as neither better nor worse).
    enrolled_ids : array_like, shape (n,)
        The subject of each template (str or finite real ids); must include ``true_id``.
    true_id : object
        The query's true subject: a str or a real number within +-2**53 (not None nor a bool).

    Returns
    -------
    int
        1 + the number of templates scoring strictly better than the true subject's best.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 6 (the identification rates; ranks are our measure of the ranking of steps 6-9).
    """
    scores = as_finite_array(scores, "scores", ndim=1)
    enrolled_ids = check_subject_ids(enrolled_ids, "enrolled_ids")
    check_subject_id(true_id, "true_id")
    if enrolled_ids.shape != scores.shape:
        raise ValueError(f"enrolled_ids must have one subject per score (scores has shape {scores.shape}), "
                         f"got {enrolled_ids.shape}")
    own = enrolled_ids == true_id
    if not np.any(own):
        raise ValueError(f"true_id {true_id!r} is not among enrolled_ids")
    best_true = scores[own].min()
    return int(np.sum(scores < best_true) + 1)


def cumulative_match(ranks: np.ndarray, max_rank: int) -> np.ndarray:
    """Cumulative match characteristic: share of queries whose true subject is within rank 1..max_rank.

    Parameters
    ----------
    ranks : array_like, shape (n,), int
        1-based ranks of the true subject (from :func:`rank_of_truth`), not empty.
    max_rank : int
        Largest rank, >= 1.

    Returns
    -------
    numpy.ndarray, shape (max_rank,)
        Entry r - 1 is the share of queries with rank <= r.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 6 (identification rates; the CMC curve is our addition).
    """
    ranks = as_finite_array(ranks, "ranks", ndim=1, dtype=int)
    if np.any(ranks < 1):
        raise ValueError(f"ranks must be 1-based (>= 1), got minimum {ranks.min()}")
    return np.array([np.mean(ranks <= r) for r in range(1, check_positive_int(max_rank, "max_rank") + 1)])


def _check_distance_threshold(value: object, name: str) -> float:
    """A step-4 threshold: a non-negative number (0 accepts nothing), or ``inf`` for no threshold
    (the matcher's default)."""
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        if value == np.inf:
            return float(value)
        if np.isnan(value) or value == -np.inf:
            raise ValueError(f"{name} must be a non-negative number or inf (no threshold), got {value}")
    return check_positive(value, name, allow_zero=True)


def check_templates(templates: object, name: str) -> None:
    """Refuse anything but a non-empty list of :class:`EarTemplate` (features, not images).

    Parameters
    ----------
    templates : object
        The argument to check.
    name : str
        The argument's name in error messages.

    Raises
    ------
    ValueError
        Not a sized sequence, or empty.
    TypeError
        An element is not an :class:`EarTemplate`.
    """
    if isinstance(templates, (str, np.ndarray)) or not hasattr(templates, "__len__") or not len(templates):
        raise ValueError(f"{name} must be a non-empty list of EarTemplate")
    wrong = [type(t).__name__ for t in templates if not isinstance(t, EarTemplate)]
    if wrong:
        raise TypeError(f"{name} must hold EarTemplate objects (from EarMatcher.extract), got {wrong[0]}")


MAX_NUMERIC_ID = 2.0**53
"""Largest magnitude of a numeric subject id: every integer up to it is exact in float64, so two
different ids never compare equal after a conversion to float."""


def check_subject_id(value: object, name: str) -> object:
    """Check one subject id: a str or a real number within +-2**53; None (rejection), booleans and NaN are refused.

    Parameters
    ----------
    value : object
        The id to check.
    name : str
        The argument's name in error messages.

    Returns
    -------
    object
        ``value``, unchanged.
    """
    if value is None:
        raise ValueError(f"{name} must not be None (None means rejection)")
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (str, numbers.Real)):
        raise TypeError(f"{name} must be a str or a real number, got {type(value).__name__}")
    if isinstance(value, numbers.Real) and not np.isfinite(value):
        raise ValueError(f"{name} must be finite, got {value}")
    if isinstance(value, numbers.Real) and abs(value) > MAX_NUMERIC_ID:
        raise ValueError(f"{name} must be at most 2**53 in magnitude (beyond, distinct ids share one float), got {value}")
    return value


def check_subject_ids(values: object, name: str) -> np.ndarray:
    """Check a 1-D sequence of subject ids (each as in :func:`check_subject_id`).

    Parameters
    ----------
    values : object
        The ids to check.
    name : str
        The argument's name in error messages (an element is named ``name[index]``).

    Returns
    -------
    numpy.ndarray, shape (n,)
        The ids as an array.
    """
    ids = np.asarray(values)
    if ids.ndim != 1:
        raise ValueError(f"{name} must be a 1-D sequence of subject ids, got shape {ids.shape}")
    for index, value in enumerate(ids.tolist()):
        check_subject_id(value, f"{name}[{index}]")
    return ids


def check_images(images: object, name: str = "images") -> None:
    """Refuse anything but a non-empty sequence of grey-level images (each as :func:`as_grey_image` accepts).

    Parameters
    ----------
    images : object
        The argument to check.
    name : str
        The argument's name in error messages (an image is named ``name[index]``).
    """
    if isinstance(images, (str, bytes)) or not hasattr(images, "__len__"):
        raise TypeError(f"{name} must be a sequence of grey-level images, got {type(images).__name__}")
    if len(images) == 0:
        raise ValueError(f"{name} must not be empty")
    for index, image in enumerate(images):
        as_grey_image(image, f"{name}[{index}]")
