"""An OpenFOAM ``blockMeshDict`` read into plain data (SPEC 15): vertices, hex blocks with
their counts and gradings, curved edges, patches and the default patch.

The file's grammar is the small part of OpenFOAM's dictionary syntax blockMesh uses:
keyword entries ending in ``;``, sub-dictionaries in braces and lists in parentheses. It is
tokenised and read into nested dicts and lists of string tokens; ``$name`` is replaced by a
top-level entry of that name, ``#include "file"`` by the file's text, and ``#eval{ expr }``,
``#eval "expr"`` and ``#calc "expr"`` by the value of their arithmetic (numbers, ``$name``,
+ - * / and powers, and the scalar functions of OpenFOAM's expressions: ``sin``,
``degToRad``, ``pi()``, ``sqrt``, ``pow``, ...). Entries blockMesh reads that this reader
does not (projection ``geometry`` and projected ``faces``, a non-empty
``mergePatchPairs``, ``#codeStream``, an expression beyond that arithmetic, blocks other
than ``hex``, edges other than ``arc``, ``spline`` and ``polyLine``) are refused in one line
naming the entry.
"""

from __future__ import annotations

import ast
import math
import operator
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pinn_engine.errors import InputError

# a 12-edge grading: for each block edge, its sections (length share, cell share, ratio)
Grading = list[list[tuple[float, float, float]]]
EDGE_KINDS = ("arc", "spline", "polyline")  # read as curves; "line" is the straight default
DEFAULT_PATCH = ("defaultFaces", "empty")  # blockMesh's name and type for unlisted faces
# entries blockMesh reads that this reader refuses, with what to do instead
UNSUPPORTED = {
    "geometry": "projection onto geometry is not supported; remove 'geometry' and project later",
    "faces": "projected faces are not supported; remove the 'faces' entry",
    "mergePatchPairs": "merging patch pairs is not supported; give the blocks shared vertices",
}
# two corners of a hex closer than this share of its largest corner distance coincide
COLLAPSED = 1e-9
MAX_INCLUDES = 8  # nested #include files at most (a file including itself is refused)
# an expression directive's text is carried to the parser as a string token with this prefix
EXPRESSION = "\x00"
# the scalar functions and constants of OpenFOAM's #eval expressions (and of #calc's C++
# where it is arithmetic), by name
FUNCTIONS = {
    **{f: getattr(math, f) for f in ("sin", "cos", "tan", "asin", "acos", "atan", "atan2")},
    **{f: getattr(math, f) for f in ("sinh", "cosh", "tanh", "sqrt", "exp", "log", "log10")},
    **{f: getattr(math, f) for f in ("pow", "hypot", "floor", "ceil", "cbrt")},
    "degToRad": math.radians,
    "radToDeg": math.degrees,
    "mag": abs,
    "sqr": lambda x: x * x,
    "min": min,
    "max": max,
    "round": round,
    "pi": lambda: math.pi,
}
CONSTANTS = {"pi": math.pi}
OPERATORS = {
    ast.Add: operator.add,
    ast.Sub: operator.sub,
    ast.Mult: operator.mul,
    ast.Div: operator.truediv,
    ast.Pow: operator.pow,
    ast.Mod: operator.mod,
    ast.USub: operator.neg,
    ast.UAdd: operator.pos,
}


@dataclass
class Block:
    """One ``hex``: its eight vertex ids, cell counts (ni, nj, nk), the grading of each of
    its 12 edges (blockMesh's numbering: 0-3 along i, 4-7 along j, 8-11 along k) and its
    cell zone's name (or "")."""

    vertices: list[int]
    counts: tuple[int, int, int]
    grading: Grading
    zone: str = ""


@dataclass
class Edge:
    """A curved edge from vertex ``start`` to ``end``: ``kind`` (arc, spline, polyline) and
    its ``points`` (the arc's point on the circle, or the interior points)."""

    kind: str
    start: int
    end: int
    points: np.ndarray


@dataclass
class Patch:
    """A named boundary patch of the dictionary: its OpenFOAM ``type`` and its faces, each
    four vertex ids."""

    name: str
    type: str
    faces: list[tuple[int, int, int, int]]
    extra: dict = field(default_factory=dict)


@dataclass
class BlockMeshDict:
    """The dictionary's meshing entries, coordinates scaled to metres."""

    vertices: np.ndarray
    blocks: list[Block]
    edges: list[Edge]
    patches: list[Patch]
    default_patch: tuple[str, str]
    source: str


