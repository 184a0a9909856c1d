"""The student release (nbgrader's layout) and the leak test of the course kit.

The release of every chapter on the new exercise format is written once for the session
(``conftest.course_release``: nbgrader's ``generate_assignment``, no execution). Then:

- its notebooks carry no Solutions section, no self-test, no hidden test, no ``EXERCISES.expect``;
  every cell has nbgrader metadata: answer cells unlocked solution cells, check cells locked
  autograder tests worth the exercise's points, "why" cells manually graded answers, the rest
  locked with a checksum; answer and check cells have no outputs;
- **the leak test**: every target the source notebooks' hidden tests register is searched for in
  the installed package's files and in ``release/``: a number at the precision the hidden test
  writes it (more digits count too), a word or phrase as words. None may be found, except a
  number that is also a given of the exercise's own prompt, and a word in a place that lists the
  options or asks the question (an exercise's prompt, answer and "why" cells, an ``Exercise``'s
  ``choices``, or any cell or package line that names every other candidate too — the choices, or the
  recorded wrong words — such as a table of all the model's terms). Numbers with fewer
  than three significant digits are not searched (they occur by chance everywhere); "implement it"
  exercises register seeds, not targets, and are not searched either.

Chapters still on the old format (an ``Exercise`` with ``expected`` computed in the package) cannot
pass the leak test: :data:`NOT_YET_MIGRATED` lists them, and the test fails when a listed chapter
has in fact migrated, so the list only shrinks.
"""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import nbformat
import pytest

import amdo_lab
from amdo_lab.chapters import available_chapters
from amdo_lab.course.cells import (ANSWER_TAG, CHECK_TAG, HIDDEN_BEGIN, SELFTEST_TAG, SOLUTION_TAG, WHY_TAG,
                                   exercise_of, hidden_targets, tags)

#: Chapters whose exercises still compute a target in the package (the lead shrinks this set).
NOT_YET_MIGRATED: set[int] = set()

CHAPTERS = available_chapters()
PACKAGE_DIR = Path(amdo_lab.__file__).resolve().parent


def _exercises(chapter):
    return importlib.import_module(chapter.exercises).EXERCISES


def _migrated(chapter) -> bool:
    return all(exercise.expected is None for exercise in _exercises(chapter).exercises)


@pytest.fixture(scope="module")
def release(course_release):
    _, paths = course_release
    return {number: nbformat.read(path, as_version=4) for number, path in paths.items()}


def _number_pattern(text: str) -> re.Pattern:
    return re.compile(r"(?<![\d.])" + re.escape(text) + r"\d*(?![\d])")


def _word_pattern(text: str) -> re.Pattern:
    # a colon joins a model term's factors (U:M inside t:U:M:D is not the term U:M)
    return re.compile(r"(?<![\w:])" + re.escape(text) + r"(?![\w]|:\w)", re.I)


def _significant(text: str) -> int:
    return len(text.replace("-", "").replace(".", "").lstrip("0").split("e")[0])


def _prompts(notebook) -> dict[int, str]:
    """The prompt of each exercise: the markdown from its ``### Exercise k`` heading to its answer cell."""
    prompts: dict[int, str] = {}
    current = None
    for cell in notebook.cells:
        if SOLUTION_TAG in tags(cell):
            break
        match = re.search(r"^### Exercise (\d+)", cell.source, re.M) if cell.cell_type == "markdown" else None
        if match:
            current = int(match.group(1))
        if current is not None and cell.cell_type == "markdown" and WHY_TAG not in tags(cell):
            prompts[current] = prompts.get(current, "") + "\n" + cell.source
        if ANSWER_TAG in tags(cell):
            current = None
    return prompts


def _literal_texts(check_source: str, number: int) -> list[str]:
    """The target of exercise ``number`` as written in the hidden test (each alternative of a set)."""
    block = check_source.split(HIDDEN_BEGIN, 1)[1].split("### END HIDDEN TESTS", 1)[0]
    match = re.search(rf"EXERCISES\.expect\(\s*{number}\s*,\s*(.*)\)\s*$", block.strip(), re.S)
    return [match.group(1).strip()] if match else []


def _cell_text(cell) -> str:
    parts = [cell.source]
    for output in cell.get("outputs", []):
        parts.append(str(output.get("text", "")))
        for value in output.get("data", {}).values():
            parts.append(value if isinstance(value, str) else str(value))
    return "\n".join(parts)


def _package_text() -> str:
    texts = []
    for path in sorted(PACKAGE_DIR.rglob("*")):
        if path.is_file() and "__pycache__" not in path.parts and path.suffix in {".py", ".txt", ".json", ".csv", ""}:
            texts.append(path.read_text(encoding="utf-8", errors="ignore"))
    return "\n".join(texts)


def _other_candidates(exercise, target: str) -> list[str]:
    """The other answers an exercise's candidates name: its choices, else its recorded wrong words."""
    words = list(exercise.choices) or [wrong.value for wrong in exercise.wrong_answers if isinstance(wrong.value, str)]
    return [word for word in words if word.strip().lower() != target.strip().lower()]


def _lists_all(text: str, others: list[str]) -> bool:
    """True when ``text`` names at least two other candidates and every one of them: it lists the options
    (a table of every model term, a tuple of choices), so finding the right one there reveals nothing."""
    return len(others) >= 2 and all(_word_pattern(word.strip()).search(text) for word in others)


