"""The manifest (SPEC 12): a CSV ``name,input,aux,options``, one case a row, each row's
options checked by the single-run command's parser before anything runs."""

from __future__ import annotations

import argparse
import contextlib
import csv
import functools
import io
import os
import shlex
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

from pinn_engine.errors import PinnMeshError
from pinn_engine.routes.cli.parser import build_parser

COLUMNS = ("name", "input", "aux", "options")
REQUIRED = ("name", "input")  # aux and options may be left out of the header
AUX_SEPARATOR = ";"  # several auxiliary-line files in one field (SPEC 12)
# Paths of the options that name inputs are relative to the manifest's folder, like `input`
# (--adapt FILE:ARRAY too: the array's name stays at its end)
INPUT_PATHS = ("aux", "blocks", "load_model", "model", "adapt")


class ManifestError(PinnMeshError, ValueError):
    """A manifest that cannot be run: the one-line message names the file and the row."""


class _ParserError(Exception):
    """argparse's complaint about one row's options (instead of its exit)."""


@dataclass
class Case:
    """One row: its ``name`` (the output's name) and the single-run ``args`` its options
    give (inputs resolved, ``-o`` left for the batch to set)."""

    name: str
    args: argparse.Namespace = field(repr=False)


def _raise(message: str) -> None:
    raise _ParserError(message)


@functools.cache
def _parser() -> argparse.ArgumentParser:
    """The single-run command's parser, raising its complaint instead of exiting."""
    parser = build_parser()
    parser.error = _raise
    return parser


def _resolve(value, base: Path):
    """A path option's value (a string or a list of them) made relative to ``base``."""
    if value is None:
        return None
    if isinstance(value, list):
        return [str(base / v) for v in value]
    return str(base / value)


def parse_case(
    name: str, source: str, aux: Iterable[str], options: str, base: Path, where: str
) -> Case:
    """One case from its fields: ``options`` parsed by the single-run parser, the input and
    input-like paths relative to ``base``; raises :class:`ManifestError` naming ``where``."""
    if not name or name in (".", "..") or "/" in name or os.sep in name:
        raise ManifestError(f"{where}: name {name!r} is not a file name")
    try:
        with contextlib.redirect_stdout(io.StringIO()):  # what --help would print
            args = _parser().parse_args(shlex.split(options or ""))
    except (ValueError, _ParserError, SystemExit) as exc:  # shlex's unclosed quote, --help
        raise ManifestError(f"{where}: bad options {options!r}: {exc}") from None
    if args.boundary is not None:
        raise ManifestError(f"{where}: the input column names the boundary, not the options")
    if args.output is not None:
        raise ManifestError(f"{where}: the batch names the output (OUTDIR/NAME); drop -o")
    args.boundary = str(base / source) if source else None
    args.aux = [*aux, *args.aux]
    for key in INPUT_PATHS:
        setattr(args, key, _resolve(getattr(args, key), base))
    return Case(name=name, args=args)


def cases_of(rows: Iterable[tuple[int, Mapping[str, str]]], base: Path, source: str) -> list[Case]:
    """The cases of numbered manifest rows (dicts of ``COLUMNS``); names must be unique."""
    cases: list[Case] = []
    seen: set[str] = set()
    for number, row in rows:
        where = f"{source} row {number}"
        name = (row.get("name") or "").strip()
        aux = [a.strip() for a in (row.get("aux") or "").split(AUX_SEPARATOR) if a.strip()]
        case = parse_case(
            name, (row.get("input") or "").strip(), aux, row.get("options") or "", base, where
        )
        if name in seen:
            raise ManifestError(f"{where}: name {name!r} is used by an earlier row")
        seen.add(name)
        cases.append(case)
    return cases


def read_manifest(path: str | os.PathLike) -> list[Case]:
    """The cases of a manifest file; every row is checked before any case runs."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise ManifestError(f"{path}: cannot be read ({exc})") from None
    reader = csv.DictReader(text.splitlines())
    header = [h.strip() for h in reader.fieldnames or []]
    missing = [c for c in REQUIRED if c not in header]
    if missing:
        raise ManifestError(
            f"{path}: the header (first line) lacks the column {', '.join(missing)}; "
            f"expected {','.join(COLUMNS)}"
        )
    reader.fieldnames = header
    rows = [(reader.line_num, row) for row in reader]
    if not rows:
        raise ManifestError(f"{path}: holds no case")
    return cases_of(rows, path.parent, str(path))
