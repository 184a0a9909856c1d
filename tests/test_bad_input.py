"""Bad input over the public API: every public callable, each argument spoiled in turn.

The package promises that bad input gets a ``ValueError`` or ``TypeError`` that names the argument,
and that nothing is silently turned into NaN. This test holds the promise to account: a table per
subpackage (``tests/bad_input_cases/<subpackage>.py``) has one entry per public callable with a valid call, and a *kind* for each argument (an array, a
count, a probability, a flag, a seed, ...). ``spoil`` makes the bad values of each kind (NaN or inf
inside an array, an empty or mis-shaped array, a string, a bool for a number, zero or negative
counts, a float for an int, None, 1e308). Every spoiled call must raise ``ValueError`` or
``TypeError`` whose message names the argument as a whole word; for a finite 1e308 returning finite
output is also fine if nothing overflowed on the way (CONTRIBUTING.md's overflow policy). Counts
are spoiled with 10**9 and 2**63 too, which a documented maximum must refuse. Any other outcome is
reported:

- *crash*: another exception type, or the interpreter dies (the calls run in a child process with
  ``faulthandler``, so a segfault names the call instead of killing the test run);
- *hang*: the call did not answer within a short time limit (it is killed and the rest go on);
- *silent accept*: the call returned (unless the entry lists that spoiled value as acceptable), or
  returned after an overflow warning;
- *wrong name*: the error does not name the argument at fault.

A second test checks that every public name of a subpackage has an entry, and a third that every
public method of its public classes has one (``"Class.method"``), so a new function or method cannot
escape. A subpackage without a table is expected to fail that test, strictly; a table's
``KNOWN_FAILURES`` lists calls not yet refused, each of which must still fail.
"""

from __future__ import annotations

import functools
import importlib
import inspect
import json
import os
import re
import select
import signal
import subprocess
import sys
import time
import warnings
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(Path(__file__).resolve().parent))  # the tables: tests/bad_input_cases/

from bad_input_cases._core import FIELD, FINITE_LABELS, Case, all_finite, spoil  # noqa: E402

from amdo_lab.chapters import CHAPTERS  # noqa: E402

#: The shared floor and every chapter's subpackage (the one holding its exercises), from the registry.
SUBPACKAGES = ("common", *(chapter.exercises.split(".")[1] for chapter in CHAPTERS))


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


@functools.cache
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


def names_word(message: str, word: str) -> bool:
    """Whether ``word`` appears in ``message`` as a whole word (``a`` does not match inside ``array``)."""
    return re.search(rf"(?<![A-Za-z0-9_]){re.escape(word)}(?![A-Za-z0-9_])", message) is not None


def run_call(dotted: str, argument: str, label: str) -> dict[str, str]:
    """Make one spoiled call and classify what happened."""
    case = all_cases()[dotted]
    bad = dict(spoil(case.kinds[argument], case.valid[argument]))[label]
    word = case.names.get(argument, argument)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", RuntimeWarning)
            result = case.function(**{**case.valid, argument: bad})
    except (ValueError, TypeError) as error:
        if names_word(str(error), word):
            return {"outcome": "clear"}
        return {"outcome": "wrong name", "detail": f"{type(error).__name__}: {error}"}
    except Exception as error:  # noqa: BLE001 - any other exception type is what we look for
        return {"outcome": "crash", "detail": f"{type(error).__name__}: {error}"}
    problem = case.check(result, {**case.valid, argument: bad}) if case.check else None
    if problem is not None:
        return {"outcome": "silent accept", "detail": f"a wrong result: {problem}"}
    if (argument, label) in case.accept:
        return {"outcome": "accepted sensibly"}
    if label in FINITE_LABELS:  # finite input: returning is fine as long as nothing overflowed on the way
        overflow = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)
                    and "overflow" in str(w.message)]
        if not all_finite(result):
            return {"outcome": "silent accept", "detail": "returned NaN or inf from finite input"}
        if overflow:
            return {"outcome": "silent accept", "detail": f"returned after an overflow: {overflow[0]}"}
        return {"outcome": "accepted sensibly"}
    return {"outcome": "silent accept", "detail": "returned without an error"}


