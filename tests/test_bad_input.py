"""Bad input over the public API: every public callable, each argument spoiled in turn.

The package promises that bad input gets a ``ValueError`` or ``TypeError`` that names the argument,
and that nothing is silently turned into NaN. This test holds the promise to account: a table per
subpackage (``tests/bad_input_cases/<subpackage>.py``) has one entry per public callable with a valid call, and a *kind* for each argument (an array, a
count, a probability, a flag, a seed, ...). ``spoil`` makes the bad values of each kind (NaN or inf
inside an array, an empty or mis-shaped array, a string, a bool for a number, zero or negative
counts, a float for an int, None, 1e308). Every spoiled call must raise ``ValueError`` or
``TypeError`` whose message contains the argument's name; for a finite 1e308 returning finite
output is also fine (CONTRIBUTING.md's overflow policy forbids only NaN or inf out). Any other outcome is reported:

- *crash*: another exception type, or the interpreter dies (the calls run in a child process with
  ``faulthandler``, so a segfault names the call instead of killing the test run);
- *silent accept*: the call returned (unless the entry lists that spoiled value as acceptable);
- *wrong name*: the error does not name the argument at fault.

A second test checks that every public name of a subpackage has an entry, so a new function cannot
escape. A subpackage without a table is expected to fail that test, strictly; a table's
``KNOWN_FAILURES`` lists calls not yet refused, each of which must still fail.
"""

from __future__ import annotations

import functools
import importlib
import inspect
import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(Path(__file__).resolve().parent))  # the tables: tests/bad_input_cases/

from bad_input_cases._core import FINITE_LABELS, Case, all_finite, spoil  # noqa: E402

SUBPACKAGES = ("common", "em_articulated", "pdm_mixtures", "cat_fluid", "ear_biometrics", "face_glmm",
               "cue_fusion_pf", "incremental_svd")


def table(subpackage: str):
    """The subpackage's table module, or None while it has none."""
    try:
        return importlib.import_module(f"bad_input_cases.{subpackage}")
    except ModuleNotFoundError:
        return None


@functools.cache
def all_cases() -> dict[str, Case]:
    """Every tabled callable, by the dotted name a user imports it under."""
    found = {}
    for subpackage in SUBPACKAGES:
        module = table(subpackage)
        if module is not None:
            found |= {f"amdo_lab.{subpackage}.{name}": case for name, case in module.cases().items()}
    return found


def known_failures() -> dict[tuple[str, str, str], str]:
    found = {}
    for subpackage in SUBPACKAGES:
        module = table(subpackage)
        if module is not None:
            found |= {(f"amdo_lab.{subpackage}.{name}", argument, label): reason
                      for (name, argument, label), reason in module.KNOWN_FAILURES.items()}
    return found


def spoiled_calls() -> list[tuple[str, str, str]]:
    """(callable, argument, spoiled label) of every spoiled call, in a fixed order."""
    calls = []
    for dotted, case in all_cases().items():
        for argument, kind in case.kinds.items():
            calls += [(dotted, argument, label) for label, _ in spoil(kind, case.valid[argument])]
    return calls


def run_call(dotted: str, argument: str, label: str) -> dict[str, str]:
    """Make one spoiled call and classify what happened."""
    case = all_cases()[dotted]
    bad = dict(spoil(case.kinds[argument], case.valid[argument]))[label]
    word = case.names.get(argument, argument)
    try:
        result = case.function(**{**case.valid, argument: bad})
    except (ValueError, TypeError) as error:
        if word in str(error):
            return {"outcome": "clear"}
        return {"outcome": "wrong name", "detail": f"{type(error).__name__}: {error}"}
    except Exception as error:  # noqa: BLE001 - any other exception type is what we look for
        return {"outcome": "crash", "detail": f"{type(error).__name__}: {error}"}
    if (argument, label) in case.accept:
        return {"outcome": "accepted sensibly"}
    if label in FINITE_LABELS:  # finite input: returning is fine as long as the output stays finite
        if all_finite(result):
            return {"outcome": "accepted sensibly"}
        return {"outcome": "silent accept", "detail": "returned NaN or inf from finite input"}
    return {"outcome": "silent accept", "detail": "returned without an error"}


def _worker(start: int) -> None:
    """Child process: run the spoiled calls from ``start`` on, one JSON line each (flushed first)."""
    import faulthandler

    faulthandler.enable()
    for index, (dotted, argument, label) in enumerate(spoiled_calls()[start:], start):
        print(json.dumps({"index": index, "call": [dotted, argument, label], "started": True}), flush=True)
        print(json.dumps({"index": index, **run_call(dotted, argument, label)}), flush=True)


def run_all() -> list[dict[str, object]]:
    """Every spoiled call's outcome; a call that kills the child is a crash and the rest go on."""
    calls, results, start = spoiled_calls(), {}, 0
    while start < len(calls):
        done = subprocess.run([sys.executable, __file__, "--worker", str(start)], capture_output=True, text=True,
                              cwd=ROOT, timeout=600)
        last = start
        for line in done.stdout.splitlines():
            record = json.loads(line)
            last = record["index"]
            if "outcome" in record:
                results[last] = record
        if last in results and last == len(calls) - 1:
            break
        if last not in results:  # the child died inside this call
            tail = (done.stderr.strip().splitlines() or ["no message"])[0]
            results[last] = {"index": last, "outcome": "crash", "detail": f"the interpreter died: {tail}"}
        start = last + 1
    return [{"call": calls[i], **results[i]} for i in range(len(calls))]


@pytest.fixture(scope="module")
def outcomes() -> list[dict[str, object]]:
    return run_all()


def test_every_spoiled_call_is_refused_by_name(outcomes):
    known = known_failures()
    failed = {tuple(o["call"]): o for o in outcomes if o["outcome"] not in ("clear", "accepted sensibly")}
    unexpected = [f"{' / '.join(call)}: {o['outcome']} ({o.get('detail', '')})"
                  for call, o in failed.items() if call not in known]
    fixed = [" / ".join(call) for call in known if call not in failed]
    counts = {kind: sum(o["outcome"] == kind for o in outcomes) for kind in
              ("clear", "accepted sensibly", "wrong name", "crash", "silent accept")}
    assert len(outcomes) > 0
    assert not unexpected, f"{counts}\n" + "\n".join(unexpected)
    assert not fixed, "now refused by name, remove from KNOWN_FAILURES:\n" + "\n".join(fixed)


def _public_callables(subpackage: str) -> set[str]:
    module = importlib.import_module(f"amdo_lab.{subpackage}")
    names = getattr(module, "__all__", None) or [n for n in dir(module) if not n.startswith("_")]
    return {f"amdo_lab.{subpackage}.{name}" for name in names
            if inspect.isfunction(getattr(module, name)) or inspect.isclass(getattr(module, name))}


@pytest.mark.parametrize(
    "subpackage",
    [pytest.param(name, marks=pytest.mark.xfail(strict=True, reason="no table yet")) if table(name) is None
     else name for name in SUBPACKAGES],
)
def test_every_public_callable_is_in_the_table(subpackage):
    module = table(subpackage)
    exempt = {f"amdo_lab.{subpackage}.{name}" for name in (module.EXEMPT if module else {})}
    missing = sorted(_public_callables(subpackage) - set(all_cases()) - exempt)
    assert not missing, f"{len(missing)} public callable(s) of amdo_lab.{subpackage} missing from its table: {missing}"


if __name__ == "__main__" and sys.argv[1:2] == ["--worker"]:
    sys.path.insert(0, str(ROOT))
    _worker(int(sys.argv[2]))