_CHOICES = re.compile(r"choices\s*=\s*\((?:[^()]|\([^()]*\))*\)", re.S)


def test_not_yet_migrated_lists_only_chapters_on_the_old_format():
    migrated = sorted(number for number in NOT_YET_MIGRATED
                      if any(c.number == number for c in CHAPTERS) and _migrated(next(c for c in CHAPTERS
                                                                                    if c.number == number)))
    assert not migrated, f"chapters {migrated} have migrated: remove them from NOT_YET_MIGRATED"


@pytest.mark.parametrize("chapter", CHAPTERS, ids=lambda chapter: f"chapter{chapter.number}")
def test_no_target_leaks_into_the_package_or_the_release(chapter, release):
    if chapter.number in NOT_YET_MIGRATED:
        pytest.xfail(f"chapter {chapter.number} still computes its targets in the package")
    source = nbformat.read(chapter.path, as_version=4)
    targets = hidden_targets(source)
    exercises = _exercises(chapter)
    assert set(targets) == {exercise.number for exercise in exercises.exercises}, \
        "every exercise registers a literal target (or seeds) in its check cell's hidden test"
    prompts = _prompts(source)
    package = _CHOICES.sub("", _package_text())
    released = release[chapter.number]
    listing = {k: "\n".join(_cell_text(cell) for cell in released.cells
                            if exercise_of(cell) == k and ANSWER_TAG in tags(cell)) for k in targets}
    leaks = []
    for k, (kind, target) in targets.items():
        if kind == "seeds":
            continue
        checks = [cell.source for cell in source.cells if CHECK_TAG in tags(cell) and exercise_of(cell) == k]
        values = sorted(target, key=repr) if isinstance(target, (set, frozenset)) else [target]
        written = _literal_texts(checks[0], k) if checks else []
        for value in values:
            if isinstance(value, str):
                pattern = _word_pattern(value.strip())
                others = _other_candidates(exercises[k], value)
                allowed = {id(cell) for cell in released.cells
                           if ((ANSWER_TAG in tags(cell) or WHY_TAG in tags(cell)) and exercise_of(cell) is not None)
                           or (cell.cell_type == "markdown" and re.search(r"^### Exercise \d+", cell.source, re.M))
                           or _lists_all(_cell_text(cell), others)}
                places = [f"release cell {i}" for i, cell in enumerate(released.cells)
                          if id(cell) not in allowed and pattern.search(_cell_text(cell))]
                if any(pattern.search(line) and not _lists_all(line, others) for line in package.splitlines()):
                    places.append("the package")
            elif isinstance(value, (int, float)) and not isinstance(value, bool):
                text = written[0] if written and len(values) == 1 and re.fullmatch(r"-?[\d.e+-]+", written[0]) \
                    else repr(value)
                if _significant(text) < 3 or _number_pattern(text).search(prompts.get(k, "")):
                    continue
                pattern = _number_pattern(text)
                places = [f"release cell {i}" for i, cell in enumerate(released.cells)
                          if pattern.search(_cell_text(cell))]
                if pattern.search(package):
                    places.append("the package")
            else:
                continue
            if places:
                leaks.append(f"exercise {k}: {value!r} found in {', '.join(places)}")
        assert listing  # the answer cells are there
    assert not leaks, "\n".join(leaks)


@pytest.mark.parametrize("number", sorted({c.number for c in CHAPTERS} - NOT_YET_MIGRATED))
def test_the_release_is_nbgraders_student_version(number, release):
    notebook = release[number]
    chapter = next(c for c in CHAPTERS if c.number == number)
    exercises = _exercises(chapter)
    assert notebook.metadata["amdo_lab"]["chapter"] == number
    text = "\n".join(cell.source for cell in notebook.cells)
    assert "HIDDEN TESTS" not in text and "EXERCISES.expect" not in text and "## Solutions" not in text
    assert "solution_" not in text and "assert_checks" not in text
    for cell in notebook.cells:
        meta = cell.metadata["nbgrader"]
        assert SOLUTION_TAG not in tags(cell) and SELFTEST_TAG not in tags(cell)
        k = exercise_of(cell)
        if ANSWER_TAG in tags(cell):
            assert meta["solution"] and not meta["locked"] and not meta["grade"]
            assert re.search(rf"^answer_{k} = None", cell.source, re.M)
        elif CHECK_TAG in tags(cell):
            assert meta["grade"] and meta["locked"] and meta["points"] == exercises[k].points
            assert cell.source.strip() == f"EXERCISES.check({k}, answer_{k})"
        elif WHY_TAG in tags(cell):
            assert meta["solution"] and meta["grade"] and meta["points"] == exercises[k].why_points
            assert cell.source.startswith("**Why?** ")
        else:
            assert meta["locked"] and meta["checksum"]
        if cell.cell_type == "code" and (ANSWER_TAG in tags(cell) or CHECK_TAG in tags(cell)):
            assert cell.outputs == [] and cell.execution_count is None
    whys = [cell for cell in notebook.cells if WHY_TAG in tags(cell)]
    assert whys, "at least one manually graded 'why' answer per chapter"
