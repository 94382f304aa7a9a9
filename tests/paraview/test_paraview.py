"""The ParaView route, in a real ParaView (Debian's ``paraview`` package, pvpython).

The pvpython scripts in ``tests/paraview/scripts`` run through ``scripts/pvenv.sh`` on a clean
copy of the checkout (tracked and unignored files only; no ``.venv``, no egg-info), with the
repository root left off PYTHONPATH: the plugin must find ``pinn_engine`` by itself.
``bash scripts/setup_paraview.sh`` installs ParaView and ``.venv-pv``; without them these
tests are skipped with the reason.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from helpers import ROOT, foam_env

pytestmark = pytest.mark.paraview

VENV_PV = Path(os.environ.get("PINN_PV_VENV", ROOT / ".venv-pv"))
TIMEOUT = 240


def _missing() -> str | None:
    if shutil.which("pvpython") is None:
        return "ParaView's pvpython is not installed (bash scripts/setup_paraview.sh installs it)"
    if not (VENV_PV / "bin" / "python").exists():
        return f"{VENV_PV} is missing (bash scripts/setup_paraview.sh creates it)"
    return None


if _missing():
    pytest.skip(_missing(), allow_module_level=True)


@pytest.fixture(scope="module")
def checkout(tmp_path_factory) -> Path:
    """A clean copy of the working tree: what ``git clone`` plus local edits would give."""
    dest = tmp_path_factory.mktemp("pv") / "checkout"
    try:
        listed = subprocess.run(
            ["git", "ls-files", "-co", "--exclude-standard", "-z"],
            cwd=ROOT,
            capture_output=True,
            check=True,
            timeout=60,
        ).stdout
        files = [f for f in listed.decode().split("\0") if f]
    except (OSError, subprocess.CalledProcessError):
        files = [
            str(p.relative_to(ROOT))
            for d in (
                "pinn_engine",
                "plugin",
                "paraview_support",
                "scripts",
                "example_data",
                "tests",
            )
            for p in (ROOT / d).rglob("*")
            if p.is_file() and "__pycache__" not in p.parts
        ]
    for name in files:
        src = ROOT / name
        if src.is_file():
            (dest / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / name)
    return dest


def run_pvpython(checkout: Path, script: str, *args: str, **env_extra: str) -> dict:
    env = dict(
        os.environ,
        PINN_PV_VENV=str(VENV_PV),
        PINN_PV_NO_REPO_PATH="1",
        PINN_PV_NO_XVFB="1",
        **env_extra,
    )  # pipeline work only: no X server needed
    env.pop("PYTHONPATH", None)
    cmd = [
        "bash",
        str(checkout / "scripts" / "pvenv.sh"),
        "pvpython",
        str(checkout / "tests" / "paraview" / "scripts" / script),
        *args,
    ]
    proc = subprocess.run(
        cmd, cwd=checkout.parent, env=env, capture_output=True, text=True, timeout=TIMEOUT
    )
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("RESULT ")]
    assert proc.returncode == 0 and lines, (
        f"{script} failed (rc {proc.returncode})\nstdout:\n{proc.stdout[-3000:]}\n"
        f"stderr:\n{proc.stderr[-3000:]}"
    )
    return json.loads(lines[-1][len("RESULT ") :])


@pytest.fixture(scope="module")
def filter_run(checkout) -> dict:
    return run_pvpython(checkout, "check_filter.py", str(checkout / "example_data"))


def test_plugin_autoloads_from_clean_checkout(filter_run, checkout):
    assert not filter_run["pinn_engine_on_pythonpath"]
    assert Path(filter_run["pinn_engine_file"]).is_relative_to(checkout)
    assert filter_run["label"] == "PINN Structured Mesh"
    assert filter_run["menu_category"] == "Mesh Generation"
    assert not filter_run["torch_after_load"]  # torch only when training


def test_filter_output_with_aux_lines(filter_run):
    first = filter_run["first"]
    assert first["class"] == "vtkStructuredGrid"
    assert first["extent"] == [0, 40, 0, 20, 0, 0] and first["points"] == 41 * 21
    assert filter_run["whole_extent"] == [0, 40, 0, 20, 0, 0]
    for name in ("MaxIncludedAngle", "MinIncludedAngle", "ScaledJacobian", "Folded"):
        assert name in first["cell_arrays"]
    assert first["method"] == "pinn" and first["trained"] == 1
    low, high, count = filter_run["progress"]
    assert low == 0.0 and high == 1.0 and count >= 3


def test_grid_size_change_trains_for_the_new_size_and_keeps_the_first(filter_run):
    resized = filter_run["resized"]
    assert resized["extent"] == [0, 60, 0, 30, 0, 0] and resized["points"] == 61 * 31
    assert resized["trained"] == 1 and resized["training_count"] == 2
    back = filter_run["back"]
    assert back["trained"] == 0 and back["training_count"] == 2
    assert filter_run["back_max_diff"] == 0.0
    assert filter_run["back_seconds"] < filter_run["first_seconds"]


def test_aux_lines_as_several_inputs(filter_run):
    assert filter_run["two_inputs"]["trained"] == 1
    assert filter_run["two_inputs_max_diff"] < 1e-9  # same lines, same seed: same grid


def test_boundary_and_aux_lines_selected_together(filter_run):
    # the GUI connects every selected source to Input: the closed one is the boundary
    assert filter_run["both_on_input"]["trained"] == 1
    assert filter_run["both_on_input_max_diff"] < 1e-9


def test_bad_boundary_gives_empty_output_and_one_message(filter_run):
    assert filter_run["bad"] == {"points": 0, "class": "vtkStructuredGrid"}
    messages = [ln for ln in filter_run["bad_vtk_text"].splitlines() if ln.strip()]
    assert messages == [
        "PINN Structured Mesh: boundary input: holds 2 separate curves; the "
        "boundary must be one closed polyline"
    ]
    assert "Traceback" not in filter_run["bad_stderr"]
    recovered = filter_run["recovered"]  # ParaView goes on
    assert recovered["points"] == 41 * 21 and recovered["trained"] == 1


def test_load_plugin_and_classical_method_without_torch(checkout, tmp_path):
    empty = tmp_path / "no_plugins"
    empty.mkdir()
    result = run_pvpython(
        checkout,
        "check_load_plugin.py",
        str(checkout / "plugin" / "pinn_mesh_plugin.py"),
        str(checkout / "example_data"),
        PINN_PV_PLUGIN_PATH=str(empty),
    )
    assert not result["before_load"] and result["after_load"]
    assert result["old_names_after_load"] == [True, True]  # defined in the session it loads in
    assert result["property_order"] == [  # no "Reload Python Module" button for users
        "Input",
        "AuxiliaryLines",
        "Field",
        "Method",
        "GridSize",
        "Preset",
        "TimeLimit",
        "AdamEpochs",
        "PaperAdamEpochs",
        "LBFGSIterations",
        "PaperLBFGSIterations",
        "HiddenLayers",
        "Neurons",
        "Lambda2",
        "PaperLambda2",
        "Seed",
        "CornerIndices",
        "Objective",
        "Topology",
        "FarFieldRadius",
        "WallSpacing",
        "FirstEdgeSpacing",
        "OrthogonalSides",
        "PatchNames",
        "Model",
        "FieldArray",
        "AdaptStrength",
    ]
    assert result["methods"] == ["pinn", "mgnet", "tfi", "elliptic"]
    # the network settings behind the gear; "NACA", not "N ACA"
    assert result["advanced"] == [
        "AdamEpochs",
        "HiddenLayers",
        "LBFGSIterations",
        "Neurons",
        "PaperAdamEpochs",
        "PaperLBFGSIterations",
        "Seed",
    ]
    # the panel shows what runs: the chosen preset's field, which is used
    assert result["presets"] == [[5000, 500, 10.0], [5000, 90, 10.0], [7, 120, 30.0]]
    shown_under = {
        key: [value for prop, value in pairs if prop == "Preset"]
        for key, pairs in result["preset_decorators"].items()
    }
    assert shown_under == {
        "AdamEpochs": ["0"],
        "PaperAdamEpochs": ["1"],
        "Lambda2": ["0"],
        "PaperLambda2": ["1"],
    }
    assert result["naca_label"] == "NACA"
    # "?" help for every proxy; the grid shows its cells from the first show
    for name, (short, long) in result["help"].items():
        assert 20 < len(short) < len(long), name
    # its help page for the GUI (docs/paraview_gui.md point 4): one per proxy, each named by a
    # (group, proxy name) ParaView knows, the 3 filters and the Airfoil source among them
    assert len(result["help_pages"]) == 12 and result["help_pages_unknown"] == []
    cgns = [page for page in result["help_pages"] if "CGNS" in page]  # one, Save Data's
    assert cgns == ["writers.CGNSPINNMeshWriter.html"]
    for name in (
        "PINNStructuredMesh",
        "PINNStructuredMeshMultiBlock",
        "PINNStructuredMeshHexahedral",
    ):
        assert f"filters.{name}.html" in result["help_pages"]
    assert "sources.PINNAirfoilSource.html" in result["help_pages"]
    assert result["help_registered"] == []  # pvpython: no help engine
    assert result["representation"] == "Surface With Edges"
    assert result["aux_optional"]
    assert result["grid"] == {
        "class": "vtkStructuredGrid",
        "extent": [0, 30, 0, 15, 0, 0],
        "max_angle": True,
        "method": "elliptic",
    }
    assert not result["torch_after_load"] and not result["torch_at_end"]


def test_plugin_folder_holds_only_the_plugin():
    assert sorted(p.name for p in (ROOT / "plugin").iterdir() if p.name != "__pycache__") == [
        "pinn_mesh_plugin.py"
    ]


def test_save_data_offers_the_solver_formats_and_writes_them(checkout, tmp_path):
    """File > Save Data: the PINN Mesh file types for the filter's output, each read back
    by the readers of tests/export_checks.py against ParaView's own .vts of the grid."""
    from export_checks import (
        check_cgns,
        check_gmsh,
        check_openfoam,
        check_plot3d,
        check_su2,
        read_vts,
    )

    helper = ROOT / ".venv" / "bin" / "python"  # CGNS: ParaView's HDF5 clashes with h5py's
    result = run_pvpython(
        checkout,
        "check_writers.py",
        str(checkout / "example_data"),
        str(tmp_path),
        PINN_MESH_PYTHON=str(helper),
    )
    assert result["patch_names"] == ["wall", "right", "wall", "inlet"]
    assert {"i", "j"} <= set(result["point_arrays"])
    assert sorted(result["file_types"]) == [  # short: Save Data's list shows them whole
        "PINN Mesh CGNS(*.cgns )",
        "PINN Mesh Gmsh(*.msh )",
        "PINN Mesh OpenFOAM(*.foam )",
        "PINN Mesh PLOT3D(*.xyz )",
        "PINN Mesh SU2(*.su2 )",
    ]
    messages = dict(result["errors"])
    case = messages.pop("case.foam")  # Save Data as OpenFOAM says where the case went
    for name, text in messages.items():  # every format says what it wrote, in one line
        assert text.startswith("PINN Mesh writer: wrote ") and "\n" not in text, (name, text)
        assert text.split(" (")[0].endswith(name), (name, text)
    assert "PINN Mesh writer: wrote the OpenFOAM case" in case and case.count("\n") == 0, case
    assert case.endswith("open case.foam)"), case
    reference = read_vts(tmp_path / "grid.vts")
    check_plot3d(tmp_path / "grid.xyz", reference, None)
    check_plot3d(tmp_path / "grid3.xyz", reference, 0.25)
    check_su2(tmp_path / "grid.su2", reference)
    check_gmsh(tmp_path / "grid.msh", reference, None)
    check_gmsh(tmp_path / "grid3.msh", reference, 0.25)
    check_cgns(tmp_path / "grid.cgns", reference, None)
    check_cgns(tmp_path / "grid3.cgns", reference, 0.25)
    assert result["cgns_writer"] == "CGNSPINNMeshWriter" and result["is_three_d"] == 0
    assert result["is_three_d_unread"] == [0]  # the writer dialog shows Extrude Thickness
    check_cgns(tmp_path / "saved.cgns", reference, None)  # Save Data's .cgns: ZoneBC, families
    assert [ln for ln in result["no_helper"]["vtk"].splitlines() if ln.strip()] == [
        "PINN Mesh writer: cgns: writing CGNS (h5py) needs the writer's helper Python: "
        "ParaView's HDF5 clashes with pip's h5py, so the writer runs the checkout's .venv "
        "Python: make it with bash scripts/setup.sh (or set PINN_MESH_PYTHON to a Python "
        "with h5py)"
    ]
    assert not result["no_helper"]["traceback"] and "none.cgns" not in result["files"]
    check_openfoam(tmp_path / "case", reference)  # last: skips when checkMesh is missing


