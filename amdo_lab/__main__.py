"""Command line of the workbook: ``python -m amdo_lab build | site | figures | execute | editions | grade | check-env``."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from amdo_lab.chapters import available_chapters, find_chapter


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m amdo_lab", description=__doc__)
    commands = parser.add_subparsers(dest="command", required=True)
    build = commands.add_parser("build", help="execute the chapters, then build the HTML book in build/book/")
    build.add_argument("--chapter", type=int, action="append", help="only this chapter (repeatable)")
    build.add_argument("--write-back", action="store_true",
                       help="also store the fresh outputs in notebooks/ (for developers)")
    build.add_argument("--no-progress", action="store_true", help="no progress bars")
    site = commands.add_parser(
        "site", help="build the HTML book from the executed notebooks, without running them")
    site.add_argument("--verbose", action="store_true", help="show sphinx-build's progress")
    figures = commands.add_parser("figures", help="execute chapters and save their figures as PNG")
    figures.add_argument("--chapter", type=int, action="append", help="only this chapter (repeatable)")
    execute = commands.add_parser("execute", help="re-run notebooks in place (refresh committed outputs)")
    execute.add_argument("--chapter", type=int, action="append", help="only this chapter (repeatable)")
    editions = commands.add_parser(
        "editions", help="write build/student/ (solutions removed) and build/instructor/ (everything)")
    editions.add_argument("--chapter", type=int, action="append", help="only this chapter (repeatable)")
    editions.add_argument("--out", type=Path, default=None, help="output root instead of build/")
    grade = commands.add_parser(
        "grade", help="grade a folder of submitted notebooks with the chapters' own checks")
    grade.add_argument("submissions", type=Path, help="folder of submitted notebooks")
    grade.add_argument("--out", type=Path, default=None, help="CSV to write (default SUBMISSIONS/grades.csv)")
    grade.add_argument("--timeout", type=float, default=600, help="seconds allowed per notebook (default 600)")
    grade.add_argument("--workers", type=int, default=1, help="notebooks graded at the same time (default 1)")
    grade.add_argument("--no-progress", action="store_true", help="no progress bar")
    commands.add_parser("check-env", help="check packages, EGL, the browser and off-screen 3-D rendering")
    return parser


def _select(numbers: list[int] | None):
    if not numbers:
        return available_chapters()
    return [find_chapter(number) for number in numbers]


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    if args.command == "check-env":
        from amdo_lab.environment import check_environment

        report = check_environment()
        print("\n".join(report.lines))
        print("environment ready" if report.ok else "environment NOT ready: see the FAIL lines")
        return 0 if report.ok else 1
    if args.command == "site":
        from amdo_lab.book import BUILD_DIR, BookError, build_site

        try:
            index = build_site(executed_dir=BUILD_DIR / "executed", quiet=not args.verbose)
        except BookError as error:
            print(f"error: {error}", file=sys.stderr)
            return 1
        print(f"The book is ready: open {Path(index).resolve()}")
        return 0
    if args.command == "grade":
        return _grade(args)
    try:
        chapters = _select(args.chapter)
    except ValueError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    if args.command == "editions":
        from amdo_lab.editions import write_editions

        written = write_editions(args.out, chapters) if args.out else write_editions(chapters=chapters)
        for edition, paths in written.items():
            folder = paths[0].parent if paths else edition
            print(f"{edition} edition: {len(paths)} chapter(s) in {folder}/")
        return 0
    from amdo_lab.book import BookError, SiteError, build_book, execute_chapter, render_figures

    try:
        if args.command == "build":
            index = build_book(chapters, progress=not args.no_progress, write_back=args.write_back)
            print(f"\nThe book is ready: open {Path(index).resolve()}")
        elif args.command == "figures":
            for chapter in chapters:
                paths = render_figures(chapter)
                folder = Path("build") / "figures" / chapter.slug
                print(f"chapter {chapter.number}: {len(paths)} figure(s) in {folder}/")
        else:
            import nbformat

            for chapter in chapters:
                nbformat.write(execute_chapter(chapter), chapter.path)
                print(f"chapter {chapter.number}: {chapter.notebook} re-executed in place")
    except SiteError as error:
        print(f"\nerror: {error}", file=sys.stderr)
        return 1
    except BookError as error:
        print(f"\nerror: {error}", file=sys.stderr)
        print("chapters executed before this one are in build/executed/; "
              "`python -m amdo_lab site` builds the book from what is there", file=sys.stderr)
        return 1
    return 0


def _grade(args) -> int:
    from amdo_lab.grading import grade_folder, summary_table

    if args.timeout <= 0 or args.workers < 1:
        print("error: --timeout must be positive and --workers at least 1", file=sys.stderr)
        return 2
    try:
        rows, csv_path = grade_folder(args.submissions, out=args.out, timeout_s=args.timeout,
                                      workers=args.workers, progress=not args.no_progress)
    except ValueError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    print(summary_table(rows))
    print(f"\n{len({row.file for row in rows})} file(s) graded; grades in {csv_path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
