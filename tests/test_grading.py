"""The grader: a folder of submissions graded by nbgrader, the verdicts computed outside the kernel.

The folder holds, for chapter 0 (the one chapter on the new exercise format in this branch; its
exercises take a number, a word and, for "implement it", a function), made from the release: a
blank notebook, recorded wrong answers, an answer cell that rebinds ``EXERCISES`` to an object
whose ``check`` prints "correct", one that rebinds ``builtins.abs``, ``math.isclose`` and
``numpy.isclose``/``numpy.allclose`` (with wrong answers), one whose check cell 3 was edited to
hold the answer, the instructor's solutions put in the answer cells in a per-student subfolder
(``alice/``), a text file named ``.ipynb`` and an endless loop. Their rows must read 0, 0,
0 + flag, 0 + flag, flag (and 0 for that exercise), full marks under the student's name, an error
line and "did not finish". A manual "why" mark set through nbgrader's gradebook API must appear in
the export.

Seven notebooks run over two workers (the loop sleeps through its budget).
"""

from __future__ import annotations

import csv
import os
import subprocess
import sys

import nbformat
import pytest

from amdo_lab.chapters import find_chapter
from amdo_lab.course.cells import ANSWER_TAG, CHECK_TAG, SOLUTION_TAG, WHY_TAG, exercise_of, tags
from amdo_lab.course.grading import COURSE_DIR, _ensure_assignment, export_grades, grade_folder, summary_table

CHAPTER = 0
#: Seconds of execution per notebook (the endless loop costs this much); a loaded machine may need
#: more: AMDO_TEST_GRADE_TIMEOUT=300.
TIMEOUT_S = int(os.environ.get("AMDO_TEST_GRADE_TIMEOUT", "60"))
WORKERS = 2


def _solution_code(source) -> dict[int, str]:
    """The Solutions section's code for each exercise, in order (the markdown ``### Exercise k`` opens it)."""
    code: dict[int, list[str]] = {}
    current = None
    for cell in source.cells:
        if SOLUTION_TAG not in tags(cell):
            continue
        if cell.cell_type == "markdown":
            for line in cell.source.splitlines():
                if line.startswith("### Exercise "):
                    current = int(line.split()[2])
        elif current is not None:
            code.setdefault(current, []).append(cell.source)
    return {k: "\n".join(parts) for k, parts in code.items()}


def _cells(notebook, tag):
    return {exercise_of(cell): cell for cell in notebook.cells if tag in tags(cell) and exercise_of(cell)}


@pytest.fixture(scope="module")
def graded(tmp_path_factory):
    chapter = find_chapter(CHAPTER)
    folder = tmp_path_factory.mktemp("submissions")
    _ensure_assignment(folder / COURSE_DIR, chapter)  # the grader finds it done and reuses it
    release = nbformat.read(folder / COURSE_DIR / "release" / "ch00" / chapter.notebook, as_version=4)
    solutions = _solution_code(nbformat.read(chapter.path, as_version=4))

    def make(name, answers=None, checks=None, whys=None):
        notebook = nbformat.reads(nbformat.writes(release), as_version=4)
        for k, text in (answers or {}).items():
            cell = _cells(notebook, ANSWER_TAG)[k]
            cell.source = cell.source.rstrip() + "\n" + text
        for k, text in (checks or {}).items():
            _cells(notebook, CHECK_TAG)[k].source = text
        for k, text in (whys or {}).items():
            cell = _cells(notebook, WHY_TAG)[k]
            cell.source = cell.source.rstrip() + "\n\n" + text
        path = folder / name
        path.parent.mkdir(exist_ok=True)
        nbformat.write(notebook, path)

    right = {k: f"{code}\nanswer_{k} = solution_{k}" for k, code in solutions.items()}
    make("blank.ipynb")
    make("alice/00_introduction.ipynb", right, whys={2: "Away: 4 of 24 directions instead of 4 of 120."})
    make("wrong.ipynb", {1: "answer_1 = 0.0283", 2: "answer_2 = 0.0268", 3: 'answer_3 = "60 points"',
                         4: "answer_4 = lambda source, target: 1.0"})
    make("fake_exercises.ipynb", {1: "class _Always:\n    def check(self, *args, **kwargs):\n        print('correct')\n"
                                     "EXERCISES = _Always()\nanswer_1 = 0.5"})
    make("patched_builtins.ipynb", {1: "import builtins, math\nimport numpy\nbuiltins.abs = lambda x: 0\n"
                                       "math.isclose = lambda *a, **k: True\nnumpy.isclose = lambda *a, **k: True\n"
                                       "numpy.allclose = lambda *a, **k: True\nanswer_1 = 0.5"})
    make("edited_check.ipynb", {k: text for k, text in right.items() if k != 3},
         checks={3: 'answer_3 = "12 points"\nprint("correct")'})
    loop = nbformat.v4.new_notebook(metadata={"amdo_lab": {"chapter": CHAPTER}})
    loop.cells = [nbformat.v4.new_code_cell("import time\nwhile True:\n    time.sleep(1)")]
    nbformat.write(loop, folder / "loop.ipynb")
    (folder / "notes.ipynb").write_text("my answers are 0.03 and 12 points\n", encoding="utf-8")
    results, csv_path = grade_folder(folder, timeout_s=TIMEOUT_S, workers=WORKERS, progress=False)
    return folder, results, csv_path


