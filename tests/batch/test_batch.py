"""`pinn-mesh batch` (SPEC 12): manifest errors, per-case failures, the single-run grids, the
rerun, a killed worker and a separately started scheduler and worker."""

from __future__ import annotations

import csv
import importlib
import io
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import dask
import numpy as np
import pytest
import pyvista as pv
from helpers import EXAMPLES

from pinn_engine.batch import mesh_many, read_manifest
from pinn_engine.batch.cluster import connect
from pinn_engine.batch.progress import Bar
from pinn_engine.command import main

TFI = "--method tfi --size 11 7"
CASES = (  # name, input, aux, options: every status, one quick pinn among them
    ("wavy", "wavy.vtp", "wavy_aux.vtp", TFI),
    ("fig2", "fig2.vtp", "", "--method elliptic --size 11 7"),
    ("pinn", "concave.vtp", "concave_aux.vtp", "--size 11 7 --lbfgs 5 --epochs 50"),
    ("naca", "", "", "--naca 0012 --topology o --method elliptic --size 33 17 --format su2"),
    ("blocks", "lshape.vtp", "", "--blocks lshape_blocks.vtp --cell-size 0.2"),
    ("box", "hexa_bend.stl", "", "--size 7 6 5 --method tfi --patch imin=inner:wall --format su2"),
    ("stopped", "wavy.vtp", "", "--size 11 7 --epochs 100000 --time-limit 0.2"),
    ("missing", "nothere.vtp", "", TFI),
    ("broken", "broken.vtp", "", TFI),
)
STATUS = {"missing": "error", "broken": "error", "stopped": "warning"}
SLOW = "--size 21 11 --epochs 4000 --lbfgs 0"  # about 8 s of training in a worker
BATCH_TIMEOUT = 300  # seconds a test waits for a batch on the busy 2-core machine


def manifest(folder: Path, rows=CASES) -> Path:
    """A manifest in ``folder`` beside copies of the example inputs and a broken file."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "hexa_bend.stl").write_bytes((EXAMPLES / "hexa_bend.stl").read_bytes())
    for name in ("wavy", "fig2", "concave", "lshape"):
        for suffix in (".vtp", "_aux.vtp", "_blocks.vtp"):
            if (EXAMPLES / f"{name}{suffix}").exists():
                (folder / f"{name}{suffix}").write_bytes(
                    (EXAMPLES / f"{name}{suffix}").read_bytes()
                )
    (folder / "broken.vtp").write_bytes(b"<VTKFile type='PolyData'>\0\0 not a file")
    path = folder / "cases.csv"
    with path.open("w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(("name", "input", "aux", "options"))
        writer.writerows(rows)
    return path


def summary(outdir: Path) -> dict[str, dict]:
    """The summary's rows by name, without the times (which differ between runs)."""
    with (outdir / "summary.csv").open() as f:
        rows = list(csv.DictReader(f))
    return {r["name"]: {k: v for k, v in r.items() if k not in ("name", "seconds")} for r in rows}


