"""The tooling around the chapters: the book, the environment check, and the course kit on nbgrader.

- :mod:`amdo_lab.course.book`: executes the chapters and builds the HTML book (``build``, ``site``,
  ``site --student``);
- :mod:`amdo_lab.course.environment`: ``python -m amdo_lab check-env`` (chapter 0 shows it);
- :mod:`amdo_lab.course.cells`: the exercise cells of a source notebook (tags, the targets its
  hidden tests register);
- :mod:`amdo_lab.course.release`: ``python -m amdo_lab release`` writes ``build/release/`` in
  nbgrader's own layout (hidden tests stripped, locked cells with checksums, manual "why" cells);
- :mod:`amdo_lab.course.records`: answers as JSON, carried out of the kernel by the check cells'
  grading records;
- :mod:`amdo_lab.course.scan`: the static scan of a submission for code that rebinds the checking
  machinery;
- :mod:`amdo_lab.course.grading`: ``python -m amdo_lab grade DIR``, autograded by nbgrader, with the
  verdicts computed outside the student's kernel, a gradebook, ``grades.csv`` and feedback HTML.

The chapters import nothing from here but the environment check (chapter 0).
"""

__all__ = ["book", "cells", "environment", "grading", "records", "release", "scan"]
