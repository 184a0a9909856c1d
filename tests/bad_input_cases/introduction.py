"""Bad-input table of ``amdo_lab.introduction`` (chapter 0): a valid call and the kind of each argument."""

from __future__ import annotations

from bad_input_cases._core import Case

#: (callable, argument, spoiled label) calls known to fail the test, with the reason; each must
#: still fail (remove it once fixed).
KNOWN_FAILURES: dict[tuple[str, str, str], str] = {}

#: Public names not called with user input, with the reason.
EXEMPT: dict[str, str] = {}


def cases() -> dict[str, Case]:
    """The public callables of ``amdo_lab.introduction``, by name."""
    from amdo_lab import introduction as intro

    return {
        "scale_case": Case(intro.scale_case, {"seed": 0}, {"seed": "seed"}),
    }
