"""The exercises of the chapters: each one specified as data, checked by a call that never raises.

An exercise in a chapter's source notebook (``notebooks/``, the instructor's copy) has these cells
and an entry in the chapter's exercise module (``amdo_lab/<method>/exercises.py``):

1. an **answer cell** the reader edits, tagged ``exercise-answer`` (``metadata.amdo_lab.exercise = k``),
   pre-filled with a placeholder (``answer_k = None``); an experiment's code sits above the
   placeholder. For an "implement it" exercise the answer is a function (``answer_k = my_function``);
2. a **check cell**, tagged ``exercise-check``, whose target sits in a hidden test::

       ### BEGIN HIDDEN TESTS
       EXERCISES.expect(k, 0.0314)          # a literal at the precision the prompt asks for
       ### END HIDDEN TESTS
       EXERCISES.check(k, answer_k)

   (an "implement it" exercise registers the seeds of its unseen cases instead:
   ``EXERCISES.expect(k, seeds=(101, 202, 303))``). The release strips the hidden test, so the
   target is in the instructor's source only, never in the package the reader installs;
3. for an exercise with a "why" half, a **why cell**: a markdown answer cell tagged
   ``exercise-why`` (same ``amdo_lab.exercise``), which the instructor marks by hand
   (:attr:`Exercise.why_points`), with a short rubric in the solution;
4. a **solution** in the chapter's ``## Solutions`` section (cells tagged ``solution``), which
   stores its result under its own name (``solution_k``).

:meth:`ExerciseSet.check` answers at once and never raises:

- ``"not attempted yet"`` for the placeholder;
- ``"not yet: <hint>"`` for an answer of the wrong kind (a word where a number is asked, a choice
  outside the options) and for each recorded wrong answer, with the hint recorded for it;
- with a target registered (the source notebook, the book, the grader): ``"correct"`` or
  ``"not yet: <the exercise's hint>"``;
- without one (the student release): ``"recorded: graded after submission"``. An "implement it"
  answer is first run on the example case the notebook shows and compared with the package's
  reference function, so a wrong function gets a hint at once.

The :class:`Exercise` entry records what is not secret: the hint, the tolerance, the options,
the points, and the plausible wrong answers a student would give (the naive value, the unchanged
experiment's value, a slip), each with a hint of its own. The last cell of each chapter (tagged
``exercise-selftest``) runs :meth:`ExerciseSet.assert_checks` on the notebook's own objects: every
check has a target, the placeholder gives "not attempted yet", each recorded wrong answer its
hint, each ``WrongAnswer.variable`` holds the recorded unchanged value, and ``solution_k`` is
"correct"; otherwise the cell raises, and the notebook tests fail.

When the course grader runs a submission (:mod:`amdo_lab.course.grading`) it sets the environment
variable ``AMDO_LAB_GRADING``: each check then also emits a record of the answer (:meth:`ExerciseSet.record`:
the value, or an "implement it" function's outputs on the hidden seeds' cases) as a display output
of MIME type ``application/vnd.amdo-lab.answer+json``, and the grader judges that record in its own
process (:meth:`ExerciseSet.judge_record`) against the target it reads from the source notebook,
so nothing the answer cell does to this kernel's objects changes the grade. The printed verdicts
are the same with or without it.

Older exercises may still compute their target in the package (``Exercise.expected``, a callable
of the notebook objects named in ``context``); new exercises leave ``expected`` as ``None``.
"""

from __future__ import annotations

import json
import numbers
import os
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