def test_airfoil_reader_source_and_topology(checkout):
    result = run_pvpython(checkout, "check_airfoil.py", str(checkout / "example_data"))
    assert result["reader_points"] == 201
    o, c = result["o_grid"], result["c_grid"]
    assert o["extent"] == [0, 80, 0, 24, 0, 0] and o["topology"] == "o"
    assert o["patches"] == ["wall", "seam", "farfield", "seam"]
    assert o["seam_gap"] == 0.0 and o["folded"] == 0
    assert abs(o["far_radius"] - 10.0) < 1e-2
    assert c["topology"] == "c" and c["folded"] == 0
    assert c["patches"] == ["wall", "outflow", "farfield", "outflow"]
    assert result["opened_with"] == "PINNAirfoilReader"


def test_the_filters_model_property_meshes_by_a_family_model(checkout, tmp_path):
    """SPEC 16's Model file property: the grid of a family model, its field data saying so."""
    result = run_pvpython(checkout, "check_family.py", str(tmp_path))
    assert result["points"] == 21 * 11 and result["result"] == "family"
    assert result["model"] == result["expected_model"]


def test_blockmeshdict_reader(checkout):
    """ParaView's reader of a blockMeshDict: the bend's three blocks and their cells as the
    command line's, SPEC 11's arrays, and File > Open picks the reader by the file's name."""
    result = run_pvpython(checkout, "check_blockmesh.py", str(checkout / "example_data"))
    assert result["bend"]["blocks"] == 3 and result["bend"]["cells"] == 12096
    for name in ("MaxIncludedAngle", "MinIncludedAngle", "ScaledJacobian", "Folded"):
        assert name in result["bend"]["arrays"]
    assert result["opened_with"] == "PINNBlockMeshDictReader"


