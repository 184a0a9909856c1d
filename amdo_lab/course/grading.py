"""Grade submitted chapter notebooks with nbgrader, the verdicts computed outside the student's kernel.

``python -m amdo_lab grade DIR [--timeout S] [--workers N] [--export]``

``DIR`` holds either notebooks (a flat folder: the student is named by the file's stem) or one
folder per student (``DIR/<student>/<notebook>.ipynb``, as course platforms hand them back). The
grader keeps an nbgrader course in ``DIR/_nbgrader/`` (its gradebook ``gradebook.db``, the
instructor versions in ``source/``, the autograded notebooks, the feedback), and for each file:

1. **Which chapter**: the notebook metadata's ``amdo_lab.chapter`` (set by the release), else the
   file name (``00_introduction``, or a leading two-digit number).
2. **Cells put back in place**: each cell is matched to the chapter's nbgrader version by its
   nbgrader id, else its tags, else its text; an edited locked cell (a check cell, the prose) is
   **flagged** ("the check cell was edited"; nbgrader's autograde then restores it from the
   gradebook), and an answer typed into a check cell is reported as "no answer in the answer cell".
3. **Scan**: every cell the student wrote (answer cells and added cells) is parsed by
   :func:`amdo_lab.course.scan.scan_source`; rebinding ``EXERCISES``, built-ins, ``print``,
   ``numpy``/``math`` functions or patching ``amdo_lab`` flags the exercise and scores it 0.
4. **Autograde**: nbgrader's ``autograde`` runs the notebook in a fresh kernel (in its own
   subprocess; ``--timeout`` seconds of execution for the whole notebook, then "did not finish
   within N s") with
   ``AMDO_LAB_GRADING`` set, so each check cell also emits a record of the answer (the value, or the
   function's outputs on the hidden seeds' cases).
5. **Verdicts, outside the kernel**: the targets are parsed from the **source notebook's** hidden
   tests (:func:`amdo_lab.course.cells.hidden_targets`); "implement it" answers are compared with
   the reference recomputed in the grader's process (:meth:`ExerciseSet.judge_record`). The points
   are written into the gradebook (the check cells' ``auto_score``); the "why" cells are left to the
   instructor (nbgrader's formgrader, or its gradebook API), whose marks ``--export`` collects.
6. **Output**: ``DIR/grades.csv``, one row per student and chapter (student, chapter, notebook,
   points per exercise ``exK`` and per "why" ``exK_why``, total, maximum, flags), a feedback page
   per student and chapter (nbgrader's ``generate_feedback``) in ``DIR/feedback/<student>/``, and a
   summary table on the terminal. Bad input never stops the run: a file that is not a notebook, a
   notebook of no known chapter or one that did not finish gets a row with the reason in ``flags``.
"""

from __future__ import annotations

import csv
import importlib
import json
import os
import re
import shutil
import subprocess
import sys
import threading
import time
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import asdict, dataclass, field
from pathlib import Path

from amdo_lab.chapters import CHAPTERS, Chapter
from amdo_lab.common.exercises import CORRECT, GRADING_ENV, RECORD_MIME
from amdo_lab.course.cells import (ANSWER_TAG, CHECK_TAG, HIDDEN_BEGIN, WHY_TAG, exercise_of, hidden_block,
                                   hidden_targets, tags)
from amdo_lab.course.release import assignment_name, course_config, nbgrader_source
from amdo_lab.course.scan import scan_source

__all__ = ["COURSE_DIR", "DEFAULT_TIMEOUT_S", "Result", "export_grades", "grade_folder", "summary_table"]

DEFAULT_TIMEOUT_S = 600
#: The nbgrader course the grader keeps inside the submissions folder.
COURSE_DIR = "_nbgrader"
FEEDBACK_DIR = "feedback"
CSV_NAME = "grades.csv"
_RESULTS = "amdo_results.json"
#: Seconds allowed on top of ``--timeout`` for nbgrader itself (start-up, gradebook, kernel start)
#: before the autograde process is killed; the notebook's own budget is enforced by nbgrader.
_OVERHEAD_S = 900
_SKIP = {COURSE_DIR, FEEDBACK_DIR}
#: One writer of the gradebook at a time in this process (the grading threads share it).
_GRADEBOOK_LOCK = threading.Lock()


