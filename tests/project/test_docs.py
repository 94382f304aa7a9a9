"""The Markdown pages: code blocks that ruff can check, and an index that lists every page.

`ruff format --check .` (make check, make test) formats the Python code blocks of Markdown
files, but skips a block that does not parse as Python without a word, and reads an
unlabelled block as Python. So every fenced block names its language, and every Python block
parses (a shell session goes in a `bash` block, printed output in a `text` block).
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest
from helpers import ROOT

FENCE = re.compile(r"^(?P<indent> *)(?P<fence>`{3,}|~{3,})\s*(?P<lang>[^\s`]*)")
PYTHON = {"python", "py", "python3"}
SKIP = {"out", "build"}


def markdown_files() -> list[Path]:
    return sorted(
        p
        for p in ROOT.rglob("*.md")
        if not any(part.startswith(".") or part in SKIP for part in p.relative_to(ROOT).parts)
    )


def code_blocks(path: Path) -> list[tuple[int, str, str]]:
    """(line of the opening fence, language, code) of each fenced block of ``path``."""
    lines, blocks, i = path.read_text().splitlines(), [], 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if m:
            fence, n = m["fence"], len(m["indent"])
            j = i + 1
            while j < len(lines) and not lines[j].lstrip().startswith(fence):
                j += 1
            blocks.append((i + 1, m["lang"], "\n".join(ln[n:] for ln in lines[i + 1 : j])))
            i = j
        i += 1
    return blocks


def test_the_markdown_files_are_found():
    names = {p.relative_to(ROOT).as_posix() for p in markdown_files()}
    assert {"README.md", "docs/SPEC.md", "docs/routes.md", "paraview_support/NOTES.md"} <= names


@pytest.mark.parametrize("path", markdown_files(), ids=lambda p: p.relative_to(ROOT).as_posix())
def test_code_blocks_are_labelled_and_python_blocks_parse(path):
    for line, lang, code in code_blocks(path):
        where = f"{path.relative_to(ROOT)}:{line}"
        assert lang, f"{where}: a code block without a language (ruff would read it as Python)"
        if lang in PYTHON:
            try:
                ast.parse(code)
            except SyntaxError as err:
                pytest.fail(
                    f"{where}: a {lang} block that is not Python ({err.msg}); ruff skips it"
                )


def test_the_block_reader_sees_what_ruff_sees():
    sample = ROOT / "docs" / "routes.md"
    langs = [lang for _, lang, _ in code_blocks(sample)]
    assert langs.count("python") == 3 and "bash" in langs


def test_the_docs_index_lists_every_page():
    index = (ROOT / "docs" / "index.md").read_text()
    linked = set(re.findall(r"\]\(([^)#]+\.md)\)", index))
    pages = {p.name for p in (ROOT / "docs").glob("*.md")} - {"index.md"}
    assert pages - linked == set(), "pages missing from docs/index.md"


README_LINES = 250  # the README is a user's page; the rest lives in docs/
# every domain kind, as the README's opening, the package's description and --help name it
KINDS = ("four-sided", "O- and C-grids", "multi-block", "hexahedral", "batches")


def test_the_readme_is_a_short_page_that_opens_with_every_domain_kind():
    readme = (ROOT / "README.md").read_text()
    assert len(readme.splitlines()) <= README_LINES
    opening = " ".join(readme.splitlines()[:6]).replace("**", "")
    assert all(kind in opening for kind in KINDS), opening
    assert "make demo" in readme and "make test" in readme


def test_the_description_and_help_name_every_domain_kind():
    from pinn_engine.routes.cli import build_parser

    description = re.search(r'^description = "(.*)"$', (ROOT / "pyproject.toml").read_text(), re.M)
    help_text = " ".join(build_parser().format_help().split())
    for text in (description[1], help_text):
        assert all(kind in text for kind in KINDS), text


# history in a page: a ticket's number, a hash of git's log, or the session that measured it
PAGE_HISTORY = re.compile(
    r"[Ii]ssues? #?\d|\b(?=[0-9a-f]*\d)(?=[0-9a-f]*[a-f])[0-9a-f]{7,40}\b"
    r"|[Ee]arlier sessions?|[Tt]his session"
)


@pytest.mark.parametrize("path", markdown_files(), ids=lambda p: p.relative_to(ROOT).as_posix())
def test_no_page_cites_an_issue_a_commit_or_a_session(path):
    """A page says what is true now and how to measure it; its history is in git's log."""
    lines = path.read_text().splitlines()
    cited = [
        f"{n}: {line.strip()[:80]}" for n, line in enumerate(lines, 1) if PAGE_HISTORY.search(line)
    ]
    assert not cited, f"{path.relative_to(ROOT)} cites history: {cited}"


