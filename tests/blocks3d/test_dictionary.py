"""The blockMeshDict reader (SPEC 15): every entry it takes, and a one-line refusal naming
each entry it does not."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import EXAMPLES

from pinn_engine.blocks3d.curves import Curve, divisions
from pinn_engine.blocks3d.dictionary import Edge, from_text, is_blockmeshdict, read
from pinn_engine.errors import InputError

BOX = """
FoamFile { version 2.0; format ascii; class dictionary; object blockMeshDict; }
convertToMeters 0.1;
n 4;
vertices ( (0 0 0) (1 0 0) (1 1 0) (0 1 0) (0 0 1) (1 0 1) (1 1 1) (0 1 1) );
blocks ( hex (0 1 2 3 4 5 6 7) fluid ($n 3 2)
         edgeGrading (2 2 2 2 ((0.2 0.3 4) (0.6 0.4 1) (0.2 0.3 0.25)) 1 1 1 1 1 1 -2) );
edges ( arc 0 1 (0.5 -0.2 0) polyLine 4 5 ((0.5 -0.1 1)) spline 3 2 ((0.3 1.1 0) (0.7 1.1 0))
        arc 7 6 origin (0.5 0.5 1) );
patches ( wall bottom ((0 1 5 4)) patch top ((3 7 6 2)) );
defaultPatch { name sides; type symmetry; }
mergePatchPairs ( );
"""


def test_every_entry_is_read():
    d = from_text(BOX)
    assert np.allclose(d.vertices[6], [0.1, 0.1, 0.1])  # convertToMeters
    (block,) = d.blocks
    assert block.counts == (4, 3, 2) and block.zone == "fluid"  # $n expanded
    assert block.grading[0] == [(1.0, 1.0, 2.0)]
    assert [s[2] for s in block.grading[4]] == [4.0, 1.0, 0.25]
    assert sum(s[0] for s in block.grading[4]) == pytest.approx(1.0)
    assert block.grading[11] == [(1.0, 1.0, 0.5)]  # a negative ratio is its inverse
    assert [e.kind for e in d.edges] == ["arc", "polyline", "spline", "arc-origin"]
    assert [(p.name, p.type, len(p.faces)) for p in d.patches] == [
        ("bottom", "wall", 1),
        ("top", "patch", 1),
    ]
    assert d.default_patch == ("sides", "symmetry")


def test_multi_grading_places_each_section():
    """Three sections of 30 %, 40 % and 30 % of 10 cells: 3, 4 and 3 cells, the first ending
    at 0.2 of the edge, its last cell 4 times its first."""
    t = divisions([(0.2, 0.3, 4.0), (0.6, 0.4, 1.0), (0.2, 0.3, 0.25)], 10)
    assert len(t) == 11 and t[0] == 0 and t[-1] == 1
    assert t[3] == pytest.approx(0.2) and t[7] == pytest.approx(0.8)
    cells = np.diff(t)
    assert cells[2] / cells[0] == pytest.approx(4.0)
    assert np.allclose(cells[3:7], 0.15)


def test_curves_pass_through_their_points():
    a, b = np.array([1.0, 0, 0]), np.array([0, 1.0, 0])
    arc = Curve(a, b, Edge("arc", 0, 1, np.array([[np.sqrt(0.5), np.sqrt(0.5), 0]])))
    pts = arc.position(np.linspace(0, 1, 9))
    assert np.allclose(np.linalg.norm(pts, axis=1), 1.0)
    assert np.allclose(pts[4], [np.sqrt(0.5), np.sqrt(0.5), 0])
    about = Curve(a, b, Edge("arc-origin", 0, 1, np.zeros((1, 3))))
    assert np.allclose(about.position(np.linspace(0, 1, 9)), pts)
    knots = np.array([[0.5, 0.2, 0.0]])
    for kind in ("spline", "polyline"):
        c = Curve(a, b, Edge(kind, 0, 1, knots))
        t = c.params[1]
        assert np.allclose(c.position(np.array([0.0, t, 1.0])), [a, knots[0], b])


@pytest.mark.parametrize(
    ("change", "named"),
    [
        (("edges (", "geometry { s { type sphere; } }\nedges ("), "'geometry'"),
        (("mergePatchPairs ( );", "mergePatchPairs ( (a b) );"), "'mergePatchPairs'"),
        (("n 4;", '#includeEtc "caseDicts/x"\nn 4;'), "'#includeEtc'"),
        (("n 4;", '#include "nowhere"\nn 4;'), "no file"),
        (("n 4;", "n #codeStream { code #{ os << 4; #}; };"), "'#codeStream'"),
        (("n 4;", "n #eval{ vector(4, 0, 0) };"), "cannot evaluate 'vector(4, 0, 0)'"),
        (("n 4;", 'n #calc "$w + 1";'), "$w in '$w + 1' is not a top-level number"),
        (("spline 3 2", "BSpline 3 2"), "edge 'BSpline'"),
        (("hex (0 1 2 3 4 5 6 7)", "prism (0 1 2 3 4 5 6 7)"), "only 'hex' blocks"),
        (("edgeGrading (2 2", "edgeGrading (2"), "edgeGrading takes twelve"),
        (("$n", "$m"), "$m is not defined"),
    ],
)
def test_unsupported_entries_are_refused_in_one_line(change, named):
    with pytest.raises(InputError) as err:
        from_text(BOX.replace(*change), "case/system/blockMeshDict")
    text = str(err.value)
    assert named in text and "\n" not in text and "case/system/blockMeshDict" in text


def test_the_boundary_form_and_the_file_name():
    path = EXAMPLES / "blockmesh" / "pipe" / "system" / "blockMeshDict"
    assert is_blockmeshdict(path)
    assert not is_blockmeshdict(EXAMPLES / "fig2.vtp")
    d = read(path)
    assert [(p.name, p.type, len(p.faces)) for p in d.patches] == [
        ("inlet", "patch", 5),
        ("outlet", "patch", 5),
        ("wall", "wall", 4),
    ]


def test_include_splices_a_file(tmp_path):
    (tmp_path / "params").write_text("n 4; // the cells along x\n")
    dict_path = tmp_path / "blockMeshDict"
    dict_path.write_text(BOX.replace("n 4;", '#include "params"'))
    assert read(dict_path).blocks[0].counts == (4, 3, 2)


def test_eval_and_calc_are_evaluated():
    """``#eval`` and ``#calc`` arithmetic, with entries, OpenFOAM's scalar functions and C++
    scopes, as the tutorials write it (pipeCyclic's vertices, channel395DFSEM's lengths)."""
    text = BOX.replace(
        "n 4;",
        "r 0.5; half 45; n #eval{ 2*2 };\n"
        "y #eval{ $r*sin(degToRad($half)) };\n"
        'z #calc "-1*$r*Foam::cos(degToRad(${half}))";\n'
        'w #eval "pi()*sqr(2)";',
    ).replace("(1 1 1)", "($y $z $w)")
    d = from_text(text)
    assert d.blocks[0].counts == (4, 3, 2)
    y = 0.5 * np.sin(np.pi / 4)
    assert np.allclose(d.vertices[6], [0.1 * y, -0.1 * y, 0.1 * 4 * np.pi])


def test_a_collapsed_block_is_refused_in_one_line():
    with pytest.raises(InputError, match="block 0: vertices 2 and 3 coincide") as err:
        from_text(BOX.replace("(1 1 0) (0 1 0)", "(1 1 0) (1 1 0)"))
    assert "\n" not in str(err.value)