def test_boundary_layer_panel_fields(filter_run):
    layer = filter_run["layer"]
    assert {"FirstEdgeSpacing", "OrthogonalSides"} <= set(layer["properties"])
    assert all(abs(v / 0.01 - 1) < 0.1 for v in layer["first_edge"])
    assert layer["angle"] <= 2.0


def _side_nodes(points: np.ndarray) -> list[np.ndarray]:
    """The (x, y) nodes of a block's four sides: bottom, top, left, right."""
    xy = points[..., :2]
    return [xy[0], xy[-1], xy[:, 0], xy[:, -1]]


def test_the_old_names_still_make_the_filters_and_stay_out_of_the_menus(checkout):
    """PINNMultiBlockMesh and PINNHexahedralMesh, the names before the filters were
    labelled PINN Structured Mesh (Multi-Block) and (Hexahedral), in scripts and saved
    states: the same filter class and the same grid, without the menus' hint."""
    result = run_pvpython(checkout, "check_old_names.py", str(checkout / "example_data"))
    for old, label, nodes in (
        ("PINNMultiBlockMesh", "PINN Multi-Block Mesh", 390),
        ("PINNHexahedralMesh", "PINN Hexahedral Mesh", 5 * 4 * 3),
    ):
        run = result[old]
        assert run["label"] == label and run["class"] == run["new_class"]
        assert run["in_menu"] == [False, True]  # the new name in the menus, the old one not
        assert run["nodes"] == nodes and run["same_grid"]