__all__ = [
    "CORRECT",
    "GRADING_ENV",
    "NOT_ATTEMPTED",
    "RECORD_MIME",
    "NOT_YET",
    "RECORDED",
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
RECORDED = "recorded: graded after submission"
#: Environment variable the course grader sets: in its kernel each check also emits a record.
GRADING_ENV = "AMDO_LAB_GRADING"
#: MIME type of that record (a display output of the check cell, read by the grader).
RECORD_MIME = "application/vnd.amdo-lab.answer+json"
#: Kinds of exercise: a value (number, word, array) or a function the reader implements.
KINDS = ("value", "function")


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
    call it through :meth:`ExerciseSet.check`.

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
    return CORRECT if right else _not_yet(hint)


def _not_yet(hint: str) -> str:
    return NOT_YET + (f": {hint}" if hint else "")


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


def _kind_mismatch(answer: object, example: object) -> bool:
    """True when ``answer`` is of another kind than ``example`` (a word for a number, a number for a word)."""
    if isinstance(example, str):
        return not isinstance(answer, str)
    if isinstance(example, (bool, np.bool_)):
        return not isinstance(answer, (bool, np.bool_))
    if isinstance(example, numbers.Number) or isinstance(example, (np.ndarray, list, tuple)):
        if isinstance(answer, (bool, np.bool_, str)):
            return True
        try:
            np.asarray(answer, dtype=float)
        except (TypeError, ValueError):
            return True
    return False


@dataclass(frozen=True)
class WrongAnswer:
    """A plausible wrong answer that an exercise's check must reject with a hint.

    Parameters
    ----------
    value : object
        The wrong answer itself. For a value exercise: a literal (rounded as a reader would give
        it), or (older exercises) a callable ``value(namespace) -> answer`` that reads it from the
        executed notebook's objects. For an "implement it" exercise: the wrong function itself.
    why : str
        Who gives it: "the naive sigma * sqrt(2)", "the unchanged experiment", "a factor-2 slip".
    unchanged_experiment : bool
        True when this is what the notebook gives if the reader runs the experiment unchanged.
    hint : str
        What the check prints after "not yet:" for this answer: a hint specific to the mistake,
        never the right answer. Empty: the exercise's own hint.
    variable : str
        The notebook variable that holds this value when the chapter runs unchanged (for the
        unchanged experiment, say ``"experiment_2"``): the self-test checks that the recorded
        literal still equals it, so the record cannot drift from the notebook.
    """

    value: object
    why: str
    unchanged_experiment: bool = False
    hint: str = ""
    variable: str = ""

    def resolve(self, namespace: Mapping[str, object]) -> object:
        """The wrong answer as a value, read from ``namespace`` when :attr:`value` is a namespace callable."""
        return self.value(namespace) if callable(self.value) else self.value


@dataclass(frozen=True)
class Exercise:
    """One exercise of a chapter: how its answer is checked and which wrong answers it rejects.

    Parameters
    ----------
    number : int
        The exercise's number in the chapter (``### Exercise 2`` has number 2).
    expected : callable or None
        ``None`` for a new exercise: the target is registered by the check cell's hidden test
        (:meth:`ExerciseSet.expect`), so it is in the instructor's source only. Older exercises:
        ``expected(**context) -> target``, computed from the notebook objects named in
        :attr:`context`.
    hint : str
        What to look at again; printed after "not yet:" for a wrong answer that has no recorded
        hint of its own. Never the answer.
    wrong_answers : sequence of WrongAnswer
        At least two plausible wrong answers; an experiment exercise records the unchanged
        experiment's value among them.
    context : tuple of str
        Older exercises: names of notebook objects the check needs, passed as keywords.
    rtol, atol : float
        Tolerances for a numeric answer (or a function's outputs), matching the precision the
        prompt asks for.
    choices : tuple of str
        For an interpretation question ("larger or smaller?"): the options the reader picks from.
        An answer outside them gets a hint that lists them.
    experiment : bool
        True when the reader changes and runs an experiment to answer.
    points : int
        What a correct answer is worth in the gradebook.
    why_points : int
        What the instructor-marked "why" answer (the cell tagged ``exercise-why``) is worth; 0 when
        the exercise has no "why" half.
    kind : {"value", "function"}
        ``"function"`` for an "implement it" exercise: the answer is a function, compared on
        cases with :attr:`reference`.
    reference : callable or None
        "Implement it": the package function (or a thin wrapper of it) the reader's function must
        agree with, called with the same keyword arguments.
    make_case : callable or None
        "Implement it": ``make_case(seed) -> dict`` of keyword arguments, one case per seed. The
        check cell's hidden test names the seeds of the unseen cases.
    example_seed : int or None
        "Implement it": the seed of the case the notebook shows; the release checks the reader's
        function on it at once.
    """

    number: int
    expected: Callable[..., object] | None
    hint: str
    wrong_answers: tuple[WrongAnswer, ...]
    context: tuple[str, ...] = ()
    rtol: float = 1e-2
    atol: float = 0.0
    choices: tuple[str, ...] = ()
    experiment: bool = False
    points: int = 1
    why_points: int = 0
    kind: str = "value"
    reference: Callable[..., object] | None = None
    make_case: Callable[[int], dict] | None = None
    example_seed: int | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "wrong_answers", tuple(self.wrong_answers))
        if len(self.wrong_answers) < 2:
            raise ValueError(f"exercise {self.number}: record at least two plausible wrong answers")
        if self.experiment and not any(wrong.unchanged_experiment for wrong in self.wrong_answers):
            raise ValueError(f"exercise {self.number}: an experiment needs a WrongAnswer(unchanged_experiment=True)")
        if self.kind not in KINDS:
            raise ValueError(f"exercise {self.number}: kind must be one of {KINDS}, got {self.kind!r}")
        if self.kind == "function":
            if self.expected is not None or self.reference is None or self.make_case is None:
                raise ValueError(f"exercise {self.number}: an 'implement it' exercise takes a reference and a "
                                 "make_case, and no expected")
            if self.example_seed is None:
                raise ValueError(f"exercise {self.number}: an 'implement it' exercise shows an example_seed")
        if self.expected is None and not all(wrong.hint for wrong in self.wrong_answers):
            raise ValueError(f"exercise {self.number}: give every recorded wrong answer a hint of its own")

    def target(self, context: Mapping[str, object]) -> object:
        """Older exercises: the right answer for these notebook objects (raises if one is missing)."""
        if self.expected is None:
            raise KeyError(f"exercise {self.number} keeps its target in the check cell's hidden test")
        missing = [name for name in self.context if name not in context]
        if missing:
            raise KeyError(f"the check needs {', '.join(missing)}")
        return self.expected(**{name: context[name] for name in self.context})

    def _choice_problem(self, answer: object) -> str:
        if self.choices and (not isinstance(answer, str)
                             or answer.strip().lower() not in {c.lower() for c in self.choices}):
            return f"{NOT_YET}: answer one of " + ", ".join(repr(c) for c in self.choices)
        return ""

    def judge(self, answer: object, target: object) -> str:
        """The verdict line for a value ``answer`` against a known ``target``. Never raises."""
        if answer is None or answer is Ellipsis:
            return NOT_ATTEMPTED
        problem = self._choice_problem(answer)
        if problem:
            return problem
        verdict = judge_answer(answer, target, hint=self.hint, rtol=self.rtol, atol=self.atol)
        if verdict == CORRECT:
            return verdict
        return self.recorded_hint(answer, {}) or verdict

    def recorded_hint(self, answer: object, namespace: Mapping[str, object]) -> str:
        """The verdict for ``answer`` when it is one of the recorded wrong answers, else ``""``."""
        for wrong in self.wrong_answers:
            try:
                if self.kind == "function":
                    continue  # wrong functions are recognised by their outputs (ExerciseSet._judge_function)
                if callable(wrong.value) and not namespace:
                    continue
                value = wrong.resolve(namespace)
                if value is None:
                    continue
                if _matches(answer, value, rtol=min(self.rtol, 1e-9) if self.rtol else 0.0,
                            atol=min(self.atol, 1e-12)) or _same_rounded(answer, value):
                    return _not_yet(wrong.hint or self.hint)
            except Exception:  # noqa: BLE001 - a record that cannot be compared is skipped
                continue
        return ""

    def outputs_match(self, got: object, want: object) -> bool:
        """True when a function's outputs ``got`` agree with the reference's ``want`` (tolerances of the exercise)."""
        try:
            if isinstance(want, tuple) or isinstance(want, list) and not _is_numeric_list(want):
                return (isinstance(got, (tuple, list)) and len(got) == len(want)
                        and all(self.outputs_match(g, w) for g, w in zip(got, want)))
            if isinstance(want, Mapping):
                return (isinstance(got, Mapping) and set(got) == set(want)
                        and all(self.outputs_match(got[key], want[key]) for key in want))
            return _matches(got, want, rtol=self.rtol, atol=self.atol)
        except Exception:  # noqa: BLE001
            return False


