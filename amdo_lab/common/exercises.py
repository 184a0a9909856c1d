"""The exercises of the chapters: each one specified as data, checked by a call that never raises.

An exercise in a chapter has three cells and an entry in the chapter's exercise module
(``amdo_lab/<method>/exercises.py``, named by the chapter registry):

1. an **answer cell** the reader edits, tagged ``exercise-answer``, pre-filled with a placeholder
   (``answer_2 = None``);
2. a **check cell**, tagged ``exercise-check``, one line: ``EXERCISES.check(2, answer_2, table=table)``.
   The expected value is computed inside the package, from the notebook objects named in the call,
   so it is not in plain view under the answer cell;
3. a **solution** in the chapter's ``## Solutions`` section (cells tagged ``solution``, folded whole
   in the book and removed from the student edition), which stores its result under its own name
   (``solution_2``) and passes the same check.

The :class:`Exercise` entry records, besides the expected value, the plausible wrong answers a
student would give (the naive value, the unchanged experiment's value, a sign or factor slip): at
least two per exercise, one of them the unchanged experiment for an experiment exercise. The last
cell of each chapter (tagged ``exercise-selftest``) runs :meth:`ExerciseSet.assert_checks` on the
notebook's own objects: the placeholder must give "not attempted yet", each recorded wrong answer a
hint, and ``solution_k`` "correct"; otherwise the cell raises, and so the notebook tests fail.
"""

from __future__ import annotations

import numbers
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field

import numpy as np

__all__ = [
    "CORRECT",
    "NOT_ATTEMPTED",
    "NOT_YET",
    "CheckOutcome",
    "Exercise",
    "ExerciseSet",
    "WrongAnswer",
    "check_answer",
    "judge_answer",
    "outcome_of",
    "wrong_answers",
]

NOT_ATTEMPTED = "not attempted yet"
CORRECT = "correct"
NOT_YET = "not yet"


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

    Never raises, so a chapter runs top to bottom with or without the reader's answers. Chapters
    call it through :meth:`ExerciseSet.check`, which keeps the expected value out of the notebook.

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
    print(judge_answer(answer, expected, hint=hint, rtol=rtol, atol=atol, placeholder=placeholder))


def judge_answer(
    answer: object,
    expected: object,
    *,
    hint: str = "",
    rtol: float = 1e-2,
    atol: float = 0.0,
    placeholder: object = None,
) -> str:
    """The line :func:`check_answer` prints, returned instead of printed. Never raises.

    Parameters
    ----------
    answer, expected, hint, rtol, atol, placeholder
        As in :func:`check_answer`.

    Returns
    -------
    str
        ``"not attempted yet"``, ``"correct"``, or ``"not yet"`` followed by ``": "`` and the hint.
    """
    if answer is placeholder or answer is Ellipsis:
        return NOT_ATTEMPTED
    try:
        right = _matches(answer, expected, rtol=rtol, atol=atol)
    except Exception as exc:  # noqa: BLE001 - a check cell must never stop the chapter
        return (f"{NOT_YET}: the answer could not be compared ({type(exc).__name__}: {exc})"
                + (f"; {hint}" if hint else ""))
    return CORRECT if right else NOT_YET + (f": {hint}" if hint else "")


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


@dataclass(frozen=True)
class WrongAnswer:
    """A plausible wrong answer that an exercise's check must reject with a hint.

    Parameters
    ----------
    value : object
        The wrong answer itself, or a callable ``value(namespace) -> answer`` that reads it from
        the executed notebook's objects (for example the unchanged experiment's result).
    why : str
        Who gives it: "the naive sigma * sqrt(2)", "the unchanged experiment", "a factor-2 slip".
    unchanged_experiment : bool
        True when this is what the notebook gives if the reader runs the experiment unchanged.
    """

    value: object
    why: str
    unchanged_experiment: bool = False

    def resolve(self, namespace: Mapping[str, object]) -> object:
        """The wrong answer as a value, read from ``namespace`` when :attr:`value` is callable."""
        return self.value(namespace) if callable(self.value) else self.value


