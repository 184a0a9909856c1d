"""Command line of the workbook: ``python -m amdo_lab build | site | figures | execute | release | grade | check-env``."""

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
    site.add_argument("--student", action="store_true",
                      help="the student book, from build/release/ (no solutions), into build/student-book/")
    figures = commands.add_parser("figures", help="execute chapters and save their figures as PNG")
    figures.add_argument("--chapter", type=int, action="append", help="only this chapter (repeatable)")
    execute = commands.add_parser("execute", help="re-run notebooks in place (refresh committed outputs)")
    execute.add_argument("--chapter", type=int, action="append", help="only this chapter (repeatable)")
    release = commands.add_parser(
        "release", help="write the student release in build/release/ (nbgrader's layout: no solutions, "
                        "hidden tests stripped, locked cells)")
    release.add_argument("--chapter", type=int, action="append", help="only this chapter (repeatable)")
    release.add_argument("--out", type=Path, default=None, help="course root instead of build/")
    grade = commands.add_parser(
        "grade", help="grade a folder of submitted notebooks (flat, or one folder per student) with nbgrader")
    grade.add_argument("submissions", type=Path, help="folder of submitted notebooks, or of student folders")
    grade.add_argument("--timeout", type=float, default=600,
                       help="seconds a notebook may run in all (default 600)")
    grade.add_argument("--workers", type=int, default=2, help="notebooks graded at the same time (default 2)")
    grade.add_argument("--no-progress", action="store_true", help="no progress bar")
    grade.add_argument("--no-feedback", action="store_true", help="no feedback pages")
    grade.add_argument("--export", action="store_true",
                       help="only re-write grades.csv with the 'why' marks entered since (no re-run)")
    lab = commands.add_parser("lab", help="JupyterLab on notebooks/ (or the release with --student); "
                                          "passes --allow-root when run as root")
    lab.add_argument("--student", action="store_true", help="open the student release build/release/")
    commands.add_parser("check-env", help="check packages, EGL, the browser and off-screen 3-D rendering")
    return parser


def _select(numbers: list[int] | None):
    if not numbers:
        return available_chapters()
    return [find_chapter(number) for number in numbers]


def _lab(student: bool, extra: list[str]) -> int:
    """Run JupyterLab on the instructor's notebooks or the release, as root too (``--allow-root``)."""
    import os

    from amdo_lab.course.book import BUILD_DIR, ROOT

    folder = ROOT / "notebooks"
    if student:
        folder = BUILD_DIR / "release"
        if not folder.exists():
            from amdo_lab.course.release import write_release

            write_release()
    command = [sys.executable, "-m", "jupyter", "lab"]
    if hasattr(os, "getuid") and os.getuid() == 0:
        command.append("--allow-root")  # Jupyter refuses root without it (containers, course VMs)
    command += extra + [str(folder)]
    sys.stdout.flush()
    os.execv(sys.executable, command)  # JupyterLab takes this process over (signals reach it directly)
    return 0  # not reached


def main(argv: list[str] | None = None) -> int:
    parser = _parser()
    args, extra = parser.parse_known_args(argv)
    if args.command == "lab":
        return _lab(args.student, extra)
    if extra:
        parser.error(f"unrecognized arguments: {' '.join(extra)}")
    if args.command == "check-env":
        from amdo_lab.course.environment import check_environment

        report = check_environment()
        print("\n".join(report.lines))
        print("environment ready" if report.ok else "environment NOT ready: see the FAIL lines")
        return 0 if report.ok else 1
    if args.command == "site":
        from amdo_lab.course.book import BUILD_DIR, BookError, build_site

        try:
            if args.student and not (BUILD_DIR / "release").exists():
                from amdo_lab.course.release import write_release

                write_release()
            index = build_site(executed_dir=BUILD_DIR / "executed", quiet=not args.verbose, student=args.student)
        except (BookError, RuntimeError) as error:
            print(f"error: {error}", file=sys.stderr)
            return 1
        print(f"The {'student ' if args.student else ''}book is ready: open {Path(index).resolve()}")
        return 0
    if args.command == "grade":
        return _grade(args)
    try:
        chapters = _select(args.chapter)
    except ValueError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    if args.command == "release":
        from amdo_lab.course.release import BUILD_DIR, write_release

        try:
            written = write_release(chapters, args.out or BUILD_DIR)
        except RuntimeError as error:
            print(f"error: {error}", file=sys.stderr)
            return 1
        folder = (args.out or BUILD_DIR) / "release"
        print(f"release: {len(written)} chapter(s) in {folder}/ (nbgrader's layout; gradebook in "
              f"{(args.out or BUILD_DIR) / 'gradebook.db'})")
        return 0
    from amdo_lab.course.book import BookError, SiteError, build_book, execute_chapter, render_figures

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
    from amdo_lab.course.grading import export_grades, grade_folder, summary_table

    if args.timeout <= 0 or args.workers < 1:
        print("error: --timeout must be positive and --workers at least 1", file=sys.stderr)
        return 2
    try:
        if args.export:
            results, csv_path = export_grades(args.submissions)
        else:
            results, csv_path = grade_folder(args.submissions, timeout_s=args.timeout, workers=args.workers,
                                             progress=not args.no_progress, feedback=not args.no_feedback)
    except ValueError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    print(summary_table(results))
    graded = sum(not result.error for result in results)
    print(f"\n{graded} of {len(results)} notebook(s) graded; grades in {csv_path}"
          + ("" if args.export else f", feedback in {Path(args.submissions) / 'feedback'}/"))
    return 0 if graded else 1


if __name__ == "__main__":
    sys.exit(main())
