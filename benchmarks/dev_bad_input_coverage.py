"""Bad input beyond the tables: unspoiled parameters, and an independent fuzz of the whole public API.

``tests/test_bad_input.py`` spoils the arguments each table lists, with the kinds the table gives
(``Case.kinds``). This script checks the tables instead of trusting them:

1. without options: every parameter of a tabled callable that its table does not spoil, and the
   public methods that are neither tabled nor exempt;
2. ``--fuzz``: an independent fuzz of the public API. The callables are read from the package, not
   from the tables: every name in ``__all__`` of every subpackage and every public method of its
   public classes (``inspect``). Every parameter of each (from its signature) is spoiled by a kind
   inferred from its *valid value* (its type, or the parameter's name for a seed or a label), never
   from the table's kinds, accepted values or error words:

   - a count or other int: 10**9 and 2**63;
   - a real number: NaN, inf, 1e308 (finite: returning finite output without an overflow is fine);
   - an array (or a list of numbers): 1e308 in every element (finite, as above), NaN in one element,
     inf in one element, a complex array, a string array, an object array holding None;
   - a flag (a bool): None, 2, ``"yes"``; an option (a str): an unknown option, a number, None;
   - a label (``name``, ``what``, ... of the ``common`` helpers): a number, None;
   - a seed (``rng``): -1, 1.5, a string;
   - anything else (a record, a model, a table): a number, a string, None;
   - every parameter: None, a complex number, a string, where the kind has not listed them.

   The only thing taken from the tables is a valid call to start from (``Case.valid``): without
   one the package cannot be called. A parameter the table's call does not pass gets its default.
   Each call runs in a forked child of its own (``--jobs`` at a time) with a time limit
   (``--limit``, 20 s) and a memory cap, and is classified as

   - *clear*: ``ValueError``/``TypeError`` raised by package code whose message names the parameter
     as a whole word (or the label the call passed for it, for the ``common`` helpers, whose
     ``value`` is named by ``name``);
   - *vague*: ``ValueError``/``TypeError`` raised by package code that does not name it;
   - *crash*: any other exception, one raised inside a library (numpy, scipy, sklearn, pandas,
     matplotlib: the innermost frame is not package code), or the child died;
   - *hang*: no answer within the time limit;
   - *silent accept*: the call returned (for a finite spoil: returned NaN or inf, or warned of an
     overflow).

   Names with no valid call (result records the package builds, methods with no arguments) are
   counted and listed; they are the ``EXEMPT`` lines of the tables.

Run (the full fuzz: about 8,600 calls; 2.5 minutes with ``--jobs 2`` on two cores at load 2, 6 to 12
minutes at load 6 to 10)::

    nice -n 10 python benchmarks/dev_bad_input_coverage.py --fuzz --jobs 2
    python benchmarks/dev_bad_input_coverage.py --fuzz --sample 10   # every 10th call, ~1 minute
    python benchmarks/dev_bad_input_coverage.py --fuzz --only amdo_lab.common.rotation_matrix

Options: ``--subpackage NAME``, ``--only DOTTED`` (one callable), ``--sample K`` (every K-th call),
``--jobs N``, ``--limit SECONDS``, ``--json PATH`` (every call's outcome).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE_DIR = str(ROOT / "amdo_lab")
#: Parameters that only label an error message (the argument's name, the expected type's wording) or
#: a plot (a legend label): any string is valid; a non-string is refused (``amdo_lab.common``'s label
#: rule, CONTRIBUTING.md).
LABELS = ("name", "what", "first_name", "second_name", "names", "axes", "label")
#: Parameters that are seeds (an int or a numpy Generator): any non-negative int is a seed.
SEEDS = ("rng", "seed")
#: Parameters that hold identities or class labels: any hashable value is one (an int, a string), so
#: they get None among them, NaN and an unhashable value instead of numeric spoils.
IDENTITIES = ("labels", "subject_id", "subject_ids", "genuine_ids", "query_ids", "enrolled_ids", "group",
              "groups", "classes")
#: Parameters that are bounds of a range rule (``common``'s ``minimum=``, ``high=``): a huge bound is a
#: bound, so they get no huge counts.
BOUNDS = ("minimum", "maximum", "low", "high")
#: Spoils a docstring documents as valid input: (callable, parameter, spoil) -> where it says so.
DOCUMENTED = {
    ("amdo_lab.ear_biometrics.open_set_rates", "thresholds", "inf in one element"):
        "thresholds: 'inf: no threshold'",
    ("amdo_lab.ear_biometrics.MatcherSettings", "distance_threshold", "inf"):
        "distance_threshold: 'or inf for no threshold' (the default)",
    ("amdo_lab.cue_fusion_pf.track", "mean", "None"): "mean: 'default the initial state' (track's options)",
    ("amdo_lab.common.check_in_range", "high", "inf"): "high: an open range (the package calls it with np.inf)",
    ("amdo_lab.common.check_instance", "value", "NaN"): "value: any instance of expected (here float)",
    ("amdo_lab.common.check_instance", "value", "inf"): "value: any instance of expected (here float)",
}
OUTCOMES = ("clear", "accepted sensibly", "vague", "crash", "hang", "silent accept")
#: Spoiled labels that are finite input: returning finite output, without an overflow, is sensible.
FINITE = frozenset({"1e308", "1e308 everywhere"})
#: Address space a child may add to the parent's (a huge allocation fails fast instead of swapping).
MEMORY_MARGIN = 3 * 2**30


def spoils_for(parameter: str, valid: object, optional: bool = False) -> list[tuple[str, object]]:
    """The fuzz's bad values for a parameter, from its valid value and its name (not from any table).

    None is left out when the parameter is optional (its default is None, or its annotation admits None).
    """
    bad = _spoils(parameter, valid)
    return [(label, value) for label, value in bad if not (optional and value is None)]


def _spoils(parameter: str, valid: object) -> list[tuple[str, object]]:
    import math
    import numbers

    import numpy as np

    generic = [("None", None), ("a complex number", 1 + 1j), ("a string", "abc")]
    if parameter in LABELS and (valid is None or isinstance(valid, str)
                                or (isinstance(valid, tuple) and all(isinstance(v, str) for v in valid))):
        return [("None", None), ("a number", 3), ("an object", object())]
    if parameter in SEEDS:
        return [("None", None), ("a string", "abc"), ("negative", -1), ("a float", 1.5), ("a complex number", 1j)]
    if parameter in IDENTITIES:
        array = _numeric_array(valid)
        if array is None and isinstance(valid, (list, tuple, np.ndarray)):
            array = np.asarray(valid, dtype=object)
        if array is None:
            return [("None", None), ("NaN", math.nan), ("an unhashable list", [1])]
        bad = [("None", None), ("an object array holding None", _with_first(array.astype(object), None))]
        return bad + ([("NaN in one element", _with_first(array.astype(float), math.nan))]
                      if np.issubdtype(array.dtype, np.number) else [])
    if isinstance(valid, (bool, np.bool_)):
        return [("None", None), ("2", 2), ("'yes'", "yes")]
    if isinstance(valid, numbers.Integral) and parameter not in BOUNDS:
        return generic + [("10**9", 10**9), ("2**63", 2**63)]
    if isinstance(valid, numbers.Real):
        return generic + [("NaN", math.nan), ("inf", math.inf), ("1e308", 1e308)]
    if isinstance(valid, str):
        if parameter.endswith(("_dir", "path", "directory")):  # a path: any string names one
            return [("None", None), ("a number", 3)]
        return [("None", None), ("a number", 3), ("an unknown option", "__no_such_option__")]
    array = _numeric_array(valid)
    if array is not None:
        bad = generic + [("a complex array", array.astype(complex) + 1j),
                         ("a string array", np.full(array.shape, "abc")),
                         ("an object array holding None", _with_first(array.astype(object), None))]
        if array.dtype == bool:
            return bad
        return bad + [("1e308 everywhere", np.full(array.shape, 1e308)),
                      ("NaN in one element", _with_first(array.astype(float), math.nan)),
                      ("inf in one element", _with_first(array.astype(float), math.inf))]
    if valid is None:
        return [("a complex number", 1 + 1j), ("an object", object())]
    return [("None", None), ("a number", 3), ("a string", "abc")]


def kind_name(parameter: str, valid: dict) -> str:
    """The name that decides a parameter's kind: a ``common`` helper's ``value`` is the argument its
    ``name`` label names (``check_seed(value, name="rng")`` checks a seed)."""
    label = valid.get("name")
    return label if parameter == "value" and isinstance(label, str) else parameter


def _numeric_array(valid: object):
    """``valid`` as a non-empty numeric or boolean array, or None if it is not one."""
    import numpy as np

    if not isinstance(valid, (np.ndarray, list, tuple)) or isinstance(valid, str):
        return None
    try:
        array = np.asarray(valid)
    except (ValueError, TypeError):
        return None
    if array.size == 0 or not (np.issubdtype(array.dtype, np.number) or array.dtype == bool):
        return None
    return array


def _with_first(array, value):
    array.flat[0] = value
    return array


def names_word(message: str, word: str) -> bool:
    """Whether ``word`` appears in ``message`` as a whole word."""
    return re.search(rf"(?<![A-Za-z0-9_]){re.escape(word)}(?![A-Za-z0-9_])", message) is not None


# --- the public API, from the package -----------------------------------------------------------

def public_api(subpackages: tuple[str, ...]) -> dict[str, object]:
    """Every public callable (``__all__``) and public method of a public class, by dotted name."""
    import importlib
    import inspect

    found = {}
    for subpackage in subpackages:
        module = importlib.import_module(f"amdo_lab.{subpackage}")
        for name in getattr(module, "__all__", None) or [n for n in dir(module) if not n.startswith("_")]:
            value = getattr(module, name)
            if not (inspect.isfunction(value) or inspect.isclass(value)):
                continue
            found[f"amdo_lab.{subpackage}.{name}"] = value
            if not inspect.isclass(value) or not value.__module__.startswith("amdo_lab"):
                continue
            for base in value.__mro__:
                if not base.__module__.startswith("amdo_lab"):
                    continue
                for method, member in vars(base).items():
                    if not method.startswith("_") and (inspect.isfunction(member)
                                                       or isinstance(member, (staticmethod, classmethod))):
                        found.setdefault(f"amdo_lab.{subpackage}.{name}.{method}", getattr(value, method))
    return found


def _parameters(target: object) -> dict[str, object]:
    """A callable's parameters (name -> inspect.Parameter), without self, private and variadic ones."""
    import inspect

    try:
        signature = inspect.signature(target)
    except (TypeError, ValueError):
        return {}
    return {name: p for name, p in signature.parameters.items()
            if name not in ("self", "cls") and not name.startswith("_")
            and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)}