@dataclass
class Result:
    """One student's grading of one notebook (a row of ``grades.csv``)."""

    student: str
    file: str
    chapter: int | None = None
    points: dict[int, int] = field(default_factory=dict)
    verdicts: dict[int, str] = field(default_factory=dict)
    why: dict[int, float | None] = field(default_factory=dict)
    maximum: int = 0
    flags: list[str] = field(default_factory=list)
    error: str = ""

    @property
    def total(self) -> float:
        """Automatic points plus the "why" marks entered so far."""
        return sum(self.points.values()) + sum(mark for mark in self.why.values() if mark is not None)


# --- finding the submissions and their chapters -----------------------------------------------------------


def _student_id(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", text).strip("._") or "student"


def _submissions(folder: Path) -> list[tuple[str, Path]]:
    found = []
    for entry in sorted(folder.iterdir()):
        if entry.name.startswith((".", "_")) or entry.name in _SKIP:
            continue
        if entry.is_dir():
            found += [(_student_id(entry.name), path) for path in sorted(entry.iterdir())
                      if path.is_file() and path.suffix.lower() == ".ipynb" and not path.name.startswith(".")]
        elif entry.is_file() and entry.suffix.lower() == ".ipynb":
            found.append((_student_id(entry.stem), entry))
    return found


def _chapter_from_name(name: str) -> int | None:
    stem = Path(name).stem.lower()
    for chapter in CHAPTERS:
        if Path(chapter.notebook).stem.lower() in stem:
            return chapter.number
    match = re.match(r"(\d{2})(?:[_\-\s.]|$)", stem)
    return int(match.group(1)) if match else None


def identify_chapter(notebook, file_name: str) -> tuple[Chapter | None, str]:
    """Which chapter a submission answers, from its metadata or else its file name; ``(None, reason)`` if unknown."""
    stated = notebook.get("metadata", {}).get("amdo_lab", {}).get("chapter")
    named = _chapter_from_name(file_name)
    number = stated if isinstance(stated, int) and not isinstance(stated, bool) else named
    if number is None:
        return None, ("cannot tell which chapter this is: no amdo_lab.chapter in the notebook metadata and no "
                      "chapter in the file name (such as 00_introduction)")
    chapter = next((c for c in CHAPTERS if c.number == number), None)
    if chapter is None or not chapter.path.exists() or not chapter.exercises:
        return None, f"no chapter {number} with exercises in this workbook"
    return chapter, ""


# --- matching the submission's cells to the chapter's -----------------------------------------------------


def _norm(text: str) -> str:
    return "\n".join(line.rstrip() for line in text.strip().splitlines())


def _without_hidden(text: str) -> str:
    block = hidden_block(text)
    if block is None:
        return text
    return text.replace(f"{HIDDEN_BEGIN}\n{block}### END HIDDEN TESTS\n", "")


def _assigns_answer(text: str) -> list[int]:
    return sorted({int(k) for k in re.findall(r"^\s*answer_(\d+)\s*=(?!=)", text, re.M)})


def prepare_submission(submission, source) -> tuple[object, dict[int, list[str]], list[str]]:
    """Give the submission's cells the nbgrader ids of the chapter's cells; flag edits and tampering.

    Parameters
    ----------
    submission : nbformat.NotebookNode
        The student's notebook (release, source or anything in between).
    source : nbformat.NotebookNode
        The chapter's nbgrader version (every cell with nbgrader metadata).

    Returns
    -------
    tuple
        ``(notebook, flags_by_exercise, notes)``: the notebook to autograde, the scan's and the
        edit check's findings per exercise (an exercise flagged here scores 0) and notes about the
        whole notebook (edited prose, answers outside their cell).
    """
    by_id = {cell.metadata["nbgrader"]["grade_id"]: cell for cell in source.cells}
    by_text: dict[str, str] = {}
    for cell in source.cells:
        meta = cell.metadata["nbgrader"]
        if meta.get("locked") and not meta.get("solution"):
            by_text.setdefault(_norm(cell.source), meta["grade_id"])
            by_text.setdefault(_norm(_without_hidden(cell.source)), meta["grade_id"])
    numbers = sorted({int(gid.split("-")[1]) for gid in by_id if gid.startswith("answer-")})
    modules = {"np", "plt", "numpy", "math"}
    flags: dict[int, list[str]] = {}
    notes: list[str] = []
    seen: set[str] = set()
    cells = []
    for cell in submission.cells:
        meta = cell.get("metadata", {}).get("nbgrader", {})
        gid = meta.get("grade_id") if meta.get("grade_id") in by_id else None
        number, cell_tags = exercise_of(cell), tags(cell)
        if gid is None and number is not None:
            kind = ("answer" if ANSWER_TAG in cell_tags else "check" if CHECK_TAG in cell_tags
                    else "why" if WHY_TAG in cell_tags else None)
            gid = f"{kind}-{number}" if kind and f"{kind}-{number}" in by_id else None
        if gid is None and cell.get("cell_type") in ("code", "markdown"):
            gid = by_text.get(_norm(cell.get("source", "")))
        if gid is not None and gid in seen:
            gid = None  # a copy of a cell: treated as the student's own
        cell.metadata.pop("nbgrader", None)
        if gid is None:
            if cell.get("cell_type") == "code" and cell.get("source", "").strip():
                later = [k for k in numbers if f"answer-{k}" not in seen]
                owner = later[0] if later else (numbers[-1] if numbers else 0)
                for reason in scan_source(cell.source, modules):
                    flags.setdefault(owner, []).append(f"an added cell {reason}")
                for k in _assigns_answer(cell.source):
                    notes.append(f"exercise {k}: answered in a cell that is not its answer cell")
            cells.append(cell)
            continue
        seen.add(gid)
        original = by_id[gid]
        cell.metadata["nbgrader"] = dict(original.metadata["nbgrader"])
        kind, _, tail = gid.partition("-")
        if kind == "answer":
            for reason in scan_source(cell.source, modules):
                flags.setdefault(int(tail), []).append(f"the answer cell {reason}")
        elif kind == "check":
            if _norm(cell.source) not in {_norm(original.source), _norm(_without_hidden(original.source))}:
                k = int(tail)
                flags.setdefault(k, []).append("the check cell was edited (restored from the source)")
                if k in _assigns_answer(cell.source):
                    notes.append(f"exercise {k}: no answer in the answer cell; the check cell was edited")
        elif kind == "locked":
            if _norm(cell.source) != _norm(original.source):
                notes.append(f"a locked cell was edited ({gid}, restored from the source)")
        cells.append(cell)
    for k in numbers:
        if f"answer-{k}" not in seen:
            notes.append(f"exercise {k}: its answer cell is missing")
    submission.cells = cells
    return submission, flags, notes


# --- one notebook: autograde (in a subprocess), then the verdicts --------------------------------------------


def _ensure_assignment(root: Path, chapter: Chapter) -> None:
    """Write the chapter's nbgrader version into the course and register it in the gradebook (once)."""
    import nbformat
    from nbgrader.apps import NbGraderAPI
    from nbgrader.coursedir import CourseDirectory

    name = assignment_name(chapter)
    folder = root / "source" / name
    target = folder / chapter.notebook
    marked = nbgrader_source(nbformat.read(chapter.path, as_version=4), chapter)
    if target.exists() and nbformat.read(target, as_version=4) == marked and (root / "gradebook.db").exists():
        return
    folder.mkdir(parents=True, exist_ok=True)
    nbformat.write(marked, target)
    config = course_config(root)
    result = NbGraderAPI(CourseDirectory(config=config), config=config).generate_assignment(name, force=True)
    if not result.get("success"):
        raise RuntimeError(f"nbgrader could not register chapter {chapter.number}: {result.get('error', '')[-400:]}")


def _records(notebook) -> tuple[dict[int, dict], dict[int, str], str]:
    records: dict[int, dict] = {}
    errors: dict[int, str] = {}
    timed_out = ""
    for cell in notebook.cells:
        gid = cell.get("metadata", {}).get("nbgrader", {}).get("grade_id", "")
        for output in cell.get("outputs", []):
            if output.get("output_type") == "error":
                name = output.get("ename", "Error")
                if name == "CellTimeoutError":  # nbgrader's stand-in for a cell stopped at the budget
                    timed_out = timed_out or gid or "a cell"
                if gid.startswith("answer-"):
                    value = re.sub(r"\x1b\[[0-9;]*m", "", str(output.get("evalue", ""))).strip().splitlines()
                    errors.setdefault(int(gid.split("-")[1]), f"{name}: {value[0] if value else ''}".rstrip(": "))
            if gid.startswith("check-") and RECORD_MIME in output.get("data", {}):
                records[int(gid.split("-")[1])] = output["data"][RECORD_MIME]
    return records, errors, timed_out


def _autograde_worker(root: str, assignment: str, student: str, timeout_s: int) -> int:
    """Entry point of the subprocess: nbgrader's autograde of one student's assignment."""
    from nbgrader.apps import NbGraderAPI
    from nbgrader.coursedir import CourseDirectory

    started: list[float] = []

    def remaining(cell) -> int:
        """The notebook's budget: ``timeout_s`` seconds of execution in all, counted from its first cell."""
        if not started:
            started.append(time.monotonic())
        return max(1, int(round(started[0] + timeout_s - time.monotonic())))

    config = course_config(root, **{"Execute.timeout": int(timeout_s), "Execute.timeout_func": remaining})
    api = NbGraderAPI(CourseDirectory(config=config), config=config)
    for attempt in range(3):  # another worker may hold the gradebook for a moment
        result = api.autograde(assignment, student, force=True, create=True)
        if result.get("success") or "locked" not in str(result.get("log", "")) + str(result.get("error", "")):
            break
        time.sleep(2 + 3 * attempt)
    if not result.get("success"):
        sys.stderr.write((result.get("error") or result.get("log") or "")[-2000:])
        return 1
    return 0


def _kill_tree(process: subprocess.Popen) -> None:
    try:
        import psutil

        parent = psutil.Process(process.pid)
        for child in parent.children(recursive=True):
            child.kill()
        parent.kill()
    except Exception:  # noqa: BLE001 - already gone
        process.kill()


def _set_scores(root: Path, chapter: Chapter, student: str, points: dict[int, int], verdicts: dict[int, str],
                flags: dict[int, list[str]]) -> dict[int, float | None]:
    """Write the automatic points and verdicts into the gradebook; return the "why" marks entered so far."""
    from nbgrader.api import Gradebook

    name, notebook = assignment_name(chapter), Path(chapter.notebook).stem
    why: dict[int, float | None] = {}
    exercises = importlib.import_module(chapter.exercises).EXERCISES
    with Gradebook(f"sqlite:///{root / 'gradebook.db'}") as gradebook:
        for exercise in exercises.exercises:
            k = exercise.number
            try:
                grade = gradebook.find_grade(f"check-{k}", notebook, name, student)
                grade.auto_score = float(points.get(k, 0))
                grade.needs_manual_grade = False
                comment = gradebook.find_comment(f"answer-{k}", notebook, name, student)
                comment.auto_comment = "; ".join([verdicts.get(k, "")] + flags.get(k, []))
            except Exception:  # noqa: BLE001 - a cell nbgrader did not record
                pass
            if exercise.why_points:
                try:
                    mark = gradebook.find_grade(f"why-{k}", notebook, name, student)
                    why[k] = mark.manual_score if mark.manual_score is not None else (
                        0.0 if mark.auto_score == 0 and not mark.needs_manual_grade else None)
                except Exception:  # noqa: BLE001
                    why[k] = None
        gradebook.db.commit()
    return why


def grade_one(root: Path, student: str, path: Path, *, timeout_s: float, feedback: bool = True) -> Result:
    """Grade one submitted file; never raises, a problem becomes the row's flag.

    Parameters
    ----------
    root : pathlib.Path
        The nbgrader course (``DIR/_nbgrader``).
    student : str
        The student's id in the gradebook.
    path : pathlib.Path
        The submitted file.
    timeout_s : float
        Seconds the notebook may run in all (counted from its first cell).
    feedback : bool
        Write nbgrader's feedback page.

    Returns
    -------
    Result
    """
    import nbformat

    result = Result(student=student, file=path.name)
    try:
        submission = nbformat.reads(path.read_text(encoding="utf-8"), as_version=4)
    except Exception as error:  # noqa: BLE001
        text = str(error).splitlines()[0][:100] if str(error) else ""
        result.error = f"not a notebook ({type(error).__name__}: {text})"
        return result
    chapter, reason = identify_chapter(submission, path.name)
    if chapter is None:
        result.error = reason
        return result
    result.chapter = chapter.number
    exercises = importlib.import_module(chapter.exercises).EXERCISES
    result.maximum = sum(e.points + e.why_points for e in exercises.exercises)
    name = assignment_name(chapter)
    source = nbformat.read(root / "source" / name / chapter.notebook, as_version=4)
    prepared, flags, notes = prepare_submission(submission, source)
    result.flags += notes
    submitted = root / "submitted" / student / name
    if submitted.exists():
        shutil.rmtree(submitted)
    submitted.mkdir(parents=True)
    nbformat.write(prepared, submitted / chapter.notebook)
    env = {**os.environ, GRADING_ENV: "1", "PYTHONPATH": os.pathsep.join(
        [str(Path(__file__).resolve().parents[2])] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p])}
    command = [sys.executable, "-m", "amdo_lab.course.grading", str(root), name, student, str(int(timeout_s))]
    process = subprocess.Popen(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               cwd=str(chapter.path.parent))
    try:
        _, stderr = process.communicate(timeout=timeout_s + _OVERHEAD_S)
    except subprocess.TimeoutExpired:
        _kill_tree(process)
        process.communicate()
        result.error = f"did not finish within {timeout_s:g} s"
        return result
    graded = root / "autograded" / student / name / chapter.notebook
    if process.returncode != 0 or not graded.exists():
        last = [line for line in stderr.strip().splitlines() if line.strip()]
        result.error = f"nbgrader could not grade it ({last[-1][:160] if last else 'no message'})"
        return result
    records, answer_errors, timed_out = _records(nbformat.read(graded, as_version=4))
    if timed_out:
        result.error = f"did not finish within {timeout_s:g} s"
        result.flags = []
        return result
    targets = hidden_targets(nbformat.read(chapter.path, as_version=4))
    for exercise in exercises.exercises:
        k = exercise.number
        if flags.get(k) and any(not f.startswith("the check cell was edited") for f in flags[k]):
            verdict = "flagged: " + "; ".join(flags[k])
        elif k in answer_errors:
            verdict = f"error: the answer cell raised {answer_errors[k]}"
        elif k not in records:
            verdict = "no verdict: the check cell emitted no record" + (" (time-out)" if timed_out else "")
        elif k not in targets:
            verdict = "no verdict: the source has no literal target for this exercise"
        else:
            verdict = exercises.judge_record(records[k], targets[k])
        result.verdicts[k] = verdict
        result.points[k] = exercise.points if verdict == CORRECT else 0
        for reason in flags.get(k, []):
            result.flags.append(f"exercise {k}: {reason}")
    for attempt in range(4):  # an autograde in another process may hold the gradebook a moment
        try:
            with _GRADEBOOK_LOCK:
                result.why = _set_scores(root, chapter, student, result.points, result.verdicts, flags)
            break
        except Exception as error:  # noqa: BLE001 - sqlite "database is locked"
            if attempt == 3:
                result.flags.append(f"the gradebook could not be updated ({type(error).__name__})")
            time.sleep(2 + 2 * attempt)
    if feedback:
        with _GRADEBOOK_LOCK:
            result.flags += _feedback(root, chapter, student)
    return result


