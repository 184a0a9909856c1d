"""Checks for the exercises of the chapters: one call per check cell, which never raises.

An exercise in a chapter has three cells: the reader's answer cell, pre-filled with a placeholder
(``answer = None``); a check cell that calls :func:`check_answer`; and a worked solution at the end
of the chapter that passes the same check. Because the check only prints, a chapter runs top to
bottom whether or not the reader has answered, and the committed output of a solution's check
("correct") is compared by the notebook tests, so a change that breaks a solution breaks a test.
"""

from __future__ import annotations

import numbers
from collections.abc import Callable

import numpy as np

__all__ = ["NOT_ATTEMPTED", "CORRECT", "check_answer"]

NOT_ATTEMPTED = "not attempted yet"
CORRECT = "correct"


def check_answer(
    answer: object,
    expected: object,
    *,
    hint: str = "",
    rtol: float = 1e-2,
    atol: float = 0.0,
    placeholder: object = None,
) -> None:
    """Print whether ``answer`` matches ``expected``: "not attempted yet", "correct", or a hint.

    Never raises, so a chapter runs top to bottom with or without the reader's answers.

    Parameters
    ----------
    answer : object
        The reader's answer. ``placeholder`` (``None`` by default) means "not attempted".
    expected : object
        What a right answer is. Numbers and arrays are compared with ``numpy.allclose(answer,
        expected, rtol=rtol, atol=atol)`` (same shape required); strings ignoring case and
        surrounding spaces; booleans exactly; a set means "any of these"; a callable is a predicate
        ``expected(answer) -> bool`` for answers with more than one right value.
    hint : str
        Printed after "not yet:" when the answer is wrong: what to look at again, never the answer.
    rtol, atol : float
        Relative and absolute tolerances for numeric answers.
    placeholder : object
        The value of an untouched answer cell.

    Examples
    --------
    >>> check_answer(None, 3.0)
    not attempted yet
    >>> check_answer(3.01, 3.0)
    correct
    >>> check_answer(2.0, 3.0, hint="count the edges again")
    not yet: count the edges again
    """
    if answer is placeholder or answer is Ellipsis:
        print(NOT_ATTEMPTED)
        return
    try:
        right = _matches(answer, expected, rtol=rtol, atol=atol)
    except Exception as exc:  # noqa: BLE001 - a check cell must never stop the chapter
        print(f"not yet: the answer could not be compared ({type(exc).__name__}: {exc})"
              + (f"; {hint}" if hint else ""))
        return
    print(CORRECT if right else "not yet" + (f": {hint}" if hint else ""))


def _matches(answer: object, expected: object, *, rtol: float, atol: float) -> bool:
    if callable(expected):
        predicate: Callable[[object], object] = expected
        return bool(predicate(answer))
    if isinstance(expected, (set, frozenset)):
        return any(_matches(answer, option, rtol=rtol, atol=atol) for option in expected)
    if isinstance(expected, (bool, np.bool_)):
        return isinstance(answer, (bool, np.bool_)) and bool(answer) == bool(expected)
    if isinstance(expected, str):
        return isinstance(answer, str) and answer.strip().lower() == expected.strip().lower()
    if isinstance(answer, (bool, np.bool_, str)):
        return False  # a flag or a word where a number is expected
    if isinstance(expected, numbers.Number) or isinstance(expected, (np.ndarray, list, tuple)):
        got = np.asarray(answer, dtype=float)
        want = np.asarray(expected, dtype=float)
        return got.shape == want.shape and bool(np.allclose(got, want, rtol=rtol, atol=atol))
    return bool(answer == expected)
