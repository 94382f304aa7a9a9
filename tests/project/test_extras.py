"""The install's optional parts (pyproject's extras, docs/install.md): each part missing its
extra says so in one line naming the extra, and the test extra pulls every extra."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest
from helpers import EXAMPLES, ROOT

tomllib = pytest.importorskip("tomllib")

EXTRAS = {"batch": ("distributed", "dask", "bokeh"), "cgns": ("h5py",), "paper": ("sklearn",)}


def run_without(modules: tuple[str, ...], code: str, cwd, **env) -> subprocess.CompletedProcess:
    """``code`` in a fresh Python where importing any of ``modules`` fails, as where the
    extra that installs them is not installed."""
    hide = f"import sys; sys.modules.update(dict.fromkeys({list(modules)!r}))"
    return subprocess.run(
        [sys.executable, "-c", f"{hide}\n{code}"],
        cwd=cwd,
        env={**os.environ, "PYTHONPATH": str(ROOT), **env},
        capture_output=True,
        text=True,
        timeout=120,
    )


def command(*argv) -> str:
    return f"from pinn_engine.command import main; sys.exit(main({[str(a) for a in argv]!r}))"


def test_the_test_extra_pulls_every_extra():
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"][
        "optional-dependencies"
    ]
    assert set(EXTRAS) <= set(extras)
    assert "pinn-mesh[all]" in extras["test"]
    assert extras["all"] == [f"pinn-mesh[{','.join(sorted(EXTRAS))}]"]


def test_batch_without_its_extra_is_one_line(tmp_path):
    manifest = tmp_path / "m.csv"
    manifest.write_text(f"name,input,aux,options\na,{EXAMPLES / 'fig2.vtp'},,--method tfi\n")
    proc = run_without(EXTRAS["batch"], command("batch", manifest, "-o", tmp_path / "o"), tmp_path)
    assert proc.returncode == 2
    assert proc.stderr == (
        "pinn-mesh batch: error: batch meshing (Dask) needs the batch extra: "
        "pip install 'pinn-mesh[batch]'\n"
    )


@pytest.mark.slow  # a fresh Python that imports torch and VTK
def test_cgns_without_its_extra_is_one_line(tmp_path):
    out = tmp_path / "g.cgns"
    argv = (EXAMPLES / "fig2.vtp", "--method", "tfi", "--size", "11", "6", "-o", out)
    proc = run_without(EXTRAS["cgns"], command(*argv), tmp_path, PINN_MESH_PYTHON="/nowhere")
    assert proc.returncode == 2 and not out.exists()
    assert proc.stderr.endswith(
        "cgns: writing CGNS (h5py) needs the cgns extra: pip install 'pinn-mesh[cgns]'\n"
    )
    assert proc.stderr.count("\n") == 1


@pytest.mark.slow  # a fresh Python that imports torch and VTK
def test_the_tree_boundary_fit_without_its_extra_is_one_line(tmp_path):
    out = tmp_path / "g.vts"
    fit = ("--boundary-mode", "penalty", "--boundary-fit", "tree", "--epochs", "0", "--lbfgs", "1")
    argv = (EXAMPLES / "fig2.vtp", *fit, "--size", "11", "6", "-o", out)
    proc = run_without(EXTRAS["paper"], command(*argv, "--quiet"), tmp_path)
    assert proc.returncode == 2 and not out.exists()
    assert proc.stderr == (
        "pinn-mesh: error: the tree boundary fit (the paper preset's) needs the paper extra: "
        "pip install 'pinn-mesh[paper]'\n"
    )


@pytest.mark.slow  # a fresh Python that imports torch and VTK
def test_the_core_routes_import_no_extra(tmp_path):
    hidden = tuple(m for modules in EXTRAS.values() for m in modules)
    code = (
        "import pyvista as pv, pinn_engine, json\n"
        f"b = pv.read({str(EXAMPLES / 'fig2.vtp')!r})\n"
        "g = b.pinn_mesh(size=(11, 6), method='elliptic')\n"
        "print(json.dumps(pinn_engine.report(g)['size']))\n"
        f"pinn_engine.save(g, {str(tmp_path / 'g.su2')!r})"
    )
    proc = run_without(hidden, code, tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout) == [11, 6] and (tmp_path / "g.su2").is_file()