def _rows(csv_path):
    with csv_path.open(encoding="utf-8") as handle:
        return {row["student"]: row for row in csv.DictReader(handle)}


def test_every_submission_gets_the_row_it_should(graded):
    folder, results, csv_path = graded
    rows = _rows(csv_path)
    table = summary_table(results)
    assert set(rows) == {"blank", "wrong", "fake_exercises", "patched_builtins", "edited_check", "alice",
                         "loop", "notes"}, table
    full = {"ex1": "1", "ex2": "2", "ex3": "1", "ex4": "1"}
    assert {key: rows["alice"][key] for key in full} == full, table  # graded under the folder's name
    assert rows["alice"]["maximum"] == "7" and rows["alice"]["chapter"] == "0"
    assert rows["alice"]["ex2_why"] == "" and "1 why answer(s) to mark" in table, table
    for name in ("blank", "wrong", "fake_exercises", "patched_builtins"):
        assert rows[name]["total"] == "0", (name, table)
    assert rows["blank"]["flags"] == "" and rows["wrong"]["flags"] == "", table
    assert "rebinds EXERCISES" in rows["fake_exercises"]["flags"], table
    assert "builtins.abs" in rows["patched_builtins"]["flags"], table
    assert "math.isclose" in rows["patched_builtins"]["flags"], table
    edited = rows["edited_check"]
    assert edited["ex3"] == "0" and edited["ex1"] == "1" and edited["ex4"] == "1", table
    assert "no answer in the answer cell; the check cell was edited" in edited["flags"], table
    assert "not a notebook" in rows["notes"]["flags"] and rows["notes"]["total"] == "", table
    assert f"did not finish within {TIMEOUT_S} s" in rows["loop"]["flags"], table
    assert "Traceback" not in "".join(row["flags"] for row in rows.values())


def test_verdicts_and_feedback_pages(graded):
    folder, results, _ = graded
    by_student = {result.student: result for result in results}
    assert set(by_student["blank"].verdicts.values()) == {"not attempted yet"}
    assert by_student["wrong"].verdicts[1].startswith("not yet: that is the residual of the true transform")
    assert by_student["wrong"].verdicts[4].startswith("not yet")
    page = (folder / "feedback" / "alice" / "ch00_00_introduction.html").read_text(encoding="utf-8")
    assert "Exercise 4" in page


def test_a_manual_why_mark_reaches_the_gradebook_export(graded):
    from nbgrader.api import Gradebook

    folder, _, _ = graded
    with Gradebook(f"sqlite:///{folder / COURSE_DIR / 'gradebook.db'}") as gradebook:
        grade = gradebook.find_grade("why-2", "00_introduction", "ch00", "alice")
        grade.manual_score = 1.0
        gradebook.db.commit()
    _, csv_path = export_grades(folder)
    row = _rows(csv_path)["alice"]
    assert row["ex2_why"] == "1" and row["total"] == "6", row
    assert _rows(csv_path)["blank"]["ex2_why"] in ("0", "")


def test_the_command_exits_non_zero_when_nothing_could_be_graded(tmp_path):
    (tmp_path / "a.ipynb").write_text("not json", encoding="utf-8")
    completed = subprocess.run([sys.executable, "-m", "amdo_lab", "grade", str(tmp_path), "--no-progress"],
                               capture_output=True, text=True, timeout=300)
    assert completed.returncode == 1, completed.stdout + completed.stderr
    assert "not a notebook" in completed.stdout and "Traceback" not in completed.stderr
