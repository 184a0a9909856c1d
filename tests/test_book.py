"""Tests of the chapter registry, the command line and the book build (execution + Sphinx site)."""

from __future__ import annotations

import re
import subprocess
import sys

import nbformat
import pytest

from amdo_lab import chapters as chapter_registry
from amdo_lab.course.book import BookError, SiteError, build_book, build_site, chapter_run_seconds
from amdo_lab.chapters import CHAPTERS, NOTEBOOK_DIR, Chapter, available_chapters, find_chapter

# The words of ../shared/tools/check_notebooks.py's PROCESS check: the landing page speaks about
# the methods, never about how the book was made.
PROCESS_WORDS = re.compile(
    r"\b(the issue|this issue|issue's|target missed|(?:our|the) (?:speed |accuracy )?target"
    r"(?! (?:image|shape|point|set|frame|pose|cloud|distribution|sequence|domain))|"
    r"previous version|earlier version|previous default|for honesty|done[- ]when)\b",
    re.IGNORECASE,
)


def test_every_notebook_is_a_registered_chapter():
    on_disk = {path.name for path in NOTEBOOK_DIR.glob("*.ipynb")}
    registered = {chapter.notebook for chapter in CHAPTERS}
    assert on_disk <= registered, f"unregistered notebooks: {sorted(on_disk - registered)}"
    assert on_disk == {chapter.notebook for chapter in available_chapters()}
    assert [chapter.number for chapter in CHAPTERS] == sorted({chapter.number for chapter in CHAPTERS})


def test_chapter_summaries_speak_about_the_method():
    for chapter in CHAPTERS:
        for text in (chapter.title, chapter.summary, chapter.paper):
            assert not PROCESS_WORDS.search(text), f"chapter {chapter.number}: {text!r}"
            assert not re.search(r"(/root/|/home/|/tmp/|/work/)", text)


@pytest.mark.parametrize("command", ["figures", "build"])
def test_unknown_chapter_gives_a_one_line_error_naming_what_exists(command):
    with pytest.raises(ValueError, match=r"no chapter 42; available chapters: 0 \(00_introduction"):
        find_chapter(42)
    completed = subprocess.run(
        [sys.executable, "-m", "amdo_lab", command, "--chapter", "42"],
        capture_output=True, text=True, timeout=120,
    )
    assert completed.returncode == 2
    assert completed.stderr.count("\n") == 1 and "no chapter 42; available chapters" in completed.stderr


def test_run_time_comes_from_the_metadata_or_the_cell_timestamps():
    notebook = nbformat.v4.new_notebook()
    assert chapter_run_seconds(notebook) is None
    first, second = nbformat.v4.new_code_cell("1"), nbformat.v4.new_code_cell("2")
    first.metadata["execution"] = {"iopub.execute_input": "2026-01-01T10:00:00.000Z",
                                   "shell.execute_reply": "2026-01-01T10:00:01.000Z"}
    second.metadata["execution"] = {"iopub.execute_input": "2026-01-01T10:00:01.500Z",
                                    "shell.execute_reply": "2026-01-01T10:00:42.250Z"}
    notebook.cells = [first, second]
    assert chapter_run_seconds(notebook) == pytest.approx(42.25)
    notebook.metadata["amdo_lab"] = {"run_seconds": 57.3}
    assert chapter_run_seconds(notebook) == 57.3


def _write_notebook(path, sources, *, tags=()):
    notebook = nbformat.v4.new_notebook()
    notebook.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    notebook.cells = [nbformat.v4.new_markdown_cell(
        "# Tiny chapter\n\nEuler: $e^{i\\pi} + 1 = 0$ and\n$$a^2 + b^2 = c^2$$\ninside a paragraph.")]
    notebook.cells += [nbformat.v4.new_code_cell(source) for source in sources]
    for cell, cell_tags in zip(notebook.cells[1:], tags):
        cell.metadata["tags"] = list(cell_tags)
    nbformat.write(notebook, path)


@pytest.fixture
def tiny_chapters(tmp_path, monkeypatch):
    notebooks = tmp_path / "notebooks"
    notebooks.mkdir()
    monkeypatch.setattr(chapter_registry, "NOTEBOOK_DIR", notebooks)
    good = Chapter(0, "00_good.ipynb", "Good", "works", "—")
    bad = Chapter(1, "01_bad.ipynb", "Bad", "fails", "—")
    _write_notebook(notebooks / good.notebook, [
        "import matplotlib\nmatplotlib.use('Agg')\nimport matplotlib.pyplot as plt\n"
        "from amdo_lab.common import savefig\nfig, ax = plt.subplots()\nax.plot([0, 1])\n"
        "savefig(fig, 'line')",
        "print('the hidden solution', 6 * 7)",
    ], tags=[(), ("hide-input",)])
    _write_notebook(notebooks / bad.notebook, ["x = 1", "raise ValueError('deliberate failure')"])
    monkeypatch.setattr(chapter_registry, "CHAPTERS", (good, bad))
    import amdo_lab.course.book as book

    monkeypatch.setattr(book, "CHAPTERS", (good, bad))
    return good, bad, tmp_path / "build"