def _feedback(root: Path, chapter: Chapter, student: str) -> list[str]:
    from nbgrader.apps import NbGraderAPI
    from nbgrader.coursedir import CourseDirectory

    config = course_config(root)
    api = NbGraderAPI(CourseDirectory(config=config), config=config)
    outcome = api.generate_feedback(assignment_name(chapter), student, force=True)
    page = root / "feedback" / student / assignment_name(chapter) / (Path(chapter.notebook).stem + ".html")
    if not outcome.get("success") or not page.exists():
        return ["no feedback page (nbgrader generate_feedback failed)"]
    target = root.parent / FEEDBACK_DIR / student / f"{assignment_name(chapter)}_{page.name}"
    target.parent.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(page, target)
    return []


# --- the folder ----------------------------------------------------------------------------------------------


def grade_folder(folder: Path | str, *, timeout_s: float = DEFAULT_TIMEOUT_S, workers: int = 1,
                 progress: bool = True, feedback: bool = True) -> tuple[list[Result], Path]:
    """Grade every submission of ``folder``; write ``grades.csv`` and the feedback; return the rows and the CSV.

    Parameters
    ----------
    folder : pathlib.Path or str
        Notebooks, or one folder per student holding that student's notebooks.
    timeout_s : float
        Seconds a notebook may run in all (it is stopped past it: "did not finish within N s").
    workers : int
        Notebooks graded at the same time, each in its own process and kernel.
    progress : bool
        Show a progress bar.
    feedback : bool
        Write a feedback page per student and chapter.

    Returns
    -------
    tuple
        ``(results, csv_path)``.
    """
    from tqdm.auto import tqdm

    folder = Path(folder)
    if not folder.is_dir():
        raise ValueError(f"{folder} is not a folder")
    if workers < 1 or timeout_s <= 0:
        raise ValueError("workers must be at least 1 and the timeout positive")
    root = folder / COURSE_DIR
    root.mkdir(exist_ok=True)
    entries = _submissions(folder)
    results: list[Result] = []
    jobs: list[tuple[str, Path]] = []
    taken: set[tuple[str, int]] = set()
    import nbformat

    for student, path in entries:
        try:
            notebook = nbformat.reads(path.read_text(encoding="utf-8"), as_version=4)
            chapter, _ = identify_chapter(notebook, path.name)
        except Exception:  # noqa: BLE001 - reported by grade_one
            chapter = None
        if chapter is not None:
            if (student, chapter.number) in taken:
                results.append(Result(student, path.name, chapter.number,
                                      error=f"a second notebook of chapter {chapter.number} for this student"))
                continue
            taken.add((student, chapter.number))
            try:
                _ensure_assignment(root, chapter)
            except Exception as error:  # noqa: BLE001
                results.append(Result(student, path.name, chapter.number, error=str(error)))
                continue
        jobs.append((student, path))
    bar = tqdm(total=len(jobs), desc="grading", unit="notebook", disable=not progress)
    try:
        with ThreadPoolExecutor(max_workers=workers) as pool:
            futures = {pool.submit(grade_one, root, student, path, timeout_s=timeout_s, feedback=feedback):
                       (student, path) for student, path in jobs}
            for future in as_completed(futures):
                student, path = futures[future]
                try:
                    results.append(future.result())
                except Exception as error:  # noqa: BLE001 - a grader bug: the row says so
                    results.append(Result(student, path.name, error=f"{type(error).__name__}: {error}"))
                bar.update(1)
    finally:
        bar.close()
    results.sort(key=lambda r: (r.student, r.chapter if r.chapter is not None else -1, r.file))
    (root / _RESULTS).write_text(json.dumps([asdict(r) for r in results], indent=1), encoding="utf-8")
    return results, write_csv(results, folder / CSV_NAME)


