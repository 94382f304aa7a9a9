"""Qt compressed help (io/qch.py): the file Qt's help engine reads, as qhelpgenerator writes
it (compared table by table with qhelpgenerator's own file where Qt's tools are installed)."""

from __future__ import annotations

import shutil
import sqlite3
import struct
import subprocess
import zlib
from pathlib import Path
from xml.sax.saxutils import quoteattr

import pytest

from pinn_engine.io.qch import Entry, Page, write_qch

PAGES = [
    Page("index.html", "Home", "<html><head><title>Home</title></head><body>é</body></html>"),
    Page(
        "filters.A.html",
        "Filter A",
        "<html><head><title>Filter A</title></head><body>A</body></html>",
        keywords=("Filter A", "A"),
    ),
    Page(  # a keyword of an earlier page is not repeated
        "filters.B.html",
        "Filter A",
        "<html><head><title>Filter A</title></head><body>B</body></html>",
        keywords=("Filter A", "B"),
    ),
]
CONTENTS = Entry("Home", "index.html", [Entry("Filter A", "filters.A.html")])
QHELPGENERATOR = shutil.which("qhelpgenerator") or shutil.which(
    "qhelpgenerator", path="/usr/lib/qt5/bin"
)


def _rows(path: Path) -> dict[str, list[tuple]]:
    with sqlite3.connect(path) as db:
        tables = [r[0] for r in db.execute("SELECT name FROM sqlite_master WHERE type='table'")]
        return {t: list(db.execute(f"SELECT * FROM {t}")) for t in tables}


def test_pages_are_found_by_namespace_folder_and_name(tmp_path):
    path = tmp_path / "help.qch"
    write_qch(path, "a-b.c", "a-b", PAGES, CONTENTS)
    rows = _rows(path)
    assert rows["NamespaceTable"] == [(1, "a-b.c")]
    assert rows["FolderTable"] == [(1, "a-b", 1)]
    names = {name: file_id for _, name, file_id, _ in rows["FileNameTable"]}
    data = dict(rows["FileDataTable"])
    html = data[names["index.html"]]
    assert struct.unpack(">I", html[:4])[0] == len(PAGES[0].html.encode())  # qCompress
    assert zlib.decompress(html[4:]).decode() == PAGES[0].html
    assert [r[1] for r in rows["IndexTable"]] == ["Filter A", "A", "B"]
    depth, length = struct.unpack(">iI", rows["ContentsTable"][0][2][:8])
    assert depth == 0 and rows["ContentsTable"][0][2][8 : 8 + length].decode("utf-16-be") == (
        "index.html"
    )


@pytest.mark.skipif(QHELPGENERATOR is None, reason="Qt's qhelpgenerator is not installed")
def test_the_file_is_what_qhelpgenerator_writes(tmp_path):
    ours = tmp_path / "ours.qch"
    write_qch(ours, "a-b.c", "a-b", PAGES[:2], CONTENTS)
    for page in PAGES[:2]:
        (tmp_path / page.name).write_text(page.html, encoding="utf-8")

    def section(entry: Entry) -> str:
        inner = "".join(section(child) for child in entry.children)
        attributes = f"title={quoteattr(entry.title)} ref={quoteattr(entry.name)}"
        return f"<section {attributes}>{inner}</section>"

    keywords = "".join(
        f"<keyword name={quoteattr(k)} id={quoteattr(k)} ref={quoteattr(p.name)}/>"
        for p in PAGES[:2]
        for k in p.keywords
    )
    files = "".join(f"<file>{p.name}</file>" for p in PAGES[:2])
    (tmp_path / "help.qhp").write_text(
        '<?xml version="1.0" encoding="UTF-8"?><QtHelpProject version="1.0">'
        "<namespace>a-b.c</namespace><virtualFolder>a-b</virtualFolder><filterSection>"
        f"<toc>{section(CONTENTS)}</toc><keywords>{keywords}</keywords><files>{files}</files>"
        "</filterSection></QtHelpProject>"
    )
    theirs = tmp_path / "theirs.qch"
    subprocess.run(
        [QHELPGENERATOR, str(tmp_path / "help.qhp"), "-o", str(theirs)],
        check=True,
        capture_output=True,
    )
    assert _rows(ours) == _rows(theirs)
