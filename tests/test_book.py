"""Tests of the chapter registry, the command line and the HTML book build."""

from __future__ import annotations

import json
import re
import subprocess
import sys

import nbformat
import pytest

from amdo_lab import chapters as chapter_registry
from amdo_lab.book import BookError, build_book
from amdo_lab.chapters import CHAPTERS, NOTEBOOK_DIR, Chapter, available_chapters, find_chapter


def test_every_notebook_is_a_registered_chapter():
    on_disk = {path.name for path in NOTEBOOK_DIR.glob("*.ipynb")}
    registered = {chapter.notebook for chapter in CHAPTERS}
    assert on_disk <= registered, f"unregistered notebooks: {sorted(on_disk - registered)}"
    assert on_disk == {chapter.notebook for chapter in available_chapters()}
    assert [chapter.number for chapter in CHAPTERS] == sorted({chapter.number for chapter in CHAPTERS})


def test_unknown_chapter_gives_a_one_line_error_naming_what_exists():
    with pytest.raises(ValueError, match=r"no chapter 99; available chapters: 0 \(00_introduction"):
        find_chapter(99)
    completed = subprocess.run(
        [sys.executable, "-m", "amdo_lab", "figures", "--chapter", "99"],
        capture_output=True, text=True, timeout=120,
    )
    assert completed.returncode == 2
    assert completed.stderr.count("\n") == 1 and "available chapters" in completed.stderr


def _write_notebook(path, sources):
    notebook = nbformat.v4.new_notebook()
    notebook.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    notebook.cells = [nbformat.v4.new_markdown_cell(r"# Tiny chapter $e^{i\pi} + 1 = 0$")]
    notebook.cells += [nbformat.v4.new_code_cell(source) for source in sources]
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
    ])
    _write_notebook(notebooks / bad.notebook, ["x = 1", "raise ValueError('deliberate failure')"])
    monkeypatch.setattr(chapter_registry, "CHAPTERS", (good, bad))
    import amdo_lab.book as book

    monkeypatch.setattr(book, "CHAPTERS", (good, bad))
    return good, bad, tmp_path / "build"


def test_build_writes_an_offline_book_and_stops_at_a_failing_chapter(tiny_chapters):
    good, bad, build_dir = tiny_chapters
    index = build_book([good], build_dir, progress=False)
    page = (build_dir / "book" / "00_good.html").read_text()
    # equations are typeset by the local MathJax copy; no script or style comes from the network
    assert 'src="mathjax/MathJax.js?config=' in page
    assert (build_dir / "book" / "mathjax" / "MathJax.js").exists()
    assert not re.search(r'<script[^>]+src="https?://', page)
    assert not re.search(r'<link[^>]+href="https?://', page)
    assert (build_dir / "figures" / "00_good" / "line.png").exists()
    assert "PosixPath" not in page  # a figure cell leaves no output value
    listing = index.read_text()
    assert '<a href="00_good.html">Good</a>' in listing and "Bad (not built yet" in listing

    with pytest.raises(BookError, match=r"chapter 1 \(01_bad.ipynb\) failed at cell 2: ValueError: deliberate failure"):
        build_book([good, bad], build_dir, progress=False)
    assert (build_dir / "book" / "00_good.html").exists()  # what was built stays
    timings = json.loads((build_dir / "book" / "chapters.json").read_text())
    assert set(timings) == {"00_good"}
