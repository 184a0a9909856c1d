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


# --- targets in the source's hidden tests: expect / recorded / implement it -------------------------

from amdo_lab.common.exercises import RECORDED  # noqa: E402


def _new_set():
    return ExerciseSet(9, [
        Exercise(1, None, "look again", (WrongAnswer(0.028, "naive", hint="the fit absorbs some noise"),
                                         WrongAnswer(0.02, "sigma", hint="a point's noise is 2-D")), rtol=0.005),
        Exercise(2, None, "square, then sum", (WrongAnswer(lambda x: x + 1, "off by one", hint="no +1"),
                                               WrongAnswer(lambda x: 2 * x, "doubled", hint="not twice")),
                 kind="function", reference=lambda x: x * x, make_case=lambda seed: {"x": float(seed)},
                 example_seed=3),
    ])


@pytest.mark.parametrize(("number", "answer", "printed"), [
    (1, None, "not attempted yet"),
    (1, 0.028, "not yet: the fit absorbs some noise"),
    (1, 0.02, "not yet: a point's noise is 2-D"),
    (1, 0.0258, RECORDED),
    (1, 0.03, RECORDED),
    (1, "big", "not yet: give a number as the prompt asks"),
    (2, None, "not attempted yet"),
    (2, 9.0, "not yet: assign your function itself (answer = my_function), not its result"),
    (2, lambda x: x + 1, "not yet: no +1"),
    (2, lambda x: x ** 3, "not yet: on the example case your outputs differ from the method's; square, then sum"),
    (2, lambda x: x * x, "recorded: right on the example case; graded on unseen cases after submission"),
])
def test_release_verdicts_without_a_target(capsys, number, answer, printed):
    _new_set().check(number, answer)
    assert capsys.readouterr().out.strip() == printed


def test_registered_targets_give_correct_and_hints():
    exercises = _new_set()
    exercises.expect(1, 0.0258)
    exercises.expect(2, seeds=(5, 7))
    assert exercises.verdict(1, 0.0258) == "correct"
    assert exercises.verdict(1, 0.03) == "not yet: look again"
    assert exercises.verdict(1, 0.028) == "not yet: the fit absorbs some noise"
    assert exercises.verdict(2, lambda x: x * x) == "correct"
    cheat = lambda x: 9.0 if x == 3.0 else 0.0  # noqa: E731 - right on the example only
    assert exercises.verdict(2, cheat).startswith("not yet: on an unseen case")
    namespace = {"solution_1": 0.02581, "solution_2": lambda x: x ** 2}
    exercises.assert_checks(namespace)


def test_self_test_needs_a_target_and_the_recorded_unchanged_value():
    exercises = ExerciseSet(3, [Exercise(1, None, "h", (
        WrongAnswer(2.5, "unchanged", unchanged_experiment=True, hint="change it first", variable="experiment_1"),
        WrongAnswer(9.0, "slip", hint="units")), experiment=True)])
    with pytest.raises(AssertionError, match="not registered"):
        exercises.assert_checks({"solution_1": 3.0, "experiment_1": 2.5})
    exercises.expect(1, 3.0)
    exercises.assert_checks({"solution_1": 3.0, "experiment_1": 2.5})
    with pytest.raises(AssertionError, match="experiment_1"):
        exercises.assert_checks({"solution_1": 3.0, "experiment_1": 2.7})


def test_new_exercises_need_a_hint_for_every_wrong_answer_and_function_parts():
    with pytest.raises(ValueError, match="hint of its own"):
        Exercise(1, None, "h", wrong_answers((2.0, "x"), (3.0, "y", "z")))
    with pytest.raises(ValueError, match="reference"):
        Exercise(1, None, "h", wrong_answers((2.0, "x", "a"), (3.0, "y", "b")), kind="function")
    with pytest.raises(ValueError, match="seeds"):
        _new_set().expect(2, 4.0)


# --- grading mode: the answer recorded in the kernel, judged outside it ------------------------------

def test_grading_mode_emits_a_record_and_keeps_the_printed_verdict(capsys, monkeypatch):
    import json

    from amdo_lab.common.exercises import GRADING_ENV, RECORD_MIME

    exercises = _new_set()
    exercises.check(1, 0.03)
    assert capsys.readouterr().out.strip() == RECORDED
    monkeypatch.setenv(GRADING_ENV, "1")
    exercises.check(1, np.float64(0.03))
    verdict, record = capsys.readouterr().out.strip().splitlines()
    assert verdict == RECORDED and record.startswith(RECORD_MIME)
    assert json.loads(record.split(" ", 1)[1]) == {"chapter": 9, "exercise": 1, "kind": "value", "attempted": True,
                                                   "answer": 0.03}


def test_records_are_judged_against_the_sources_target_outside_the_kernel():
    exercises = _new_set()  # no target registered here: the grader passes the one parsed from the source
    assert exercises.judge_record(exercises.record(1, 0.0258), ("value", 0.0258)) == "correct"
    assert exercises.judge_record(exercises.record(1, 0.028), ("value", 0.0258)) == "not yet: the fit absorbs some noise"
    assert exercises.judge_record(exercises.record(1, None), ("value", 0.0258)) == "not attempted yet"
    assert exercises.judge_record(exercises.record(1, "0.0258"), ("value", 0.0258)).startswith("not yet")
    exercises.expect(2, seeds=(5, 7))  # as the restored hidden test does in the grading kernel
    square = exercises.record(2, lambda x: x * x)
    assert set(square["outputs"]) == {"5", "7"}
    assert exercises.judge_record(square, ("seeds", (5, 7))) == "correct"
    assert exercises.judge_record(square, ("seeds", (5, 8))).startswith("not yet: your function was not run")
    assert exercises.judge_record(exercises.record(2, lambda x: 2 * x), ("seeds", (5, 7))) == "not yet: not twice"
    raising = exercises.record(2, lambda x: 1 / 0)
    assert exercises.judge_record(raising, ("seeds", (5, 7))).startswith("not yet: your function raised")


@pytest.mark.parametrize("value", [1, 2.5, float("nan"), "word", True, None, (1.0, 2.0), [1, [2, 3]], {"a", "b"},
                                   np.arange(3.0), {"k": np.float32(1.5)}])
def test_encoded_answers_come_back_as_they_were(value):
    import json

    from amdo_lab.course.records import decode_value, encode_value

    back = decode_value(json.loads(json.dumps(encode_value(value))))
    if isinstance(value, float) and value != value:
        assert back != back
    elif isinstance(value, np.ndarray):
        assert np.array_equal(back, value)
    else:
        assert back == value and type(back) is type(value) or isinstance(value, dict)


def test_the_reference_itself_is_not_an_implementation():
    exercises = _new_set()
    exercises.expect(2, seeds=(5,))
    reference = exercises[2].reference
    assert exercises.verdict(2, reference) == "not yet: that is the package's own function: write the steps yourself"
    assert exercises.verdict(2, lambda x: x * x) == "correct"
