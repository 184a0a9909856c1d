"""Student and instructor editions of the chapters, written from the one source in ``notebooks/``.

``python -m amdo_lab editions`` (``make editions``) writes

- ``build/student/``: each chapter without its solutions (every cell tagged ``solution``, which
  covers the whole ``## Solutions`` section) and without the self-test cell (tagged
  ``exercise-selftest``, which needs the solutions), with the outputs of the answer and check
  cells (``exercise-answer``, ``exercise-check``) cleared, so the handed-out notebook shows no
  verdict and no answer. It still runs from top to bottom, every check printing
  "not attempted yet";
- ``build/instructor/``: each chapter as it is, solutions and outputs included.

Both carry the chapter's number in the notebook metadata (``amdo_lab.chapter``), which the grader
(:mod:`amdo_lab.grading`) reads to know which chapter a submission answers. The rewriting is done
with nbformat: a cell's tags decide everything, so no other assignment format is needed (see
CONTRIBUTING.md for why not nbgrader or otter-grader).
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from pathlib import Path

from amdo_lab.chapters import CHAPTERS, Chapter

__all__ = [
    "ANSWER_TAG", "CHECK_TAG", "SELFTEST_TAG", "SOLUTION_TAG", "instructor_edition", "student_edition",
    "write_editions",
]

SOLUTION_TAG = "solution"
SELFTEST_TAG = "exercise-selftest"
ANSWER_TAG = "exercise-answer"
CHECK_TAG = "exercise-check"
_BUILD_DIR = Path(__file__).resolve().parent.parent / "build"


def _tags(cell) -> list[str]:
    return list(cell.get("metadata", {}).get("tags", []))


def _stamp(notebook, chapter: int, edition: str) -> None:
    meta = notebook.metadata.setdefault("amdo_lab", {})
    meta["chapter"] = int(chapter)
    meta["edition"] = edition


def student_edition(notebook, chapter: int):
    """The student edition of a chapter notebook: a new notebook, ``notebook`` is left unchanged.

    Parameters
    ----------
    notebook : nbformat.NotebookNode
        The chapter as committed (instructor edition).
    chapter : int
        The chapter's number, stored as ``metadata.amdo_lab.chapter``.

    Returns
    -------
    nbformat.NotebookNode
        Without ``solution`` and ``exercise-selftest`` cells; answer and check cells without
        outputs or execution counts.
    """
    student = copy.deepcopy(notebook)
    kept = []
    for cell in student.cells:
        tags = _tags(cell)
        if SOLUTION_TAG in tags or SELFTEST_TAG in tags:
            continue
        if cell.cell_type == "code" and (ANSWER_TAG in tags or CHECK_TAG in tags):
            cell.outputs = []
            cell.execution_count = None
        kept.append(cell)
    student.cells = kept
    _stamp(student, chapter, "student")
    return student


def instructor_edition(notebook, chapter: int):
    """The instructor edition: the chapter as it is, with its number in the metadata.

    Parameters
    ----------
    notebook : nbformat.NotebookNode
        The chapter as committed.
    chapter : int
        The chapter's number.

    Returns
    -------
    nbformat.NotebookNode
        A copy of ``notebook`` with ``metadata.amdo_lab.chapter`` set.
    """
    instructor = copy.deepcopy(notebook)
    _stamp(instructor, chapter, "instructor")
    return instructor


def write_editions(build_dir: Path = _BUILD_DIR, chapters: Sequence[Chapter] | None = None) -> dict[str, list[Path]]:
    """Write ``build_dir/student/`` and ``build_dir/instructor/``, one notebook per chapter.

    Parameters
    ----------
    build_dir : pathlib.Path
        Output root.
    chapters : sequence of Chapter, optional
        By default every registered chapter whose notebook exists.

    Returns
    -------
    dict
        ``{"student": [paths], "instructor": [paths]}``.
    """
    import nbformat

    if chapters is None:
        chapters = [chapter for chapter in CHAPTERS if chapter.path.exists()]
    written: dict[str, list[Path]] = {"student": [], "instructor": []}
    for edition, make in (("student", student_edition), ("instructor", instructor_edition)):
        folder = Path(build_dir) / edition
        folder.mkdir(parents=True, exist_ok=True)
        for chapter in chapters:
            notebook = nbformat.read(chapter.path, as_version=4)
            target = folder / chapter.notebook
            nbformat.write(make(notebook, chapter.number), target)
            written[edition].append(target)
    return written