#: Seconds one spoiled call may take before it counts as a hang (the slowest refused or accepted call
#: takes about a second, a lazy import included; an accepted huge count runs far longer).
CALL_LIMIT = 5.0
#: Seconds for a call listed in KNOWN_FAILURES: it need only show that it still fails (a fixed call
#: is refused at once), so a known hang costs little.
KNOWN_LIMIT = 0.5
#: Address space a forked child may add to the worker's (a huge count that allocates fails fast with
#: MemoryError, reported as a crash, instead of swapping the shared machine).
MEMORY_MARGIN = 3 * 2**30


def _memory_limit() -> None:
    import resource

    with open("/proc/self/status") as status:
        vm_kib = next(int(line.split()[1]) for line in status if line.startswith("VmSize:"))
    limit = vm_kib * 1024 + MEMORY_MARGIN
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))


def _run_in_fork(calls: list[tuple[str, str, str]], start: int, stop: int, emit) -> int:
    """Run calls ``start:stop`` (one case's) in a forked child; return where the next child starts.

    A call with no answer within ``CALL_LIMIT`` seconds is killed and reported as a hang; a child that
    dies inside a call is reported as a crash; either way the next child goes on after that call.
    """
    read_end, write_end = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: nothing it does can reach the worker but these lines
        os.close(read_end)
        try:
            os.dup2(os.open(os.devnull, os.O_WRONLY), 1)  # a function that prints cannot garble the records
            _memory_limit()
            with os.fdopen(write_end, "w", buffering=1) as out:
                for index in range(start, stop):
                    out.write(json.dumps({"index": index, "started": True}) + "\n")
                    out.flush()
                    began = time.perf_counter()
                    record = run_call(*calls[index])
                    out.write(json.dumps({"index": index, **record, "seconds": time.perf_counter() - began}) + "\n")
                    out.flush()
        finally:
            os._exit(0)
    os.close(write_end)
    known = known_failures()
    current, deadline, pending, finished = None, None, b"", set()
    try:
        while True:
            wait = 120.0 if deadline is None else max(0.0, deadline - time.monotonic())
            if not select.select([read_end], [], [], wait)[0]:
                os.kill(pid, signal.SIGKILL)
                emit({"index": current if current is not None else start, "outcome": "hang",
                      "detail": "no answer within the time limit"})
                return (current if current is not None else start) + 1
            data = os.read(read_end, 1 << 16)
            if not data:  # the child exited
                break
            *lines, pending = (pending + data).split(b"\n")
            for line in lines:
                record = json.loads(line)
                if "started" in record:
                    current = record["index"]
                    deadline = time.monotonic() + (KNOWN_LIMIT if tuple(calls[current]) in known else CALL_LIMIT)
                else:
                    finished.add(record["index"])
                    deadline = None
                    emit(record)
    finally:
        os.close(read_end)
        _, status = os.waitpid(pid, 0)
    if current is not None and current not in finished:
        how = f"signal {signal.Signals(os.WTERMSIG(status)).name}" if os.WIFSIGNALED(status) else "exit"
        emit({"index": current, "outcome": "crash", "detail": f"the interpreter died ({how})"})
        return current + 1
    return stop


def _worker() -> None:
    """Worker process: every case's spoiled calls in a forked child of their own, one JSON line each."""
    import faulthandler

    faulthandler.enable()
    calls = spoiled_calls()

    def emit(record: dict[str, object]) -> None:
        sys.stdout.write(json.dumps(record) + "\n")
        sys.stdout.flush()

    start = 0
    while start < len(calls):
        stop = start
        while stop < len(calls) and calls[stop][0] == calls[start][0]:
            stop += 1
        position = start
        while position < stop:
            position = _run_in_fork(calls, position, stop, emit)
        start = stop


def run_all() -> list[dict[str, object]]:
    """Every spoiled call's outcome."""
    calls = spoiled_calls()
    environment = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
    done = subprocess.run([sys.executable, __file__, "--worker"], capture_output=True, text=True, cwd=ROOT,
                          timeout=900, env=environment)
    results = {}
    for line in done.stdout.splitlines():
        record = json.loads(line)
        results[record["index"]] = record
    missing = [i for i in range(len(calls)) if i not in results]
    assert not missing, f"the worker stopped before {len(missing)} call(s): {done.stderr[-2000:]}"
    return [{"call": calls[i], **results[i]} for i in range(len(calls))]


