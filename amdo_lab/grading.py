"""Grade a folder of submitted chapter notebooks with the chapters' own checks.

``python -m amdo_lab grade SUBMISSIONS_DIR [--out PATH] [--timeout S] [--workers N]``

For each file of the folder:

1. **Which chapter.** The notebook metadata's ``amdo_lab.chapter`` (set by the editions), else the
   file name (a chapter's notebook stem such as ``00_introduction``, or a leading two-digit
   number). A metadata and a file name that disagree, or a notebook whose cells are not the
   chapter's (cell ids and markdown compared with the chapter's student edition), get an error line.
2. **What is kept.** Only the submission's answer cells (tagged ``exercise-answer``, matched to the
   exercises by ``metadata.amdo_lab.exercise``) are kept, put in place of the answer cells of a
   fresh student edition built from the package's own notebook: every other cell, the check
   cells included, comes from the source, so an edited check cell changes nothing.
3. **Execution.** The assembled notebook runs in its own kernel with nbclient, errors allowed (an
   answer cell that raises costs that exercise only) and a time budget for the whole notebook.
4. **Verdicts.** Each pristine check cell's printed line ("correct", "not attempted yet",
   "not yet: <hint>") is read; a correct answer earns :attr:`Exercise.points`.

The result is ``grades.csv`` (columns ``file, chapter, exercise, verdict, points``) in the folder,
or at ``--out``, and a summary table on the terminal. Bad input never stops the run: a file that
is not a notebook, a notebook of another chapter, one that cannot be matched or one that times
out gets a line whose verdict starts with ``error:``, and the other files are graded.
"""

from __future__ import annotations

import csv
import importlib
import re
import time
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import astuple, dataclass
from multiprocessing import get_context
from pathlib import Path

from amdo_lab.chapters import CHAPTERS, NOTEBOOK_DIR, Chapter
from amdo_lab.common.exercises import CORRECT, outcome_of
from amdo_lab.editions import ANSWER_TAG, CHECK_TAG, student_edition

__all__ = ["COLUMNS", "DEFAULT_TIMEOUT_S", "GradeRow", "grade_folder", "grade_notebook", "identify_chapter",
           "summary_table"]

COLUMNS = ("file", "chapter", "exercise", "verdict", "points")
DEFAULT_TIMEOUT_S = 600
ERROR = "error"
#: Least share of the chapter's cells (by id, or markdown text) a submission must hold.
MIN_SHARED_CELLS = 0.5
_ANSI_ESCAPE = re.compile(r"\x1b\[[0-9;]*m")


@dataclass(frozen=True)
class GradeRow:
    """One line of ``grades.csv``: a file's verdict on one exercise (or an error for the whole file)."""

    file: str
    chapter: int | str
    exercise: int | str
    verdict: str
    points: int

    @property
    def is_error(self) -> bool:
        """True when the line reports a problem rather than a check's verdict."""
        return self.verdict.startswith(ERROR + ":")


def _exercise(cell) -> int | None:
    value = cell.get("metadata", {}).get("amdo_lab", {}).get("exercise")
    return value if isinstance(value, int) and not isinstance(value, bool) else None


def _tags(cell) -> list[str]:
    return list(cell.get("metadata", {}).get("tags", []))


def _chapter_from_name(name: str) -> int | None:
    stem = Path(name).stem.lower()
    for chapter in CHAPTERS:
        if chapter.slug.lower() in stem:
            return chapter.number
    match = re.match(r"(\d{2})(?:[_\-\s.]|$)", stem)
    return int(match.group(1)) if match else None


def _find(number: int) -> Chapter | None:
    return next((chapter for chapter in CHAPTERS if chapter.number == number), None)