def test_multiblock_filter_on_the_step(checkout):
    """PINN Structured Mesh (Multi-Block): the step's four blocks as the command line
    makes them, a side shared node for node, the quality arrays, one line for an edge that
    ends nowhere."""
    from helpers import run_blocks
    from scipy.spatial.distance import cdist

    from pinn_engine.settings import make_settings

    result = run_pvpython(checkout, "check_multiblock.py", str(checkout / "example_data"))
    assert result["label"] == "PINN Structured Mesh (Multi-Block)"
    assert result["menu_category"] == "Mesh Generation"
    assert 20 < len(result["help"][0]) < len(result["help"][1])
    assert set(result["properties"]) == {
        "Input",
        "BlockEdges",
        "AuxiliaryLines",
        "Blocking",
        "Method",
        "CellSize",
        "CellCounts",
        "Gradings",
        "Interfaces",
        "PatchNames",
        "FirstEdgeSpacing",
        "OrthogonalPatches",
        "Model",
        "TimeLimit",
        "Field",
        "FieldArray",
        "AdaptStrength",
    }
    assert result["methods"] == ["tfi", "elliptic", "pinn"]
    assert result["interfaces"] == ["free", "fixed"]
    assert result["class"] == "vtkMultiBlockDataSet" and result["progress"] == [0.0, 1.0]
    told = [ln for ln in result["together_messages"].splitlines() if ln.strip()]
    assert len(told) == 2 and told[0].startswith(
        "PINN Structured Mesh (Multi-Block): pinn 4 blocks, "
    )
    assert told[1].startswith("PINN Structured Mesh (Multi-Block): chose the ")  # the choice
    assert result["file_types"] == [  # Save Data offers the solver formats for the blocks
        "PINN Mesh CGNS(*.cgns )",
        "PINN Mesh Gmsh(*.msh )",
        "PINN Mesh OpenFOAM(*.foam )",
        "PINN Mesh PLOT3D(*.xyz )",
        "PINN Mesh SU2(*.su2 )",
    ]
    assert "NELEM= 1748" in result["su2"] and "MARKER_TAG= boundary" in result["su2"]
    assert re.search(r"boundary\s*\{\s*type\s+patch;", result["foam_boundary"])
    assert "wrote the OpenFOAM case" in result["save_messages"]
    boundary, edges = ROOT / "example_data" / "step.vtp", ROOT / "example_data" / "step_blocks.vtp"
    for key, method, interfaces in (
        ("together", "pinn", "free"),
        ("apart_tfi", "tfi", "fixed"),
    ):
        blocks = result[key]
        settings = make_settings(method, cell_size=0.1, interfaces=interfaces)
        expected = run_blocks(settings, boundary, [edges]).grids
        assert [b["name"] for b in blocks] == ["block0", "block1", "block2", "block3"]
        for block, grid in zip(blocks, expected):
            assert block["class"] == "vtkStructuredGrid" and block["folded"] == 0
            assert block["cell_arrays"] == [
                "MaxIncludedAngle",
                "MinIncludedAngle",
                "ScaledJacobian",
                "Folded",
            ]
            assert np.array_equal(np.array(block["points"])[..., :2], grid), key
    points = [np.array(b["points"]) for b in result["together"]]
    whole_sides = 0
    for a, pa in enumerate(points):
        for b, pb in enumerate(points):
            if a == b:
                continue
            theirs = np.concatenate(_side_nodes(pb))
            for side in _side_nodes(pa):
                distance = cdist(side, theirs).min(axis=1)
                assert np.array_equal(distance < 1e-9, distance == 0.0)  # equal or apart
                whole_sides += bool(np.all(distance == 0.0))
    assert whole_sides >= 2  # a side shared whole, seen from both blocks
    messages = [ln for ln in result["bad_vtk_text"].splitlines() if ln.strip()]
    assert messages == [
        "PINN Structured Mesh (Multi-Block): block edges input line 0: ends nowhere at (1, 0.6): "
        "each end must lie on the boundary, a hole or another block edge (within 0.001 of the "
        "diagonal)"
    ]
    assert result["bad_blocks"] == 0 and "Traceback" not in result["bad_stderr"]
    assert result["recovered_blocks"] == 4
    wall = result["walls"]["cylinder"]  # the spacing from the panel: 0.005 within 10 %
    assert abs(wall["first_edge"]["min"] / 0.005 - 1) <= 0.1
    assert abs(wall["first_edge"]["max"] / 0.005 - 1) <= 0.1
    assert wall["max_angle_deviation"] <= 2.0
    assert result["piece_names"] == ["boundary", "cylinder"]
    distance = result["aux_line_distance"]["auxiliary lines input line 0"]
    expected = run_blocks(
        make_settings("elliptic", cell_size=0.1),
        ROOT / "example_data" / "lshape.vtp",
        [ROOT / "example_data" / "lshape_blocks.vtp"],
        aux=[ROOT / "example_data" / "lshape_aux.vtp"],
    ).report["aux_line_distance"]
    assert distance == pytest.approx(list(expected.values())[0], rel=1e-9)
    assert result["blockings"] == ["Manual", "Automatic"]
    assert result["auto_blocks"] == 2 and result["auto_edges"] == 1  # the L's one cut


