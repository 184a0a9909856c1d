"""The exercise check helper: prints one of three outcomes and never raises."""

import numpy as np
import pytest

from amdo_lab.common import check_answer


@pytest.mark.parametrize(
    ("answer", "expected", "kwargs", "printed"),
    [
        (None, 3.0, {}, "not attempted yet"),
        (..., 3.0, {}, "not attempted yet"),
        (3.01, 3.0, {}, "correct"),
        (3.5, 3.0, {"hint": "look again"}, "not yet: look again"),
        (3.5, 3.0, {}, "not yet"),
        (np.array([1.0, 2.0]), [1.0, 2.0], {}, "correct"),
        (np.array([1.0, 2.0, 3.0]), [1.0, 2.0], {}, "not yet"),
        (" Rigid ", "rigid", {}, "correct"),
        (True, True, {}, "correct"),
        (1, True, {}, "not yet"),
        (True, 1.0, {}, "not yet"),
        ("b", {"a", "b"}, {}, "correct"),
        (7, lambda a: a > 5, {}, "correct"),
        (-1, "placeholder-free", {"placeholder": -1}, "not attempted yet"),
        (0.0, 1e-9, {"atol": 1e-6}, "correct"),
    ],
)
def test_outcomes(capsys, answer, expected, kwargs, printed):
    assert check_answer(answer, expected, **kwargs) is None
    assert capsys.readouterr().out.strip() == printed


@pytest.mark.parametrize("answer", ["three", object(), [[1, 2], [3]], {"a": 1}])
def test_never_raises_on_odd_answers(capsys, answer):
    check_answer(answer, [1.0, 2.0], hint="two numbers")
    assert capsys.readouterr().out.startswith("not yet")


def test_predicate_that_raises_is_reported(capsys):
    check_answer("x", lambda a: a / 2 > 1, hint="a number")
    out = capsys.readouterr().out
    assert out.startswith("not yet: the answer could not be compared (TypeError") and out.rstrip().endswith("a number")


# --- the exercise specification: Exercise, WrongAnswer, ExerciseSet -------------------------------

from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer, wrong_answers  # noqa: E402


def _demo_set():
    return ExerciseSet(9, [
        Exercise(1, lambda scale: 2.0 * scale, "double it", wrong_answers((1.0, "the input"), (4.0, "squared")),
                 context=("scale",), rtol=1e-3),
        Exercise(2, lambda: "smaller", "compare the two", wrong_answers(("larger", "the other way"),
                                                                         (lambda ns: ns["unchanged"], "unchanged"),
                                                                         unchanged=[1]),
                 choices=("larger", "smaller"), experiment=True),
    ])


@pytest.mark.parametrize(("number", "answer", "context", "printed"), [
    (1, None, {"scale": 1.0}, "not attempted yet"),
    (1, 2.0, {"scale": 1.0}, "correct"),
    (1, 2.01, {"scale": 1.0}, "not yet: double it"),
    (1, 2.0, {}, "not yet: the check could not run (KeyError: 'the check needs scale')"),
    (2, " Smaller", {}, "correct"),
    (2, "bigger", {}, "not yet: answer one of 'larger', 'smaller'"),
    (2, 3, {}, "not yet: answer one of 'larger', 'smaller'"),
])
def test_exercise_set_verdicts(capsys, number, answer, context, printed):
    _demo_set().check(number, answer, **context)
    assert capsys.readouterr().out.strip() == printed


def test_self_test_passes_when_solutions_right_and_wrong_answers_rejected(capsys):
    namespace = {"scale": 1.0, "unchanged": "larger", "solution_1": 2.0, "solution_2": "smaller"}
    _demo_set().assert_checks(namespace)
    assert "2 exercises" in capsys.readouterr().out


@pytest.mark.parametrize(("namespace", "message"), [
    ({"scale": 1.0, "unchanged": "larger", "solution_1": 3.0, "solution_2": "smaller"}, "solution_1"),
    ({"scale": 1.0, "unchanged": "smaller", "solution_1": 2.0, "solution_2": "smaller"}, "unchanged"),
    ({"scale": 1.0, "unchanged": "larger", "solution_1": 2.0}, "solution_2 is not defined"),
    ({"unchanged": "larger", "solution_1": 2.0, "solution_2": "smaller"}, "the expected value"),
])
def test_self_test_fails_on_any_wrong_verdict(namespace, message):
    with pytest.raises(AssertionError, match=message):
        _demo_set().assert_checks(namespace)


def test_an_exercise_needs_two_wrong_answers_and_an_experiment_its_unchanged_value():
    with pytest.raises(ValueError, match="at least two"):
        Exercise(1, lambda: 1.0, "h", (WrongAnswer(2.0, "x"),))
    with pytest.raises(ValueError, match="unchanged"):
        Exercise(1, lambda: 1.0, "h", wrong_answers((2.0, "x"), (3.0, "y")), experiment=True)
    with pytest.raises(ValueError, match="numbered"):
        ExerciseSet(0, [Exercise(2, lambda: 1.0, "h", wrong_answers((2.0, "x"), (3.0, "y")))])