def _not_supported(name: str, source: str) -> InputError:
    return InputError(
        f"'#{name}' is not supported; expand the dictionary first "
        "(foamDictionary -expand system/blockMeshDict)",
        source,
    )


def _expanded(text: str, source: str, depth: int = 0) -> str:
    """``text`` without comments, each ``#include "file"`` replaced by that file's text
    (relative to ``source``'s folder), each ``#eval``/``#calc`` by its expression as an
    ``EXPRESSION`` string token; any other directive refused, naming it."""
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    text = re.sub(r"//[^\n]*", " ", text)
    start = 0
    while found := re.compile(r"#(\w+)").search(text, start):
        name, rest = found.group(1), text[found.start() :]
        include = re.match(r'#include\s+"([^"]+)"', rest)
        expression = re.match(r'#(?:eval|calc)\s*"([^"]*)"|#eval\s*\{([^{}]*)\}', rest)
        if expression is not None:
            token = f'"{EXPRESSION}{expression.group(1) or expression.group(2)}"'
            text = text[: found.start()] + token + text[found.start() + expression.end() :]
            start = found.start() + len(token)
            continue
        if name != "include" or include is None or depth >= MAX_INCLUDES:
            raise _not_supported(name, source)
        path = Path(source).parent / include.group(1)
        if not path.is_file():
            raise InputError(f'#include "{include.group(1)}": no file {path}', source)
        inner = _expanded(path.read_text(errors="replace"), str(path), depth + 1)
        text = text[: found.start()] + inner + text[found.start() + include.end() :]
    return text


def _evaluate(node: ast.AST) -> float:
    """The value of an arithmetic expression tree of numbers, ``CONSTANTS``, ``OPERATORS``
    and ``FUNCTIONS``; anything else raises ValueError."""
    if isinstance(node, ast.Expression):
        return _evaluate(node.body)
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):
        return float(node.value)
    if isinstance(node, ast.Name) and node.id in CONSTANTS:
        return CONSTANTS[node.id]
    if isinstance(node, ast.BinOp) and type(node.op) in OPERATORS:
        return OPERATORS[type(node.op)](_evaluate(node.left), _evaluate(node.right))
    if isinstance(node, ast.UnaryOp) and type(node.op) in OPERATORS:
        return OPERATORS[type(node.op)](_evaluate(node.operand))
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and not node.keywords:
        if node.func.id in FUNCTIONS:
            return float(FUNCTIONS[node.func.id](*(_evaluate(a) for a in node.args)))
    raise ValueError(f"'{ast.unparse(node)}' is not arithmetic")


def expression_value(expression: str, names: dict, source: str) -> str:
    """An ``#eval``/``#calc`` expression's value as a number token: ``$name`` (or
    ``${name}``) from ``names`` (top-level entries), C++ scopes (``Foam::``) dropped."""

    def entry(match: re.Match) -> str:
        value = names.get(match.group(1))
        if not isinstance(value, str):
            raise InputError(
                f"${match.group(1)} in '{expression.strip()}' is not a top-level number", source
            )
        return f"({value})"

    text = re.sub(r"\$\{?(\w+)\}?", entry, expression)
    text = re.sub(r"\b(?:\w+::)+", "", text).strip()
    try:
        value = _evaluate(ast.parse(text, mode="eval"))
        return repr(int(value)) if value.is_integer() else repr(value)
    except (SyntaxError, ValueError, TypeError, ArithmeticError) as error:
        raise InputError(
            f"cannot evaluate '{expression.strip()}' ({error}); expand the dictionary first "
            "(foamDictionary -expand system/blockMeshDict)",
            source,
        ) from None


def _tokens(text: str, source: str) -> list[str]:
    """The dictionary's tokens, comments removed and included files spliced in."""
    return re.findall(r'"[^"]*"|[(){};]|[^\s(){};]+', _expanded(text, source))


