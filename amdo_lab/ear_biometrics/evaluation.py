"""Evaluation of Choraś's classifier (AMDO 2004, Sec. 6): closed-set and open-set rates, ranks, the
genuine-versus-impostor separation, the peers under the same protocol and the nuisance study."""

from __future__ import annotations

import copy
from collections.abc import Mapping
from dataclasses import dataclass, replace

import numpy as np

from amdo_lab.common import MAX_SAMPLES, MAX_SIDE, as_finite_array, check_fitted, check_positive_int, make_rng
from amdo_lab.ear_biometrics.enrolment import check_subject_id, check_subject_ids
from amdo_lab.ear_biometrics.images import check_images, check_record
from amdo_lab.ear_biometrics.matcher import (EarMatcher, EarTemplate, MatcherSettings, check_distance_threshold,
                                             check_templates)
from amdo_lab.ear_biometrics.peers import HogNearestNeighbour, LbpNearestNeighbour
from amdo_lab.ear_biometrics.synthetic import MAX_SUBJECTS, MIN_SIZE, check_disable, make_ear_database


@dataclass(frozen=True)
class Separation:
    """How far genuine distances lie below impostor ones (lower distance = more alike).

    Parameters
    ----------
    genuine : numpy.ndarray, shape (n_queries,)
        Distance of each query to its own subject (the closest of its templates).
    impostor : numpy.ndarray, shape (n_queries, n_enrolled)
        Distances to the other subjects' templates, NaN where the template is the query's subject.
    d_prime : float
        (mean impostor - mean genuine) / sqrt((var genuine + var impostor) / 2). When both spreads
        are 0: 0 for equal means (identical distributions), else inf with the sign of the gap.
    auc : float
        Mean over queries of the share of that query's impostor distances above its genuine distance
        (ties count one half), in [0, 1]; 1 means every query is closest to its own subject.
    ratio : float
        Median genuine over median impostor distance (within- over between-subject spread); 1 when
        both medians are 0, inf (signed as the genuine median) when only the impostor median is.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 5, step 4 (the distance-sum difference these numbers describe).
    """

    genuine: np.ndarray  # (n_queries,) distance to the query's own subject (closest template)
    impostor: np.ndarray  # (n_queries, n_enrolled) distances to other subjects, NaN for own
    d_prime: float
    auc: float
    ratio: float


def genuine_impostor_separation(distances: object, enrolled_ids: object, query_ids: object) -> Separation:
    """Separation of genuine from impostor distances in a query-by-enrolled distance matrix.

    Parameters
    ----------
    distances : array_like, shape (n_queries, n_enrolled)
        Finite distances within +-1e150 (their variances must stay finite), lower = more alike.
    enrolled_ids : array_like, shape (n_enrolled,)
        Subject of each enrolled template (str or finite real ids).
    query_ids : array_like, shape (n_queries,)
        Subject of each query; every one must be enrolled, together with at least one other subject.

    Returns
    -------
    Separation
        Genuine and impostor distances, d', AUC and the median ratio.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 5, step 4.
    """
    distances = as_finite_array(distances, "distances", ndim=2, max_abs=1e150)  # squared in the variances
    enrolled_ids = check_subject_ids(enrolled_ids, "enrolled_ids", size=distances.shape[1], per="column of distances")
    query_ids = check_subject_ids(query_ids, "query_ids", size=distances.shape[0], per="row of distances")
    own = query_ids[:, None] == enrolled_ids[None, :]
    if not own.any(axis=1).all() or own.all(axis=1).any():
        raise ValueError("every subject of query_ids must be in enrolled_ids, together with at least one other subject")
    genuine = np.where(own, distances, np.inf).min(axis=1)
    impostor = np.where(own, np.nan, distances)
    wins = (distances > genuine[:, None]) + 0.5 * (distances == genuine[:, None])
    above = np.where(own, 0.0, wins).sum(axis=1) / (~own).sum(axis=1)
    flat = impostor[~own]
    pooled = np.sqrt(0.5 * (genuine.var() + flat.var()))
    gap = flat.mean() - genuine.mean()  # both spreads 0: d' is 0 for equal means, else ±inf (never 0/0)
    d_prime = float(gap / pooled) if pooled > 0 else (0.0 if gap == 0 else float(np.copysign(np.inf, gap)))
    middle_genuine, middle_impostor = np.median(genuine), np.median(flat)  # ratio 1 for two zero medians
    ratio = (float(middle_genuine / middle_impostor) if middle_impostor != 0
             else 1.0 if middle_genuine == 0 else float(np.copysign(np.inf, middle_genuine)))
    return Separation(genuine, impostor, d_prime, float(above.mean()), ratio)


