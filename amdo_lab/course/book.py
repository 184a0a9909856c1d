"""Execute the chapter notebooks headless and build the book, a Sphinx site, from them.

``python -m amdo_lab build`` (what ``make book`` runs) executes every chapter in order with a
progress bar, saves every figure as PNG under ``build/figures/<chapter>/`` (through
``AMDO_FIG_DIR``), keeps the executed notebooks in ``build/executed/`` and then builds the site
into ``build/book/``. ``python -m amdo_lab site`` (``make site``) builds the same site from the
executed notebooks as they are, without running them.

The site itself is ordinary Sphinx: ``book/conf.py`` (MyST-NB, the Book theme, a local MathJax)
and ``book/index.md`` (the landing page, whose chapter table is filled in here from
:data:`amdo_lab.chapters.CHAPTERS`). A chapter that fails to execute stops the build with the
chapter, the cell and the error.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import time
from collections.abc import Mapping, Sequence
from datetime import datetime
from pathlib import Path

from amdo_lab.chapters import CHAPTERS, Chapter
from amdo_lab.common.plotting import FIG_DIR_VARIABLE

__all__ = [
    "BookError", "SOLUTION_CLASS", "SiteError", "build_book", "build_site", "chapter_run_seconds",
    "execute_chapter", "fold_solutions", "render_figures",
]

ROOT = Path(__file__).resolve().parents[2]
BUILD_DIR = ROOT / "build"
SITE_CONFIG_DIR = ROOT / "book"
CELL_TIMEOUT_S = 900
#: Where a notebook records how long its last full execution took (seconds, wall clock).
RUN_TIME_KEY = "run_seconds"
CHAPTERS_MARKER = "<!-- chapters -->"
#: Cells tagged ``solution`` are folded whole in the book; the folded parts carry this class (code
#: cells as the tag ``amdo-solution``, which MyST-NB turns into the class ``tag_amdo-solution``).
SOLUTION_TAG = "solution"
SOLUTION_CLASS = "amdo-solution"
SOLUTION_TITLE = "Solution (click to open)"
_FOLD_TAGS = {"hide-input", "hide-output", "hide-cell", "remove-input", "remove-output"}
_HEADING = re.compile(r"^ {0,3}#{1,6}\s")
_FENCE = re.compile(r"^ {0,3}(`{3,}|~{3,}|:{3,})")
_ANSI_ESCAPE = re.compile(r"\x1b\[[0-9;]*m")


class BookError(RuntimeError):
    """A chapter failed to execute; the message names the chapter, the cell and the error."""


class SiteError(BookError):
    """sphinx-build could not build the site; the message gives its last line of error."""


def execute_chapter(chapter: Chapter, *, figure_dir: Path | None = None, progress: bool = True):
    """Execute ``chapter``'s notebook in a fresh kernel and return the executed notebook node.

    The wall-clock run time is stored in the notebook's metadata (``amdo_lab.run_seconds``) so the
    landing page can show it even when the site is built later from the saved notebook.

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
    start = time.perf_counter()
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
    notebook.metadata.setdefault("amdo_lab", {})[RUN_TIME_KEY] = round(time.perf_counter() - start, 1)
    return notebook


def render_figures(chapter: Chapter, build_dir: Path = BUILD_DIR) -> list[Path]:
    """Execute ``chapter`` and return the PNG files it saved under ``build/figures/<slug>/``."""
    figure_dir = build_dir / "figures" / chapter.slug
    execute_chapter(chapter, figure_dir=figure_dir)
    return sorted(figure_dir.glob("*.png"))


def chapter_run_seconds(notebook: Mapping) -> float | None:
    """How long the executed ``notebook`` took to run, in seconds, or None when unknown.

    The value recorded by :func:`execute_chapter` wins; otherwise the span of the per-cell
    execution timestamps that Jupyter clients store (first cell started to last cell replied).
    """
    recorded = notebook.get("metadata", {}).get("amdo_lab", {}).get(RUN_TIME_KEY)
    if isinstance(recorded, (int, float)):
        return float(recorded)
    starts, ends = [], []
    for cell in notebook.get("cells", []):
        timing = cell.get("metadata", {}).get("execution", {})
        if "iopub.execute_input" in timing and "shell.execute_reply" in timing:
            starts.append(_timestamp(timing["iopub.execute_input"]))
            ends.append(_timestamp(timing["shell.execute_reply"]))
    if not starts:
        return None
    return max(ends) - min(starts)


def _timestamp(text: str) -> float:
    return datetime.fromisoformat(text.replace("Z", "+00:00")).timestamp()