def bad_manifest(tmp_path, capsys, text: str) -> str:
    path = tmp_path / "bad.csv"
    path.write_text(text)
    assert main(["batch", str(path), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and not (tmp_path / "out").exists()
    return err


@pytest.mark.parametrize(
    "text, words",
    [
        ("wavy,wavy.vtp,,\n", "lacks the column name, input"),
        ("name,aux,options\nwavy,,\n", "lacks the column input"),
        ("name,input,aux,options\n", "holds no case"),
        (f"name,input,aux,options\na,x.vtp,,{TFI}\nb,x.vtp,,--size 11\n", "row 3"),
        ("name,input,aux,options\na,x.vtp,,--frobnicate\n", "row 2: bad options"),
        (
            "name,input,aux,options\na,x.vtp,,--sise 41 21\n",
            "row 2: bad options '--sise 41 21': unknown option --sise; did you mean --size?",
        ),
        ("name,input,aux,options\na,x.vtp,,--method magic\n", "invalid choice"),
        ("name,input,aux,options\na,x.vtp,,--seed 'open\n", "row 2: bad options"),
        ("name,input,aux,options\na,x.vtp,,--help\n", "row 2: bad options"),
        ("name,input,aux,options\na,x.vtp,,-o a.vts\n", "drop -o"),
        ("name,input,aux,options\na,x.vtp,,y.vtp\n", "the input column names the boundary"),
        (f"name,input,aux,options\na,x.vtp,,{TFI}\na,y.vtp,,{TFI}\n", "row 3: name 'a'"),
        (f"name,input,aux,options\n../a,x.vtp,,{TFI}\n", "is not a file name"),
    ],
)
def test_a_bad_manifest_exits_2_with_one_line_naming_the_row(tmp_path, capsys, text, words):
    assert words in bad_manifest(tmp_path, capsys, text)


def test_every_rows_options_are_checked_before_any_case_runs(tmp_path, capsys):
    """The bad row is the last: nothing was meshed for the good rows before it."""
    rows = "".join(f"c{k},{EXAMPLES / 'wavy.vtp'},,{TFI}\n" for k in range(3))
    err = bad_manifest(tmp_path, capsys, f"name,input,aux,options\n{rows}c3,x.vtp,,--size\n")
    assert "row 5" in err


def test_manifest_paths_are_relative_to_its_folder(tmp_path):
    path = manifest(tmp_path / "in")
    cases = {c.name: c.args for c in read_manifest(path)}
    assert cases["wavy"].boundary == str(tmp_path / "in" / "wavy.vtp")
    assert cases["wavy"].aux == [str(tmp_path / "in" / "wavy_aux.vtp")]
    assert cases["naca"].boundary is None and cases["naca"].naca == "0012"


@pytest.fixture(scope="module")
def client():
    """A local cluster of two worker processes, which have imported the engine already."""
    with connect(workers=2) as c:
        c.run(importlib.import_module, "pinn_engine.batch.task")
        yield c


@pytest.mark.slow
def test_each_case_is_the_single_run_and_failures_stay_per_case(client, tmp_path, capsys):
    path = manifest(tmp_path / "in")
    out = tmp_path / "out"
    address = client.scheduler.address
    assert main(["batch", str(path), "-o", str(out), "--scheduler", address]) == 1
    err = capsys.readouterr().err
    assert "2 of 9 cases failed" in err and "[9/9] 2 failed" in err
    rows = summary(out)
    assert list(rows) == [c[0] for c in CASES]
    for name, row in rows.items():
        assert row["status"] == STATUS.get(name, "ok"), (name, row)
    assert rows["missing"]["message"].endswith("nothere.vtp: file not found")
    assert "broken.vtp" in rows["broken"]["message"]
    assert "time limit" in rows["stopped"]["message"]
    assert rows["wavy"]["cells"] == "60" and rows["naca"]["cells"] == "512"
    assert rows["box"]["cells"] == "120"  # a six-faced surface's hexahedra (6 x 5 x 4)
    assert sorted(p.name for p in out.iterdir()) == [
        "blocks", "blocks.vtm", "box.su2", "fig2.vts", "naca.su2", "pinn.vts", "stopped.vts",
        "summary.csv", "wavy.vts",
    ]  # fmt: skip
    single = tmp_path / "single_box.su2"
    assert main([str(path.parent / "hexa_bend.stl"), *CASES[5][3].split(), "-o", str(single)]) == 0
    assert (out / "box.su2").read_text() == single.read_text()
    for name, source, aux, options in CASES[:3]:  # the single-run command's grid, exactly
        single = tmp_path / f"single_{name}.vts"
        extra = ["--aux", str(path.parent / aux)] if aux else []
        argv = [str(path.parent / source), *extra, *options.split(), "-o", str(single)]
        assert main([*argv, "--quiet"]) == 0
        assert np.array_equal(pv.read(out / f"{name}.vts").points, pv.read(single).points)
    # a rerun skips what is done and redoes the failures; --force redoes everything
    before = {p.name: p.stat().st_mtime_ns for p in out.glob("*.vts")}
    (out / "fig2.vts").unlink()
    assert main(["batch", str(path), "-o", str(out), "--scheduler", address]) == 1
    assert "6 skipped" in capsys.readouterr().err
    after = {p.name: p.stat().st_mtime_ns for p in out.glob("*.vts")}
    assert {k for k in before if after[k] != before[k]} == {"fig2.vts"}
    assert summary(out) == rows
    assert main(["batch", str(path), "-o", str(out), "--scheduler", address, "--force"]) == 1
    again = {p.name: p.stat().st_mtime_ns for p in out.glob("*.vts")}
    assert all(again[k] != after[k] for k in after)
    assert not [p for p in out.iterdir() if p.name.startswith(".")]  # no temporary file left


@pytest.mark.slow
def test_mesh_many_returns_the_summary_and_exit_0_when_all_are_ok(client, tmp_path, capsys):
    records = [
        {"name": "a", "input": str(EXAMPLES / "wavy.vtp"), "options": TFI},
        {"name": "b", "input": str(EXAMPLES / "fig2.vtp"), "aux": [], "options": TFI},
    ]
    rows = mesh_many(records, client=client, outdir=tmp_path / "py")
    rows = rows.to_dict("records") if hasattr(rows, "to_dict") else rows
    assert [(r["name"], r["status"], r["cells"]) for r in rows] == [
        ("a", "ok", 60),
        ("b", "ok", 60),
    ]
    path = manifest(tmp_path / "in", [r for r in CASES if r[0] in ("wavy", "fig2")])
    address = client.scheduler.address
    assert main(["batch", str(path), "-o", str(tmp_path / "cli"), "--scheduler", address]) == 0
    assert "0 failed" in capsys.readouterr().out


@pytest.mark.slow
def test_a_killed_worker_costs_a_retry_and_the_others_finish(client, tmp_path):
    records = [{"name": "slow", "input": str(EXAMPLES / "wavy.vtp"), "options": SLOW}] + [
        {"name": f"tfi{k}", "input": str(EXAMPLES / "wavy.vtp"), "options": TFI} for k in range(3)
    ]
    got: dict = {}
    batch = threading.Thread(
        target=lambda: got.update(rows=mesh_many(records, client=client, outdir=tmp_path))
    )
    batch.start()
    deadline = time.monotonic() + BATCH_TIMEOUT
    worker = None
    while worker is None and time.monotonic() < deadline:
        for address, keys in client.processing().items():
            if any(str(k).startswith("pinn-mesh-slow-") for k in keys):
                worker = address
        time.sleep(0.1)
    time.sleep(2.0)  # well inside its training
    pid = client.run(os.getpid, workers=[worker])[worker]
    running = client.processing(workers=[worker])[worker]
    assert any(str(k).startswith("pinn-mesh-slow-") for k in running)  # still meshing it
    os.kill(pid, signal.SIGKILL)
    batch.join(BATCH_TIMEOUT)
    rows = got["rows"]
    rows = rows.to_dict("records") if hasattr(rows, "to_dict") else rows
    assert [r["status"] for r in rows] == ["ok"] * 4  # the slow case was run again
    with pytest.raises(ProcessLookupError):
        os.kill(pid, 0)
    assert (tmp_path / "slow.vts").exists()


def test_a_scheduler_that_cannot_be_reached_exits_2(tmp_path, capsys):
    path = manifest(tmp_path / "in", CASES[:1])
    address = f"tcp://127.0.0.1:{free_port()}"
    with dask.config.set({"distributed.comm.timeouts.connect": "1s"}):
        assert main(["batch", str(path), "-o", str(tmp_path / "out"), "--scheduler", address]) == 2
    err = capsys.readouterr().err
    assert err.startswith("pinn-mesh batch: error:") and err.count("\n") == 1


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.slow
def test_a_separate_scheduler_and_worker_give_the_local_summary(client, tmp_path):
    """``dask scheduler`` and ``dask worker`` started as on a cluster, then --scheduler."""
    command = str(Path(sys.executable).with_name("dask"))
    address = f"tcp://127.0.0.1:{free_port()}"
    local = ["--host", "127.0.0.1", "--no-dashboard"]
    scheduler = subprocess.Popen(
        [command, "scheduler", *local, "--port", address.rsplit(":", 1)[1]],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    worker = subprocess.Popen(
        [command, "worker", address, *local, "--nworkers", "1", "--nthreads", "1"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        path = manifest(tmp_path / "in", CASES[:2] + CASES[-2:])
        assert main(["batch", str(path), "-o", str(tmp_path / "far"), "--scheduler", address]) == 1
    finally:
        for process in (worker, scheduler):
            process.send_signal(signal.SIGINT)
            try:
                process.wait(30)
            except subprocess.TimeoutExpired:
                process.kill()
    here = client.scheduler.address
    assert main(["batch", str(path), "-o", str(tmp_path / "near"), "--scheduler", here]) == 1
    assert summary(tmp_path / "far") == summary(tmp_path / "near")
    assert len(summary(tmp_path / "far")) == 4


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_the_progress_line_counts_and_redraws_in_place_on_a_terminal():
    log = io.StringIO()
    bar = Bar(total=22, skipped=2, stream=log)
    for k in range(20):
        bar.update(failed=k % 10 == 0)
    bar.close()
    lines = log.getvalue().splitlines()  # off a terminal: a line a tenth of the cases
    assert len(lines) == 11 and lines[-1].startswith("[22/22] 2 failed, 2 skipped, ")
    assert lines[-1].endswith(" 0 s left")
    terminal = _Terminal()
    bar = Bar(total=3, stream=terminal)
    for text in ("a long first line", "short", "done"):
        bar.text = lambda text=text: text
        bar.update(failed=False)
    bar.close()  # each redraw covers the longer line before it
    assert terminal.getvalue() == "\ra long first line\rshort            \rdone \n"


@pytest.mark.slow  # a Dask cluster started and asked
def test_the_dashboard_address_is_printed_and_answers(tmp_path, capsys, monkeypatch):
    """With bokeh installed (the test extra), a local cluster serves Dask's dashboard (a
    batch above ``pool.SMALL_BATCH`` cases: none here); the command prints its address and
    the address answers."""
    from urllib.request import urlopen

    from pinn_engine.batch import pool
    from pinn_engine.batch.cluster import dashboard

    path = manifest(tmp_path / "in", CASES[:1])
    monkeypatch.setattr(pool, "SMALL_BATCH", 0)
    assert main(["batch", str(path), "-o", str(tmp_path / "out"), "--workers", "1"]) == 0
    printed = [x for x in capsys.readouterr().err.splitlines() if x.startswith("Dask dashboard")]
    assert len(printed) == 1 and printed[0].startswith("Dask dashboard: http://127.0.0.1:")
    with connect(1) as client:
        link = dashboard(client)
        with urlopen(link, timeout=30) as page:
            assert page.status == 200 and b"Dask" in page.read()


class _AbortWhenSent:
    """An argument whose unpickling aborts the process it is sent to: a worker that dies."""

    def __reduce__(self):
        return os.abort, ()


def test_a_small_local_batch_runs_on_the_warm_pool_and_a_worker_that_dies_is_named(
    tmp_path, capsys
):
    """At most ``pool.SMALL_BATCH`` local cases run on the warm pool (no Dask cluster): the
    rows the command gives; a case that kills its worker each time is retried alone, then
    gets the error row, and the others are meshed."""
    from pinn_engine.batch import pool
    from pinn_engine.batch.manifest import read_manifest
    from pinn_engine.batch.task import DIED, prepared

    path = manifest(tmp_path / "in", CASES[:2] + CASES[-2:])
    assert main(["batch", str(path), "-o", str(tmp_path / "out"), "--workers", "2"]) == 1
    err = capsys.readouterr().err
    assert "Dask dashboard: none (up to" in err and "[4/4] 2 failed" in err
    assert [r["status"] for r in summary(tmp_path / "out").values()] == [
        "ok", "ok", "error", "error"
    ]  # fmt: skip
    cases = read_manifest(path)[:2]
    todo = [(c.name, prepared(c, tmp_path / "pool")) for c in cases]
    todo[0][1].report = _AbortWhenSent()
    rows = dict(pool.WarmPool(2).results(todo))
    assert rows["wavy"]["message"] == DIED and rows["fig2"]["status"] == "ok"
    assert (tmp_path / "pool" / "fig2.vts").exists()
    records = [{"name": "a", "input": str(EXAMPLES / "fig2.vtp"), "options": TFI}]
    table = mesh_many(records, outdir=tmp_path / "py", workers=1)  # mesh_many's local pool
    table = table.to_dict("records") if hasattr(table, "to_dict") else table
    assert [(r["name"], r["status"], r["cells"]) for r in table] == [("a", "ok", 60)]


def _imported_after(code: str, before: str) -> str:
    """What a fresh Python prints after running ``before`` and then ``code``."""
    done = subprocess.run(
        [sys.executable, "-c", f"{before}\n{code}"],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=EXAMPLES.parent,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    return done.stdout.strip().splitlines()[-1]


def test_the_workers_server_starts_before_dask_and_the_engine_are_imported():
    printed = _imported_after(
        "print(sorted({'distributed', 'torch', 'scipy', 'vtkmodules'} & set(sys.modules)))",
        "import sys\nfrom pinn_engine.batch import cli, pool, warm",
    )
    assert printed == "[]"


@pytest.mark.slow  # imports the engine in a fresh Python (about 6 s)
def test_a_case_imports_nothing_the_workers_server_did_not_preload():
    """Four-sided and body cases that do not train (training imports torch in its worker)."""
    runs = [
        ["example_data/wavy.vtp", "--aux", "example_data/wavy_aux.vtp", "--method", "elliptic"],
        ["--naca", "0012", "--topology", "o", "--size", "33", "9", "--method", "elliptic"],
    ]
    code = f"""
before = set(sys.modules)
from pinn_engine.routes import cli
for argv in {runs!r}:
    cli.run(cli.build_parser().parse_args([*argv, "-o", f"{{tmp}}/grid.vts", "--quiet"]))
heavy = {{"pinn_engine", "torch", "scipy", "vtkmodules", "numpy", "sklearn", "distributed"}}
print(sorted(m for m in set(sys.modules) - before if m.split(".")[0] in heavy))
"""
    preload = (
        "import importlib, sys, tempfile\nfrom pinn_engine.batch import warm\n"
        "tmp = tempfile.mkdtemp()\nfor name in warm.ENGINE:\n    importlib.import_module(name)"
    )
    assert _imported_after(code, preload) == "[]"