def _takes(function: object, name: str) -> bool:
    """Whether ``function`` accepts the keyword ``name`` (by name or through ``**kwargs``)."""
    import inspect

    try:
        parameters = inspect.signature(function).parameters
    except (TypeError, ValueError):
        return False
    return name in parameters or any(p.kind is p.VAR_KEYWORD for p in parameters.values())


def plan(api: dict[str, object], cases: dict[str, object]) -> tuple[list, dict, dict[str, list[str]]]:
    """The fuzz's calls ``(recipe, parameter, label)``, the recipes, and what it cannot reach, by reason.

    A recipe is ``(function, valid arguments, parameters whose default is None)``: the table's call of
    the callable (or of a variant of it), with the default of every parameter it does not pass.
    """
    import inspect

    recipes, unreached = {}, {"no valid call": [], "parameter no valid call can pass": []}
    reached: dict[str, set[str]] = {}
    for dotted, target in api.items():
        parameters = _parameters(target.__init__ if inspect.isclass(target) else target)
        variants = [d for d in cases if d == dotted or d.startswith((dotted + " (", dotted + "("))]
        if not variants and all(p.default is not p.empty for p in parameters.values()) and (
                inspect.isclass(target) or "." not in dotted.split(".", 2)[2]):
            recipes[dotted] = (target, {}, set())
            variants = [dotted]
        if not variants:
            unreached["no valid call"].append(dotted)
            continue
        none_default = {n for n, p in parameters.items() if p.default is None or "None" in str(p.annotation)}
        for variant in variants:
            function, valid = (cases[variant].function, dict(cases[variant].valid)) if variant in cases else \
                recipes[variant][:2]
            for name, parameter in parameters.items():
                if name not in valid and parameter.default is not parameter.empty and _takes(function, name):
                    valid[name] = parameter.default
            recipes[variant] = (function, valid, none_default)
            reached.setdefault(dotted, set()).update(valid)
        unreached["parameter no valid call can pass"] += [f"{dotted} / {n}" for n in parameters
                                                          if n not in reached[dotted]]
    calls = [(recipe, name, label) for recipe, (_, valid, none_default) in recipes.items()
             for name in valid for label, _ in spoils_for(kind_name(name, valid), valid[name], name in none_default)]
    return calls, recipes, unreached


