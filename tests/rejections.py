"""What each test module's single table of rejection cases shares: a row, and how a row is run.

The generic promises (NaN, empty, wrong shape, wrong type, named by argument) are the bad-input
test's (``tests/test_bad_input.py``); a module's table holds the rules of its method.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable

import pytest


def reject(case_id: str, call: Callable[..., object], error: type[Exception], message: str):
    """A row: ``call`` must raise ``error`` with a message matching ``message``.

    ``call``'s parameters without a default name the fixtures it needs (``lambda hand: ...``).
    """
    return pytest.param(call, error, message, id=case_id)


def check_rejection(request: pytest.FixtureRequest, call: Callable[..., object], error: type[Exception],
                    message: str) -> None:
    """Run one row, handing ``call`` the fixtures its parameters name."""
    fixtures = {name: request.getfixturevalue(name) for name, parameter in inspect.signature(call).parameters.items()
                if parameter.default is inspect.Parameter.empty}
    with pytest.raises(error, match=message):
        call(**fixtures)