def identify_chapter(notebook, file_name: str) -> tuple[Chapter | None, str]:
    """Which chapter a submission answers, from its metadata or else its file name.

    Parameters
    ----------
    notebook : nbformat.NotebookNode
        The submitted notebook.
    file_name : str
        Its file name.

    Returns
    -------
    tuple
        ``(chapter, "")`` when found, ``(None, reason)`` when not.
    """
    stated = notebook.get("metadata", {}).get("amdo_lab", {}).get("chapter")
    named = _chapter_from_name(file_name)
    if isinstance(stated, int) and not isinstance(stated, bool):
        if named is not None and named != stated:
            return None, (f"the notebook's metadata says chapter {stated} but its file name says "
                          f"chapter {named}: rename the file or hand in the right notebook")
        number = stated
    elif named is not None:
        number = named
    else:
        return None, ("cannot tell which chapter this is: no amdo_lab.chapter in the notebook metadata "
                      "and no chapter in the file name (such as 00_introduction)")
    chapter = _find(number)
    if chapter is None or not chapter.path.exists():
        return None, f"no chapter {number} in this workbook"
    if not chapter.exercises:
        return None, f"chapter {number} has no exercise module to grade with"
    return chapter, ""


def _shared_share(submission, source) -> float:
    ids = {cell.get("id") for cell in source.cells if cell.get("id")}
    theirs = {cell.get("id") for cell in submission.cells if cell.get("id")}
    by_id = len(ids & theirs) / len(ids) if ids else 0.0
    texts = {cell.source.strip() for cell in source.cells if cell.cell_type == "markdown" and cell.source.strip()}
    their_texts = {cell.source.strip() for cell in submission.cells if cell.cell_type == "markdown"}
    by_text = len(texts & their_texts) / len(texts) if texts else 0.0
    return max(by_id, by_text)


def _assemble(submission, chapter: Chapter):
    """The chapter's student edition with the submission's answer cells in place of its own."""
    import nbformat

    source = student_edition(nbformat.read(chapter.path, as_version=4), chapter.number)
    share = _shared_share(submission, source)
    if share < MIN_SHARED_CELLS:
        raise ValueError(f"this notebook does not match chapter {chapter.number} ({chapter.notebook}): "
                         f"only {share:.0%} of the chapter's cells are in it (a notebook of another chapter?)")
    answers: dict[int, list[str]] = {}
    for cell in submission.cells:
        number = _exercise(cell)
        if cell.cell_type == "code" and number is not None and ANSWER_TAG in _tags(cell):
            answers.setdefault(number, []).append(cell.source)
    slots: dict[int, list] = {}
    for cell in source.cells:
        number = _exercise(cell)
        if cell.cell_type == "code" and number is not None and ANSWER_TAG in _tags(cell):
            slots.setdefault(number, []).append(cell)
    unknown = sorted(set(answers) - set(slots))
    if unknown:
        raise ValueError(f"answer cells for exercise(s) {unknown}, which chapter {chapter.number} does not have "
                         "(a notebook of another chapter?)")
    for number, cells in slots.items():
        given = answers.get(number)
        if given is None:
            continue  # the placeholder stays: "not attempted yet"
        if len(given) == len(cells):
            for cell, text in zip(cells, given):
                cell.source = text
        else:
            cells[0].source = "\n\n".join(given)
            for cell in cells[1:]:
                cell.source = ""
    for cell in source.cells:
        if cell.cell_type == "code":
            cell.outputs, cell.execution_count = [], None
    return source, sorted(set(slots) - set(answers))


def _error_text(cell) -> str | None:
    for output in cell.get("outputs", []):
        if output.get("output_type") == "error":
            value = _ANSI_ESCAPE.sub("", str(output.get("evalue", ""))).strip().splitlines()
            return f"{output.get('ename', 'Error')}: {value[0] if value else ''}".rstrip(": ")
    return None


def _printed_line(cell) -> str | None:
    text = "".join(output.get("text", "") for output in cell.get("outputs", [])
                   if output.get("output_type") == "stream" and output.get("name") == "stdout")
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    return lines[-1] if lines else None


