"""A static scan of a submission's own code for anything that could change how it is graded.

The grader judges answers outside the student's kernel (:mod:`amdo_lab.course.grading`), from a
record that each locked check cell emits. Code in the cells a student writes (answer cells and any
cell they added) could still tamper with that record from inside the kernel, so before grading
every such cell is parsed (never executed) and these are flagged:

- rebinding a name the checks rely on: ``EXERCISES``, ``print``, ``display``, built-ins such as
  ``abs``/``isinstance``/``round``, the modules ``json``, ``math``, ``numpy``/``np``, ``sys``,
  ``builtins``, ``amdo_lab``, ``get_ipython``;
- assigning or deleting an attribute or item of such a name or of any imported module
  (``builtins.abs = ...``, ``np.isclose = ...``, ``EXERCISES.check = ...``, ``sys.modules[...] = ...``,
  ``amdo_lab.common.exercises.judge_answer = ...``);
- ``setattr``/``delattr``, ``exec``/``eval``/``compile``/``__import__``, ``importlib.reload``,
  ``globals()[...] = ...``/``globals().update``, ``__builtins__``, ``get_ipython()`` and
  ``import builtins``/``unittest.mock``, which reach the same ends indirectly.

A flagged cell scores 0 for its exercise, with the reason in ``grades.csv``.
"""

from __future__ import annotations

import ast
import re

__all__ = ["PROTECTED_NAMES", "scan_source"]

#: Names whose rebinding (in a student's cell) is flagged.
PROTECTED_NAMES = frozenset({
    "EXERCISES", "print", "display", "json", "math", "np", "numpy", "sys", "builtins", "__builtins__",
    "amdo_lab", "get_ipython", "IPython", "abs", "isinstance", "round", "float", "int", "str", "bool", "len",
    "callable", "type", "repr", "os", "importlib",
})
#: Calls flagged wherever they appear.
FORBIDDEN_CALLS = frozenset({"setattr", "delattr", "exec", "eval", "compile", "__import__", "get_ipython", "reload"})
#: Modules whose import is flagged.
FORBIDDEN_IMPORTS = ("builtins", "unittest.mock", "mock", "ctypes", "gc", "inspect")
_MAGIC = re.compile(r"^\s*[%!].*$", re.M)


def _root(node: ast.AST) -> str | None:
    while isinstance(node, (ast.Attribute, ast.Subscript, ast.Call)):
        node = node.func if isinstance(node, ast.Call) else node.value
    return node.id if isinstance(node, ast.Name) else None


def _bound_names(target: ast.AST):
    if isinstance(target, ast.Name):
        yield target.id
    elif isinstance(target, (ast.Tuple, ast.List)):
        for element in target.elts:
            yield from _bound_names(element)
    elif isinstance(target, ast.Starred):
        yield from _bound_names(target.value)


def scan_source(source: str, modules: set[str] | frozenset[str] = frozenset()) -> list[str]:
    """The reasons a cell's code is flagged (empty when it is clean).

    Parameters
    ----------
    source : str
        The cell's code (IPython magics are ignored).
    modules : set of str
        Names bound to imported modules elsewhere in the notebook (``np``, ``plt``, ...): an
        attribute write on any of them is flagged too.

    Returns
    -------
    list of str
        One line per finding, e.g. ``"assigns builtins.abs"``.
    """
    try:
        tree = ast.parse(_MAGIC.sub("", source))
    except SyntaxError:
        return []  # it cannot run either; the kernel reports the error on the exercise
    local_modules = set(modules)
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            local_modules.update((alias.asname or alias.name).split(".")[0] for alias in node.names)
    protected = PROTECTED_NAMES | local_modules
    found: list[str] = []

    def flag(text: str) -> None:
        if text not in found:
            found.append(text)

    for node in ast.walk(tree):
        if isinstance(node, (ast.Assign, ast.AugAssign, ast.AnnAssign, ast.Delete)):
            targets = node.targets if isinstance(node, (ast.Assign, ast.Delete)) else [node.target]
            for target in targets:
                for name in _bound_names(target):
                    if name in PROTECTED_NAMES:
                        flag(f"rebinds {name}")
                if isinstance(target, (ast.Attribute, ast.Subscript)):
                    root = _root(target)
                    if root in protected or root == "globals" or isinstance(target.value, ast.Call):
                        flag(f"assigns {ast.unparse(target)[:60]}")
        elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            if node.name in PROTECTED_NAMES:
                flag(f"rebinds {node.name}")
        elif isinstance(node, (ast.For, ast.AsyncFor, ast.comprehension)):
            for name in _bound_names(node.target):
                if name in PROTECTED_NAMES:
                    flag(f"rebinds {name}")
        elif isinstance(node, (ast.With, ast.AsyncWith)):
            for item in node.items:
                if item.optional_vars is not None:
                    for name in _bound_names(item.optional_vars):
                        if name in PROTECTED_NAMES:
                            flag(f"rebinds {name}")
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            module = node.module if isinstance(node, ast.ImportFrom) else None
            for alias in node.names:
                full = f"{module}.{alias.name}" if module else alias.name
                if any(full == bad or full.startswith(bad + ".") or (module or "").startswith(bad)
                       for bad in FORBIDDEN_IMPORTS):
                    flag(f"imports {full}")
                    continue
                bound = alias.asname or (alias.name if module else alias.name.split(".")[0])
                if bound in PROTECTED_NAMES and not (bound == alias.name.split(".")[0] and module is None
                                                      and bound in {"numpy", "math", "json", "sys", "os",
                                                                    "importlib", "amdo_lab", "IPython"}):
                    if not (module is None and alias.asname == "np" and alias.name == "numpy"):
                        flag(f"rebinds {bound} by an import")
        elif isinstance(node, ast.Global):
            for name in node.names:
                if name in PROTECTED_NAMES:
                    flag(f"rebinds {name} (global)")
        elif isinstance(node, ast.NamedExpr):
            if node.target.id in PROTECTED_NAMES:
                flag(f"rebinds {node.target.id}")
        if isinstance(node, ast.Call):
            name = node.func.id if isinstance(node.func, ast.Name) else (
                node.func.attr if isinstance(node.func, ast.Attribute) else None)
            if name in FORBIDDEN_CALLS:
                flag(f"calls {name}()")
            if (isinstance(node.func, ast.Attribute) and node.func.attr in {"update", "__setitem__", "setdefault",
                                                                            "pop", "__setattr__"}
                    and _root(node.func.value) in protected | {"globals", "vars", "locals"}):
                flag(f"calls {ast.unparse(node.func)[:60]}()")
        if isinstance(node, ast.Name) and node.id == "__builtins__":
            flag("uses __builtins__")
        if isinstance(node, ast.Attribute) and node.attr in {"modules", "__dict__", "__globals__", "__code__",
                                                              "__class__", "environ", "stdout", "displayhook"}:
            if isinstance(node.ctx, ast.Store) or _root(node) in protected:
                flag(f"touches {ast.unparse(node)[:60]}")
    return found