@pytest.mark.parametrize("dotted", [d for d, case in all_cases().items() if case.check is not None])
def test_known_answers_hold_on_the_valid_call(dotted):
    case = all_cases()[dotted]
    assert case.check(case.function(**case.valid), case.valid) is None


OUTCOMES = ("clear", "accepted sensibly", "wrong name", "crash", "hang", "silent accept")


@pytest.fixture(scope="module")
def outcomes() -> list[dict[str, object]]:
    return run_all()


def test_every_spoiled_call_is_refused_by_name(outcomes, capsys):
    known = known_failures()
    failed = {tuple(o["call"]): o for o in outcomes if o["outcome"] not in ("clear", "accepted sensibly")}
    unexpected = [f"{' / '.join(call)}: {o['outcome']} ({o.get('detail', '')})"
                  for call, o in failed.items() if call not in known]
    fixed = [" / ".join(call) for call in known if call not in failed]
    counts = {kind: sum(o["outcome"] == kind for o in outcomes) for kind in OUTCOMES}
    fields = [o for o in outcomes if o["call"][2].startswith(FIELD)]  # kind "record": edited input records
    with capsys.disabled():
        print(f"\n{len(all_cases())} tabled callables, {len(outcomes)} spoiled calls: {counts} "
              f"({len(known)} known failures); {len(fields)} of them spoil a field of an input record, "
              f"{sum(o['outcome'] == 'clear' for o in fields)} refused by name")
    assert len(outcomes) > 0
    assert not unexpected, f"{counts}\n" + "\n".join(unexpected)
    assert not fixed, "now refused by name, remove from KNOWN_FAILURES:\n" + "\n".join(fixed)


def _public_callables(subpackage: str) -> set[str]:
    module = importlib.import_module(f"amdo_lab.{subpackage}")
    names = getattr(module, "__all__", None) or [n for n in dir(module) if not n.startswith("_")]
    return {f"amdo_lab.{subpackage}.{name}" for name in names
            if inspect.isfunction(getattr(module, name)) or inspect.isclass(getattr(module, name))}


def _public_methods(subpackage: str) -> set[str]:
    """``Class.method`` of every public method of the subpackage's public classes.

    A method counts when a class of ``amdo_lab`` defines it (its own or an ``amdo_lab`` base class's);
    what a library class brings (``tuple.count``, ``sklearn``'s ``get_params``) does not. Properties
    are attributes, not calls, and are left out.
    """
    module = importlib.import_module(f"amdo_lab.{subpackage}")
    names = getattr(module, "__all__", None) or [n for n in dir(module) if not n.startswith("_")]
    found = set()
    for name in names:
        cls = getattr(module, name)
        if not inspect.isclass(cls) or not cls.__module__.startswith("amdo_lab"):
            continue
        for base in cls.__mro__:
            if base.__module__.startswith("amdo_lab"):
                found |= {f"amdo_lab.{subpackage}.{name}.{method}" for method, value in vars(base).items()
                          if not method.startswith("_")
                          and (inspect.isfunction(value) or isinstance(value, (staticmethod, classmethod)))}
    return found


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


@pytest.mark.parametrize(
    "subpackage",
    [pytest.param(name, marks=pytest.mark.xfail(strict=True, reason="no table yet")) if table(name) is None
     else name for name in SUBPACKAGES],
)
def test_every_public_method_is_in_the_table(subpackage):
    """A public method takes user input like a function: it is tabled as ``"Class.method"``, or exempt."""
    module = table(subpackage)
    exempt = {f"amdo_lab.{subpackage}.{name}" for name in (module.EXEMPT if module else {})}
    missing = sorted(_public_methods(subpackage) - set(all_cases()) - exempt)
    assert not missing, f"{len(missing)} public method(s) of amdo_lab.{subpackage} missing from its table: {missing}"


if __name__ == "__main__" and sys.argv[1:2] == ["--worker"]:
    sys.path.insert(0, str(ROOT))
    _worker()