def export_grades(folder: Path | str) -> tuple[list[Result], Path]:
    """Re-write ``grades.csv`` from the last grading and the gradebook's current "why" marks (no re-run)."""
    from nbgrader.api import Gradebook

    folder = Path(folder)
    root = folder / COURSE_DIR
    stored = root / _RESULTS
    if not stored.exists():
        raise ValueError(f"{folder} has not been graded yet (no {COURSE_DIR}/{_RESULTS})")
    results = []
    for raw in json.loads(stored.read_text(encoding="utf-8")):
        result = Result(**{**raw, "points": {int(k): v for k, v in raw["points"].items()},
                           "verdicts": {int(k): v for k, v in raw["verdicts"].items()},
                           "why": {int(k): v for k, v in raw["why"].items()}})
        results.append(result)
    with Gradebook(f"sqlite:///{root / 'gradebook.db'}") as gradebook:
        for result in results:
            if result.chapter is None or result.error:
                continue
            chapter = next(c for c in CHAPTERS if c.number == result.chapter)
            for k in list(result.why):
                try:
                    mark = gradebook.find_grade(f"why-{k}", Path(chapter.notebook).stem, assignment_name(chapter),
                                                result.student)
                    if mark.manual_score is not None:
                        result.why[k] = mark.manual_score
                except Exception:  # noqa: BLE001
                    continue
    return results, write_csv(results, folder / CSV_NAME)


