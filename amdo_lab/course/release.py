"""The student release of the chapters, in nbgrader's own course layout.

``python -m amdo_lab release [--chapter N]`` writes, under a course root (``build/`` by default):

- ``source/chNN/<notebook>.ipynb``: the chapter as nbgrader's instructor version: the source
  notebook without its ``## Solutions`` section (cells tagged ``solution``) and self-test cell,
  with nbgrader metadata on every cell:

  * answer cells (``exercise-answer``): unlocked solution cells (the reader edits them);
  * check cells (``exercise-check``): locked autograder-test cells worth the exercise's points,
    whose ``### BEGIN HIDDEN TESTS`` block holds the target;
  * "why" cells (``exercise-why``): manually graded answer cells worth ``why_points``;
  * every other cell: locked (read-only, with a checksum), so an edit is detected at grading;

- ``release/chNN/<notebook>.ipynb``: what students get, made by nbgrader's ``generate_assignment``
  from the source version: hidden tests stripped, checksums computed, answer and check cells
  without outputs (the other cells keep theirs, so the student book shows the figures);
- ``gradebook.db``: nbgrader's gradebook with the assignment's cells and points.

The release runs top to bottom with every check printing "not attempted yet". nbgrader's own
commands work on that root (``nbgrader autograde chNN --CourseDirectory.root=build``), and
:mod:`amdo_lab.course.grading` wraps them.
"""

from __future__ import annotations

import copy
import importlib
import os
import shutil
import sys
from collections.abc import Sequence
from pathlib import Path

from amdo_lab.chapters import CHAPTERS, Chapter
from amdo_lab.course.cells import ANSWER_TAG, CHECK_TAG, SELFTEST_TAG, SOLUTION_TAG, WHY_TAG, exercise_of, tags

__all__ = ["BUILD_DIR", "RELEASE_TAG", "assignment_name", "course_config", "nbgrader_source", "write_release"]

BUILD_DIR = Path(__file__).resolve().parents[2] / "build"
#: The notebook metadata's ``amdo_lab.edition`` of a release notebook.
RELEASE_TAG = "release"
_SOLUTION_REGION = "\n### BEGIN SOLUTION\n### END SOLUTION"


def assignment_name(chapter: Chapter | int) -> str:
    """nbgrader's assignment name of a chapter: ``ch00``, ``ch01``, ..."""
    number = chapter if isinstance(chapter, int) else chapter.number
    return f"ch{number:02d}"


def _venv_on_path() -> None:
    """Put this interpreter's ``bin/`` on PATH: nbgrader runs the ``alembic`` command found there."""
    folder = str(Path(sys.executable).parent)
    if folder not in os.environ.get("PATH", "").split(os.pathsep):
        os.environ["PATH"] = folder + os.pathsep + os.environ.get("PATH", "")


def course_config(root: Path | str, **extra):
    """The nbgrader configuration of a course root (solution stubs empty, outputs kept)."""
    from traitlets.config import Config

    _venv_on_path()
    config = Config()
    config.CourseDirectory.root = str(Path(root).resolve())
    config.CourseDirectory.db_url = f"sqlite:///{Path(root).resolve() / 'gradebook.db'}"
    config.ClearSolutions.code_stub = {"python": ""}
    config.ClearSolutions.text_stub = ""
    config.ClearOutput.enabled = False  # answer and check outputs are cleared here; figures stay
    exchange = Path(root).resolve() / "exchange"  # unused (no hand-in server), but nbgrader checks it exists
    exchange.mkdir(parents=True, exist_ok=True)
    config.Exchange.root = str(exchange)
    for key, value in extra.items():
        section, name = key.split(".", 1)
        setattr(config[section], name, value)
    return config


def _nbgrader(cell, grade_id: str, *, solution=False, grade=False, locked=False, points=None) -> None:
    meta = {"grade": grade, "grade_id": grade_id, "locked": locked, "schema_version": 3,
            "solution": solution, "task": False}
    if grade:
        meta["points"] = int(points)
    cell.metadata["nbgrader"] = meta