def _distance_sum_gaps(queries: list[EarTemplate], references: list[EarTemplate]) -> np.ndarray:
    """Step 4's distance for all pairs: mean over circles of |sum d (query) - sum d (reference)|.

    On checked templates with the same number of circles (those of one matcher), shape
    (n_queries, n_references), normalised units.
    """
    q = np.array([t.circles.distance_sums for t in queries])
    r = np.array([t.circles.distance_sums for t in references])
    return np.abs(q[:, None, :] - r[None, :, :]).mean(axis=2)


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
    check_record(matcher, "matcher", EarMatcher, "EarMatcher()")
    check_fitted(matcher, "templates_")
    check_templates(genuine, "genuine")
    check_templates(impostors, "impostors")
    check_subject_ids(genuine_ids, "genuine_ids", size=len(genuine), per="genuine template")
    values = np.asarray(thresholds, dtype=object)
    if values.ndim != 1 or values.size == 0:
        raise ValueError(f"thresholds must be a non-empty 1-D sequence, got shape {values.shape}")
    thresholds = np.array([check_distance_threshold(t, "thresholds") for t in values.tolist()])
    saved = matcher.settings
    far, frr, mis = [], [], []
    try:
        for threshold in thresholds:
            matcher.settings = replace(saved, distance_threshold=float(threshold))
            g = [matcher.identify_template(t).subject_id for t in genuine]
            far.append(np.mean([matcher.identify_template(t).subject_id is not None for t in impostors]))
            frr.append(np.mean([s is None for s in g]))
            mis.append(np.mean([s is not None and s != truth for s, truth in zip(g, genuine_ids)]))
    finally:
        matcher.settings = saved
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
    enrolled_ids = check_subject_ids(enrolled_ids, "enrolled_ids", size=len(scores), per="entry of scores")
    check_subject_id(true_id, "true_id")
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
        Largest rank, from 1 to ``MAX_SAMPLES`` (1,000,000).

    Returns
    -------
    numpy.ndarray, shape (max_rank,)
        Entry r - 1 is the share of queries with rank <= r.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 6 (identification rates; the CMC curve is our addition).
    """
    ranks = as_finite_array(ranks, "ranks", ndim=1, dtype=int, bounds=(1, np.inf))  # 1-based
    max_rank = check_positive_int(max_rank, "max_rank", maximum=MAX_SAMPLES)
    return np.searchsorted(np.sort(ranks), np.arange(1, max_rank + 1), side="right") / len(ranks)


@dataclass(frozen=True)
class ClosedSetResult:
    """Closed-set identification: capture 0 of every subject enrolled, capture 1 queried.

    Parameters
    ----------
    decided : numpy.ndarray, shape (n_queries,), object
        Subject named by the paper's rule, or None for a rejection.
    ranks : numpy.ndarray, shape (n_queries,), int
        Rank of the true subject by the matcher's ranking score.
    truth : numpy.ndarray, shape (n_queries,)
        True subject ids.
    separation : Separation
        Separation of the step-4 distance (mean |delta sum d|).

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 6 (two captures per subject) and Sec. 5 (the rule).
    """

    decided: np.ndarray  # (n_queries,) object: subject id or None (rejected), paper's rule
    ranks: np.ndarray  # (n_queries,) rank of the true subject by the matcher's ranking score
    truth: np.ndarray  # (n_queries,) true subject ids
    separation: Separation  # of the step-4 distance (mean |delta sum d|)

    @property
    def recognised(self) -> np.ndarray:
        """Per query, whether the paper's rule named the true subject: (n_queries,) bool."""
        return np.asarray(self.decided == self.truth, dtype=bool)

    @property
    def correct(self) -> float:
        """Share of queries the paper's rule named correctly."""
        return float(np.mean(self.recognised))

    @property
    def rejected(self) -> float:
        """Share of queries the paper's rule rejected (no candidate passed steps 2-4)."""
        return float(np.mean([d is None for d in self.decided]))

    @property
    def rank1(self) -> float:
        """Share of queries whose true subject ranks first."""
        return float(np.mean(self.ranks == 1))


