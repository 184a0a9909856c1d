"""The package as a model: how much of each subpackage's code is input checking, and what is too big.

Prints, per subpackage: function-body lines (docstrings excluded), the lines spent on validation and
their share, modules over 800 lines, public functions with more than 12 parameters, and whether the
subpackage declares ``__all__``. A line counts as validation when it belongs to

- an ``if`` statement whose body only raises (``if np.any(x < 0): raise ValueError(...)``), or
- a simple statement (assignment, expression, ``return``) that calls, anywhere in it, a checking
  helper of ``amdo_lab.common`` (every ``check_*`` and ``as_*`` function that ``common/validation.py``
  defines) or a local ``_check*``/``_validate*``: a check written inside a maths line
  (``return _warp(image, _check_displacement(d))``) counts, so the share cannot be lowered by hiding
  checks in other expressions. ``make_rng`` (which turns a seed into the generator the maths draws
  from) is not counted.

``common/validation.py`` (the helpers themselves) is left out. Run: ``python benchmarks/dev_package_shape.py [--json]``. The goal (CONTRIBUTING.md): at most 15 %
validation in every subpackage, no module over 800 lines, no public function over 12 parameters.
"""

from __future__ import annotations

import argparse
import ast
import json
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1] / "amdo_lab"
VALIDATION = ROOT / "common" / "validation.py"
#: common's checking helpers (read from validation.py, so a new helper counts) and local checkers.
CHECKERS = tuple(sorted(
    node.name for node in ast.parse(VALIDATION.read_text(encoding="utf-8")).body
    if isinstance(node, ast.FunctionDef) and node.name.startswith(("check_", "as_"))
)) + ("check_", "_check", "_validate")
MAX_MODULE_LINES = 800
MAX_PARAMETERS = 12


def _called_name(node: ast.AST) -> str | None:
    if isinstance(node, ast.Call):
        func = node.func
        if isinstance(func, ast.Name):
            return func.id
        if isinstance(func, ast.Attribute):
            return func.attr
    return None


def _is_check(statement: ast.stmt) -> bool:
    if isinstance(statement, ast.If):
        return bool(statement.body) and all(isinstance(s, ast.Raise) for s in statement.body) and not statement.orelse
    if isinstance(statement, ast.Raise):
        return True
    if not isinstance(statement, (ast.Assign, ast.AnnAssign, ast.AugAssign, ast.Expr, ast.Return)):
        return False
    names = (_called_name(node) for node in ast.walk(statement))
    return any(name is not None and name.startswith(CHECKERS) for name in names)


def _body_lines(function: ast.FunctionDef) -> tuple[set[int], set[int]]:
    """(all body lines, validation lines) of one function, docstring and nested functions' own lines included."""
    body = function.body
    if body and isinstance(body[0], ast.Expr) and isinstance(getattr(body[0], "value", None), ast.Constant) \
            and isinstance(body[0].value.value, str):
        body = body[1:]
    lines, checks = set(), set()
    for statement in body:
        span = set(range(statement.lineno, statement.end_lineno + 1))
        lines |= span
        for node in ast.walk(statement):
            if isinstance(node, ast.stmt) and _is_check(node):
                checks |= set(range(node.lineno, node.end_lineno + 1))
    return lines, checks


def measure(root: Path = ROOT) -> dict[str, dict]:
    report: dict[str, dict] = {}
    for package in sorted(p for p in root.iterdir() if (p / "__init__.py").exists()):
        body, checks, big, wide = 0, 0, [], []
        for path in sorted(package.rglob("*.py")):
            if path.relative_to(root).as_posix() == "common/validation.py":
                continue  # the checking helpers themselves: all of it is validation, by design
            source = path.read_text(encoding="utf-8")
            n_lines = source.count("\n") + 1
            if n_lines > MAX_MODULE_LINES:
                big.append(f"{path.relative_to(root.parent)} ({n_lines})")
            tree = ast.parse(source)
            outer = [n for n in ast.walk(tree) if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))]
            nested = {id(m) for n in outer for m in ast.walk(n) if m is not n and isinstance(m, ast.FunctionDef)}
            for function in outer:
                if id(function) in nested:
                    continue
                lines, found = _body_lines(function)
                body += len(lines)
                checks += len(found)
                arguments = function.args
                count = len(arguments.posonlyargs) + len(arguments.args) + len(arguments.kwonlyargs)
                if arguments.args and arguments.args[0].arg in ("self", "cls"):
                    count -= 1
                if count > MAX_PARAMETERS and not function.name.startswith("_"):
                    wide.append(f"{path.stem}.{function.name} ({count})")
        init = (package / "__init__.py").read_text(encoding="utf-8")
        report[package.name] = {"body_lines": body, "validation_lines": checks,
                                "validation_share": round(checks / body, 3) if body else 0.0,
                                "modules_over_800_lines": big, "functions_over_12_parameters": wide,
                                "has___all__": "__all__" in init}
    return report


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true", help="print the report as JSON")
    args = parser.parse_args()
    report = measure()
    if args.json:
        print(json.dumps(report, indent=2))
        return
    print(f"{'subpackage':18s} {'body':>6s} {'checks':>6s} {'share':>6s}  __all__  too big / too many parameters")
    for name, row in report.items():
        extra = "; ".join(row["modules_over_800_lines"] + row["functions_over_12_parameters"])
        print(f"{name:18s} {row['body_lines']:6d} {row['validation_lines']:6d} {row['validation_share']:6.1%}  "
              f"{'yes' if row['has___all__'] else 'NO ':7s}  {extra}")


if __name__ == "__main__":
    main()
