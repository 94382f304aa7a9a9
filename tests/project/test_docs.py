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
