"""The equation map: where each equation a chapter cites lives in its subpackage, and which test checks it.

Each chapter subpackage keeps one table, ``amdo_lab.<method>.equations.EQUATIONS``, mapping every
equation number its notebook cites to an :class:`EquationPath`: the public, documented function that
computes it in plain numpy (its source, or the check-free kernel it calls, carries a ``# eq. (N)``
comment) and the test that calls it and checks its output; or the reason the equation has no code.
The subpackage's docstring shows the table (:func:`with_equation_map`), so a student goes from an
equation number to its code in one step, and ``tests/test_equation_paths.py`` checks the same table
against the notebook, the source and the tests, so the two cannot disagree.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

__all__ = ["EquationPath", "equation_map", "with_equation_map"]


@dataclass(frozen=True)
class EquationPath:
    """Where one equation lives: ``code`` and ``test``, or a ``reason`` it has no code of its own.

    Parameters
    ----------
    code : str, optional
        Dotted name of the public function or method, ``"amdo_lab.<method>.<module>.<name>"``.
    test : str, optional
        Name of the test (in the chapter's test file) that calls ``code`` and checks its output.
    reason : str, optional
        Why the equation has no code (notation, a form only discussed); given instead of the two.
    """

    code: str | None = None
    test: str | None = None
    reason: str | None = None

    def __post_init__(self) -> None:
        if not bool(self.code) == bool(self.test) == (self.reason is None):  # both, or neither and a reason
            raise ValueError("an EquationPath needs code and test, or a reason instead of both")


def equation_map(equations: Mapping[int, EquationPath], test_file: str) -> str:
    """The table as a docstring section (reStructuredText, one bullet per equation).

    Parameters
    ----------
    equations : mapping of int to EquationPath
        The subpackage's table.
    test_file : str
        The chapter's test file under ``tests/``.

    Returns
    -------
    str
        An "Equation map" section.
    """
    lines = ["Equation map", "------------",
             f"Each equation the chapter cites, its code, and its test in ``tests/{test_file}``:", ""]
    for number, path in sorted(equations.items()):
        if path.reason is not None:
            lines.append(f"- eq. ({number}): no code of its own: {path.reason}.")
        else:
            lines.append(f"- eq. ({number}): :func:`{path.code}`, tested by ``{path.test}``.")
    return "\n".join(lines) + "\n"


def with_equation_map(doc: str | None, equations: Mapping[int, EquationPath], test_file: str) -> str:
    """A subpackage docstring with its equation map appended (see :func:`equation_map`)."""
    return (doc or "").rstrip() + "\n\n" + equation_map(equations, test_file)