def closed_set(matcher: EarMatcher, templates: list[EarTemplate], subject_ids: object) -> ClosedSetResult:
    """Enrol the even-indexed templates (capture 0), identify the odd-indexed ones (capture 1).

    Parameters
    ----------
    matcher : EarMatcher
        An empty matcher; its settings decide the rule (``max_count_violations``) and the ranking.
    templates : list of EarTemplate
        Two per subject, capture 0 then capture 1 (from :meth:`EarMatcher.extract`).
    subject_ids : array_like, shape (n,)
        Subject of each template (str or finite real ids); n even, the same length as ``templates``.

    Returns
    -------
    ClosedSetResult
        Decisions, ranks, truth and the step-4 separation.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 5 (steps 1-9) and Sec. 6 (the protocol: perpendicular and 30-degree captures).
    """
    check_record(matcher, "matcher", EarMatcher, "EarMatcher()")
    if matcher.n_enrolled:
        raise ValueError("matcher must be empty (a fresh EarMatcher)")
    check_templates(templates, "templates")
    ids = check_subject_ids(subject_ids, "subject_ids")
    _check_pairs(len(templates), ids, "templates")
    for template, subject in zip(templates[0::2], ids[0::2]):
        matcher.enroll_template(subject, template)
    results = [matcher.identify_template(t) for t in templates[1::2]]
    truth = ids[1::2]
    ranks = np.array([rank_of_truth(r.scores, ids[0::2], s) for r, s in zip(results, truth)])
    decided = np.array([r.subject_id for r in results], dtype=object)
    separation = genuine_impostor_separation(_distance_sum_gaps(templates[1::2], templates[0::2]), ids[0::2], truth)
    return ClosedSetResult(decided, ranks, truth, separation)


def _check_pairs(n_items: int, ids: np.ndarray, name: str) -> None:
    """Two captures per subject: as many ids as items, an even number of them."""
    if len(ids) != n_items or len(ids) % 2:
        raise ValueError(f"{name} and subject_ids must have the same even length (two per subject), got {n_items}")


