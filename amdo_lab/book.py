"""Execute the chapter notebooks headless and write the static, offline HTML book.

``python -m amdo_lab build`` (what ``make book`` runs) executes every chapter in order with a
progress bar, saves every figure as PNG under ``build/figures/<chapter>/`` (through
``AMDO_FIG_DIR``), converts each executed notebook to HTML whose equations are typeset by a local
copy of MathJax (from the ``jupyter-server-mathjax`` package, no CDN), and writes
``build/book/index.html``. A chapter that fails stops the build with the chapter, the cell and the
error; chapters already built stay in place.
"""

from __future__ import annotations

import html
import json
import os
import re
import shutil
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from amdo_lab.chapters import CHAPTERS, Chapter
from amdo_lab.common.plotting import FIG_DIR_VARIABLE

__all__ = ["BookError", "build_book", "execute_chapter", "render_figures"]

ROOT = Path(__file__).resolve().parent.parent
BUILD_DIR = ROOT / "build"
MATHJAX_CONFIG = "TeX-AMS-MML_HTMLorMML-full,Safe"
CELL_TIMEOUT_S = 900
_ANSI_ESCAPE = re.compile(r"\x1b\[[0-9;]*m")


class BookError(RuntimeError):
    """A chapter failed to execute; the message names the chapter, the cell and the error."""


@dataclass(frozen=True)
class ChapterRun:
    chapter: Chapter
    seconds: float
    n_figures: int


def execute_chapter(chapter: Chapter, *, figure_dir: Path | None = None, progress: bool = True):
    """Execute ``chapter``'s notebook in a fresh kernel and return the executed notebook node.

    Parameters
    ----------
    chapter : Chapter
        Which notebook to run (its working directory is ``notebooks/``).
    figure_dir : pathlib.Path, optional
        When given, ``AMDO_FIG_DIR`` is set to it so every ``savefig`` call writes a PNG there.
    progress : bool
        Show a per-cell progress bar.
    """
    import nbformat
    from nbclient import NotebookClient
    from nbclient.exceptions import CellExecutionError
    from tqdm.auto import tqdm

    if not chapter.path.exists():
        raise BookError(f"chapter {chapter.number}: notebook {chapter.path.name} is missing")
    notebook = nbformat.read(chapter.path, as_version=4)
    code_cells = [i for i, cell in enumerate(notebook.cells) if cell.cell_type == "code"]
    bar = tqdm(
        total=len(code_cells), desc=f"ch{chapter.number:02d} {chapter.slug}", unit="cell",
        disable=not progress, leave=True,
    )
    current = {"index": -1}

    def on_start(cell, cell_index):
        current["index"] = cell_index

    def on_complete(cell, cell_index):
        if cell.cell_type == "code":
            bar.update(1)

    client = NotebookClient(
        notebook,
        timeout=CELL_TIMEOUT_S,
        kernel_name="python3",
        resources={"metadata": {"path": str(chapter.path.parent)}},
        on_cell_start=on_start,
        on_cell_complete=on_complete,
    )
    previous = os.environ.get(FIG_DIR_VARIABLE)
    if figure_dir is not None:
        figure_dir.mkdir(parents=True, exist_ok=True)
        os.environ[FIG_DIR_VARIABLE] = str(figure_dir)
    try:
        client.execute()
    except CellExecutionError as error:
        lines = _ANSI_ESCAPE.sub("", str(error)).strip().splitlines()
        last = next((line for line in reversed(lines) if line.strip()), "unknown error")
        raise BookError(
            f"chapter {chapter.number} ({chapter.notebook}) failed at cell {current['index']}: {last}"
        ) from None
    finally:
        bar.close()
        if figure_dir is not None:
            if previous is None:
                os.environ.pop(FIG_DIR_VARIABLE, None)
            else:
                os.environ[FIG_DIR_VARIABLE] = previous
    return notebook


def render_figures(chapter: Chapter, build_dir: Path = BUILD_DIR) -> list[Path]:
    """Execute ``chapter`` and return the PNG files it saved under ``build/figures/<slug>/``."""
    figure_dir = build_dir / "figures" / chapter.slug
    execute_chapter(chapter, figure_dir=figure_dir)
    return sorted(figure_dir.glob("*.png"))


