"""What the bad-input test does not spoil yet: options and flags left out of the tables, public methods.

``tests/test_bad_input.py`` spoils the arguments each table lists (``Case.kinds``). This script looks
at the same callables from their signatures instead, independently of the tables:

1. every parameter of a tabled callable that its table does not spoil, with its default;
2. with ``--fuzz``, those parameters spoiled by the kind their default implies (a ``bool`` default: a
   string, an int and None; a ``str`` default: an unknown option and a number; a number: NaN, inf,
   a string, a bool and 1e308; a count-like name: zero, negative, a float, 10**9) in the test's
   forked, time-limited children, classified as the test classifies its calls;
3. the public methods of the public classes that are neither tabled (``"Class.method"``) nor exempt
   (the test ``test_every_public_method_is_in_the_table`` fails on each).

Run: ``python benchmarks/dev_bad_input_coverage.py [--fuzz] [--subpackage NAME] [--json]``.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
COUNT_PREFIXES = ("n_", "max_", "num_")
#: Parameters that only label an error message (the argument's name, the expected type's wording):
#: any string is valid, so they are listed but not spoiled.
LABELS = ("name", "what", "source", "first_name", "second_name", "names", "axes")
COUNT_SUFFIXES = ("_iter", "_steps", "_size", "_rounds", "_levels", "_sweeps")


def _spoils(name: str, default: object) -> list[tuple[str, object]] | None:
    """Bad values for a parameter whose table gives no kind, inferred from its default."""
    import math

    if isinstance(default, bool):
        return [("None", None), ("a string", "yes"), ("an int", 1)]
    if isinstance(default, str):
        return [("an unknown option", "__no_such_option__"), ("a number", 3)]
    if isinstance(default, int) and (name.startswith(COUNT_PREFIXES) or name.endswith(COUNT_SUFFIXES)):
        return [("None", None), ("zero", 0), ("negative", -1), ("a float", 2.5), ("a billion", 10**9)]
    if isinstance(default, (int, float)):
        return [("a string", "abc"), ("NaN", math.nan), ("inf", math.inf), ("a bool", True), ("huge", 1e308)]
    return None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fuzz", action="store_true", help="spoil the untabled parameters (forked, time-limited)")
    parser.add_argument("--subpackage", help="only this subpackage")
    parser.add_argument("--json", action="store_true", help="print the report as JSON")
    args = parser.parse_args()

    import inspect

    sys.path[:0] = [str(ROOT / "tests"), str(ROOT)]
    import test_bad_input as t
    from bad_input_cases._core import Case

    cases = {d: c for d, c in t.all_cases().items() if not args.subpackage or d.split(".")[1] == args.subpackage}
    untabled, methods, extra, defaults = [], [], {}, {}
    for dotted, case in cases.items():
        target = case.function
        signature = inspect.signature(target.__init__ if inspect.isclass(target) else target)
        for name, parameter in signature.parameters.items():
            if name in ("self", "cls") or name in case.kinds or parameter.kind in (parameter.VAR_POSITIONAL,
                                                                                    parameter.VAR_KEYWORD):
                continue
            default = None if parameter.default is parameter.empty else parameter.default
            untabled.append({"callable": dotted, "parameter": name, "default": repr(default)})
            bad = None if name in LABELS else _spoils(name, default)
            if bad is not None:
                extra.setdefault(dotted, {})[name] = bad
                defaults.setdefault(dotted, {})[name] = default

    for subpackage in t.SUBPACKAGES:
        module = t.table(subpackage)
        if args.subpackage in (None, subpackage) and module is not None:
            exempt = {f"amdo_lab.{subpackage}.{name}" for name in module.EXEMPT}
            methods += sorted(t._public_methods(subpackage) - set(t.all_cases()) - exempt)
    report = {"tabled_callables": len(cases), "untabled_parameters": untabled, "public_methods": methods}
    if args.fuzz:
        spoiled = {dotted: {**{n: dict(bad) for n, bad in params.items()}} for dotted, params in extra.items()}
        augmented = {}
        for dotted, case in cases.items():
            kinds = {**case.kinds, **{n: f"untabled:{n}" for n in spoiled.get(dotted, {})}}
            valid = {**defaults.get(dotted, {}), **case.valid}
            augmented[dotted] = Case(case.function, valid, kinds, names=case.names, accept=case.accept)
        original_spoil = t.spoil

        def spoil(kind, valid):
            if isinstance(kind, str) and kind.startswith("untabled:"):
                return list(current_spoils[kind.split(":", 1)[1]].items())
            return original_spoil(kind, valid)

        calls = []
        for dotted, params in spoiled.items():
            for name, bad in params.items():
                calls += [(dotted, name, label) for label in bad]
        t.all_cases = lambda: augmented
        t.known_failures = lambda: {}

        def run_call(dotted, argument, label):
            global current_spoils
            current_spoils = spoiled[dotted]
            return original_run(dotted, argument, label)

        original_run = t.run_call
        t.spoil = spoil
        t.run_call = run_call
        results = {}
        start = 0
        while start < len(calls):
            stop = start
            while stop < len(calls) and calls[stop][0] == calls[start][0]:
                stop += 1
            position = start
            while position < stop:
                position = t._run_in_fork(calls, position, stop, lambda r: results.__setitem__(r["index"], r))
            start = stop
        outcomes = [{"call": calls[i], **results.get(i, {"outcome": "lost"})} for i in range(len(calls))]
        report["fuzz"] = outcomes
        report["fuzz_counts"] = {o: sum(r["outcome"] == o for r in outcomes) for o in t.OUTCOMES}

    if args.json:
        print(json.dumps(report, indent=1, default=str))
        return
    print(f"{report['tabled_callables']} tabled callables; {len(untabled)} parameters not spoiled by their table; "
          f"{len(methods)} public methods neither tabled nor exempt")
    by_package: dict[str, int] = {}
    for row in untabled:
        by_package[row["callable"].split(".")[1]] = by_package.get(row["callable"].split(".")[1], 0) + 1
    print("untabled parameters per subpackage:", by_package)
    if args.fuzz:
        print("fuzz of the untabled parameters:", report["fuzz_counts"])
        for row in report["fuzz"]:
            if row["outcome"] not in ("clear", "accepted sensibly"):
                print(f"  {' / '.join(row['call'])}: {row['outcome']} {row.get('detail', '')}"[:200])


current_spoils: dict = {}

if __name__ == "__main__":
    main()
