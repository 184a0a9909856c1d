"""The grader: a folder of submissions for two chapters, graded with the chapters' own checks.

For each chapter of :data:`GRADED_CHAPTERS` the test hands in five notebooks made from the
chapter's student edition: a blank one, one with a recorded wrong answer in every answer cell, one
with the right answers, one with only exercise 1 right and every check cell edited to print
"correct" (a tampered notebook), and one whose first answer cell raises. The answers are written
generically from the chapter's ``EXERCISES``, in the answer cells themselves: a wrong answer is the
first recorded :class:`WrongAnswer`, resolved in the kernel from the notebook's objects; the right
one is the value the check itself expects (``Exercise.target``), which every solution ``solution_k``
must match. Bad input sits in the same folder: a file that is not a notebook, a notebook whose
metadata names a chapter its file name contradicts, and one that cannot be matched to any chapter.

Five executions of each chapter run over two workers; chapter 0 takes about half a minute.
"""

from __future__ import annotations

import csv
import importlib

import nbformat
import pytest

from amdo_lab.chapters import find_chapter
from amdo_lab.editions import ANSWER_TAG, CHECK_TAG, student_edition
from amdo_lab.grading import grade_folder, grade_notebook, identify_chapter, summary_table

#: The two chapters whose submissions are graded (chapter 0 and one method chapter).
GRADED_CHAPTERS = (0, 4)
WORKERS = 2


def _exercise_set(number: int):
    chapter = find_chapter(number)
    try:
        return importlib.import_module(chapter.exercises).EXERCISES
    except ModuleNotFoundError:
        pytest.skip(f"chapter {number} has no exercise module ({chapter.exercises}) in this checkout")


def _answer_cells(notebook):
    return [cell for cell in notebook.cells
            if ANSWER_TAG in cell.metadata.get("tags", []) and cell.metadata.get("amdo_lab", {}).get("exercise")]


def _number(cell) -> int:
    return cell.metadata["amdo_lab"]["exercise"]


def _right(k: int) -> str:
    return (f"_target = EXERCISES[{k}].target(globals())\n"
            f"answer_{k} = sorted(_target)[0] if isinstance(_target, (set, frozenset)) else _target\n"
            f"assert not callable(answer_{k}), 'exercise {k}: a predicate check needs a constructed answer'")


def _wrong(k: int) -> str:
    return f"answer_{k} = EXERCISES[{k}].wrong_answers[0].resolve(globals())"


def _submission(number: int, kind: str):
    """The student edition of chapter ``number`` answered as ``kind`` says."""
    chapter = find_chapter(number)
    notebook = student_edition(nbformat.read(chapter.path, as_version=4), number)
    first = min(_number(cell) for cell in _answer_cells(notebook))
    for cell in _answer_cells(notebook):
        k, original = _number(cell), cell.source
        if kind == "wrong" or (kind == "tampered" and k != first):
            cell.source = original + "\n" + _wrong(k)
        elif kind in ("right", "tampered") or (kind == "raises" and k != first):
            cell.source = original + "\n" + _right(k)
        elif kind == "raises":
            cell.source = "raise RuntimeError('a bug in my answer')"
    if kind == "tampered":
        for cell in notebook.cells:
            if CHECK_TAG in cell.metadata.get("tags", []):
                cell.source = "print('correct')"
    return notebook


@pytest.fixture(scope="module")
def graded(tmp_path_factory):
    folder = tmp_path_factory.mktemp("submissions")
    expected = {}
    for number in GRADED_CHAPTERS:
        try:
            exercises = importlib.import_module(find_chapter(number).exercises).EXERCISES
        except ModuleNotFoundError:
            continue  # reported by test_every_graded_chapter_is_converted
        slug = find_chapter(number).slug
        full = sum(exercise.points for exercise in exercises.exercises)
        first = exercises.exercises[0].points
        for kind, total in (("blank", 0), ("wrong", 0), ("right", full), ("tampered", first),
                            ("raises", full - first)):
            name = f"{slug}_{kind}.ipynb"
            notebook = _submission(number, "blank" if kind == "blank" else kind)
            nbformat.write(notebook, folder / name)
            expected[name] = (number, total, len(exercises))
    (folder / "notes.txt").write_text("my answers are in the notebook\n")
    if expected:
        number = next(iter(expected.values()))[0]
        other = next(n for n in (4, 1, 2, 0) if n != number)
        mislabelled = _submission(number, "right")
        nbformat.write(mislabelled, folder / f"{find_chapter(other).slug}_mislabelled.ipynb")
        stray = nbformat.v4.new_notebook()
        stray.cells = [nbformat.v4.new_code_cell("answer_1 = 3")]
        nbformat.write(stray, folder / "homework.ipynb")
    rows, csv_path = grade_folder(folder, timeout_s=300, workers=WORKERS, progress=False)
    with csv_path.open(newline="") as handle:
        table = list(csv.DictReader(handle))
    return rows, table, expected, csv_path