def _execute(notebook, timeout_s: float) -> str | None:
    """Run ``notebook`` in place in a fresh kernel; return why it stopped early, or None."""
    from nbclient import NotebookClient
    from nbclient.exceptions import CellTimeoutError, DeadKernelError

    deadline = time.monotonic() + timeout_s

    def remaining(cell) -> int:
        return max(1, int(deadline - time.monotonic()))

    client = NotebookClient(notebook, timeout=int(timeout_s), timeout_func=remaining, allow_errors=True,
                            kernel_name="python3", resources={"metadata": {"path": str(NOTEBOOK_DIR)}})
    try:
        client.execute()
    except CellTimeoutError:
        return f"the notebook did not finish within {timeout_s:g} s"
    except DeadKernelError as error:
        return f"the kernel died ({error})"
    except Exception as error:  # noqa: BLE001 - reported on the file's line, the others are graded
        return f"the notebook could not run ({type(error).__name__}: {error})"
    return None


def grade_notebook(path: Path | str, *, timeout_s: float = DEFAULT_TIMEOUT_S) -> list[GradeRow]:
    """Grade one submitted file; never raises, problems become ``error:`` lines.

    Parameters
    ----------
    path : pathlib.Path or str
        The submitted file.
    timeout_s : float
        Time budget for executing the whole notebook, in seconds.

    Returns
    -------
    list of GradeRow
        One row per exercise of the chapter, or one error row for the file.
    """
    import nbformat

    path = Path(path)
    name = path.name

    def failure(reason: str, chapter: int | str = "") -> list[GradeRow]:
        return [GradeRow(name, chapter, "", f"{ERROR}: {reason}", 0)]

    try:
        submission = nbformat.reads(path.read_text(encoding="utf-8"), as_version=4)
    except Exception as error:  # noqa: BLE001
        return failure(f"not a notebook ({type(error).__name__}: {str(error).splitlines()[0][:120] if str(error) else ''})")
    chapter, reason = identify_chapter(submission, name)
    if chapter is None:
        return failure(reason)
    try:
        assembled, missing = _assemble(submission, chapter)
        exercises = importlib.import_module(chapter.exercises).EXERCISES
    except Exception as error:  # noqa: BLE001
        return failure(str(error) if isinstance(error, ValueError) else f"{type(error).__name__}: {error}",
                       chapter.number)
    stopped = _execute(assembled, timeout_s)
    answer_errors: dict[int, str] = {}
    verdicts: dict[int, str] = {}
    for cell in assembled.cells:
        number = _exercise(cell)
        if cell.cell_type != "code" or number is None:
            continue
        tags = _tags(cell)
        if ANSWER_TAG in tags:
            error = _error_text(cell)
            if error is not None:
                answer_errors.setdefault(number, error)
        elif CHECK_TAG in tags:
            error, line = _error_text(cell), _printed_line(cell)
            if number in answer_errors:
                verdicts[number] = f"{ERROR}: the answer cell raised {answer_errors[number]}"
            elif error is not None:
                verdicts[number] = f"{ERROR}: the check raised {error}"
            elif line is not None:
                verdicts[number] = line
    rows = []
    for exercise in exercises.exercises:
        verdict = verdicts.get(exercise.number)
        if verdict is None:
            verdict = f"{ERROR}: the check did not run ({stopped or 'no check cell'})"
        elif exercise.number in missing and verdict == "not attempted yet":
            verdict = "not attempted yet (no answer cell for it in the submission)"
        points = exercise.points if outcome_of(verdict) == CORRECT else 0
        rows.append(GradeRow(name, chapter.number, exercise.number, verdict, points))
    if stopped is not None:
        rows.append(GradeRow(name, chapter.number, "", f"{ERROR}: {stopped}", 0))
    return rows


def _submissions(folder: Path, out: Path) -> list[Path]:
    return sorted(path for path in folder.iterdir()
                  if path.is_file() and not path.name.startswith(".") and path.resolve() != out.resolve())