def nbgrader_source(notebook, chapter: Chapter):
    """nbgrader's instructor version of a chapter: a new notebook (``notebook`` is left unchanged).

    Parameters
    ----------
    notebook : nbformat.NotebookNode
        The chapter's source notebook.
    chapter : Chapter
        Its registry entry (the exercise module gives the points).

    Returns
    -------
    nbformat.NotebookNode
        Without solutions and self-test; every cell with nbgrader metadata.
    """
    exercises = importlib.import_module(chapter.exercises).EXERCISES if chapter.exercises else None
    marked = copy.deepcopy(notebook)
    kept = []
    for index, cell in enumerate(marked.cells):
        cell_tags, number = tags(cell), exercise_of(cell)
        if SOLUTION_TAG in cell_tags or SELFTEST_TAG in cell_tags:
            continue
        cell.metadata.pop("nbgrader", None)
        if number is not None and exercises is not None and ANSWER_TAG in cell_tags and cell.cell_type == "code":
            cell.source = cell.source.rstrip("\n") + _SOLUTION_REGION
            _nbgrader(cell, f"answer-{number}", solution=True)
        elif number is not None and exercises is not None and CHECK_TAG in cell_tags and cell.cell_type == "code":
            _nbgrader(cell, f"check-{number}", grade=True, locked=True, points=exercises[number].points)
        elif number is not None and exercises is not None and WHY_TAG in cell_tags:
            _nbgrader(cell, f"why-{number}", solution=True, grade=True,
                      points=max(1, exercises[number].why_points))
            cell.source = cell.source.rstrip("\n") + _SOLUTION_REGION
        else:
            _nbgrader(cell, f"locked-{index:03d}", locked=True)
        if cell.cell_type == "code" and (ANSWER_TAG in cell_tags or CHECK_TAG in cell_tags):
            cell.outputs, cell.execution_count = [], None
        kept.append(cell)
    marked.cells = kept
    meta = marked.metadata.setdefault("amdo_lab", {})
    meta["chapter"] = int(chapter.number)
    meta["edition"] = RELEASE_TAG
    return marked


def write_release(chapters: Sequence[Chapter] | None = None, root: Path | str = BUILD_DIR) -> list[Path]:
    """Write the nbgrader source and the student release of ``chapters`` under ``root``.

    Parameters
    ----------
    chapters : sequence of Chapter, optional
        By default every registered chapter whose notebook exists.
    root : pathlib.Path or str
        The course root (``build/`` by default): ``source/``, ``release/`` and ``gradebook.db``.

    Returns
    -------
    list of pathlib.Path
        The release notebooks written.

    Raises
    ------
    RuntimeError
        When nbgrader's ``generate_assignment`` fails (its log is in the message).
    """
    import nbformat
    from nbgrader.apps import NbGraderAPI
    from nbgrader.coursedir import CourseDirectory

    root = Path(root)
    if chapters is None:
        chapters = [chapter for chapter in CHAPTERS if chapter.path.exists()]
    config = course_config(root)
    api = NbGraderAPI(CourseDirectory(config=config), config=config)
    written = []
    for chapter in chapters:
        name = assignment_name(chapter)
        source_dir = root / "source" / name
        if source_dir.exists():
            shutil.rmtree(source_dir)
        source_dir.mkdir(parents=True)
        nbformat.write(nbgrader_source(nbformat.read(chapter.path, as_version=4), chapter),
                       source_dir / chapter.notebook)
        result = api.generate_assignment(name, force=True, create=True)
        if not result.get("success"):
            raise RuntimeError(f"nbgrader generate_assignment failed for chapter {chapter.number}:\n"
                               f"{result.get('error') or result.get('log')}")
        written.append(root / "release" / name / chapter.notebook)
    return written
