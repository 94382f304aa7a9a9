"""Qt compressed help (.qch): the SQLite file Qt's help engine reads, written as Qt 5's
``qhelpgenerator`` writes it (the same tables, each file's data zlib-compressed behind its
length as ``qCompress`` gives it, the table of contents as a ``QDataStream``), so that no Qt
tool is needed to make one."""

from __future__ import annotations

import sqlite3
import struct
import zlib
from dataclasses import dataclass, field
from pathlib import Path

# qhelpgenerator's schema (Qt 5.15); the help engine reads these tables by name
_TABLES = (
    "CREATE TABLE NamespaceTable (Id INTEGER PRIMARY KEY,Name TEXT )",
    "CREATE TABLE FilterAttributeTable (Id INTEGER PRIMARY KEY, Name TEXT )",
    "CREATE TABLE FilterNameTable (Id INTEGER PRIMARY KEY, Name TEXT )",
    "CREATE TABLE FilterTable (NameId INTEGER, FilterAttributeId INTEGER )",
    "CREATE TABLE IndexTable (Id INTEGER PRIMARY KEY, Name TEXT, Identifier TEXT, "
    "NamespaceId INTEGER, FileId INTEGER, Anchor TEXT )",
    "CREATE TABLE IndexFilterTable (FilterAttributeId INTEGER, IndexId INTEGER )",
    "CREATE TABLE ContentsTable (Id INTEGER PRIMARY KEY, NamespaceId INTEGER, Data BLOB )",
    "CREATE TABLE ContentsFilterTable (FilterAttributeId INTEGER, ContentsId INTEGER )",
    "CREATE TABLE FileAttributeSetTable (Id INTEGER, FilterAttributeId INTEGER )",
    "CREATE TABLE FileDataTable (Id INTEGER PRIMARY KEY, Data BLOB )",
    "CREATE TABLE FileFilterTable (FilterAttributeId INTEGER, FileId INTEGER )",
    "CREATE TABLE FileNameTable (FolderId INTEGER, Name TEXT, FileId INTEGER, Title TEXT )",
    "CREATE TABLE FolderTable(Id INTEGER PRIMARY KEY, Name Text, NamespaceID INTEGER )",
    "CREATE TABLE MetaDataTable(Name Text, Value BLOB )",
)
QCH_VERSION = "1.0"  # the format version qhelpgenerator 5.15 stamps


@dataclass
class Page:
    """One file of the help: its ``name`` (a path inside the virtual folder), ``title`` and
    ``html``; ``keywords`` are its entries in the help's index."""

    name: str
    title: str
    html: str
    keywords: tuple[str, ...] = ()


@dataclass
class Entry:
    """A table-of-contents entry: ``title`` linking to the page ``name``, with ``children``."""

    title: str
    name: str
    children: list[Entry] = field(default_factory=list)


def q_compress(data: bytes) -> bytes:
    """``qCompress``: the length, 4 bytes big-endian, then the zlib stream."""
    return struct.pack(">I", len(data)) + zlib.compress(data)


def _qstring(text: str) -> bytes:
    """A QString in a QDataStream: its byte length, then UTF-16 big-endian."""
    raw = text.encode("utf-16-be")
    return struct.pack(">I", len(raw)) + raw


def _contents(entry: Entry, depth: int = 0) -> bytes:
    """The table of contents as qhelpgenerator streams it: depth, reference, title, children."""
    own = struct.pack(">i", depth) + _qstring(entry.name) + _qstring(entry.title)
    return own + b"".join(_contents(child, depth + 1) for child in entry.children)


def write_qch(path: Path, namespace: str, folder: str, pages: list[Page], contents: Entry) -> None:
    """Write ``pages`` as the .qch ``path``: URLs ``qthelp://<namespace>/<folder>/<page>``,
    ``contents`` its table of contents. ``namespace`` must be lower case (a URL's host)."""
    path = Path(path)
    path.unlink(missing_ok=True)
    db = sqlite3.connect(path)
    try:
        for table in _TABLES:
            db.execute(table)
        db.execute("INSERT INTO MetaDataTable VALUES ('qchVersion', ?)", (QCH_VERSION,))
        # the empty file that stands for a page not found, as qhelpgenerator adds it
        db.execute("INSERT INTO FileDataTable VALUES (1, NULL)")
        db.execute("INSERT INTO FileNameTable VALUES (0, '', 1, '')")
        db.execute("INSERT INTO NamespaceTable VALUES (1, ?)", (namespace,))
        db.execute("INSERT INTO FolderTable VALUES (1, ?, 1)", (folder,))
        keywords = set()  # a keyword once, at its first page, as qhelpgenerator does
        for file_id, page in enumerate(pages, start=2):
            db.execute(
                "INSERT INTO FileDataTable VALUES (?, ?)",
                (file_id, q_compress(page.html.encode("utf-8"))),
            )
            db.execute(
                "INSERT INTO FileNameTable VALUES (1, ?, ?, ?)", (page.name, file_id, page.title)
            )
            for keyword in [k for k in dict.fromkeys(page.keywords) if k not in keywords]:
                keywords.add(keyword)
                db.execute(
                    "INSERT INTO IndexTable (Name, Identifier, NamespaceId, FileId, Anchor) "
                    "VALUES (?, ?, 1, ?, NULL)",
                    (keyword, keyword, file_id),
                )
        db.execute("INSERT INTO ContentsTable VALUES (1, 1, ?)", (_contents(contents),))
        db.commit()
    finally:
        db.close()