def test_hexahedral_filter_on_the_bend(checkout):
    """PINN Structured Mesh (Hexahedral): the bend's grid as the command line makes it
    (the same nodes, arrays and field data), for every method; one line for a surface
    without FaceId, and ParaView goes on."""
    from pinn_engine.kinds.hexa.mesh import mesh_surface
    from pinn_engine.settings import HEXA_METHODS, make_settings

    result = run_pvpython(checkout, "check_hexa.py", str(checkout / "example_data"))
    assert result["label"] == "PINN Structured Mesh (Hexahedral)"
    assert result["menu_category"] == "Mesh Generation"
    assert result["representation"] == "Surface With Edges"
    assert 20 < len(result["help"][0]) < len(result["help"][1])
    assert set(result["properties"]) == {
        "Input",
        "Method",
        "GridSize",
        "TimeLimit",
        "FaceAngle",
        "PatchNames",
        "FirstEdgeSpacing",
        "OrthogonalPatches",
    }
    assert result["methods"] == list(HEXA_METHODS)
    assert result["progress"] == [0.0, 1.0]
    told = [ln for ln in result["messages"].splitlines() if ln.strip()]  # the summary lines
    assert told[0].startswith("PINN Structured Mesh (Hexahedral): tfi 11x9x7 hexa")
    assert len(told) == 3 and "faces face0=jmin face1=jmax face2=imax face3=imin" in told[2]
    assert "PINN Structured Mesh (Hexahedral): face grids" in result["progress_texts"]
    size = (11, 9, 7)
    for method in ("tfi", "elliptic", "pinn"):
        grid = result[method]
        assert grid["class"] == "vtkStructuredGrid"
        assert grid["extent"] == [0, 10, 0, 8, 0, 6]
        assert grid["cell_arrays"] == [
            "MaxIncludedAngle",
            "MinIncludedAngle",
            "ScaledJacobian",
            "Folded",
        ]
        assert grid["folded"] == 0 and grid["min_scaled_jacobian"] > 0.5  # right-handed
        assert grid["method"] == method and grid["report"]["size"] == list(size)
        assert grid["patches"] == ["imin", "imax", "jmin", "jmax", "kmin", "kmax"]
        expected = mesh_surface(
            str(ROOT / "example_data" / "hexa_bend.vtp"), make_settings(method, size=size)
        )
        points = np.array(grid["points"]).transpose(2, 1, 0, 3)  # (nk, nj, ni) -> (ni, nj, nk)
        np.testing.assert_allclose(points, expected.grid, atol=1e-9)
    spaced = result["spaced"]  # Patch Names and First Edge Spacing: the command line's grid
    assert spaced["patches"] == ["inlet", "imax", "jmin", "jmax", "floor", "kmax"]
    assert spaced["types"] == ["inflow", "patch", "patch", "patch", "wall", "patch"]
    expected = mesh_surface(
        str(ROOT / "example_data" / "hexa_bend.vtp"),
        make_settings("tfi", size=size, spacing={"kmin": 0.01}),
    )
    points = np.array(spaced["points"]).transpose(2, 1, 0, 3)
    np.testing.assert_allclose(points, expected.grid, atol=1e-9)
    assert result["orthogonal_tfi_points"] == 0
    assert [ln for ln in result["orthogonal_tfi_text"].splitlines() if ln.strip()] == [
        "PINN Structured Mesh (Hexahedral): Orthogonal Patches kmin: use Method elliptic or pinn "
        "(tfi's "
        "grid lines cannot turn to a patch's normal)"
    ]
    messages = [ln for ln in result["bad_vtk_text"].splitlines() if ln.strip()]
    assert messages == [
        "PINN Structured Mesh (Hexahedral): input: found 1 faces at edges sharper than 40 degrees; "
        "a six-faced domain needs 6 (try another Face Angle or a FaceId cell array)"
    ]
    assert result["bad_points"] == 0 and "Traceback" not in result["bad_stderr"]
    assert result["recovered_points"] == 11 * 9 * 7
    stl = result["stl"]  # the STL's faces found at 40 degrees, named by FaceId
    assert stl["patches"] == ["outlet", "imax", "inner", "jmax", "kmin", "kmax"]
    assert "faces face0=jmin face1=jmax face2=imax face3=imin" in result["stl_told"]
    assert result["curve_points"] == 0
    assert (
        "holds no surface triangles: a 2D curve is meshed by PINN Structured Mesh"
        in (result["curve_text"])
    )
    assert result["cgns_writer"] == "CGNSPINNMeshWriter" and result["is_three_d"] == 1