def test_build_writes_an_offline_site_and_stops_at_a_failing_chapter(tiny_chapters):
    good, bad, build_dir = tiny_chapters
    index = build_book([good], build_dir, progress=False)
    site = build_dir / "book"
    assert index == site / "index.html"
    page = (site / "00_good.html").read_text()
    # equations go to the local MathJax 3 (the $$ line inside the paragraph too); nothing from the net
    assert '_static/mathjax/tex-chtml.js' in page and (site / "_static/mathjax/tex-chtml.js").exists()
    assert page.count('class="math') >= 2 and "$$" not in page
    for html_file in site.glob("*.html"):
        text = html_file.read_text()
        assert not re.search(r'<(script|img)[^>]+src="https?://', text), html_file.name
        assert not re.search(r'<link[^>]+href="https?://', text), html_file.name
    assert (build_dir / "figures" / "00_good" / "line.png").exists()
    assert "PosixPath" not in page  # a figure cell leaves no output value
    assert re.search(r'<details class="[^"]*hide above-input', page)  # the tagged cell is folded
    assert (site / "_sources" / "00_good.ipynb").exists()  # the download button's file
    landing = index.read_text()
    assert 'href="00_good.html"' in landing and "works" in landing
    executed = nbformat.read(build_dir / "executed" / good.notebook, as_version=4)
    seconds = executed.metadata["amdo_lab"]["run_seconds"]
    assert seconds > 0 and f"{seconds:.0f} s" in landing  # the run time is on the landing page

    with pytest.raises(BookError, match=r"chapter 1 \(01_bad.ipynb\) failed at cell 2: ValueError: deliberate failure"):
        build_book([good, bad], build_dir, progress=False)
    assert (build_dir / "executed" / good.notebook).exists()  # what was executed stays
    assert (site / "00_good.html").exists()


def test_a_broken_equation_reference_fails_the_strict_site_build(tiny_chapters):
    good, _, build_dir = tiny_chapters
    notebook = nbformat.read(good.path, as_version=4)
    notebook.cells[0].source += "\n\nSee equation {eq}`no-such-label`."
    nbformat.write(notebook, good.path)
    build_site(build_dir)  # a reader's build still writes the site
    with pytest.raises(SiteError, match=r"sphinx-build failed: .*no-such-label"):
        build_site(build_dir, warnings_as_errors=True)


# --- solutions folded whole in the book ---------------------------------------------------------

from amdo_lab.course.book import SOLUTION_CLASS, fold_solutions  # noqa: E402


def test_solution_cells_are_folded_whole_headings_aside():
    notebook = nbformat.v4.new_notebook()
    prose = ("## Solutions\n\n### Exercise 1\n\nThe answer is 42 because\n\n```python\n# not a heading\n```\n\n"
             "#### Part b\n\n:::{note}\ninner\n:::")
    notebook.cells = [nbformat.v4.new_markdown_cell("## Exercises"), nbformat.v4.new_markdown_cell(prose),
                      nbformat.v4.new_code_cell("solution_1 = 42"), nbformat.v4.new_code_cell("x = 1")]
    notebook.cells[1].metadata["tags"] = ["solution"]
    notebook.cells[2].metadata["tags"] = ["solution", "hide-input"]
    assert fold_solutions(notebook) == 2
    assert notebook.cells[0].source == "## Exercises" and "tags" not in notebook.cells[3].metadata
    assert notebook.cells[2].metadata["tags"] == ["solution", "hide-cell", SOLUTION_CLASS]
    folded = notebook.cells[1].source
    visible = re.sub(r"(?s)::::\{admonition\}.*?\n::::(?=\n|$)", "", folded)
    assert visible.split() == ["##", "Solutions", "###", "Exercise", "1", "####", "Part", "b"], folded
    assert folded.count(f":class: dropdown {SOLUTION_CLASS}") == 2 and "# not a heading" in folded


def test_the_reading_map_lists_every_chapter_and_its_prerequisites_agree_with_what_chapters_teach():
    table = chapter_registry.reading_map()
    for chapter in CHAPTERS[1:]:
        assert f"| {chapter.number} · {chapter.title} |" in table
        assert chapter.difficulty in (1, 2, 3) and chapter.study_minutes > 0, \
            f"chapter {chapter.number}: give difficulty and study_minutes in amdo_lab/chapters.py"
        assert chapter.prerequisites and chapter.teaches, \
            f"chapter {chapter.number}: give prerequisites and teaches in amdo_lab/chapters.py"
        for need in chapter.prerequisites:
            if need.taught_in is not None:
                teacher = next(c for c in CHAPTERS if c.number == need.taught_in)
                assert need.topic in teacher.teaches, \
                    f"chapter {chapter.number} needs {need.topic!r} from chapter {teacher.number}, which does not teach it"
