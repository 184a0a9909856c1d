"""Every equation a chapter cites can be found in its package: plain numpy, numbered, tested.

One table per chapter, ``amdo_lab.<method>.equations.EQUATIONS`` (shown in the subpackage's
docstring), maps every equation number the chapter's notebook cites to either

- ``EquationPath(code="amdo_lab.<sub>.<module>.<function>", test="<test>")``: the readable reference
  path, public and documented, whose source (or the check-free kernel it calls) carries a comment naming the equation (``# eq. (17): ...``), and the test in the chapter's test
  file that checks it (against the fast path where there is one, else against an independent
  computation); or
- ``EquationPath(reason="<reason>")``: the equation has no code of its own (notation, a definition the chapter
  only discusses, a printed form the chapter shows only to explain why it is not used).

The tables list equations in their order. A notebook that cites a new equation, or stops citing
one, fails here until the table follows; so does a reference function that loses its comment or a
test that is renamed or stops calling it. The tests named are not run here (their own files run them).
"""

from __future__ import annotations

import ast
import functools
import importlib
import inspect
import io
import json
import re
import textwrap
import tokenize
from pathlib import Path

import pytest

from amdo_lab.chapters import CHAPTERS as REGISTRY
from amdo_lab.common.equations import equation_map

ROOT = Path(__file__).resolve().parents[1]

# ---------------------------------------------------------------------------------------------
# Which equations a notebook cites: ``\tag{N}`` (or ``\qquad (N)``) in its LaTeX, and "eq. N",
# "eqs. N–M", "Eq. (N)", "equations N and M" in its prose (markdown cells). "\simeq 3" is not one.

_CITATION = re.compile(r"(?<![A-Za-z\\])[Ee]q(?:s|uations?)?\.?\s*"
                       r"((?:\(?\d+[a-z]?\)?(?:\s*(?:[-–,]|and|or|to)\s*)?)+)")


def _expand(numbers: str) -> set[int]:
    """Every number of "4–9", "(17)-(18)", "7, 8 and 10"; ranges are inclusive."""
    found = {int(n) for n in re.findall(r"\d+", numbers)}
    for first, last in re.findall(r"(\d+)\s*\)?\s*[-–]\s*\(?(\d+)", numbers):
        found |= set(range(int(first), int(last) + 1))
    return found


def cited_equations(text: str) -> set[int]:
    """Equation numbers cited in a text (LaTeX tags and prose citations)."""
    found = {int(n) for n in re.findall(r"\\tag\{(\d+)\}", text)}
    found |= {int(n) for n in re.findall(r"\\qquad\s*\((\d+)\)", text)}  # a display numbered by hand
    for match in _CITATION.finditer(text):
        found |= _expand(match.group(1))
    return found


def notebook_citations(chapter: int) -> set[int]:
    (path,) = sorted((ROOT / "notebooks").glob(f"{chapter:02d}_*.ipynb"))
    cells = json.loads(path.read_text(encoding="utf-8"))["cells"]
    return cited_equations("\n".join("".join(c["source"]) for c in cells if c["cell_type"] == "markdown"))


def comments_of(source: str) -> str:
    """The ``#`` comments of a piece of source code (not its strings or docstrings)."""
    tokens = tokenize.generate_tokens(io.StringIO(source).readline)
    return "\n".join(tok.string for tok in tokens if tok.type == tokenize.COMMENT)


def resolve(dotted: str) -> object:
    """The object named ``amdo_lab.sub.module.function`` or ``amdo_lab.sub.module.Class.method``."""
    parts = dotted.split(".")
    for split in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:split]))
        except ModuleNotFoundError:
            continue
        for name in parts[split:]:
            obj = getattr(obj, name)
        return obj
    raise ImportError(dotted)


@functools.lru_cache(maxsize=None)
def _test_functions(test_file: str) -> dict[str, ast.FunctionDef]:
    """{name: node} of the top-level functions of a test file (parsed, not imported)."""
    source = (ROOT / "tests" / test_file).read_text(encoding="utf-8")
    return {node.name: node for node in ast.parse(source).body if isinstance(node, ast.FunctionDef)}


def called_names(test_file: str, test_name: str) -> set[str]:
    """Names the test calls (``f(...)``, ``obj.f(...)``), also through the test file's own helper
    functions it calls (one level deep: ``_fit(...)`` whose body calls ``register_em``)."""
    functions = _test_functions(test_file)

    def calls(node: ast.AST) -> set[str]:
        found = set()
        for sub in ast.walk(node):
            if isinstance(sub, ast.Call):
                if isinstance(sub.func, ast.Name):
                    found.add(sub.func.id)
                elif isinstance(sub.func, ast.Attribute):
                    found.add(sub.func.attr)
        return found

    direct = calls(functions[test_name])
    helpers = {name for name in direct if name in functions and not name.startswith("test_")}
    return direct.union(*(calls(functions[name]) for name in helpers))


# ---------------------------------------------------------------------------------------------
# The tables live in the package, one per chapter (``amdo_lab.<method>.equations``), and the
# subpackage's docstring shows them; chapter 0 cites no equation of its own.


def _package_of(chapter) -> str:
    return chapter.exercises.rsplit(".", 1)[0]


def _equation_tables() -> dict[int, tuple[dict, str]]:
    """{chapter: ({equation: (dotted or None, test name or reason)}, test file)} from the package."""
    tables = {}
    for chapter in REGISTRY:
        if chapter.number == 0:
            continue
        module = importlib.import_module(f"{_package_of(chapter)}.equations")
        rows = {number: (path.code, path.test if path.reason is None else path.reason)
                for number, path in module.EQUATIONS.items()}
        tables[chapter.number] = (rows, module.TEST_FILE)
    return tables