# --- one call, in a forked child ----------------------------------------------------------------

def _innermost_outside_package(error: BaseException) -> str | None:
    """The library file the exception was raised in, or None if its innermost frame is package code."""
    tb = error.__traceback__
    while tb is not None and tb.tb_next is not None:
        tb = tb.tb_next
    if tb is None:
        return None
    filename = tb.tb_frame.f_code.co_filename
    if filename.startswith(PACKAGE_DIR) or "site-packages" not in filename:
        return None
    return filename.split("site-packages/")[-1]


def classify(recipe: tuple, parameter: str, label: str, documented: bool = False) -> dict[str, str]:
    """Make one spoiled call and classify what happened (runs in the child)."""
    import warnings

    sys.path.insert(0, str(ROOT / "tests"))
    from bad_input_cases._core import all_finite

    function, valid, none_default = recipe
    bad = dict(spoils_for(kind_name(parameter, valid), valid[parameter], parameter in none_default))[label]
    words = [parameter]  # and the label(s) the call passes for it (a common helper names its value by ``name``)
    for key, value in valid.items():
        if key in LABELS and key != parameter:
            words += [value] if isinstance(value, str) else [v for v in value if isinstance(v, str)] \
                if isinstance(value, tuple) else []
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", RuntimeWarning)
            result = function(**{**valid, parameter: bad})
    except (ValueError, TypeError) as error:
        library = _innermost_outside_package(error)
        message = f"{type(error).__name__}: {error}"[:300]
        if library is not None:
            return {"outcome": "crash", "detail": f"raised inside {library}: {message}"}
        if any(names_word(str(error), word) for word in words):
            return {"outcome": "clear"}
        return {"outcome": "vague", "detail": message}
    except Exception as error:  # noqa: BLE001 - any other exception type is what the fuzz looks for
        return {"outcome": "crash", "detail": f"{type(error).__name__}: {error}"[:300]}
    if documented:
        return {"outcome": "accepted sensibly"}
    if label in FINITE:
        overflow = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)
                    and "overflow" in str(w.message)]
        if not all_finite(result):
            return {"outcome": "silent accept", "detail": "returned NaN or inf from finite input"}
        if overflow:
            return {"outcome": "silent accept", "detail": f"returned after an overflow: {overflow[0]}"}
        return {"outcome": "accepted sensibly"}
    return {"outcome": "silent accept", "detail": "returned without an error"}


