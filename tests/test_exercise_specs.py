"""Every chapter's exercises are specified as data and wired into its notebook the same way.

The checks' verdicts themselves are tested inside each notebook: its last cell (tagged
``exercise-selftest``) feeds every check the placeholder, each recorded wrong answer and the
solution, and raises on a wrong verdict, so nbval fails. This module checks, without executing
anything, that every chapter has that cell and the cells the release and the grader rely on (answer,
check and "why" cells, hidden tests, rubrics).
"""

from __future__ import annotations

import ast
import importlib
import re

import nbformat
import pytest

from amdo_lab.chapters import available_chapters
from amdo_lab.common.exercises import ExerciseSet

CHAPTERS = available_chapters()


def _tags(cell) -> set[str]:
    return set(cell.get("metadata", {}).get("tags", []))


def _exercise(cell) -> int | None:
    return cell.get("metadata", {}).get("amdo_lab", {}).get("exercise")


@pytest.fixture(scope="module", params=CHAPTERS, ids=lambda chapter: f"chapter{chapter.number}")
def chapter_and_notebook(request):
    chapter = request.param
    return chapter, nbformat.read(chapter.path, as_version=4)


def test_every_chapter_names_an_exercise_set_with_recorded_wrong_answers(chapter_and_notebook):
    chapter, _ = chapter_and_notebook
    exercises = importlib.import_module(chapter.exercises).EXERCISES
    assert isinstance(exercises, ExerciseSet) and exercises.chapter == chapter.number
    assert all(len(exercise.wrong_answers) >= 2 for exercise in exercises.exercises)
    if chapter.number >= 1:  # TEACHING.md: at least four exercises, two of them experiments
        assert len(exercises) >= 4
        assert sum(exercise.experiment for exercise in exercises.exercises) >= 2
    for exercise in exercises.exercises:
        if exercise.experiment:
            assert any(wrong.unchanged_experiment for wrong in exercise.wrong_answers), exercise.number


def test_each_exercise_has_one_answer_cell_one_check_cell_and_a_solution(chapter_and_notebook):
    chapter, notebook = chapter_and_notebook
    exercises = importlib.import_module(chapter.exercises).EXERCISES
    for exercise in exercises.exercises:
        k = exercise.number
        answers = [cell for cell in notebook.cells if "exercise-answer" in _tags(cell) and _exercise(cell) == k]
        checks = [cell for cell in notebook.cells if "exercise-check" in _tags(cell) and _exercise(cell) == k]
        assert len(answers) == 1 and re.search(rf"^answer_{k} = None", answers[0].source, re.M), \
            f"exercise {k}: one answer cell with the placeholder answer_{k} = None"
        assert len(checks) == 1, f"exercise {k}: one check cell"
        source = checks[0].source
        hidden = re.search(r"### BEGIN HIDDEN TESTS\n(.*?)### END HIDDEN TESTS\n?", source, re.S)
        visible = source.replace(hidden.group(0), "") if hidden else source
        calls = ast.parse(visible).body
        assert len(calls) == 1 and visible.lstrip().startswith(f"EXERCISES.check({k}, answer_{k}"), \
            f"exercise {k}: the check cell's visible part is the one call EXERCISES.check({k}, answer_{k}, ...)"
        if exercise.expected is None:  # the target lives in the hidden test only
            assert hidden and re.fullmatch(rf"\s*EXERCISES\.expect\({k}, .*\)\s*", hidden.group(1), re.S), \
                f"exercise {k}: the hidden test is the one call EXERCISES.expect({k}, ...)"
        solutions = [cell for cell in notebook.cells if "solution" in _tags(cell) and cell.cell_type == "code"]
        assert any(re.search(rf"^(solution_{k}\b.*=|def solution_{k}\()", cell.source, re.M) for cell in solutions), \
            f"exercise {k}: a solution cell stores solution_{k} (an 'implement it' solution defines it)"


def test_solutions_never_overwrite_the_readers_answers(chapter_and_notebook):
    _, notebook = chapter_and_notebook
    for cell in notebook.cells:
        if "solution" in _tags(cell) and cell.cell_type == "code":
            assert not re.search(r"^\s*answer_\d+\s*=", cell.source, re.M), cell.source[:200]


def test_the_last_cell_self_tests_every_check(chapter_and_notebook):
    _, notebook = chapter_and_notebook
    last = notebook.cells[-1]
    assert {"exercise-selftest", "remove-cell"} <= _tags(last)
    assert "EXERCISES.assert_checks(globals())" in last.source


def test_why_cells_are_markdown_after_their_check_with_a_rubric_in_the_solutions(chapter_and_notebook):
    chapter, notebook = chapter_and_notebook
    exercises = importlib.import_module(chapter.exercises).EXERCISES
    cells = notebook.cells
    for exercise in exercises.exercises:
        k = exercise.number
        whys = [i for i, cell in enumerate(cells) if "exercise-why" in _tags(cell) and _exercise(cell) == k]
        assert len(whys) == (1 if exercise.why_points else 0), \
            f"exercise {k}: one 'why' cell exactly when why_points is set (why_points={exercise.why_points})"
        if not whys:
            continue
        why = cells[whys[0]]
        assert why.cell_type == "markdown" and why.source.startswith("**Why?** ") and "*Your answer:*" in why.source, \
            f"exercise {k}: the why cell is markdown, '**Why?** question' then '*Your answer:*'"
        before = cells[whys[0] - 1]
        assert "exercise-check" in _tags(before) and _exercise(before) == k, \
            f"exercise {k}: the why cell comes right after the check cell"
        rubrics = [cell for cell in cells if "solution" in _tags(cell) and cell.cell_type == "markdown"
                   and f"*Rubric (why, {k}):*" in cell.source]
        assert len(rubrics) == 1, f"exercise {k}: one '*Rubric (why, {k}):*' in the Solutions section"


def test_new_exercises_check_with_the_answer_alone(chapter_and_notebook):
    chapter, notebook = chapter_and_notebook
    exercises = importlib.import_module(chapter.exercises).EXERCISES
    for exercise in exercises.exercises:
        if exercise.expected is not None:
            continue  # older exercises pass notebook objects as context
        k = exercise.number
        check = next(cell for cell in notebook.cells if "exercise-check" in _tags(cell) and _exercise(cell) == k)
        assert check.source.rstrip().endswith(f"EXERCISES.check({k}, answer_{k})"), \
            f"exercise {k}: the check's visible line is EXERCISES.check({k}, answer_{k}), no context"
