"""Classification of Choraś (AMDO 2004), Sec. 5, steps 1-9: the stored features, the gates of steps 2-5
and the ranking of steps 6-9 by the characteristic points of F."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import partial

import cv2
import numpy as np

from amdo_lab.common import (MAX_ITERATIONS, MAX_SIDE, as_finite_array, check_choice, check_fitted, check_in_range,
                             check_instance, check_positive, check_positive_int)
from amdo_lab.ear_biometrics.circles import MAX_CIRCLES, READING_RULES, CircleFeatures
from amdo_lab.ear_biometrics.contours import MAX_CLOSING_PX, MAX_K, clean_contours, detect_contours
from amdo_lab.ear_biometrics.enrolment import Enrolment, check_subject_id
from amdo_lab.ear_biometrics.frame import (FRAME_SOURCES, CanonicalFrame, frame_normalisation, moment_frame_fast,
                                           silhouette, to_canonical)
from amdo_lab.ear_biometrics.images import as_grey_image, check_record
from amdo_lab.ear_biometrics.normalisation import NORMALISATION_MODES, Normalisation
from amdo_lab.ear_biometrics.skeleton import EQ8_READINGS
from amdo_lab.ear_biometrics.topology import TopologyFeatures, topology_features

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
        Subjects of the enrolled templates that passed steps 2-4, best first (at most :data:`SHORTLIST`).
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


COORDINATE_TOLERANCE = 0.2
"""Largest mean point distance (normalised units) of two contours that :func:`topology_similarity`
counts as matched."""

COUNT_TOLERANCE = 1
"""Steps 2-3: the allowed |l_r - l_r,ref| per radius (the paper's 1)."""

TOPOLOGY_WEIGHT = 1.0
"""``ranking="triples"``: candidates are ordered by their distance-sum gap minus this weight times
:func:`topology_similarity`."""

SHORTLIST = 10
"""Most candidates that pass steps 2-4 and are ranked by steps 6-9."""

MAX_BLUR_PX = 64.0
"""Largest Gaussian blur before contour detection, pixels: beyond, an ear image is flat."""

MAX_COMPONENT_SIZE = MAX_SIDE * MAX_SIDE
"""Largest ``min_component_size``: every pixel of the largest image."""


def topology_similarity(query: TopologyFeatures, reference: TopologyFeatures) -> float:
    """Steps 7-9 read literally: the share of contours whose triple and points match.

    A contour counts as matched when its triple (N_E, N_B, N_I) equals that of an unused contour of
    the other image *and* its characteristic points lie within :data:`COORDINATE_TOLERANCE` (mean
    nearest-point distance) of that contour's. Greedy, outermost contour first (the paper's tracing
    order); the count is divided by the larger number of contours.

    Parameters
    ----------
    query : TopologyFeatures
        F of the query image.
    reference : TopologyFeatures
        F of an enrolled image.

    Returns
    -------
    float
        Similarity in [0, 1]; 1 when every contour has a matching partner.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 5, steps 7-9, on F of eq. (9).
    """
    check_record(query, "query", TopologyFeatures, "topology_features")
    check_record(reference, "reference", TopologyFeatures, "topology_features")
    return _topology_similarity(query, reference)


def _topology_similarity(query: TopologyFeatures, reference: TopologyFeatures) -> float:
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
                if gaps > COORDINATE_TOLERANCE:
                    continue
            used[index] = True
            matched += 1
            break
    return matched / max(len(query.contours), len(reference.contours), 1)


POINT_DISTANCE_CAP = 0.5
"""Largest distance (normalised units) one characteristic point can add to :func:`point_distance`:
a point with no partner nearby (a contour break, a spur) costs at most this much."""


RANKINGS = ("points", "triples")
"""Readings of steps 6-9: the distance between the points of F, or exact triples then coordinates."""


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
    return _points(check_record(features, "features", TopologyFeatures, "topology_features"))


def _points(features: TopologyFeatures) -> np.ndarray:
    parts = [c.points for c in features.contours]
    return np.vstack(parts) if parts else np.zeros((0, 2))


def point_distance(query: TopologyFeatures, reference: TopologyFeatures) -> float:
    """Steps 8-9 read as a distance: do the stored points of F lie at the same coordinates?

    Plain-numpy reference: for every characteristic point (eq. 9) of one image, the distance to
    the nearest one of the other image, capped at :data:`POINT_DISTANCE_CAP`; the mean over the query's
    points and the
    mean over the reference's points are averaged (symmetric, a chamfer distance). Unlike steps 7-8
    read literally (the triples (N_E, N_B, N_I) must match exactly before coordinates are compared),
    one extra or missing point changes the distance by at most the cap / n.

    Parameters
    ----------
    query : TopologyFeatures
        F of the query image.
    reference : TopologyFeatures
        F of an enrolled image.

    Returns
    -------
    float
        Distance in [0, :data:`POINT_DISTANCE_CAP`]: 0 for the same points, the cap when one image has
        no point.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 5, steps 8-9, on the points of eq. (9).
    """
    check_record(query, "query", TopologyFeatures, "topology_features")
    check_record(reference, "reference", TopologyFeatures, "topology_features")
    a, b = _points(query), _points(reference)
    cap = POINT_DISTANCE_CAP
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


def check_distance_threshold(value: object, name: str) -> float:
    """Check a step-4 threshold: a non-negative number (0 accepts nothing), or ``inf`` for no threshold.

    Parameters
    ----------
    value : object
        The threshold to check (``inf`` is the matcher's default).
    name : str
        The argument's name in error messages.

    Returns
    -------
    float
        ``value``.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 5, step 4.
    """
    return np.inf if value == np.inf and not isinstance(value, bool) else check_positive(value, name, allow_zero=True)


SETTING_RULES = {  # the range of each of MatcherSettings' fields, as scikit-learn's _parameter_constraints
    "k": partial(check_in_range, low=0, high=MAX_K, closed="both"),
    "smoothing": partial(check_in_range, low=0, high=MAX_BLUR_PX, closed="both"),
    "min_component_size": partial(check_positive_int, maximum=MAX_COMPONENT_SIZE),
    "closing": partial(check_positive_int, minimum=0, maximum=MAX_CLOSING_PX),
    "max_count_violations": partial(check_positive_int, minimum=0, maximum=MAX_CIRCLES),
    "distance_threshold": check_distance_threshold,
    **READING_RULES,  # n_circles, step, mode, min_gap_px, crossings, polyline_smoothing, band_px, spur_length_px
    "frame": partial(check_choice, choices=FRAME_SOURCES),
    "origin": partial(check_choice, choices=("frame", "contours")),
    "ranking": partial(check_choice, choices=RANKINGS),
    "eq8": partial(check_choice, choices=EQ8_READINGS),
}
"""How :class:`MatcherSettings` checks each field: a function of (value, name) from ``amdo_lab.common``."""


@dataclass(frozen=True)
class MatcherSettings:
    """Settings of :class:`EarMatcher`: contour detection, the reading of V and F, the frame and the rule.

    The defaults are ours; :data:`PAPER_SETTINGS` (the pipeline as printed),
    :data:`PAPER_WITH_OUR_READINGS` and :data:`OUR_SETTINGS` are the named settings the chapter
    compares. ``MatcherSettings(max_count_violations=2)`` is ours with one field changed
    (as ``dataclasses.replace(OUR_SETTINGS, max_count_violations=2)``). Each field is checked when the
    settings are built (:data:`SETTING_RULES`). Pixel settings are for 256 x 256 images (the database
    default); they were chosen on development seeds, not on the notebook's data.

    Parameters
    ----------
    k : float
        Sensitivity of the contour detector, eq. (4), in [0, 1e6] (12 with the default smoothing: the
        blur lowers the local contrast sigma / mu, so the detector is made more sensitive; the paper's
        figures use 6-10 on unblurred images). The window of eqs. (1)-(3) is the paper's 3 x 3.
    smoothing : float
        Gaussian blur before contour detection, sigma in pixels, in [0, :data:`MAX_BLUR_PX`] (0 follows
        the paper). The default 1.5 makes
        the contours indifferent to one more interpolation of the image: a rotated or rescaled copy
        has been resampled once more than the original, which blurs it by about 0.4 pixel and drops
        weak contour pixels; after a 1.5-pixel blur that extra blur hardly changes the image.
    n_circles : int
        Number of circles N_r of eq. (7), from 1 to 64.
    step : float
        Radius step between circles, normalised units, > 0.
    min_component_size : int
        Contour fragments with fewer pixels are dropped (:func:`clean_contours`), from 1 to
        :data:`MAX_COMPONENT_SIZE`.
    closing : int
        Half-width of the closing square of :func:`clean_contours`, pixels, from 0 to 64.
    max_count_violations : int
        Radii that may break the count rule of steps 2-3, from 0 (the paper's rule) to 64.
    distance_threshold : float
        Step 4: largest mean |sum d - sum d_ref|, >= 0, or inf for no threshold.
    mode : {"principal", "axes", "isotropic"}
        Reading of eq. (6) (see :func:`normalise_coordinates`).
    min_gap_px : float
        ``crossings="pixels"``: runs of contour pixels closer than this arc length, pixels, are one
        crossing; >= 0 (0 is the literal count).
    crossings : {"polyline", "pixels"}
        Reading of "the contour crosses a circle" (see :func:`circle_features`).
    polyline_smoothing : int
        ``crossings="polyline"``: smoothing rounds of the thinned contours, from 0 to 100,000.
    band_px : float
        ``crossings="polyline"``: dead band around each circle, pixels, >= 0.
    spur_length_px : int
        ``crossings="polyline"``: skeleton spurs shorter than this, pixels, are pruned, from 0 to 4,096.
    frame : {"silhouette", "contours", "image"}
        Where the canonical frame comes from: the silhouette's moments, the contour pixels detected in
        the given image, or none (the image as given, the paper's pipeline).
    origin : {"frame", "contours"}
        With a canonical frame: eq. (6)'s centroid and spreads from the silhouette's moments
        (``"frame"``) or from the contour pixels (eq. 6 as printed, in the reading ``mode``).
    ranking : {"points", "triples"}
        Steps 6-9: :func:`point_distance` between the characteristic points of F (``"points"``), or
        the literal exact triples then coordinates (:func:`topology_similarity`), combined with the
        distance-sum gap (``"triples"``).
    eq8 : {"crossing", "yokoi"}
        Reading of eq. (8) for F's endings and bifurcations (see
        :func:`~amdo_lab.ear_biometrics.topology.topology_features`).

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 2 (eqs. 1-5), Sec. 3 (eq. 6), Sec. 4 (eqs. 7-9) and Sec. 5 (steps 1-9).
    """

    k: float = 12.0
    smoothing: float = 1.5
    n_circles: int = 8
    step: float = 0.25
    min_component_size: int = 40
    closing: int = 2
    max_count_violations: int = 0
    distance_threshold: float = np.inf
    mode: str = "principal"
    min_gap_px: float = 6.0
    crossings: str = "polyline"
    polyline_smoothing: int = 4
    band_px: float = 6.0
    spur_length_px: int = 8
    frame: str = "silhouette"
    origin: str = "frame"
    ranking: str = "points"
    eq8: str = "crossing"

    def __post_init__(self) -> None:
        for name, rule in SETTING_RULES.items():
            rule(getattr(self, name), name)


#: The paper's pipeline as printed: the image as given (no canonical frame), eq. (6) on the contour
#: pixels divided per image axis, no blur, k = 8 (within the 6-10 of the paper's figures), crossings
#: counted as runs of contour pixels along each circle (no dead band, no spur pruning), steps 6-9 read
#: literally (exact triples, then coordinates) and the strict count rule of steps 2-3. The clean-up
#: (closing, small fragments dropped) is ours: the paper's "binarization" is not described.
PAPER_SETTINGS = MatcherSettings(frame="image", origin="contours", ranking="triples", smoothing=0.0, k=8.0,
                                 mode="axes", crossings="pixels", min_gap_px=0.0, band_px=0.0, spur_length_px=0)
#: The paper's pipeline with our readings of V and F: as :data:`PAPER_SETTINGS`, but eq. (6) along the
#: principal axes, crossings on the thinned contour lines with a 6-px dead band and 8-px spurs pruned.
PAPER_WITH_OUR_READINGS = MatcherSettings(frame="image", origin="contours", ranking="triples", smoothing=0.0, k=8.0)
#: Ours (see the chapter's ablation): the silhouette's canonical frame, a 1.5-pixel blur, k = 12 and
#: steps 6-9 as a distance between the points of F.
OUR_SETTINGS = MatcherSettings()


@dataclass
class EarMatcher(Enrolment):
    """Choraś's classifier (Sec. 5): features of enrolled images, identification of a query.

    Steps: (2-3) a reference is a candidate when |l_r - l_r,ref| <= 1 on every
    radius, except at most ``max_count_violations`` radii (0 = the paper's rule); (4) its mean
    absolute difference of the distance sums must be below ``distance_threshold``; (5) no candidate
    -> rejection (``subject_id=None``); (6-9) candidates are ranked (``ranking``). The decision
    (``subject_id``) is the best-ranked template among those that pass steps 2-4. The names in
    double backquotes are fields of :class:`MatcherSettings`.

    Invariance (beyond the paper's text): with a canonical frame (``frame``) the image is resampled
    into the frame of its silhouette (:func:`~amdo_lab.ear_biometrics.frame.moment_frame`) *before*
    step 1, so a rotated, rescaled or shifted copy is detected at the same place, orientation and
    size; the ``smoothing`` blur then makes detection indifferent to the copy's extra resampling.
    Both need the whole ear inside the image: an ear cut by the image border has a different
    silhouette in every copy, hence a different frame.

    Parameters
    ----------
    settings : MatcherSettings, default OUR_SETTINGS
        Detection, reading and decision settings (:data:`PAPER_SETTINGS` for the paper's pipeline).

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
    >>> images, ids = eb.make_ear_database(3, 2, "easy", rng=1)
    >>> matcher = eb.EarMatcher()
    >>> for subject, image in zip(ids[0::2], images[0::2]):
    ...     _ = matcher.enroll(subject, image)
    >>> int(matcher.identify(images[1]).subject_id)
    0
    """

    settings: MatcherSettings = OUR_SETTINGS
    # learned from the enrolled images (scikit-learn's trailing underscore); None until the first one
    subject_ids_: list | None = field(default=None, init=False, repr=False)
    templates_: list | None = field(default=None, init=False, repr=False)

    def __post_init__(self) -> None:
        check_instance(self.settings, "settings", MatcherSettings, what="a MatcherSettings (e.g. OUR_SETTINGS)")

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
        return None if self.settings.frame == "image" else self._frame_of(self._input(image, grey))

    def _frame_of(self, work: np.ndarray) -> CanonicalFrame:
        """:meth:`canonical_frame` of validated input (8-bit or float)."""
        mask = silhouette(work) if self.settings.frame == "silhouette" else self._contours(work)
        if np.count_nonzero(mask) < 3:
            raise ValueError("image has no contour (blank, constant or too smooth image): no ear silhouette")
        return moment_frame_fast(mask, work.shape)

    def _input(self, image: object, grey: np.ndarray) -> np.ndarray:
        """8-bit input keeps the detector's fast uint8 path; anything else is used as float."""
        return np.asarray(image) if np.asarray(image).dtype == np.uint8 else grey

    def _contours(self, image: np.ndarray) -> np.ndarray:
        """Step 1: optional smoothing, contours (eqs. 1-5) and the clean-up."""
        settings = self.settings
        if settings.smoothing > 0:  # image normalisation step before contour detection (Fig. 3)
            image = cv2.GaussianBlur(np.asarray(image, float), (0, 0), settings.smoothing)
        contours = detect_contours(image, settings.k)
        contours = clean_contours(contours, min(settings.min_component_size, contours.size), settings.closing)
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
        if self.settings.frame != "image":
            frame = self._frame_of(work)
            work = to_canonical(work, frame)
            if self.settings.origin == "frame":
                normalisation = frame_normalisation(frame, grey.shape, self.settings.mode)
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
        settings = self.settings
        topology = topology_features(self._contours(work), settings.n_circles, settings.step, mode=settings.mode,
                                     min_gap_px=settings.min_gap_px, crossings=settings.crossings,
                                     polyline_smoothing=settings.polyline_smoothing, band_px=settings.band_px,
                                     spur_length_px=settings.spur_length_px, eq8=settings.eq8,
                                     normalisation=normalisation)
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
        return self.enroll_template(subject_id, self.extract(image))  # which checks subject_id

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
        self._check_template(template, "template")
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

    def _check_template(self, template: object, name: str) -> None:
        """An :class:`EarTemplate` with this matcher's number of circles, else an error naming ``name``."""
        check_template(template, name)
        expected = self.settings.n_circles
        if len(template.circles.counts) != expected:
            raise ValueError(f"{name} has {len(template.circles.counts)} circles, matcher expects {expected}")

    @property
    def n_enrolled(self) -> int:
        """Number of enrolled templates (0 before the first enrolment)."""
        return 0 if self.templates_ is None else len(self.templates_)

    def _forget(self) -> None:
        """Drop every enrolled template (before :meth:`fit` enrols afresh)."""
        self.subject_ids_, self.templates_ = None, None

    def identify(self, image: object) -> IdentificationResult:
        """Identify one query image (steps 1-9); a blank or constant image is rejected, not an error.

        Parameters
        ----------
        image : array_like, shape (rows, cols)
            Grey levels of the query.

        Returns
        -------
        IdentificationResult
            The decision, the candidates and every enrolled template's score.
        """
        check_fitted(self, "templates_")  # NotFittedError (a ValueError) before any enrolment
        try:  # a bad image raises in extract (TypeError, or a ValueError about the image)
            query = self.extract(image)
        except ValueError as error:
            if "no contour" in str(error):
                return IdentificationResult(None, (), np.zeros(0), np.full(self.n_enrolled, np.inf), "no contour")
            raise
        return self.identify_template(query)

    def identify_template(self, query: EarTemplate) -> IdentificationResult:
        """Steps 2-9 on already extracted features.

        Parameters
        ----------
        query : EarTemplate
            The query's features (from :meth:`extract` with the same settings).

        Returns
        -------
        IdentificationResult
            The decision, the candidates and every enrolled template's score.
        """
        check_fitted(self, "templates_")
        self._check_template(query, "query")
        count_gap = np.abs(self._counts - query.circles.counts)
        violations = np.sum(count_gap > COUNT_TOLERANCE, axis=1)
        sum_gap = np.abs(self._sums - query.circles.distance_sums).mean(axis=1)
        scores = sum_gap + violations.astype(float)  # ranking for CMC: count violations cost 1 each
        settings = self.settings
        gate = (violations <= settings.max_count_violations) & (sum_gap < settings.distance_threshold)
        if settings.ranking == "points":  # steps 6-9 as a distance between the points of F
            scores = _point_distances(_points(query.topology), self._points, self._point_starts, POINT_DISTANCE_CAP)
        candidates = np.flatnonzero(gate)
        if len(candidates) == 0:
            return IdentificationResult(None, (), np.zeros(0), scores, "no reference passed steps 2-4")
        if settings.ranking == "points":
            candidates = candidates[np.argsort(scores[candidates], kind="stable")][:SHORTLIST]
            return IdentificationResult(self.subject_ids_[candidates[0]], tuple(self.subject_ids_[i] for i in candidates),
                                        scores[candidates], scores)
        candidates = candidates[np.argsort(sum_gap[candidates])][:SHORTLIST]
        topo = np.array([_topology_similarity(query.topology, self.templates_[i].topology) for i in candidates])
        final = sum_gap[candidates] - TOPOLOGY_WEIGHT * topo
        order = np.argsort(final, kind="stable")
        candidates, final = candidates[order], final[order]
        scores = scores.copy()
        scores[candidates] = final - 10.0  # gated candidates rank ahead of all others
        return IdentificationResult(self.subject_ids_[candidates[0]], tuple(self.subject_ids_[i] for i in candidates),
                                    final, scores)


def check_template(template: object, name: str) -> EarTemplate:
    """Return ``template`` after checking it is an :class:`EarTemplate` whose fields keep their rules.

    ``circles`` a :class:`CircleFeatures` with finite ``radii``, and ``counts`` and ``distance_sums``
    non-negative, one per radius; ``topology`` a :class:`TopologyFeatures`. A template edited with
    ``dataclasses.replace`` is checked here, where the matcher receives it.

    Parameters
    ----------
    template : EarTemplate
        From :meth:`EarMatcher.extract`.
    name : str
        The argument's name in error messages.

    Returns
    -------
    EarTemplate
        ``template``.
    """
    check_record(template, name, EarTemplate, "EarMatcher.extract")
    circles = check_record(template.circles, f"{name}.circles", CircleFeatures, "circle_features")
    n = len(as_finite_array(circles.radii, f"{name}.circles.radii", ndim=1))
    as_finite_array(circles.counts, f"{name}.circles.counts", shape=(n,), bounds=(0.0, np.inf))
    as_finite_array(circles.distance_sums, f"{name}.circles.distance_sums", shape=(n,), bounds=(0.0, np.inf))
    check_record(template.topology, f"{name}.topology", TopologyFeatures, "topology_features")
    return template


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
    for index, template in enumerate(templates):
        check_template(template, f"{name}[{index}]")
