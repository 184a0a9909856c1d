"""Closed-set evaluation helpers and the genuine-versus-impostor separation used by the nuisance study."""

from __future__ import annotations

import copy
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from amdo_lab.common import as_finite_array, check_positive_int, make_rng
from amdo_lab.ear_biometrics.matcher import EarMatcher, EarTemplate, HogNearestNeighbour, _check_templates, rank_of_truth
from amdo_lab.ear_biometrics.synthetic import check_disable, generate_ear_database


@dataclass(frozen=True)
class Separation:
    """How far genuine distances lie below impostor ones (lower distance = more alike).

    ``d_prime`` = (mean impostor - mean genuine) / sqrt((var genuine + var impostor) / 2);
    ``auc`` = mean over queries of the fraction of that query's impostor distances above its
    genuine distance (ties count one half); 1 means every query is closest to its own subject.
    ``ratio`` = median genuine / median impostor distance (within- over between-subject spread).
    """

    genuine: np.ndarray  # (n_queries,) distance to the query's own subject (closest template)
    impostor: np.ndarray  # (n_queries, n_enrolled) distances to other subjects, NaN for own
    d_prime: float
    auc: float
    ratio: float


def genuine_impostor_separation(distances: object, enrolled_ids: object, query_ids: object) -> Separation:
    """Separation of a (n_queries, n_enrolled) distance matrix; every query's subject must be enrolled."""
    distances = as_finite_array(distances, "distances", ndim=2)
    enrolled_ids, query_ids = np.asarray(enrolled_ids), np.asarray(query_ids)
    if distances.shape != (len(query_ids), len(enrolled_ids)):
        raise ValueError(f"distances must have shape (n_queries, n_enrolled) = ({len(query_ids)}, "
                         f"{len(enrolled_ids)}), got {distances.shape}")
    own = query_ids[:, None] == enrolled_ids[None, :]
    if not own.any(axis=1).all() or own.all(axis=1).any():
        raise ValueError("every query's subject must be enrolled, together with at least one other subject")
    genuine = np.where(own, distances, np.inf).min(axis=1)
    impostor = np.where(own, np.nan, distances)
    wins = (distances > genuine[:, None]) + 0.5 * (distances == genuine[:, None])
    above = np.where(own, 0.0, wins).sum(axis=1) / (~own).sum(axis=1)
    flat = impostor[~own]
    pooled = np.sqrt(0.5 * (genuine.var() + flat.var()))
    d_prime = float((flat.mean() - genuine.mean()) / pooled) if pooled > 0 else np.inf
    return Separation(genuine, impostor, d_prime, float(above.mean()), float(np.median(genuine) / np.median(flat)))


def distance_sum_gaps(queries: list[EarTemplate], references: list[EarTemplate]) -> np.ndarray:
    """Step 4's distance: mean over circles of |sum d (query) - sum d (reference)|, all pairs.

    ``queries`` and ``references`` are non-empty lists of :class:`EarTemplate` with equally many circles.
    """
    _check_templates(queries, "queries")
    _check_templates(references, "references")
    n_circles = {len(t.circles.distance_sums) for t in [*queries, *references]}
    if len(n_circles) > 1:
        raise ValueError(f"queries and references must all have the same number of circles, got {sorted(n_circles)}")
    q = np.array([t.circles.distance_sums for t in queries])
    r = np.array([t.circles.distance_sums for t in references])
    return np.abs(q[:, None, :] - r[None, :, :]).mean(axis=2)


@dataclass(frozen=True)
class ClosedSetResult:
    """Enrol capture 0 of every subject, query capture 1: decisions of the paper's rule and ranks."""

    decided: np.ndarray  # (n_queries,) object: subject id or None (rejected), paper's rule
    ranks: np.ndarray  # (n_queries,) rank of the true subject by the matcher's ranking score
    truth: np.ndarray  # (n_queries,) true subject ids
    separation: Separation  # of the step-4 distance (mean |delta sum d|)

    @property
    def recognised(self) -> np.ndarray:
        """(n_queries,) bool: the paper's rule named the true subject."""
        return np.asarray(self.decided == self.truth, dtype=bool)

    @property
    def correct(self) -> float:
        return float(np.mean(self.recognised))

    @property
    def rejected(self) -> float:
        return float(np.mean([d is None for d in self.decided]))

    @property
    def rank1(self) -> float:
        return float(np.mean(self.ranks == 1))