def _start_child(recipes: dict, call: tuple, scratch: str) -> tuple[int, int]:
    """Fork a child that makes ``call`` in the directory ``scratch`` (a spoiled path or option that a
    function accepts writes there, not into the checkout) and writes one JSON line; return (pid, read end)."""
    read_end, write_end = os.pipe()
    pid = os.fork()
    if pid == 0:
        os.close(read_end)
        try:
            import resource

            os.chdir(scratch)

            os.dup2(os.open(os.devnull, os.O_WRONLY), 1)
            with open("/proc/self/status") as status:
                vm_kib = next(int(line.split()[1]) for line in status if line.startswith("VmSize:"))
            limit = vm_kib * 1024 + MEMORY_MARGIN
            resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
            recipe, parameter, label = call
            base = recipe.split(" (")[0].split("(")[0]
            record = classify(recipes[recipe], parameter, label, (base, parameter, label) in DOCUMENTED)
            os.write(write_end, (json.dumps(record) + "\n").encode())
        except BaseException as error:  # noqa: BLE001 - reported as a crash by the parent
            os.write(write_end, (json.dumps({"outcome": "crash", "detail": f"{type(error).__name__}: {error}"[:300]})
                                 + "\n").encode())
        finally:
            os._exit(0)
    os.close(write_end)
    return pid, read_end