def build_book(
    chapters: Sequence[Chapter] | None = None,
    build_dir: Path = BUILD_DIR,
    *,
    progress: bool = True,
    write_back: bool = False,
) -> Path:
    """Execute ``chapters``, then build the site from the executed notebooks; return ``index.html``.

    Parameters
    ----------
    chapters : sequence of Chapter, optional
        Chapters to (re)execute, in order; by default every chapter whose notebook exists.
        The site always holds every available chapter: those not executed now come from
        ``build/executed/`` when that copy is newer than the notebook, else from ``notebooks/``.
    build_dir : pathlib.Path
        Output root: ``book/`` (the site), ``figures/<slug>/`` (PNG), ``executed/`` (notebooks).
    write_back : bool
        Also overwrite the notebooks in ``notebooks/`` with the fresh outputs (for developers
        refreshing the committed outputs).
    """
    import nbformat

    if chapters is None:
        chapters = [chapter for chapter in CHAPTERS if chapter.path.exists()]
    executed_dir = build_dir / "executed"
    executed_dir.mkdir(parents=True, exist_ok=True)
    for chapter in chapters:
        figure_dir = build_dir / "figures" / chapter.slug
        if figure_dir.exists():
            shutil.rmtree(figure_dir)
        notebook = execute_chapter(chapter, figure_dir=figure_dir, progress=progress)
        nbformat.write(notebook, executed_dir / chapter.notebook)
        if write_back:
            nbformat.write(notebook, chapter.path)
    return build_site(build_dir, executed_dir=executed_dir)


def fold_solutions(notebook):
    """Fold every ``solution`` cell of ``notebook`` whole, in place, for the HTML book.

    A code cell gets the ``hide-cell`` tag (input and output folded behind one toggle) and the tag
    ``amdo-solution``; a markdown cell keeps its headings and has every other block of text put
    in a dropdown admonition of class ``amdo-solution`` (sphinx-togglebutton folds it). Nothing of
    a solution but its headings is shown before the reader clicks.

    Parameters
    ----------
    notebook : nbformat.NotebookNode
        An executed chapter notebook.

    Returns
    -------
    int
        The number of solution cells folded.
    """
    folded = 0
    for cell in notebook.cells:
        tags = list(cell.get("metadata", {}).get("tags", []))
        if SOLUTION_TAG not in tags:
            continue
        folded += 1
        if cell.cell_type == "code":
            kept = [tag for tag in tags if tag not in _FOLD_TAGS and tag != SOLUTION_CLASS]
            cell.metadata["tags"] = kept + ["hide-cell", SOLUTION_CLASS]
        elif cell.cell_type == "markdown":
            cell.source = _fold_prose(cell.source)
    return folded


def _fold_prose(source: str) -> str:
    """Headings stay; each run of other lines goes into a dropdown admonition."""
    longest = max([len(match.group(1)) for line in source.splitlines()
                   if (match := re.match(r"^\s*(:{3,})", line))] + [3])
    fence = ":" * (longest + 1)
    blocks: list[tuple[bool, list[str]]] = []
    in_code = None
    for line in source.splitlines():
        fence_match = _FENCE.match(line)
        if fence_match and fence_match.group(1)[0] != ":":
            marker = fence_match.group(1)
            in_code = None if in_code and marker.startswith(in_code) else (in_code or marker[:3])
        is_heading = in_code is None and bool(_HEADING.match(line))
        if blocks and blocks[-1][0] == is_heading and not is_heading:
            blocks[-1][1].append(line)
        else:
            blocks.append((is_heading, [line]))
    out: list[str] = []
    for is_heading, lines in blocks:
        text = "\n".join(lines).strip("\n")
        if is_heading or not text.strip():
            out.append(text)
            continue
        out.append(f"{fence}{{admonition}} {SOLUTION_TITLE}\n:class: dropdown {SOLUTION_CLASS}\n\n{text}\n{fence}")
    return "\n\n".join(part for part in out if part)


def _site_sources(executed_dir: Path | None) -> list[tuple[Chapter, Path]]:
    sources = []
    for chapter in CHAPTERS:
        if not chapter.path.exists():
            continue
        path = chapter.path
        if executed_dir is not None:
            fresh = executed_dir / chapter.notebook
            if fresh.exists() and fresh.stat().st_mtime >= chapter.path.stat().st_mtime:
                path = fresh
        sources.append((chapter, path))
    return sources


def _release_sources(release_root: Path) -> list[tuple[Chapter, Path]]:
    sources = []
    for chapter in CHAPTERS:
        path = release_root / "release" / f"ch{chapter.number:02d}" / chapter.notebook
        if path.exists():
            sources.append((chapter, path))
    return sources