def test_every_graded_chapter_is_converted():
    for number in GRADED_CHAPTERS:
        _exercise_set(number)


def test_grades_csv_gives_zero_zero_full_the_true_score_and_an_error_line(graded):
    rows, table, expected, csv_path = graded
    assert csv_path.name == "grades.csv" and list(table[0]) == ["file", "chapter", "exercise", "verdict", "points"]
    assert expected, "no graded chapter has an exercise module"
    for name, (number, total, n_exercises) in expected.items():
        mine = [row for row in table if row["file"] == name]
        graded_rows = [row for row in mine if row["exercise"]]
        assert len(graded_rows) == n_exercises, (name, mine)
        assert all(row["chapter"] == str(number) for row in mine)
        assert sum(int(row["points"]) for row in mine) == total, (name, mine)
        if name.endswith("_blank.ipynb"):
            assert all(row["verdict"] == "not attempted yet" for row in graded_rows), mine
        if name.endswith("_wrong.ipynb"):
            assert all(row["verdict"].startswith("not yet:") for row in graded_rows), mine
        if name.endswith("_raises.ipynb"):
            errors = [row for row in graded_rows if row["verdict"].startswith("error:")]
            assert len(errors) == 1 and "RuntimeError: a bug in my answer" in errors[0]["verdict"], mine


def test_bad_input_gets_a_clear_line_and_nothing_is_lost(graded):
    rows, table, expected, _ = graded
    by_file = {}
    for row in table:
        by_file.setdefault(row["file"], []).append(row)
    assert set(expected) | {"notes.txt", "homework.ipynb"} <= set(by_file)
    assert by_file["notes.txt"][0]["verdict"].startswith("error: not a notebook")
    assert "cannot tell which chapter" in by_file["homework.ipynb"][0]["verdict"]
    mislabelled = [name for name in by_file if name.endswith("_mislabelled.ipynb")]
    assert len(mislabelled) == 1
    assert "but its file name says chapter" in by_file[mislabelled[0]][0]["verdict"]
    summary = summary_table(rows)
    assert all(name in summary for name in by_file)


def test_a_notebook_of_another_chapter_is_not_graded_as_this_one(tmp_path):
    exercises = _exercise_set(0)
    notebook = _submission(0, "right")
    del notebook.metadata["amdo_lab"]["chapter"]
    other = 4
    path = tmp_path / f"{find_chapter(other).slug}_alice.ipynb"
    nbformat.write(notebook, path)
    chapter, _ = identify_chapter(notebook, path.name)
    assert chapter.number == other  # the file name is all there is to go by
    rows = grade_notebook(path, timeout_s=60)
    assert len(rows) == 1 and rows[0].is_error and "does not match chapter" in rows[0].verdict, rows
    assert len(exercises) >= 1


def test_command_line_grades_a_folder_and_refuses_a_missing_one(tmp_path):
    import subprocess
    import sys

    (tmp_path / "notes.txt").write_text("not a notebook")
    done = subprocess.run([sys.executable, "-m", "amdo_lab", "grade", str(tmp_path), "--no-progress",
                           "--out", str(tmp_path / "out" / "marks.csv")], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert "notes.txt" in done.stdout and "not a notebook" in done.stdout
    with (tmp_path / "out" / "marks.csv").open(newline="") as handle:
        assert [row["verdict"][:21] for row in csv.DictReader(handle)] == ["error: not a notebook"]
    missing = subprocess.run([sys.executable, "-m", "amdo_lab", "grade", str(tmp_path / "nowhere")],
                             capture_output=True, text=True, timeout=120)
    assert missing.returncode == 2 and missing.stderr.count("\n") == 1 and "is not a folder" in missing.stderr


def test_a_notebook_over_its_time_budget_gets_error_lines_for_every_exercise(tmp_path):
    exercises = _exercise_set(0)
    notebook = _submission(0, "blank")
    _answer_cells(notebook)[0].source = "import time\ntime.sleep(600)"
    path = tmp_path / "00_introduction_slow.ipynb"
    nbformat.write(notebook, path)
    rows = grade_notebook(path, timeout_s=8)
    assert [row.exercise for row in rows] == [exercise.number for exercise in exercises.exercises] + [""]
    assert all(row.is_error and row.points == 0 for row in rows), rows
    assert "did not finish within 8 s" in rows[-1].verdict
