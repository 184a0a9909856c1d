"""Fixtures shared by the course-kit tests: one release of the chapters on the new exercise format."""

from __future__ import annotations

import importlib

import pytest


def migrated_chapters():
    """The chapters whose exercises all keep their target in the source's hidden tests."""
    from amdo_lab.chapters import available_chapters

    return [chapter for chapter in available_chapters()
            if all(exercise.expected is None
                   for exercise in importlib.import_module(chapter.exercises).EXERCISES.exercises)]


@pytest.fixture(scope="session")
def course_release(tmp_path_factory):
    """``(root, {chapter number: release path})``: nbgrader's release of the migrated chapters, written once."""
    from amdo_lab.course.release import write_release

    root = tmp_path_factory.mktemp("course")
    chapters = migrated_chapters()
    paths = write_release(chapters, root=root)
    return root, {chapter.number: path for chapter, path in zip(chapters, paths)}