def _is_numeric_list(values: list) -> bool:
    return all(isinstance(v, numbers.Number) and not isinstance(v, bool) for v in values)


def _same_rounded(answer: object, value: object) -> bool:
    """True when a number ``answer`` equals the recorded wrong ``value`` at the digits the record gives."""
    if not isinstance(value, numbers.Real) or isinstance(value, bool) or isinstance(answer, (bool, str)):
        return False
    try:
        got = float(answer)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return False
    text = repr(float(value))
    decimals = len(text.split(".")[1]) if "." in text and "e" not in text else 12
    return round(got, decimals) == round(float(value), decimals)


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
        if self.wanted == NOT_YET:
            return self.verdict.startswith(NOT_YET + ":")
        if self.wanted.startswith(NOT_YET + ":"):
            return self.verdict == self.wanted
        return self.verdict == self.wanted

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
    >>> demo = ExerciseSet(0, [Exercise(1, None, "count again",
    ...                                 (WrongAnswer(1.0, "one", hint="both ends count"),
    ...                                  WrongAnswer(4.0, "squared", hint="no square here")))])
    >>> demo.check(1, None)
    not attempted yet
    >>> demo.check(1, 4.0)
    not yet: no square here
    >>> demo.check(1, 2.0)
    recorded: graded after submission
    >>> demo.expect(1, 2.0)
    >>> demo.check(1, 2.0)
    correct
    """

    chapter: int
    exercises: tuple[Exercise, ...] = field(default_factory=tuple)
    _targets: dict = field(default_factory=dict, repr=False, compare=False)

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

    # --- targets, registered by the source notebook's hidden tests --------------------------------

    def expect(self, number: int, target: object = None, *, seeds: Sequence[int] | None = None) -> None:
        """Register exercise ``number``'s target (a value) or the seeds of its unseen cases (a function).

        Called only from the hidden test of a check cell in the instructor's source; the release
        strips that line, so its checks answer "recorded: graded after submission".

        Parameters
        ----------
        number : int
            The exercise.
        target : object
            A value exercise's right answer: a literal at the precision the prompt asks for (or a
            set of alternatives, or a predicate).
        seeds : sequence of int
            An "implement it" exercise's unseen cases (``Exercise.make_case(seed)`` for each).
        """
        exercise = self[number]
        if exercise.kind == "function":
            if not seeds or target is not None:
                raise ValueError(f"exercise {number}: an 'implement it' exercise expects seeds=..., not a target")
            self._targets[number] = ("seeds", tuple(int(seed) for seed in seeds))
        else:
            if target is None or seeds is not None:
                raise ValueError(f"exercise {number}: a value exercise expects a target, not seeds")
            self._targets[number] = ("value", target)

    def has_target(self, number: int) -> bool:
        """True when exercise ``number``'s target is known here (registered, or computed by an older spec)."""
        return number in self._targets or self[number].expected is not None

    def registered(self, number: int) -> tuple[str, object] | None:
        """What the hidden test registered for exercise ``number``: ``("value", target)``, ``("seeds", seeds)`` or None."""
        return self._targets.get(number)

    # --- verdicts -----------------------------------------------------------------------------------

    def verdict(self, number: int, answer: object, **context: object) -> str:
        """The line :meth:`check` prints. Never raises (a failing check is reported in the line)."""
        if answer is None or answer is Ellipsis:
            return NOT_ATTEMPTED
        try:
            exercise = self[number]
            if exercise.kind == "function":
                return self._judge_function(exercise, answer)
            return self._judge_value(exercise, answer, context)
        except Exception as exc:  # noqa: BLE001 - a check cell must never stop the chapter
            return f"{NOT_YET}: the check could not run ({type(exc).__name__}: {exc})"

    def _judge_value(self, exercise: Exercise, answer: object, context: Mapping[str, object]) -> str:
        problem = exercise._choice_problem(answer)
        if problem:
            return problem
        recorded = exercise.recorded_hint(answer, context)
        registered = self._targets.get(exercise.number)
        if registered is not None:
            target = registered[1]
        elif exercise.expected is not None:
            target = exercise.target(context)
        else:
            example = next((w.value for w in exercise.wrong_answers if not callable(w.value)), None)
            if example is not None and _kind_mismatch(answer, example):
                return _not_yet("give a " + ("word" if isinstance(example, str) else "number")
                                + " as the prompt asks")
            return recorded or RECORDED
        verdict = judge_answer(answer, target, hint=exercise.hint, rtol=exercise.rtol, atol=exercise.atol)
        if verdict == CORRECT:
            return verdict
        return recorded or verdict

    def _judge_function(self, exercise: Exercise, answer: object) -> str:
        if not callable(answer):
            return _not_yet("assign your function itself (answer = my_function), not its result")
        if answer is exercise.reference or getattr(answer, "__wrapped__", None) is exercise.reference:
            return _not_yet("that is the package's own function: write the steps yourself")
        seeds = [exercise.example_seed]
        registered = self._targets.get(exercise.number)
        if registered is not None:
            seeds += list(registered[1])
        for position, seed in enumerate(seeds):
            case = exercise.make_case(seed)
            want = exercise.reference(**case)
            try:
                got = answer(**case)
            except Exception as exc:  # noqa: BLE001 - the reader's function may raise
                where = "the example case" if position == 0 else "an unseen case"
                return _not_yet(f"your function raised {type(exc).__name__} on {where}: {exc}")
            if not exercise.outputs_match(got, want):
                for wrong in exercise.wrong_answers:
                    try:
                        if exercise.outputs_match(got, wrong.value(**case)):
                            return _not_yet(wrong.hint or exercise.hint)
                    except Exception:  # noqa: BLE001
                        continue
                where = "the example case" if position == 0 else "an unseen case"
                return _not_yet(f"on {where} your outputs differ from the method's; {exercise.hint}")
        if registered is None:
            return "recorded: right on the example case; graded on unseen cases after submission"
        return CORRECT

    def check(self, number: int, answer: object, **context: object) -> None:
        """Print "not attempted yet", "correct", "not yet: <hint>" or "recorded: ..." for exercise ``number``.

        Parameters
        ----------
        number : int
            The exercise.
        answer : object
            The reader's answer (``None`` while not attempted).
        **context
            Older exercises: the notebook objects the exercise names in :attr:`Exercise.context`.
        """
        print(self.verdict(number, answer, **context))
        if os.environ.get(GRADING_ENV):
            self._emit_record(number, answer)

    # --- grading: the answer recorded in the kernel, judged outside it --------------------------------

    def record(self, number: int, answer: object) -> dict:
        """What the grader needs of ``answer`` to judge it in its own process (JSON-ready).

        A value exercise records the value itself; an "implement it" exercise the function's outputs
        on the cases of the seeds its hidden test registered (the grader re-computes the reference's
        outputs from the seeds in the instructor's source, so the kernel's targets are never used).
        Never raises.
        """
        base = {"chapter": self.chapter, "exercise": int(number)}
        try:
            exercise = self[number]
        except KeyError:
            return {**base, "kind": "unknown"}
        if answer is None or answer is Ellipsis:
            return {**base, "kind": exercise.kind, "attempted": False}
        if exercise.kind != "function":
            return {**base, "kind": "value", "attempted": True, "answer": _encode(answer)}
        registered = self._targets.get(exercise.number)
        seeds = list(registered[1]) if registered and registered[0] == "seeds" else []
        outputs: dict[str, object] = {}
        errors: dict[str, str] = {}
        if not callable(answer):
            return {**base, "kind": "function", "attempted": True, "callable": False}
        for seed in seeds:
            try:
                outputs[str(seed)] = _encode(answer(**exercise.make_case(seed)))
            except Exception as exc:  # noqa: BLE001 - the reader's function may raise
                errors[str(seed)] = f"{type(exc).__name__}: {exc}"
        return {**base, "kind": "function", "attempted": True, "callable": True, "outputs": outputs,
                "errors": errors}

    def _emit_record(self, number: int, answer: object) -> None:
        record = self.record(number, answer)
        try:
            from IPython import get_ipython
            from IPython.display import display

            if get_ipython() is None:
                raise RuntimeError("not in IPython")
            display({RECORD_MIME: record, "text/plain": "(answer recorded for grading)"}, raw=True)
        except Exception:  # noqa: BLE001 - outside IPython: one JSON line
            print(RECORD_MIME, json.dumps(record))

    def judge_record(self, record: Mapping[str, object], registered: tuple[str, object]) -> str:
        """The verdict for a grading ``record`` against the ``registered`` target read from the source.

        Parameters
        ----------
        record : mapping
            What :meth:`record` emitted in the reader's kernel.
        registered : tuple
            ``("value", target)`` or ``("seeds", seeds)``, parsed from the instructor's hidden test.

        Returns
        -------
        str
            The same kinds of line as :meth:`verdict`. Never raises.
        """
        try:
            exercise = self[int(record.get("exercise", -1))]
            if not record.get("attempted"):
                return NOT_ATTEMPTED
            if exercise.kind != "function":
                answer = _decode(record.get("answer"))
                problem = exercise._choice_problem(answer)
                if problem:
                    return problem
                verdict = judge_answer(answer, registered[1], hint=exercise.hint, rtol=exercise.rtol,
                                       atol=exercise.atol)
                return verdict if verdict == CORRECT else (exercise.recorded_hint(answer, {}) or verdict)
            if not record.get("callable"):
                return _not_yet("assign your function itself (answer = my_function), not its result")
            outputs, errors = record.get("outputs", {}), record.get("errors", {})
            for seed in registered[1]:
                key = str(seed)
                if key in errors:
                    return _not_yet(f"your function raised on an unseen case: {errors[key]}")
                if key not in outputs:
                    return _not_yet("your function was not run on the unseen cases")
                case = exercise.make_case(int(seed))
                got = _decode(outputs[key])
                if not exercise.outputs_match(got, exercise.reference(**case)):
                    for wrong in exercise.wrong_answers:
                        try:
                            if exercise.outputs_match(got, wrong.value(**case)):
                                return _not_yet(wrong.hint or exercise.hint)
                        except Exception:  # noqa: BLE001
                            continue
                    return _not_yet(f"on an unseen case your outputs differ from the method's; {exercise.hint}")
            return CORRECT
        except Exception as exc:  # noqa: BLE001 - a record that cannot be judged scores nothing
            return f"{NOT_YET}: the answer could not be judged ({type(exc).__name__}: {exc})"

    # --- the self-test of the source notebook ---------------------------------------------------------

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
            k = exercise.number
            context = {name: namespace[name] for name in exercise.context if name in namespace}
            if not self.has_target(k):
                rows.append(CheckOutcome(k, "the target", "not registered (no EXERCISES.expect in a hidden test)",
                                         CORRECT))
                continue
            if exercise.expected is not None:
                try:
                    exercise.target(context)
                except Exception as exc:  # noqa: BLE001 - reported as a failed row
                    rows.append(CheckOutcome(k, "the expected value",
                                             f"could not be computed ({type(exc).__name__}: {exc})", CORRECT))
                    continue
            rows.append(CheckOutcome(k, "the placeholder", self.verdict(k, None), NOT_ATTEMPTED))
            for wrong in exercise.wrong_answers:
                wanted = _not_yet(wrong.hint) if wrong.hint else NOT_YET
                if exercise.kind == "function":
                    rows.append(CheckOutcome(k, wrong.why, self.verdict(k, wrong.value), wanted))
                    continue
                try:
                    value = wrong.resolve(namespace)
                except Exception as exc:  # noqa: BLE001
                    rows.append(CheckOutcome(k, wrong.why, f"could not be read ({type(exc).__name__}: {exc})",
                                             NOT_YET))
                    continue
                rows.append(CheckOutcome(k, wrong.why, self.verdict(k, value, **context), wanted))
                if wrong.variable:
                    held = namespace.get(wrong.variable, f"{wrong.variable} is not defined")
                    same = (not isinstance(held, str) or isinstance(value, str)) and (
                        _matches(held, value, rtol=exercise.rtol, atol=exercise.atol) or _same_rounded(held, value))
                    rows.append(CheckOutcome(k, f"{wrong.variable} (the recorded {wrong.why})",
                                             "matches" if same else f"holds {held!r}, recorded {value!r}",
                                             "matches"))
            solution_name = f"solution_{k}"
            verdict = (self.verdict(k, namespace[solution_name], **context) if solution_name in namespace
                       else f"{solution_name} is not defined")
            rows.append(CheckOutcome(k, solution_name, verdict, CORRECT))
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


def _encode(value: object) -> object:
    from amdo_lab.course.records import encode_value

    return encode_value(value)


def _decode(data: object) -> object:
    from amdo_lab.course.records import decode_value

    return decode_value(data)


def outcome_of(line: str) -> str:
    """Classify a check cell's printed line as "not attempted yet", "correct", "recorded" or "not yet"."""
    line = line.strip()
    if line == CORRECT:
        return CORRECT
    if line == NOT_ATTEMPTED:
        return NOT_ATTEMPTED
    if line.startswith("recorded"):
        return "recorded"
    return NOT_YET


def wrong_answers(*pairs: tuple, unchanged: Iterable[int] = ()) -> tuple[WrongAnswer, ...]:
    """Shorthand for a tuple of :class:`WrongAnswer`: ``wrong_answers((1.0, "naive", "hint"), (2.0, "slip", "hint"))``.

    Each pair is ``(value, why)`` or ``(value, why, hint)``; indices in ``unchanged`` mark the
    unchanged experiment's value.
    """
    marked = set(unchanged)
    return tuple(WrongAnswer(pair[0], pair[1], unchanged_experiment=index in marked,
                             hint=pair[2] if len(pair) > 2 else "")
                 for index, pair in enumerate(pairs))