def grade_folder(folder: Path | str, *, out: Path | str | None = None, timeout_s: float = DEFAULT_TIMEOUT_S,
                 workers: int = 1, progress: bool = True) -> tuple[list[GradeRow], Path]:
    """Grade every file of ``folder`` and write the CSV; return the rows and the CSV's path.

    Parameters
    ----------
    folder : pathlib.Path or str
        The folder of submissions (not searched recursively; hidden files are skipped).
    out : pathlib.Path or str, optional
        Where to write the CSV; ``folder/grades.csv`` by default.
    timeout_s : float
        Time budget per notebook, in seconds.
    workers : int
        Notebooks graded at the same time, each in its own process and kernel.
    progress : bool
        Show a progress bar.

    Returns
    -------
    tuple
        ``(rows, csv_path)``, the rows sorted by file and exercise.
    """
    from tqdm.auto import tqdm

    folder = Path(folder)
    if not folder.is_dir():
        raise ValueError(f"folder: {folder} is not a folder")
    if workers < 1:
        raise ValueError(f"workers must be at least 1, got {workers}")
    out = Path(out) if out is not None else folder / "grades.csv"
    files = _submissions(folder, out)
    rows: list[GradeRow] = []
    bar = tqdm(total=len(files), desc="grading", unit="notebook", disable=not progress)
    try:
        if workers == 1:
            for path in files:
                rows += grade_notebook(path, timeout_s=timeout_s)
                bar.update(1)
        else:
            with ProcessPoolExecutor(max_workers=workers, mp_context=get_context("spawn")) as pool:
                futures = {pool.submit(grade_notebook, path, timeout_s=timeout_s): path for path in files}
                for future in as_completed(futures):
                    try:
                        rows += future.result()
                    except Exception as error:  # noqa: BLE001 - a worker that died
                        rows.append(GradeRow(futures[future].name, "", "", f"{ERROR}: {type(error).__name__}: {error}", 0))
                    bar.update(1)
    finally:
        bar.close()
    rows.sort(key=lambda row: (row.file, str(row.exercise).zfill(4)))
    out.parent.mkdir(parents=True, exist_ok=True)
    with out.open("w", newline="", encoding="utf-8") as handle:
        writer = csv.writer(handle)
        writer.writerow(COLUMNS)
        writer.writerows(astuple(row) for row in rows)
    return rows, out


def summary_table(rows: Sequence[GradeRow]) -> str:
    """One line per file: chapter, points out of the maximum, exercises correct, problems.

    Parameters
    ----------
    rows : sequence of GradeRow
        What :func:`grade_folder` returned.

    Returns
    -------
    str
        The table, ready to print.
    """
    files: dict[str, list[GradeRow]] = {}
    for row in rows:
        files.setdefault(row.file, []).append(row)
    width = max([len("file")] + [len(name) for name in files])
    lines = [f"{'file':<{width}}  chapter  points  correct  problems"]
    for name, group in files.items():
        graded = [row for row in group if row.exercise != ""]
        chapter = group[0].chapter
        maximum = _max_points(chapter) if graded else ""
        points = sum(row.points for row in group)
        correct = sum(outcome_of(row.verdict) == CORRECT for row in graded)
        problems = "; ".join(row.verdict[len(ERROR) + 2:] for row in group if row.is_error)
        score = f"{points}/{maximum}" if graded else "—"
        lines.append(f"{name:<{width}}  {str(chapter):>7}  {score:>6}  {correct if graded else '—':>7}  "
                     f"{problems[:100]}")
    return "\n".join(lines)


def _max_points(chapter: int | str) -> int | str:
    found = _find(chapter) if isinstance(chapter, int) else None
    if found is None or not found.exercises:
        return "?"
    return sum(exercise.points for exercise in importlib.import_module(found.exercises).EXERCISES.exercises)