def run_fuzz(calls: list, recipes: dict, jobs: int, limit: float, progress: bool) -> list[dict]:
    """Every call in a forked child of its own, ``jobs`` at a time, each killed after ``limit`` seconds."""
    import select
    import signal
    import tempfile

    scratch = tempfile.TemporaryDirectory(prefix="amdo-fuzz-")
    results: dict[int, dict] = {}
    running: dict[int, tuple[int, int, float, bytes]] = {}  # read end -> (index, pid, deadline, data)
    queue = list(range(len(calls)))
    began, reported, shown = time.monotonic(), 0, set()
    while queue or running:
        while queue and len(running) < jobs:
            index = queue.pop(0)
            pid, read_end = _start_child(recipes, calls[index], scratch.name)
            running[read_end] = (index, pid, time.monotonic() + limit, b"")
        wait = max(0.0, min(deadline for _, _, deadline, _ in running.values()) - time.monotonic())
        ready = select.select(list(running), [], [], wait)[0]
        for read_end in list(running):
            index, pid, deadline, data = running[read_end]
            if read_end in ready:
                chunk = os.read(read_end, 1 << 16)
                if chunk:
                    running[read_end] = (index, pid, deadline, data + chunk)
                    continue
                os.close(read_end)
                _, status = os.waitpid(pid, 0)
                del running[read_end]
                if data.strip():
                    results[index] = json.loads(data.decode().splitlines()[0])
                else:
                    how = (f"signal {signal.Signals(os.WTERMSIG(status)).name}" if os.WIFSIGNALED(status)
                           else "exit")
                    results[index] = {"outcome": "crash", "detail": f"the interpreter died ({how})"}
            elif time.monotonic() >= deadline:
                os.kill(pid, signal.SIGKILL)
                os.waitpid(pid, 0)
                os.close(read_end)
                del running[read_end]
                results[index] = {"outcome": "hang", "detail": f"no answer within {limit:g} s"}
        for index in sorted(set(results) - shown):  # problems as they come, so a long run is readable early
            shown.add(index)
            if progress and results[index]["outcome"] not in ("clear", "accepted sensibly"):
                print(f"  {results[index]['outcome']}: {' / '.join(calls[index])}", file=sys.stderr)
        if progress and len(results) >= reported + 1000:
            reported = len(results)
            print(f"  {len(results)}/{len(calls)} calls, {time.monotonic() - began:.0f} s", file=sys.stderr)
    return [{"call": calls[i], **results[i]} for i in range(len(calls))]