def test_a_readers_solution_on_the_field_input_adapts_the_grid(checkout, tmp_path):
    """SPEC 14 in ParaView: a reader's output on the Field port, its array picked."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "adapt"))
    from test_adapt import front, image, write

    field = write(image(front, (-0.3, -0.4), (4.4, 2.5)), tmp_path / "field.vti")
    wavy = str(checkout / "example_data" / "wavy.vtp")
    result = run_pvpython(checkout, "check_field.py", wavy, field, "p", "21", "11")
    assert "p" in result["arrays"] and result["points"] == 21 * 11
    assert result["array"] == "p" and result["strength"] == 10.0
    assert result["error"]["after"] < result["error"]["before"]


@pytest.mark.skipif(
    shutil.which("simpleFoam") is None,
    reason="OpenFOAM's simpleFoam is missing (apt-get install openfoam; .ci/run installs it)",
)
def test_an_openfoam_result_on_the_field_input_meshes_the_same_domain_guarded(checkout, tmp_path):
    """SPEC 14 from a solver: the bump channel solved by simpleFoam (its example's run.sh),
    its .foam file opened in ParaView's OpenFOAM reader and connected to the Field port: the
    solution's arrays are offered, the grid keeps its node count and is adapted within the
    guard or kept (the velocity's gradient does not say where a parabola's error is)."""
    case = tmp_path / "bump"
    env = foam_env()
    command = Path(sys.executable).with_name("pinn-mesh")
    if command.exists():
        env["PINN_MESH"] = str(command)
    run = [str(checkout / "examples" / "openfoam_bump" / "run.sh"), str(case)]
    subprocess.run(["bash", *run], env=env, check=True, capture_output=True, timeout=240)
    channel = str(checkout / "example_data" / "bump_channel.vtp")
    result = run_pvpython(
        checkout, "check_field.py", channel, str(case / "bump.foam"), "U", "41", "21"
    )
    assert {"U", "p"} <= set(result["arrays"]) and result["points"] == 41 * 21
    assert "CasePath" not in result["arrays"]  # the reader's field data is no field to adapt to
    assert result["array"] == "U" and result["folded"]["after"] == 0
    assert result["worst"]["after"] <= result["worst"]["limit"]
    assert result["error"]["after"] <= result["error"]["before"]
