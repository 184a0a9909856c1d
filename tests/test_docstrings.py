"""Every public function, class and method of the package has a numpydoc docstring that says what
it takes and returns and, in a chapter's subpackage, which paper it follows.

numpydoc's own validator does the reading; the codes enforced are the ones a reader of the package
needs (``ENFORCED``); style-only codes (a summary's full stop, See Also, an extended summary) are not.
"""

from __future__ import annotations

import importlib
import inspect

import pytest

numpydoc_validate = pytest.importorskip("numpydoc.validate")

from amdo_lab.chapters import CHAPTERS  # noqa: E402

#: The shared floor and every chapter's subpackage (the one holding its exercises), from the registry.
SUBPACKAGES = ("common", *(c.exercises.split(".")[1] for c in CHAPTERS if c.number > 0))
CHAPTER_SUBPACKAGES = SUBPACKAGES[1:]

#: GL08 no docstring; SS01 no summary; PR01 a parameter not documented; PR02 a documented parameter
#: that does not exist; PR07 a parameter without description; RT01 no Returns section where the
#: function returns something; YD01 no Yields section for a generator.
ENFORCED = {"GL08", "SS01", "PR01", "PR02", "PR07", "RT01", "YD01"}


def public_objects(subpackage: str) -> list[tuple[str, object]]:
    """(dotted name, object) of every public function, class and public method of a subpackage."""
    module = importlib.import_module(f"amdo_lab.{subpackage}")
    names = getattr(module, "__all__", None) or [n for n in dir(module) if not n.startswith("_")]
    found = []
    for name in names:
        obj = getattr(module, name)
        if not (inspect.isfunction(obj) or inspect.isclass(obj)):
            continue  # constants document themselves in the module
        home = f"{obj.__module__}.{obj.__qualname__}"
        if not obj.__module__.startswith(f"amdo_lab.{subpackage}"):
            continue  # re-exported from elsewhere
        found.append((home, obj))
        if inspect.isclass(obj):
            for attribute, member in vars(obj).items():
                if attribute.startswith("_") or not (inspect.isfunction(member) or isinstance(member, property)):
                    continue
                found.append((f"{home}.{attribute}", member))
    return sorted(set(found), key=lambda item: item[0])


def docstring_problems(subpackage: str) -> list[str]:
    problems = []
    for dotted, obj in public_objects(subpackage):
        if isinstance(obj, property):
            if not (obj.__doc__ or "").strip():
                problems.append(f"{dotted}: GL08 property has no docstring")
            continue
        report = numpydoc_validate.validate(dotted)
        problems += [f"{dotted}: {code} {message}" for code, message in report["errors"] if code in ENFORCED]
        is_function = inspect.isfunction(obj) and "." not in obj.__qualname__
        if subpackage in CHAPTER_SUBPACKAGES and (is_function or inspect.isclass(obj)):
            if "References\n" not in inspect.cleandoc(obj.__doc__ or ""):
                problems.append(f"{dotted}: no References section (the paper, and the equation where one applies)")
    return problems


@pytest.mark.parametrize("subpackage", SUBPACKAGES)
def test_public_api_has_numpydoc_docstrings(subpackage):
    problems = docstring_problems(subpackage)
    assert not problems, f"{len(problems)} docstring problem(s):\n" + "\n".join(problems)
