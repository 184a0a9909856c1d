"""How sure is a recognition or success rate? Intervals and paired tests for per-item outcomes.

The chapters compare rates against a paper's number and against baselines on the same items.
A rate from n items carries a binomial uncertainty (for n = 100, a 95 % interval of about ±6 points
around a rate of 90 %, ±10 around 50 %), and two methods scored on the same items must be compared
pairwise: the items both get right or both get wrong say nothing about which is better. Both
computations are statsmodels'; this module only checks the input and returns small result objects.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common.validation import as_finite_array, as_outcomes, check_in_range, check_same_shape

__all__ = ["RateInterval", "PairedComparison", "rate_interval", "paired_comparison"]


@dataclass(frozen=True)
class RateInterval:
    """A rate with its Wilson score interval: ``successes`` of ``trials``, ``low`` ≤ rate ≤ ``high``.

    Parameters
    ----------
    successes : int
        Items right (recognised, succeeded).
    trials : int
        Items scored, at least 1.
    low, high : float
        Ends of the interval, in [0, 1].
    confidence : float
        Its coverage, in (0, 1).
    """

    successes: int
    trials: int
    low: float
    high: float
    confidence: float

    @property
    def rate(self) -> float:
        """The observed rate, ``successes / trials``."""
        return self.successes / self.trials

    def contains(self, value: float) -> bool:
        """Whether ``value`` (a rate in [0, 1], e.g. a paper's number) lies inside the interval.

        Parameters
        ----------
        value : float
            A rate in [0, 1].

        Returns
        -------
        bool
            ``low <= value <= high``.
        """
        value = float(as_finite_array(value, "value", ndim=0))
        return self.low <= value <= self.high


@dataclass(frozen=True)
class PairedComparison:
    """Two methods scored on the same items (McNemar's exact test).

    ``only_first`` items are right for the first method and wrong for the second, ``only_second``
    the reverse; ``p_value`` is the two-sided exact binomial test of ``only_first`` against half of
    the discordant items (1.0 when there are none).

    Parameters
    ----------
    only_first : int
        Items right for the first method only.
    only_second : int
        Items right for the second method only.
    both, neither : int
        Items right for both, and for neither.
    p_value : float
        Two-sided exact p-value.
    """

    only_first: int
    only_second: int
    both: int
    neither: int
    p_value: float

    @property
    def difference(self) -> float:
        """First rate minus second rate."""
        return (self.only_first - self.only_second) / (self.only_first + self.only_second + self.both + self.neither)


def rate_interval(outcomes: np.ndarray, confidence: float = 0.95) -> RateInterval:
    """Rate of ``True`` in ``outcomes`` with its Wilson score interval.

    The Wilson interval (Wilson 1927; Brown, Cai & DasGupta, Stat. Sci. 2001, recommend it over the
    normal approximation) stays inside [0, 1] and keeps close to its nominal coverage for rates
    near 0 or 1 and for small n, where the normal approximation p ± z·sqrt(p(1-p)/n) does not.

    Parameters
    ----------
    outcomes : (n,) bool array_like
        One outcome per item (True = recognised / succeeded), n >= 1.
    confidence : float
        Coverage of the interval, in (0, 1).

    Returns
    -------
    RateInterval
        Successes, trials, the interval's ends and its confidence.
    """
    from statsmodels.stats.proportion import proportion_confint  # lazy: statsmodels is slow to import

    outcomes = as_outcomes(outcomes, "outcomes")
    confidence = check_in_range(confidence, "confidence", 0, 1)
    successes, trials = int(outcomes.sum()), int(outcomes.size)
    low, high = proportion_confint(successes, trials, alpha=1 - confidence, method="wilson")
    return RateInterval(successes, trials, float(low), float(high), confidence)


def paired_comparison(first: np.ndarray, second: np.ndarray) -> PairedComparison:
    """Compare two methods' per-item outcomes on the same items (McNemar's exact test).

    Parameters
    ----------
    first : (n,) bool array_like
        The first method's outcomes (True = right), n >= 1.
    second : (n,) bool array_like
        The second method's outcomes on the same items in the same order.

    Returns
    -------
    PairedComparison
        The four counts and McNemar's exact two-sided p-value.
    """
    from statsmodels.stats.contingency_tables import mcnemar  # lazy: statsmodels is slow to import

    first = as_outcomes(first, "first")
    second = as_outcomes(second, "second")
    check_same_shape(first, second, "first", "second")  # the same items, scored by both
    only_first, only_second = int(np.sum(first & ~second)), int(np.sum(~first & second))
    both, neither = int(np.sum(first & second)), int(np.sum(~first & ~second))
    if only_first + only_second == 0:
        p_value = 1.0  # no discordant item: nothing tells the methods apart
    else:
        p_value = float(mcnemar([[both, only_first], [only_second, neither]], exact=True).pvalue)
    return PairedComparison(only_first, only_second, both, neither, p_value)