def parse(text: str, source: str = "blockMeshDict") -> dict:
    """The dictionary as nested dicts (entries) and lists of string tokens, ``$name``
    replaced by the top-level entry ``name``."""
    toks = _tokens(text, source)
    pos = 0
    top: dict = {}

    def fail(what: str) -> InputError:
        return InputError(f"cannot read the dictionary: {what}", source)

    def value():
        nonlocal pos
        if pos >= len(toks):
            raise fail("it ends inside a list or entry")
        tok = toks[pos]
        pos += 1
        if tok == "(":
            items = []
            while pos < len(toks) and toks[pos] != ")":
                items.extend(expand(value()))
            pos += 1
            return items
        if tok == "{":
            return entries("}")
        return tok.strip('"')

    def expand(item):
        if isinstance(item, str) and item.startswith(EXPRESSION):
            return [expression_value(item[1:], top, source)]
        if isinstance(item, str) and item.startswith("$"):
            name = item[1:].strip("{}").lstrip(":")
            if name not in top:
                raise fail(f"${name} is not defined at the top level")
            return [top[name]]
        return [item]

    def entries(end: str | None) -> dict:
        nonlocal pos
        out: dict = {}
        while pos < len(toks) and toks[pos] != end:
            key = toks[pos]
            pos += 1
            if pos < len(toks) and toks[pos] == "{":
                pos += 1
                out[key] = entries("}")
                continue
            items = []
            while pos < len(toks) and toks[pos] != ";":
                items.extend(expand(value()))
            if pos >= len(toks):
                raise fail(f"entry '{key}' has no closing ';'")
            pos += 1
            out[key] = items[0] if len(items) == 1 else items
            if end is None:
                top[key] = out[key]
        pos += 1
        return out

    return entries(None)


def _floats(item, what: str, source: str, n: int = 3) -> np.ndarray:
    try:
        out = np.array([float(v) for v in item])
    except (TypeError, ValueError):
        raise InputError(f"{what}: expected {n} numbers, found {item!r}", source) from None
    if out.shape != (n,):
        raise InputError(f"{what}: expected {n} numbers, found {len(out)}", source)
    return out


def _sections(spec, what: str, source: str) -> list[tuple[float, float, float]]:
    """One edge's grading: a ratio, or a list of (length share, cell share, ratio), shares
    normalised to one."""
    if isinstance(spec, str):
        ratio = float(spec)
        return [(1.0, 1.0, 1.0 / -ratio if ratio < 0 else ratio)]
    try:
        rows = [tuple(float(v) for v in s) for s in spec]
    except (TypeError, ValueError):
        raise InputError(f"{what}: a grading section is (length cells ratio)", source) from None
    if not rows or any(len(r) != 3 for r in rows):
        raise InputError(f"{what}: a grading section is (length cells ratio)", source)
    lengths, cells = sum(r[0] for r in rows), sum(r[1] for r in rows)
    return [(a / lengths, b / cells, 1.0 / -c if c < 0 else c) for a, b, c in rows]