CODE = re.compile(
    r"`([A-Za-z_][\w/.<>]*?\.py)(?:::(\w+))?`|`((?:pinn_engine\.)?[A-Za-z_]\w*(?:\.\w+)+)`"
)
# first parts of dotted names that are other projects' code, the examples' own variables
# (`boundary`, `grid`) or OpenFOAM's log files
FOREIGN = {
    "np",
    "numpy",
    "pv",
    "pyvista",
    "torch",
    "nn",
    "scipy",
    "os",
    "sys",
    "time",
    "meshio",
    "paraview",
    "vtk",
    "gmsh",
    "Mesh",
    "PolyData",
    "dask",
    "distributed",
    "sklearn",
    "pytest",
    "math",
    "boundary",
    "grid",
    "log",
}
SUFFIXES = {
    "py",
    "sh",
    "csv",
    "json",
    "vtp",
    "vts",
    "vtm",
    "dat",
    "cpp",
    "toml",
    "md",
    "txt",
    "stl",
    "png",
    "foam",
    "cgns",
    "su2",
    "msh",
    "so",
    "pt",
    "xml",
    "qch",
    "html",
    "yaml",
}


def _python_files() -> list[Path]:
    folders = (
        "pinn_engine",
        "tests",
        "benchmarks",
        "examples",
        "example_data",
        "scripts",
        "plugin",
        "experiments",
        "paraview_support",
    )
    nested = [p for f in folders for p in (ROOT / f).rglob("*.py")]
    return sorted([*ROOT.glob("*.py"), *nested])


def _defined(tree: ast.AST) -> tuple[set[str], set[str]]:
    """The names a module defines or uses, at any depth (functions, classes and
    ``Class.member``, variables, attributes, imports), and the strings it uses as a
    dictionary's keys (a report's entries)."""
    names, keys = set(), set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ClassDef):
            names.add(node.name)
            members = _defined(ast.Module(body=node.body, type_ignores=[]))[0]
            names |= {f"{node.name}.{m}" for m in members}
        elif isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            names.add(node.name)
        elif isinstance(node, ast.Name):
            names.add(node.id)
        elif isinstance(node, ast.arg):
            names.add(node.arg)
        elif isinstance(node, ast.Attribute):
            names.add(node.attr)
        elif isinstance(node, ast.alias):
            names.add(node.asname or node.name.split(".")[-1])
        if isinstance(node, ast.Dict | ast.Subscript):
            candidates = node.keys if isinstance(node, ast.Dict) else [node.slice]
            keys |= {k.value for k in candidates if isinstance(k, ast.Constant)}
    return names, {k for k in keys if isinstance(k, str)}


def _code_index() -> tuple[dict[str, set[str]], set[str], set[str]]:
    """Module names (each dotted tail of each file's path) -> the names defined there; every
    dictionary key of the package (its reports' entries); every Python file's path."""
    modules: dict[str, set[str]] = {}
    keys: set[str] = set()
    for path in _python_files():
        parts = path.relative_to(ROOT).with_suffix("").parts
        parts = parts[:-1] if parts[-1] == "__init__" else parts
        names, constants = _defined(ast.parse(path.read_text()))
        keys |= constants if parts[0] == "pinn_engine" else set()
        for k in range(len(parts)):
            modules.setdefault(".".join(parts[k:]), set()).update(names)
    files = {p.relative_to(ROOT).as_posix() for p in _python_files()}
    return modules, keys, files


def _resolves(name: str, modules: dict[str, set[str]], keys: set[str]) -> bool:
    """``a.b.c`` names code when its longest module prefix exists and the rest are defined
    there, ``Class.member`` when the class has it, or a report's entry when every part is a
    dictionary key of the package."""
    parts = name.split(".")
    prefixes = [k for k in range(len(parts), 0, -1) if ".".join(parts[:k]) in modules]
    in_module = bool(prefixes) and all(
        p in modules[".".join(parts[: prefixes[0]])] for p in parts[prefixes[0] :]
    )
    method = len(parts) == 2 and any(name in names for names in modules.values())
    return in_module or method or all(p in keys for p in parts)


def test_every_code_name_a_page_cites_exists():
    """A page that cites `module.name` or `path.py` (or `path.py::name`) of this repository
    cites something that is there now (a file a user writes lies under `out/`)."""
    modules, keys, files = _code_index()
    missing = []
    for page in markdown_files():
        for py, member, dotted in CODE.findall(page.read_text()):
            where = f"{page.relative_to(ROOT)}: "
            if py:
                if "<" in py or py.startswith("out/"):  # a pattern, or the user's own file
                    continue
                found = [f for f in files if f == py or f.endswith("/" + py)]
                if not found:
                    missing.append(where + py)
                elif member and not any(
                    member in _defined(ast.parse((ROOT / f).read_text()))[0] for f in found
                ):
                    missing.append(f"{where}{py}::{member}")
            elif (
                dotted.split(".")[0] not in FOREIGN
                and not dotted.startswith("vtk")
                and dotted.split(".")[-1] not in SUFFIXES
            ):
                if not _resolves(dotted, modules, keys):
                    missing.append(where + dotted)
    assert not missing, f"code names that are not in the repository: {missing}"