def build_site(
    build_dir: Path = BUILD_DIR,
    *,
    executed_dir: Path | None = None,
    quiet: bool = True,
    warnings_as_errors: bool = False,
    student: bool = False,
) -> Path:
    """Build the HTML book from executed notebooks with sphinx-build; return ``index.html``.

    Nothing is executed: each available chapter is rendered from its saved outputs (the copy in
    ``executed_dir`` when it is newer than ``notebooks/``, else the committed notebook).
    The sources are staged in ``build/site-src/`` and the site is written to ``build/book/``.

    Parameters
    ----------
    build_dir : pathlib.Path
        Output root (``site-src/``, ``site-doctrees/``, ``book/``).
    executed_dir : pathlib.Path, optional
        Folder of freshly executed notebooks that win over ``notebooks/`` when newer.
    quiet : bool
        Only warnings and errors from sphinx-build (printed to stderr).
    warnings_as_errors : bool
        Fail on any sphinx warning (a broken equation or cross reference, an unknown cell
        output); the tests build this way.
    student : bool
        Build the student book into ``build/student-book/`` from the release
        (``build/release/chNN/``, written by ``python -m amdo_lab release``): no solutions, and the
        download button serves the release notebook.
    """
    import nbformat

    sources = _release_sources(build_dir) if student else _site_sources(executed_dir)
    if not sources:
        raise SiteError("no release notebook in build/release/: run `python -m amdo_lab release` first"
                        if student else "no chapter notebook found in notebooks/")
    prefix = "student-" if student else ""
    staging = build_dir / f"{prefix}site-src"
    if staging.exists():
        shutil.rmtree(staging)
    staging.mkdir(parents=True)
    rows = []
    for chapter, path in sources:
        # a fresh copy (new modification time): sphinx re-reads every chapter, whichever source won;
        # solutions folded whole
        notebook = nbformat.read(path, as_version=4)
        fold_solutions(notebook)
        nbformat.write(notebook, staging / chapter.notebook)
        seconds = chapter_run_seconds(notebook)
        rows.append((chapter, seconds))
    landing = (SITE_CONFIG_DIR / "index.md").read_text(encoding="utf-8")
    if CHAPTERS_MARKER not in landing:
        raise SiteError(f"book/index.md lacks the line {CHAPTERS_MARKER} where the chapters go")
    landing = landing.replace(CHAPTERS_MARKER, _chapter_list(rows))
    (staging / "index.md").write_text(landing, encoding="utf-8")

    site_dir = build_dir / f"{prefix}book"
    doctrees = build_dir / f"{prefix}site-doctrees"
    command = [
        sys.executable, "-m", "sphinx", "-b", "html", "-c", str(SITE_CONFIG_DIR),
        "-d", str(doctrees), str(staging), str(site_dir),
    ]
    if quiet:
        command.insert(3, "-q")
    if warnings_as_errors:
        command.insert(3, "-W")
    completed = subprocess.run(command, capture_output=quiet, text=True)
    if completed.returncode != 0:
        details = (completed.stderr or "").strip().splitlines() if quiet else []
        problems = [line for line in details if "WARNING" in line or "ERROR" in line]
        shown = problems[:10] or details[-1:] or [f"exit status {completed.returncode}"]
        raise SiteError("sphinx-build failed: " + "\n".join(shown))
    if quiet and completed.stderr.strip():
        print(completed.stderr.strip(), file=sys.stderr)
    for chapter, path in sources:  # the download button gives the chapter as written, not as staged
        download = site_dir / "_sources" / chapter.notebook
        if download.exists():
            shutil.copyfile(path, download)
    return site_dir / "index.html"


def _format_run_time(seconds: float | None) -> str:
    if seconds is None:
        return "—"
    if seconds < 90:
        return f"{seconds:.0f} s"
    return f"{seconds / 60:.1f} min"


def _chapter_list(rows: Sequence[tuple[Chapter, float | None]]) -> str:
    """The landing page's list of chapters (title, summary, paper, run time) and the toctree."""
    lines = []
    for chapter, seconds in rows:
        lines += [
            f"### {chapter.number} · [{chapter.title}]({chapter.notebook})",
            "",
            chapter.summary,
            "",
        ]
        details = [] if chapter.paper in ("", "—") else [f"*Paper:* {chapter.paper}"]
        details.append(f"*Run time:* {_format_run_time(seconds)}")
        lines += [" · ".join(details), ""]
    lines.append(
        "The run time is how long the chapter took to execute from top to bottom when its "
        "outputs were last produced."
    )
    toctree = ["", "```{toctree}", ":hidden:", ":maxdepth: 2", ":caption: Chapters", ""]
    toctree += [chapter.slug for chapter, _ in rows]
    toctree.append("```")
    return "\n".join(lines + toctree) + "\n"