@dataclass(frozen=True)
class Exercise:
    """One exercise of a chapter: how its answer is checked and which wrong answers it rejects.

    Parameters
    ----------
    number : int
        The exercise's number in the chapter (``### Exercise 2`` has number 2).
    expected : callable
        ``expected(**context) -> target``: the right answer, computed from the notebook objects
        named in :attr:`context`. The target is anything :func:`check_answer` accepts: a number
        or array (compared with ``rtol``/``atol``), a string, a bool, a set of alternatives or a
        predicate.
    hint : str
        What to look at again; printed after "not yet:". Never the answer.
    wrong_answers : sequence of WrongAnswer
        At least two plausible wrong answers; an experiment exercise records the unchanged
        experiment's value among them.
    context : tuple of str
        Names of notebook objects the check needs, passed as keywords by the check cell.
    rtol, atol : float
        Tolerances for a numeric answer, matching the precision the prompt asks for.
    choices : tuple of str
        For an interpretation question ("larger or smaller?"): the options the reader picks from.
        An answer outside them gets a hint that lists them.
    experiment : bool
        True when the reader changes and runs an experiment to answer.
    points : int
        What a correct answer is worth in the grader's table.
    """

    number: int
    expected: Callable[..., object]
    hint: str
    wrong_answers: tuple[WrongAnswer, ...]
    context: tuple[str, ...] = ()
    rtol: float = 1e-2
    atol: float = 0.0
    choices: tuple[str, ...] = ()
    experiment: bool = False
    points: int = 1

    def __post_init__(self) -> None:
        if len(self.wrong_answers) < 2:
            raise ValueError(f"exercise {self.number}: record at least two plausible wrong answers")
        if self.experiment and not any(wrong.unchanged_experiment for wrong in self.wrong_answers):
            raise ValueError(f"exercise {self.number}: an experiment needs a WrongAnswer(unchanged_experiment=True)")

    def target(self, context: Mapping[str, object]) -> object:
        """The right answer for these notebook objects (raises if one is missing or the call fails)."""
        missing = [name for name in self.context if name not in context]
        if missing:
            raise KeyError(f"the check needs {', '.join(missing)}")
        return self.expected(**{name: context[name] for name in self.context})

    def judge(self, answer: object, target: object) -> str:
        """The verdict line for ``answer`` against a precomputed ``target``. Never raises."""
        if self.choices and answer is not None and answer is not Ellipsis:
            if not isinstance(answer, str) or answer.strip().lower() not in {c.lower() for c in self.choices}:
                return f"{NOT_YET}: answer one of " + ", ".join(repr(c) for c in self.choices)
        return judge_answer(answer, target, hint=self.hint, rtol=self.rtol, atol=self.atol)


@dataclass(frozen=True)
class CheckOutcome:
    """One row of a self-test: which answer was fed to which exercise, the verdict and whether it is right."""

    number: int
    fed: str
    verdict: str
    wanted: str

    @property
    def ok(self) -> bool:
        """True when the verdict is the one this answer must get."""
        return self.verdict == self.wanted if self.wanted != NOT_YET else self.verdict.startswith(NOT_YET + ":")

    def describe(self) -> str:
        """One line for a report: the exercise, the answer fed, the verdict got and the one wanted."""
        return f"exercise {self.number}, {self.fed}: got {self.verdict!r}, wanted {self.wanted!r}"