def closed_set(matcher: EarMatcher, templates: list[EarTemplate], subject_ids: object) -> ClosedSetResult:
    """Enrol the even-indexed templates (capture 0), identify the odd-indexed ones (capture 1).

    ``matcher`` must be empty; its settings decide the rule (``max_count_violations``) and ranking.
    """
    if not isinstance(matcher, EarMatcher):
        raise TypeError(f"matcher must be an EarMatcher, got {type(matcher).__name__}")
    if matcher.n_enrolled:
        raise ValueError("matcher must be empty (a fresh EarMatcher)")
    ids = np.asarray(subject_ids)
    if len(ids) != len(templates) or len(ids) % 2:
        raise ValueError("templates and subject_ids must have the same even length (two captures per subject)")
    for template, subject in zip(templates[0::2], ids[0::2]):
        matcher.enroll_template(subject, template)
    results = [matcher.identify_template(t) for t in templates[1::2]]
    truth = ids[1::2]
    ranks = np.array([rank_of_truth(r.scores, ids[0::2], s) for r, s in zip(results, truth)])
    decided = np.array([r.subject_id for r in results], dtype=object)
    separation = genuine_impostor_separation(distance_sum_gaps(templates[1::2], templates[0::2]), ids[0::2], truth)
    return ClosedSetResult(decided, ranks, truth, separation)


def hog_closed_set(images: np.ndarray, subject_ids: object, pixels_per_cell: int | None = None
                   ) -> tuple[np.ndarray, Separation]:
    """HOG + 1-NN baseline with the same protocol: ranks of the true subject and the separation.

    ``pixels_per_cell`` defaults to an eighth of the image side (16 px at 128, 32 px at 256), so the
    HOG grid covers the ear the same way at every resolution."""
    ids = np.asarray(subject_ids)
    if ids.ndim != 1 or len(ids) != len(images) or len(ids) % 2:
        raise ValueError("images and subject_ids must have the same even length (two captures per subject), "
                         f"got {len(images)} images and subject_ids of shape {ids.shape}")
    if pixels_per_cell is None:
        pixels_per_cell = max(2, int(np.shape(images)[-1]) // 8)
    baseline = HogNearestNeighbour(pixels_per_cell)
    for image, subject in zip(images[0::2], ids[0::2]):
        baseline.enroll(subject, image)
    distances = np.array([baseline.distances(image) for image in images[1::2]])
    ranks = np.array([rank_of_truth(d, ids[0::2], s) for d, s in zip(distances, ids[1::2])])
    return ranks, genuine_impostor_separation(distances, ids[0::2], ids[1::2])


def nuisance_study(n_subjects: int, conditions: Mapping[str, tuple], *, rng: int | np.random.Generator,
                   difficulty: str = "easy", size: int = 256, relaxed_violations: int = 2, **matcher_settings) -> list[dict]:
    """Rates and separations of our method and HOG on databases that differ only in which nuisance
    factors are disabled.

    ``conditions`` maps a row name to the factors to disable; every database is drawn from the same
    state of ``rng`` (an int seed, or a generator that is copied, not advanced), so the subjects and
    all other factors are identical. Per row: our
    paper-rule decisions ("correct"), our rank-1 under the relaxed rule (``relaxed_violations``
    radii may break the +-1 count rule), HOG's rank-1, and both methods' AUC and d' (separation).
    """
    n_subjects = check_positive_int(n_subjects, "n_subjects", minimum=2)
    generator = make_rng(rng, "rng")  # each condition draws from a copy of this state
    # Everything is checked before the first (slow) database is drawn.
    if not isinstance(conditions, Mapping):
        raise TypeError(f"conditions must map row names to factors to disable, got {type(conditions).__name__}")
    for disabled in conditions.values():
        check_disable(disabled)
    check_positive_int(relaxed_violations, "relaxed_violations", minimum=0)
    EarMatcher(**matcher_settings)  # checks the settings under their own names
    rows = []
    for name, disabled in conditions.items():
        database = generate_ear_database(n_subjects, 2, difficulty, rng=copy.deepcopy(generator), size=size,
                                         disable=disabled)
        templates = [EarMatcher(**matcher_settings).extract(image) for image in database.images]
        paper = closed_set(EarMatcher(**matcher_settings), templates, database.subject_ids)
        relaxed = closed_set(EarMatcher(**matcher_settings, max_count_violations=relaxed_violations),
                             templates, database.subject_ids)
        hog_ranks, hog_sep = hog_closed_set(database.images, database.subject_ids)
        rows.append({"condition": name, "ours correct (paper rule)": paper.correct, "ours rank-1": relaxed.rank1,
                     "HOG rank-1": float(np.mean(hog_ranks == 1)), "ours AUC": paper.separation.auc,
                     "HOG AUC": hog_sep.auc, "ours d'": paper.separation.d_prime, "HOG d'": hog_sep.d_prime})
    return rows
