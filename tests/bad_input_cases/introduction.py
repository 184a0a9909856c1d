"""Bad-input table of ``amdo_lab.introduction`` (chapter 0): a valid call and the kind of each argument."""

from __future__ import annotations

import numpy as np

from bad_input_cases._core import Case

#: (callable, argument, spoiled label) calls known to fail the test, with the reason; each must
#: still fail (remove it once fixed).
KNOWN_FAILURES: dict[tuple[str, str, str], str] = {}

#: Public names not called with user input, with the reason.
EXEMPT: dict[str, str] = {}


def cases() -> dict[str, Case]:
    """The public callables of ``amdo_lab.introduction``, by name (a small outline, few draws)."""
    from amdo_lab import introduction as intro

    template = np.random.default_rng(0).normal(size=(6, 2))
    clean = 2.0 * template @ np.array([[0.0, -1.0], [1.0, 0.0]]).T + 1.0
    return {
        "simulated_rms": Case(
            intro.simulated_rms,
            {"template": template, "clean": clean, "noise": 0.1, "rng": 0},
            {"template": "points", "clean": "points", "noise": "positive", "rng": "seed"}),
    }