def _columns(results: Sequence[Result]) -> list[str]:
    most = 0
    why = set()
    for result in results:
        if result.chapter is not None:
            exercises = importlib.import_module(
                next(c for c in CHAPTERS if c.number == result.chapter).exercises).EXERCISES
            most = max(most, len(exercises))
            why |= {e.number for e in exercises.exercises if e.why_points}
    columns = ["student", "chapter", "notebook"]
    for k in range(1, most + 1):
        columns.append(f"ex{k}")
        if k in why:
            columns.append(f"ex{k}_why")
    return columns + ["total", "maximum", "flags"]


def _number(value: float | None) -> str:
    if value is None:
        return ""
    return f"{value:g}"


def write_csv(results: Sequence[Result], path: Path) -> Path:
    """Write ``grades.csv``: one row per student and chapter (see the module's docstring)."""
    columns = _columns(results)
    with path.open("w", newline="", encoding="utf-8") as handle:
        writer = csv.DictWriter(handle, fieldnames=columns)
        writer.writeheader()
        for result in results:
            row = {"student": result.student, "chapter": "" if result.chapter is None else result.chapter,
                   "notebook": result.file, "maximum": result.maximum or "",
                   "total": "" if result.error else _number(result.total),
                   "flags": "; ".join(([f"error: {result.error}"] if result.error else []) + result.flags)}
            for k, points in result.points.items():
                if f"ex{k}" in columns:
                    row[f"ex{k}"] = points
            for k, mark in result.why.items():
                if f"ex{k}_why" in columns:
                    row[f"ex{k}_why"] = _number(mark)
            writer.writerow(row)
    return path


def summary_table(results: Sequence[Result], width: int = 20) -> str:
    """One line per student and chapter: points of the maximum with a bar, and the problems found."""
    name_width = max([len("student")] + [len(r.student) for r in results])
    lines = [f"{'student':<{name_width}}  ch  {'points':>9}  {'':{width}}  problems"]
    for result in results:
        chapter = "" if result.chapter is None else f"{result.chapter:>2}"
        if result.error:
            score, bar = "—", " " * width
        else:
            share = result.total / result.maximum if result.maximum else 0.0
            filled = int(round(share * width))
            score, bar = f"{result.total:g}/{result.maximum}", "█" * filled + "·" * (width - filled)
        problems = "; ".join(([f"error: {result.error}"] if result.error else []) + result.flags)
        pending = sum(mark is None for mark in result.why.values())
        if pending and not result.error:
            problems = (f"{pending} why answer(s) to mark; " + problems).rstrip("; ")
        lines.append(f"{result.student:<{name_width}}  {chapter:>2}  {score:>9}  {bar}  {problems[:110]}")
    return "\n".join(lines)


if __name__ == "__main__":  # the autograde subprocess
    sys.exit(_autograde_worker(sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])))
