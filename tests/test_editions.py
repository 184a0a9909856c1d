"""Student and instructor editions: written from the one source, nothing of a solution left.

The student edition of every chapter is checked without executing it (too slow for every
chapter): the solutions sit at the end of each notebook, so executing the instructor notebook
(nbval does) shows the student edition runs; the grader's test executes student editions.
"""

from __future__ import annotations

import subprocess
import sys

import nbformat
import pytest

from amdo_lab.chapters import available_chapters
from amdo_lab.editions import ANSWER_TAG, CHECK_TAG, SELFTEST_TAG, SOLUTION_TAG, student_edition, write_editions


def _tags(cell) -> list[str]:
    return cell.metadata.get("tags", [])


@pytest.fixture(scope="module")
def editions(tmp_path_factory):
    build = tmp_path_factory.mktemp("editions")
    completed = subprocess.run([sys.executable, "-m", "amdo_lab", "editions", "--out", str(build)],
                               capture_output=True, text=True, timeout=300)
    assert completed.returncode == 0, completed.stderr
    assert "student edition" in completed.stdout and "instructor edition" in completed.stdout
    return build


@pytest.mark.parametrize("chapter", available_chapters(), ids=lambda chapter: chapter.slug)
def test_student_edition_has_no_solution_and_keeps_every_answer_and_check(editions, chapter):
    source = nbformat.read(chapter.path, as_version=4)
    student = nbformat.read(editions / "student" / chapter.notebook, as_version=4)
    instructor = nbformat.read(editions / "instructor" / chapter.notebook, as_version=4)
    assert student.metadata["amdo_lab"]["chapter"] == chapter.number
    assert instructor.metadata["amdo_lab"]["chapter"] == chapter.number
    assert [cell.source for cell in instructor.cells] == [cell.source for cell in source.cells]
    solutions = [cell for cell in source.cells if SOLUTION_TAG in _tags(cell) or SELFTEST_TAG in _tags(cell)]
    student_text = "\n".join(cell.source for cell in student.cells)
    for cell in solutions:
        assert cell.id not in {kept.id for kept in student.cells}
        if cell.cell_type != "markdown":  # code is checked by the cell ids: a call may recur in the chapter
            continue
        lines = [line for line in cell.source.splitlines() if len(line.strip()) > 30 and not line.startswith("#")]
        leaked = [line for line in lines if line in student_text]
        assert not leaked, f"solution text left in the student edition: {leaked[:2]}"
    for tag in (ANSWER_TAG, CHECK_TAG):
        wanted = [cell.id for cell in source.cells if tag in _tags(cell)]
        kept = [cell for cell in student.cells if tag in _tags(cell)]
        assert [cell.id for cell in kept] == wanted
        assert all(not cell.outputs and cell.execution_count is None for cell in kept)
    assert len(student.cells) == len(source.cells) - len(solutions)


def test_solutions_section_is_last_so_the_student_edition_is_a_prefix():
    """Removing the solutions removes a tail: what the student edition runs, the instructor's ran first."""
    for chapter in available_chapters():
        notebook = nbformat.read(chapter.path, as_version=4)
        tagged = [i for i, cell in enumerate(notebook.cells)
                  if SOLUTION_TAG in _tags(cell) or SELFTEST_TAG in _tags(cell)]
        if tagged:
            assert tagged == list(range(tagged[0], len(notebook.cells))), \
                f"chapter {chapter.number}: a cell after the Solutions section is not tagged 'solution'"


def test_editions_leave_the_source_untouched_and_write_both_folders(tmp_path):
    chapter = available_chapters()[0]
    notebook = nbformat.read(chapter.path, as_version=4)
    before = nbformat.writes(notebook)
    student_edition(notebook, chapter.number)
    assert nbformat.writes(notebook) == before
    written = write_editions(tmp_path, [chapter])
    assert [path.parent.name for path in written["student"] + written["instructor"]] == ["student", "instructor"]
