"""The built wheel: the engine and its licence only, installable, and its command meshes.

Builds the wheel for other machines as docs/install.md says (``PINN_MESH_PORTABLE=1``; pip
with no build isolation: setuptools from this environment), installs it with ``--no-deps``
into a fresh venv that borrows this environment's dependencies through a path entry (their
``.pth`` files, such as the editable install of this checkout, are not run), and meshes an
example from a folder outside the checkout with no compiler on the PATH, as on a machine
that has none.
"""

from __future__ import annotations

import os
import site
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
from helpers import EXAMPLES, ROOT, has_compiler

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> tuple[Path, str]:
    out = tmp_path_factory.mktemp("wheel")
    env = dict(os.environ, PINN_MESH_PORTABLE="1")
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "wheel",
            "--no-deps",
            "--no-build-isolation",
            "-w",
            str(out),
            str(ROOT),
        ],
        capture_output=True,
        text=True,
        timeout=900,  # the kernels' build may take COMPILE_TIMEOUT
        env=env,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    return next(out.glob("pinn_mesh-*.whl")), proc.stdout + proc.stderr


def test_wheel_holds_the_engine_and_licence_only(wheel):
    path, log = wheel
    assert "deprecat" not in log.lower(), log[-3000:]
    names = zipfile.ZipFile(path).namelist()
    assert "pinn_engine/routes/cli/__main__.py" in names
    assert "pinn_engine/neural/jet/kernels.cpp" in names
    built = [n for n in names if n.startswith("pinn_engine/neural/jet/jet_kernels-")]
    assert len(built) == (1 if has_compiler else 0)  # compiled by the install, not a first run
    assert any(n.endswith(".dist-info/licenses/LICENSE") for n in names)
    assert not [n for n in names if n.startswith(("experiments/", "tests/", "benchmarks/"))]
    metadata = zipfile.ZipFile(path).read(next(n for n in names if n.endswith("METADATA")))
    assert b"License-Expression: MIT" in metadata


def test_installed_wheel_meshes_an_example(wheel, tmp_path):
    path, _ = wheel
    env_dir = tmp_path / "env"
    subprocess.run([sys.executable, "-m", "venv", str(env_dir)], check=True, timeout=120)
    python = env_dir / "bin" / "python"
    subprocess.run(
        [str(python), "-m", "pip", "install", "--quiet", "--no-deps", "--no-index", str(path)],
        check=True,
        timeout=300,
    )
    fresh_site = subprocess.run(
        [str(python), "-c", "import site; print(site.getsitepackages()[0])"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    (Path(fresh_site.strip()) / "borrowed_deps.pth").write_text(
        "\n".join(site.getsitepackages()) + "\n"
    )
    work = tmp_path / "work"
    work.mkdir()
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "CXX")}
    env["PINN_MESH_CACHE"] = str(tmp_path / "cache")
    env["PATH"] = str(env_dir / "bin")  # no compiler: the wheel's own library must serve
    proc = subprocess.run(
        [
            str(env_dir / "bin" / "pinn-mesh"),
            str(EXAMPLES / "fig2.vtp"),
            "--aux",
            str(EXAMPLES / "fig2_aux.vtp"),
            *("--objective", "winslow", "--epochs", "100", "--lbfgs", "20"),  # a network trains
            "-o",
            "grid.vts",
        ],
        cwd=work,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert (work / "grid.vts").stat().st_size > 10_000
    if has_compiler:  # the wheel's own library ran: nothing compiled, nothing said about it
        assert not (tmp_path / "cache").exists()
        assert "compiler" not in proc.stderr, proc.stderr
    where = subprocess.run(
        [
            str(python),
            "-c",
            "import pinn_engine; print(pinn_engine.__file__, pinn_engine.__version__)",
        ],
        cwd=work,
        env=env,
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    import tomllib

    version = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    file, found = where.split()
    assert file.startswith(str(env_dir)) and found == version  # the wheel's copy and number