CHAPTERS = _equation_tables()


@pytest.mark.parametrize("chapter", [c for c in REGISTRY if c.number > 0], ids=lambda c: f"ch{c.number}")
def test_the_subpackage_docstring_shows_the_equation_map(chapter):
    package = importlib.import_module(_package_of(chapter))
    table = importlib.import_module(f"{_package_of(chapter)}.equations")
    assert equation_map(table.EQUATIONS, table.TEST_FILE) in package.__doc__
    assert (ROOT / "tests" / table.TEST_FILE).exists(), table.TEST_FILE


def _rows():
    for chapter, (table, test_file) in CHAPTERS.items():
        for equation, (dotted, second) in table.items():
            if dotted is not None:
                yield pytest.param(chapter, equation, dotted, second, test_file, id=f"ch{chapter}-eq{equation}")


@pytest.mark.parametrize("chapter", sorted(CHAPTERS))
def test_every_cited_equation_is_in_the_table(chapter):
    table = CHAPTERS[chapter][0]
    cited = notebook_citations(chapter)
    assert cited, "no citation found: the extraction is broken"
    missing, stale = sorted(cited - set(table)), sorted(set(table) - cited)
    assert not missing, f"chapter {chapter} cites equations missing from its table: {missing}"
    assert not stale, f"chapter {chapter}'s table lists equations it no longer cites: {stale}"


@pytest.mark.parametrize("chapter", sorted(CHAPTERS))
def test_tables_are_in_equation_order_and_reasons_are_given(chapter):
    table = CHAPTERS[chapter][0]
    assert list(table) == sorted(table)
    for equation, (dotted, second) in table.items():
        assert isinstance(second, str) and second.strip(), f"eq. {equation}: name a test or give a reason"
        if dotted is None:
            assert len(second.split()) >= 5, f"eq. {equation}: say why it has no code"


@pytest.mark.parametrize("chapter, equation, dotted, test_name, test_file", list(_rows()))
def test_reference_path_names_the_equation_in_a_comment(chapter, equation, dotted, test_name, test_file):
    assert dotted.startswith("amdo_lab."), dotted
    function = resolve(dotted)
    assert callable(function), dotted
    comments = comments_of(textwrap.dedent(inspect.getsource(function)))
    for kernel in private_kernels(dotted):  # a checked wrapper's maths sits in the kernel it calls
        comments += "\n" + comments_of(textwrap.dedent(inspect.getsource(kernel)))
    assert equation in cited_equations(comments), f"no comment of {dotted} names eq. ({equation})"


@pytest.mark.parametrize("chapter, equation, dotted, test_name, test_file", list(_rows()))
def test_reference_path_is_public_and_documented(chapter, equation, dotted, test_name, test_file):
    private = [part for part in dotted.split(".") if part.startswith("_")]
    assert not private, f"eq. ({equation}) maps to a private name {dotted}: map its public, checked wrapper"
    assert inspect.getdoc(resolve(dotted)), f"{dotted} has no docstring"


def private_kernels(dotted: str) -> list[object]:
    """The module-level private functions (and private methods of its class) that ``dotted`` calls by
    name: the check-free kernels of the checked-wrapper pattern."""
    function = resolve(dotted)
    owner = resolve(dotted.rsplit(".", 1)[0])
    module = importlib.import_module(function.__module__)
    source = textwrap.dedent(inspect.getsource(function))
    kernels = []
    for name in set(re.findall(r"\b(_[A-Za-z]\w*)\(", source)):
        candidate = getattr(owner, name, None) or getattr(module, name, None)
        if inspect.isfunction(candidate) and candidate.__module__.startswith("amdo_lab."):
            kernels.append(candidate)
    return kernels


def names_that_reach(dotted: str) -> set[str]:
    """The function's own name and, for a private kernel, the public names beside it that call it
    (a test reaches ``_update`` through ``material_update``)."""
    owner_name, short_name = dotted.rsplit(".", 1)
    names = {short_name}
    if short_name.startswith("_"):
        owner = resolve(owner_name)
        members = list(vars(owner).items())
        for cls in [m for n, m in members if inspect.isclass(m) and not n.startswith("_")]:
            members += list(vars(cls).items())  # the public methods of the module's classes
        for name, member in members:
            if name.startswith("_") or not inspect.isfunction(member):
                continue
            try:
                source = inspect.getsource(member)
            except OSError:  # generated (a dataclass's methods): calls nothing of ours
                continue
            if re.search(rf"\b{short_name}\(", source):
                names.add(name)
    return names


@pytest.mark.parametrize("chapter, equation, dotted, test_name, test_file", list(_rows()))
def test_reference_path_has_a_test_that_calls_it(chapter, equation, dotted, test_name, test_file):
    assert test_name in _test_functions(test_file), f"{test_name} not found in tests/{test_file}"
    names = names_that_reach(dotted)
    assert names & called_names(test_file, test_name), \
        f"{test_name} never calls {' or '.join(sorted(names))} (a mention is not a check of its output)"


def test_citation_extraction():
    text = r"eqs. 4–9, eq. (17), Eqs. (17)–(18), eqs. 7, 8 and 10, $a \simeq 3$, $$x \tag{21}$$ $$y \qquad (23)$$"
    assert cited_equations(text) == {4, 5, 6, 7, 8, 9, 10, 17, 18, 21, 23}
    assert comments_of("x = 1  # eq. (3): blend\ny = '# eq. (4)'\n") == "# eq. (3): blend"
