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