def _blocks(items: list, source: str) -> list[Block]:
    blocks, i = [], 0
    while i < len(items):
        kind = items[i]
        what = f"block {len(blocks)}"
        if kind != "hex":
            raise InputError(f"{what}: only 'hex' blocks are supported, found '{kind}'", source)
        ids = [int(v) for v in items[i + 1]]
        i += 2
        zone = ""
        if isinstance(items[i], str):
            zone, i = items[i], i + 1
        counts = tuple(int(v) for v in items[i])
        kind, spec = items[i + 1], items[i + 2]
        i += 3
        if len(ids) != 8 or len(counts) != 3 or min(counts) < 1:
            raise InputError(f"{what}: expected hex (8 vertices) (ni nj nk)", source)
        if len(set(ids)) != 8:
            raise InputError(f"{what} is collapsed (repeated vertices): not supported", source)
        if kind == "simpleGrading":
            if len(spec) != 3:
                raise InputError(f"{what}: simpleGrading takes three gradings", source)
            grading = [_sections(spec[e // 4], what, source) for e in range(12)]
        elif kind == "edgeGrading":
            if len(spec) != 12:
                raise InputError(f"{what}: edgeGrading takes twelve gradings", source)
            grading = [_sections(spec[e], what, source) for e in range(12)]
        else:
            raise InputError(f"{what}: unknown grading '{kind}'", source)
        blocks.append(Block(ids, counts, grading, zone))
    return blocks


def _edges(items: list, scale: float, source: str) -> list[Edge]:
    edges, i = [], 0
    while i < len(items):
        kind = str(items[i])
        if kind.lower() not in (*EDGE_KINDS, "line"):
            raise InputError(
                f"edge '{kind}' is not supported (arc, spline, polyLine and line are)", source
            )
        a, b = int(items[i + 1]), int(items[i + 2])
        what = f"edge {kind} {a} {b}"
        i += 3
        if kind.lower() == "line":
            continue
        if kind == "arc" and items[i] == "origin":
            if isinstance(items[i + 1], str):
                raise InputError(f"{what}: an arc's origin factor is not supported", source)
            centre = _floats(items[i + 1], what, source) * scale
            edges.append(Edge("arc-origin", a, b, centre[None]))
            i += 2
            continue
        if kind == "arc":
            edges.append(Edge("arc", a, b, _floats(items[i], what, source)[None] * scale))
        else:
            pts = np.array([_floats(p, what, source) for p in items[i]]).reshape(-1, 3)
            edges.append(Edge(kind.lower(), a, b, pts * scale))
        i += 1
    return edges


def _patches(d: dict, source: str) -> list[Patch]:
    out = []
    if "boundary" in d:
        items = d["boundary"]
        if isinstance(items, dict):
            items = [x for kv in items.items() for x in kv]
        for name, body in zip(items[::2], items[1::2]):
            if not isinstance(body, dict):
                raise InputError(f"boundary: patch '{name}' is not a dictionary", source)
            faces = [tuple(int(v) for v in f) for f in body.get("faces", [])]
            extra = {k: v for k, v in body.items() if k not in ("type", "faces")}
            out.append(Patch(str(name), str(body.get("type", "patch")), faces, extra))
    elif "patches" in d:
        items = d["patches"]
        for kind, name, faces in zip(items[::3], items[1::3], items[2::3]):
            out.append(Patch(name, kind, [tuple(int(v) for v in f) for f in faces]))
    for p in out:
        if any(len(f) != 4 for f in p.faces):
            raise InputError(f"patch '{p.name}': every face has four vertices", source)
    return out


def read(path: str | Path) -> BlockMeshDict:
    """The dictionary in ``path``, checked: what blockMesh reads and this reader does not is
    refused in one line naming the entry."""
    source = str(path)
    return from_text(Path(path).read_text(errors="replace"), source)


def from_text(text: str, source: str = "blockMeshDict") -> BlockMeshDict:
    """The dictionary of ``text`` (see :func:`read`)."""
    d = parse(text, source)
    for key, why in UNSUPPORTED.items():
        if key in d and d[key] not in ([], "()"):
            raise InputError(f"'{key}': {why}", source)
    for key in ("vertices", "blocks"):
        if key not in d:
            raise InputError(f"no '{key}' entry: not a blockMeshDict", source)
    scale = float(d.get("scale", d.get("convertToMeters", 1.0)))
    verts = []
    for k, v in enumerate(d["vertices"]):
        if v in ("project", "name"):
            raise InputError(f"vertex {k}: '{v}' vertices are not supported", source)
        verts.append(_floats(v, f"vertex {k}", source))
    vertices = np.array(verts).reshape(-1, 3) * scale
    blocks = _blocks(d["blocks"], source)
    for b, block in enumerate(blocks):
        if max(block.vertices) >= len(vertices):
            raise InputError(f"block {b}: vertex {max(block.vertices)} does not exist", source)
        corners = vertices[block.vertices]
        gap = np.linalg.norm(corners[:, None] - corners[None], axis=2)
        same = np.argwhere(np.triu(gap <= COLLAPSED * gap.max(), 1))
        if len(same):
            i, j = (block.vertices[k] for k in same[0])
            raise InputError(
                f"block {b}: vertices {i} and {j} coincide (a collapsed, wedge-shaped hex); "
                "collapsed blocks are not supported: give every block eight distinct vertices",
                source,
            )
    edges = _edges(d.get("edges", []), scale, source)
    default = d.get("defaultPatch", {})
    default_patch = (
        str(default.get("name", DEFAULT_PATCH[0])),
        str(default.get("type", DEFAULT_PATCH[1])),
    )
    return BlockMeshDict(vertices, blocks, edges, _patches(d, source), default_patch, source)


def is_blockmeshdict(path: str | Path) -> bool:
    """Whether ``path`` names a blockMeshDict: by its name, or a FoamFile header naming it."""
    path = Path(path)
    if path.name.startswith("blockMeshDict"):
        return True
    if path.suffix or not path.is_file():
        return False
    with open(path, errors="replace") as f:
        head = f.read(2000)
    return "FoamFile" in head and re.search(r"object\s+blockMeshDict", head) is not None