@dataclass(frozen=True)
class ExerciseSet:
    """The exercises of one chapter, checked by :meth:`check` from the notebook's check cells.

    Parameters
    ----------
    chapter : int
        The chapter's number.
    exercises : sequence of Exercise
        Numbered 1, 2, ... in order.

    Examples
    --------
    >>> demo = ExerciseSet(0, [Exercise(1, lambda: 2.0, "count again",
    ...                                 (WrongAnswer(1.0, "one"), WrongAnswer(4.0, "squared")))])
    >>> demo.check(1, None)
    not attempted yet
    >>> demo.check(1, 2.0)
    correct
    >>> demo.check(1, 4.0)
    not yet: count again
    """

    chapter: int
    exercises: tuple[Exercise, ...] = field(default_factory=tuple)

    def __post_init__(self) -> None:
        object.__setattr__(self, "exercises", tuple(self.exercises))
        numbers_seen = [exercise.number for exercise in self.exercises]
        if numbers_seen != list(range(1, len(numbers_seen) + 1)):
            raise ValueError(f"chapter {self.chapter}: exercises must be numbered 1, 2, ...; got {numbers_seen}")

    def __getitem__(self, number: int) -> Exercise:
        for exercise in self.exercises:
            if exercise.number == number:
                return exercise
        raise KeyError(f"chapter {self.chapter} has no exercise {number}")

    def __len__(self) -> int:
        return len(self.exercises)

    def verdict(self, number: int, answer: object, **context: object) -> str:
        """The line :meth:`check` prints. Never raises (a failing expected value is reported)."""
        if answer is None or answer is Ellipsis:
            return NOT_ATTEMPTED
        try:
            exercise = self[number]
            target = exercise.target(context)
        except Exception as exc:  # noqa: BLE001 - a check cell must never stop the chapter
            return f"{NOT_YET}: the check could not run ({type(exc).__name__}: {exc})"
        return exercise.judge(answer, target)

    def check(self, number: int, answer: object, **context: object) -> None:
        """Print "not attempted yet", "correct" or "not yet: <hint>" for exercise ``number``.

        Parameters
        ----------
        number : int
            The exercise.
        answer : object
            The reader's answer (``None`` while not attempted).
        **context
            The notebook objects the exercise names in :attr:`Exercise.context`.
        """
        print(self.verdict(number, answer, **context))

    def self_test(self, namespace: Mapping[str, object]) -> list[CheckOutcome]:
        """Feed each check the placeholder, every recorded wrong answer and ``solution_k``.

        Parameters
        ----------
        namespace : mapping
            The executed notebook's objects (``globals()`` of its last cell).

        Returns
        -------
        list of CheckOutcome
            One row per answer fed; :attr:`CheckOutcome.ok` says whether its verdict is right.
        """
        rows: list[CheckOutcome] = []
        for exercise in self.exercises:
            context = {name: namespace[name] for name in exercise.context if name in namespace}
            try:
                target = exercise.target(context)
            except Exception as exc:  # noqa: BLE001 - reported as a failed row
                rows.append(CheckOutcome(exercise.number, "the expected value",
                                         f"could not be computed ({type(exc).__name__}: {exc})", CORRECT))
                continue
            rows.append(CheckOutcome(exercise.number, "the placeholder", self.verdict(exercise.number, None),
                                     NOT_ATTEMPTED))
            for wrong in exercise.wrong_answers:
                try:
                    value = wrong.resolve(namespace)
                except Exception as exc:  # noqa: BLE001
                    rows.append(CheckOutcome(exercise.number, wrong.why,
                                             f"could not be read ({type(exc).__name__}: {exc})", NOT_YET))
                    continue
                rows.append(CheckOutcome(exercise.number, wrong.why, exercise.judge(value, target), NOT_YET))
            solution_name = f"solution_{exercise.number}"
            verdict = (exercise.judge(namespace[solution_name], target) if solution_name in namespace
                       else f"{solution_name} is not defined")
            rows.append(CheckOutcome(exercise.number, solution_name, verdict, CORRECT))
        return rows

    def assert_checks(self, namespace: Mapping[str, object]) -> None:
        """Run :meth:`self_test` and raise ``AssertionError`` naming every row with the wrong verdict.

        Prints one summary line when every check gives the verdict it should.
        """
        rows = self.self_test(namespace)
        failed = [row.describe() for row in rows if not row.ok]
        if failed:
            raise AssertionError("exercise checks with the wrong verdict:\n  " + "\n  ".join(failed))
        n_wrong = sum(len(exercise.wrong_answers) for exercise in self.exercises)
        print(f"{len(self.exercises)} exercises: the placeholder, {n_wrong} recorded wrong answers and "
              f"{len(self.exercises)} solutions each get the verdict they should")


def outcome_of(line: str) -> str:
    """Classify a check cell's printed line as "not attempted yet", "correct" or "not yet"."""
    line = line.strip()
    if line == CORRECT:
        return CORRECT
    if line == NOT_ATTEMPTED:
        return NOT_ATTEMPTED
    return NOT_YET


def wrong_answers(*pairs: tuple[object, str], unchanged: Iterable[int] = ()) -> tuple[WrongAnswer, ...]:
    """Shorthand for a tuple of :class:`WrongAnswer`: ``wrong_answers((1.0, "naive"), (2.0, "slip"))``.

    Indices in ``unchanged`` mark the unchanged experiment's value.
    """
    marked = set(unchanged)
    return tuple(WrongAnswer(value, why, unchanged_experiment=index in marked)
                 for index, (value, why) in enumerate(pairs))