def build_book(
    chapters: Sequence[Chapter] | None = None,
    build_dir: Path = BUILD_DIR,
    *,
    progress: bool = True,
    write_back: bool = False,
) -> Path:
    """Execute ``chapters`` and write the HTML book; return the path of ``index.html``.

    Parameters
    ----------
    chapters : sequence of Chapter, optional
        Chapters to (re)build, in order; by default every chapter whose notebook exists.
        Chapters built before and not named here stay listed.
    build_dir : pathlib.Path
        Output root: ``book/`` (HTML), ``figures/<slug>/`` (PNG) and ``executed/`` (notebooks).
    write_back : bool
        Also overwrite the notebooks in ``notebooks/`` with the fresh outputs (for developers
        refreshing the committed outputs).
    """
    import nbformat

    if chapters is None:
        chapters = [chapter for chapter in CHAPTERS if chapter.path.exists()]
    book_dir = build_dir / "book"
    executed_dir = build_dir / "executed"
    book_dir.mkdir(parents=True, exist_ok=True)
    executed_dir.mkdir(parents=True, exist_ok=True)
    _install_mathjax(book_dir)
    timings = _load_timings(book_dir)
    for chapter in chapters:
        start = time.perf_counter()
        figure_dir = build_dir / "figures" / chapter.slug
        if figure_dir.exists():
            shutil.rmtree(figure_dir)
        notebook = execute_chapter(chapter, figure_dir=figure_dir, progress=progress)
        seconds = time.perf_counter() - start
        nbformat.write(notebook, executed_dir / chapter.notebook)
        if write_back:
            nbformat.write(notebook, chapter.path)
        (book_dir / f"{chapter.slug}.html").write_text(_to_html(notebook), encoding="utf-8")
        timings[chapter.slug] = {
            "seconds": round(seconds, 1),
            "figures": len(list(figure_dir.glob("*.png"))),
        }
        _save_timings(book_dir, timings)
        _write_index(book_dir, timings)
    _write_index(book_dir, timings)
    return book_dir / "index.html"


def _install_mathjax(book_dir: Path) -> None:
    """Copy MathJax 2 from the installed jupyter-server-mathjax package next to the pages."""
    target = book_dir / "mathjax"
    if (target / "MathJax.js").exists():
        return
    import jupyter_server_mathjax

    source = Path(jupyter_server_mathjax.__file__).parent / "static"
    if not (source / "MathJax.js").exists():
        raise BookError("jupyter-server-mathjax is installed without its MathJax files; reinstall it")
    shutil.copytree(source, target, dirs_exist_ok=True)


def _to_html(notebook) -> str:
    from nbconvert import HTMLExporter

    exporter = HTMLExporter(template_name="lab")
    exporter.mathjax_url = f"mathjax/MathJax.js?config={MATHJAX_CONFIG}"
    # No page of the book may reach the network: widget and diagram scripts are not used.
    exporter.require_js_url = ""
    exporter.jquery_url = ""
    exporter.mermaid_js_url = ""
    body, _ = exporter.from_notebook_node(notebook)
    return body


def _load_timings(book_dir: Path) -> dict:
    path = book_dir / "chapters.json"
    return json.loads(path.read_text()) if path.exists() else {}


def _save_timings(book_dir: Path, timings: dict) -> None:
    (book_dir / "chapters.json").write_text(json.dumps(timings, indent=1, sort_keys=True))


def _write_index(book_dir: Path, timings: dict) -> None:
    rows = []
    for chapter in CHAPTERS:
        built = chapter.slug in timings and (book_dir / f"{chapter.slug}.html").exists()
        title = html.escape(chapter.title)
        if built:
            link = f'<a href="{chapter.slug}.html">{title}</a>'
        elif chapter.path.exists():
            link = f"{title} (not built yet: run <code>make book</code>)"
        else:
            link = f"{title} (in preparation)"
        run = f"{timings[chapter.slug]['seconds']:.0f} s" if built else "—"
        figures = str(timings[chapter.slug]["figures"]) if built else "—"
        rows.append(
            f"<tr><td>{chapter.number}</td><td>{link}<br><small>{html.escape(chapter.summary)}"
            f"</small></td><td><small>{html.escape(chapter.paper)}</small></td>"
            f"<td>{run}</td><td>{figures}</td></tr>"
        )
    page = _INDEX_TEMPLATE.format(rows="\n".join(rows))
    (book_dir / "index.html").write_text(page, encoding="utf-8")


_INDEX_TEMPLATE = """<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<title>AMDO Lab</title>
<style>
body {{ font-family: system-ui, sans-serif; max-width: 70em; margin: 2em auto; padding: 0 1em;
       color: #222; }}
table {{ border-collapse: collapse; width: 100%; }}
td, th {{ border-bottom: 1px solid #ddd; padding: 0.5em; text-align: left; vertical-align: top; }}
th {{ background: #f4f4f4; }}
small {{ color: #555; }}
</style></head>
<body>
<h1>AMDO Lab</h1>
<p>A workbook on registering, modelling and recognising articulated and deformable objects.
Each chapter implements one published method step by step with the <code>amdo_lab</code> package,
reproduces the paper's figures and tables, and goes beyond the paper. Figures are also saved as
PNG files under <code>build/figures/&lt;chapter&gt;/</code>.</p>
<table>
<tr><th>#</th><th>Chapter</th><th>Paper</th><th>Run time</th><th>Figures</th></tr>
{rows}
</table>
</body></html>
"""
