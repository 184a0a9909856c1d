"""The exercise cells of a chapter's source notebook, and the targets its hidden tests register.

A source notebook (``notebooks/NN_*.ipynb``) marks its exercise cells with tags and
``metadata.amdo_lab.exercise`` (see :mod:`amdo_lab.common.exercises`); the check cells register
each target in a hidden test::

    ### BEGIN HIDDEN TESTS
    EXERCISES.expect(1, 0.0314)
    ### END HIDDEN TESTS
    EXERCISES.check(1, answer_1)

:func:`hidden_targets` reads those literals with :func:`ast.literal_eval`, so the grader and the
leak test know every target without running the notebook.
"""

from __future__ import annotations

import ast
import re

__all__ = [
    "ANSWER_TAG", "CHECK_TAG", "HIDDEN_BEGIN", "HIDDEN_END", "SELFTEST_TAG", "SOLUTION_TAG", "WHY_TAG",
    "exercise_of", "hidden_block", "hidden_targets", "tags",
]

SOLUTION_TAG = "solution"
SELFTEST_TAG = "exercise-selftest"
ANSWER_TAG = "exercise-answer"
CHECK_TAG = "exercise-check"
WHY_TAG = "exercise-why"
HIDDEN_BEGIN = "### BEGIN HIDDEN TESTS"
HIDDEN_END = "### END HIDDEN TESTS"
_HIDDEN = re.compile(re.escape(HIDDEN_BEGIN) + r"\n(.*?)" + re.escape(HIDDEN_END) + r"\n?", re.S)


def tags(cell) -> list[str]:
    """The cell's tags."""
    return list(cell.get("metadata", {}).get("tags", []))


def exercise_of(cell) -> int | None:
    """The exercise a cell belongs to (``metadata.amdo_lab.exercise``), or None."""
    value = cell.get("metadata", {}).get("amdo_lab", {}).get("exercise")
    return value if isinstance(value, int) and not isinstance(value, bool) else None


def hidden_block(source: str) -> str | None:
    """The text between the hidden-test delimiters of a check cell's source, or None."""
    match = _HIDDEN.search(source)
    return match.group(1) if match else None


def hidden_targets(notebook) -> dict[int, tuple[str, object]]:
    """Every target the check cells' hidden tests register: ``{k: ("value", target) | ("seeds", seeds)}``.

    Parameters
    ----------
    notebook : nbformat.NotebookNode
        A source notebook.

    Returns
    -------
    dict
        Exercise number to what ``EXERCISES.expect`` registers, parsed as literals (a check whose
        hidden test computes its target is left out: it has no literal target).
    """
    found: dict[int, tuple[str, object]] = {}
    for cell in notebook.cells:
        if cell.cell_type != "code" or CHECK_TAG not in tags(cell):
            continue
        block = hidden_block(cell.source)
        if block is None:
            continue
        try:
            statements = ast.parse(block).body
        except SyntaxError:
            continue
        for statement in statements:
            call = statement.value if isinstance(statement, ast.Expr) else None
            if not (isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute)
                    and call.func.attr == "expect" and call.args):
                continue
            try:
                number = ast.literal_eval(call.args[0])
                keywords = {kw.arg: ast.literal_eval(kw.value) for kw in call.keywords}
                if "seeds" in keywords:
                    found[int(number)] = ("seeds", tuple(int(seed) for seed in keywords["seeds"]))
                elif len(call.args) > 1:
                    found[int(number)] = ("value", ast.literal_eval(call.args[1]))
            except (ValueError, TypeError, SyntaxError):
                continue
    return found