def peer_closed_set(images: np.ndarray, subject_ids: object,
                    baseline: HogNearestNeighbour | None = None) -> tuple[np.ndarray, Separation]:
    """A nearest-neighbour baseline (HOG or LBP) with the protocol of :func:`closed_set`.

    The images are compared as given: to give the baseline our canonical frame, pass
    ``EarMatcher().canonical_image`` of each image.

    Parameters
    ----------
    images : array_like, shape (n, rows, cols)
        Two images per subject, capture 0 then capture 1.
    subject_ids : array_like, shape (n,)
        Subject of each image (str or finite real ids); n even.
    baseline : HogNearestNeighbour or LbpNearestNeighbour or None
        The descriptor, unfitted (it is fitted on the first captures here); None for HOG with cells of
        an eighth of the image side (32 px at 256), so that its grid covers the ear the same way at
        every resolution.

    Returns
    -------
    ranks : numpy.ndarray, shape (n // 2,), int
        Rank of the true subject for each query.
    separation : Separation
        Separation of the descriptor's distances.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 6 (the protocol).
    N. Dalal, B. Triggs, "Histograms of Oriented Gradients for Human Detection", CVPR 2005.
    T. Ojala, M. Pietikäinen, T. Mäenpää, "Multiresolution Gray-Scale and Rotation Invariant Texture
    Classification with Local Binary Patterns", IEEE TPAMI 24(7), 2002.
    """
    check_images(images)
    ids = check_subject_ids(subject_ids, "subject_ids")
    _check_pairs(len(images), ids, "images")
    if baseline is None:
        baseline = HogNearestNeighbour(max(2, int(np.shape(images)[-1]) // 8))
    check_record(baseline, "baseline", HogNearestNeighbour, "HogNearestNeighbour() or LbpNearestNeighbour()")
    baseline = copy.deepcopy(baseline).fit(images[0::2], ids[0::2])
    distances = np.array([baseline.distances(image) for image in images[1::2]])
    ranks = np.array([rank_of_truth(d, ids[0::2], s) for d, s in zip(distances, ids[1::2])])
    return ranks, genuine_impostor_separation(distances, ids[0::2], ids[1::2])


def hog_closed_set(images: np.ndarray, subject_ids: object, pixels_per_cell: int | None = None
                   ) -> tuple[np.ndarray, Separation]:
    """HOG + 1-NN baseline with the protocol of :func:`closed_set` (:func:`peer_closed_set` with HOG).

    Parameters
    ----------
    images : array_like, shape (n, rows, cols)
        Two images per subject, capture 0 then capture 1.
    subject_ids : array_like, shape (n,)
        Subject of each image (str or finite real ids); n even.
    pixels_per_cell : int or None
        HOG cell side, pixels, >= 2; None for an eighth of the image side (16 px at 128, 32 px at
        256), so the HOG grid covers the ear the same way at every resolution.

    Returns
    -------
    ranks : numpy.ndarray, shape (n // 2,), int
        Rank of the true subject for each query.
    separation : Separation
        Separation of the HOG distances.

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 6 (the protocol).
    N. Dalal, B. Triggs, "Histograms of Oriented Gradients for Human Detection", CVPR 2005.
    """
    baseline = None if pixels_per_cell is None else HogNearestNeighbour(pixels_per_cell)
    return peer_closed_set(images, subject_ids, baseline)


RELAXED_VIOLATIONS = 2
"""``max_count_violations`` of the relaxed rule in :func:`nuisance_study` (the chapter's relaxed rule)."""


def nuisance_study(n_subjects: int, conditions: Mapping[str, tuple], *, rng: int | np.random.Generator,
                   size: int = 256) -> list[dict]:
    """Rates and separations of our method and HOG on databases that differ in one nuisance factor.

    Every database is drawn from the same state of ``rng`` (an int seed, or a generator that is
    copied, not advanced), so the subjects and all other factors are identical; only the disabled
    factors are set to neutral values. Easy images, the matcher's default settings. Per row: our
    paper-rule decisions ("correct"), our rank-1 under the relaxed rule (:data:`RELAXED_VIOLATIONS`
    radii may break the +-1 count rule), HOG's rank-1, and both methods' AUC and d' (separation):
    ours of step 4's distance-sum gaps, and the AUC of the distance D between F's points that ranks.

    Parameters
    ----------
    n_subjects : int
        Subjects per database, from 2 to ``MAX_SUBJECTS`` (10,000).
    conditions : Mapping
        Row name -> collection of factors to disable (names from :data:`NUISANCE_FACTORS`).
    rng : int or numpy.random.Generator
        Seed or generator of every database (each condition draws from a copy of its state).
    size : int
        Image side in pixels, from 32 to ``MAX_SIDE`` (4,096).

    Returns
    -------
    list of dict
        One row per condition: "condition", "ours correct (paper rule)", "ours rank-1",
        "HOG rank-1", "ours AUC", "ours AUC (F points)", "HOG AUC", "ours d'", "HOG d'".

    References
    ----------
    M. Choraś, "Ear Biometrics Based on Geometrical Method of Feature Extraction", AMDO 2004,
    LNCS 3179, pp. 51-61, Sec. 6 (easy and difficult images, the 30-degree capture).
    """
    n_subjects = check_positive_int(n_subjects, "n_subjects", minimum=2, maximum=MAX_SUBJECTS)
    generator = make_rng(rng, "rng")  # each condition draws from a copy of this state
    # Everything is checked before the first (slow) database is drawn.
    check_record(conditions, "conditions", Mapping, "a dict of row names and factors to disable")
    for disabled in conditions.values():
        check_disable(disabled)
    check_positive_int(size, "size", minimum=MIN_SIZE, maximum=MAX_SIDE)
    rows = []
    for name, disabled in conditions.items():
        database = make_ear_database(n_subjects, 2, "easy", rng=copy.deepcopy(generator), size=size, disable=disabled)
        templates = [EarMatcher().extract(image) for image in database.images]
        paper = closed_set(EarMatcher(), templates, database.subject_ids)
        matcher, ids = EarMatcher(MatcherSettings(max_count_violations=RELAXED_VIOLATIONS)), database.subject_ids
        relaxed = closed_set(matcher, templates, ids)  # enrols capture 0 into matcher
        points_d = np.array([matcher.identify_template(t).scores for t in templates[1::2]])  # D of steps 8-9
        points_auc = genuine_impostor_separation(points_d, ids[0::2], ids[1::2]).auc
        hog_ranks, hog_sep = hog_closed_set(database.images, ids)
        rows.append({"condition": name, "ours correct (paper rule)": paper.correct, "ours rank-1": relaxed.rank1,
                     "HOG rank-1": float(np.mean(hog_ranks == 1)), "ours AUC": paper.separation.auc,
                     "ours AUC (F points)": points_auc, "HOG AUC": hog_sep.auc, "ours d'": paper.separation.d_prime,
                     "HOG d'": hog_sep.d_prime})
    return rows