# --- the report ---------------------------------------------------------------------------------

def untabled(cases: dict) -> list[dict[str, str]]:
    """Every parameter of a tabled callable that no case of it (variants included) spoils."""
    import inspect

    rows, spoiled = [], {}
    for dotted, case in cases.items():
        spoiled.setdefault(dotted.split(" (")[0].split("(")[0], set()).update(case.kinds)
    for dotted, case in cases.items():
        target = case.function
        if dotted.split(" (")[0].split("(")[0] != dotted:
            continue  # a variant: its parameters count under the callable's own case
        for name, parameter in _parameters(target.__init__ if inspect.isclass(target) else target).items():
            if name not in spoiled[dotted]:
                default = None if parameter.default is parameter.empty else parameter.default
                rows.append({"callable": dotted, "parameter": name, "default": repr(default)})
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fuzz", action="store_true", help="fuzz every parameter of the public API")
    parser.add_argument("--subpackage", help="only this subpackage")
    parser.add_argument("--only", help="only this callable (dotted name, as printed)")
    parser.add_argument("--sample", type=int, default=1, help="fuzz every K-th call only")
    parser.add_argument("--jobs", type=int, default=1, help="children at a time")
    parser.add_argument("--limit", type=float, default=20.0, help="seconds per call before it is a hang")
    parser.add_argument("--json", help="write every outcome to this file")
    args = parser.parse_args()
    for variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[variable] = "1"
    os.environ.setdefault("MPLBACKEND", "Agg")

    sys.path[:0] = [str(ROOT / "tests"), str(ROOT)]
    import test_bad_input as t

    subpackages = tuple(s for s in t.SUBPACKAGES if args.subpackage in (None, s))
    cases = {d: c for d, c in t.all_cases().items() if d.split(".")[1] in subpackages}
    if not args.fuzz:
        rows = untabled(cases)
        methods = []
        for subpackage in subpackages:
            module = t.table(subpackage)
            exempt = {f"amdo_lab.{subpackage}.{name}" for name in (module.EXEMPT if module else {})}
            methods += sorted(t._public_methods(subpackage) - set(t.all_cases()) - exempt)
        print(f"{len(cases)} tabled callables; {len(rows)} parameters not spoiled by their table; "
              f"{len(methods)} public methods neither tabled nor exempt")
        for row in rows:
            print(f"  {row['callable']} / {row['parameter']} (default {row['default']})")
        for method in methods:
            print(f"  not tabled: {method}")
        return

    api = public_api(subpackages)
    calls, recipes, unreached = plan(api, cases)
    if args.only:
        calls = [c for c in calls if c[0] == args.only or c[0].startswith(args.only + " (")]
    calls = calls[::args.sample]
    began = time.monotonic()
    outcomes = run_fuzz(calls, recipes, args.jobs, args.limit, progress=True)
    seconds = time.monotonic() - began
    counts = {kind: sum(o["outcome"] == kind for o in outcomes) for kind in OUTCOMES}
    print(f"{len(api)} public callables and methods; {len(recipes)} called "
          f"({len({c[0] for c in calls})} in this run); {len(calls)} spoiled calls in {seconds:.0f} s "
          f"(--sample {args.sample}, --jobs {args.jobs}, --limit {args.limit:g} s)")
    print("fuzz:", counts)
    for reason, names in unreached.items():
        print(f"not fuzzed, {reason}: {len(names)}" + (f" ({', '.join(n.split('.', 1)[1] for n in names)})"
                                                        if names else ""))
    for row in outcomes:
        if row["outcome"] not in ("clear", "accepted sensibly"):
            print(f"  {row['outcome']}: {' / '.join(row['call'])}: {row.get('detail', '')}"[:240])
    if args.json:
        Path(args.json).write_text(json.dumps({"counts": counts, "unreached": unreached, "outcomes": outcomes},
                                              indent=1, default=str))


if __name__ == "__main__":
    main()
