"""VTK files read by a new Python (io/childread.py): all of a run's files by one child
started early, each file's result as a child of its own would give it, a crash named."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from helpers import EXAMPLES

from pinn_engine.io import childread


@pytest.fixture
def counted(monkeypatch):
    """The children started (their files), with nothing read earlier in this process."""
    monkeypatch.setattr(childread, "_READ", childread.OrderedDict())
    started = []
    real = childread.subprocess.Popen

    def popen(command, **kwargs):
        if command[2:3] == [childread._CHILD_CODE]:  # not another program's start
            started.append([c.rsplit("/", 1)[-1] for c in command[5:]])
        return real(command, **kwargs)

    monkeypatch.setattr(childread.subprocess, "Popen", popen)
    return started


def _damaged(tmp_path):
    """A .vtp whose point count makes VTK's reader abort (or refuse it)."""
    text = (EXAMPLES / "wavy.vtp").read_text()
    path = tmp_path / "damaged.vtp"
    path.write_text(text.replace('NumberOfPoints="240"', 'NumberOfPoints="999999999999"'))
    return path


def test_a_runs_files_are_read_by_one_child_as_each_alone(counted):
    boundary, aux = EXAMPLES / "wavy.vtp", EXAMPLES / "wavy_aux.vtp"
    childread.prefetch([boundary, aux, None, EXAMPLES / "annulus_270.csv", "auto"])
    assert counted == [["wavy.vtp", "wavy_aux.vtp"]]
    together = [childread.read(boundary), childread.read(aux)]
    assert len(counted) == 1 and all(problem is None for problem, _ in together)
    childread._READ.clear()
    alone = [childread.read(boundary), childread.read(aux)]
    assert len(counted) == 3 and alone == together


def test_a_file_that_crashes_the_child_is_named_and_the_others_still_read(counted, tmp_path):
    damaged, good = _damaged(tmp_path), EXAMPLES / "wavy.vtp"
    childread.prefetch([damaged, good])
    problem, data = childread.read(damaged)
    assert data == b"" and problem.startswith(("VTK's reader crashed (SIGABRT)", "VTK: "))
    assert childread.read(good)[0] is None  # a new child where the first died before it
    assert counted[0] == ["damaged.vtp", "wavy.vtp"]


def test_the_childs_output_says_where_it_died():
    keys = [(".vtp", b"a"), (".vtp", b"b"), (".vtp", b"c")]
    one = b"reading\n0 4\nDATA"
    assert childread._parse(one + b"reading\n", keys, -6) == {
        keys[0]: (None, b"DATA"),
        keys[1]: ("VTK's reader crashed (SIGABRT) on it", b""),
    }
    stalled = childread._parse(one + b"reading\n", keys, None)[keys[1]][0]
    assert stalled == "VTK's reader did not finish in 60 s on it"
    error = b"ERROR: In reader.cxx, line 5\nvtkXMLReader (0x1): bad offset\n"
    record = b"reading\n%d 0\n" % len(error) + error
    assert childread._parse(record, keys, 0) == {keys[0]: ("VTK: bad offset", b"")}
    assert childread._parse(b"", keys, 1) == {}  # no VTK in the child: read here


@pytest.mark.skipif(not Path("/proc/self").exists(), reason="Linux's /proc")
def test_a_prefetched_file_nobody_reads_ends_with_the_process():
    code = (
        "from pinn_engine.io import childread; "
        f"childread.prefetch([{str(EXAMPLES / 'wavy.vtp')!r}]); "
        "print(childread._PENDING[0].process.pid)"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert not Path(f"/proc/{int(done.stdout)}").exists()


def test_the_command_reads_its_boundary_and_block_edges_in_one_child(counted, tmp_path):
    from pinn_engine.routes.cli import main

    argv = [str(EXAMPLES / "lshape.vtp"), "--blocks", str(EXAMPLES / "lshape_blocks.vtp")]
    assert main([*argv, "--method", "tfi", "-o", str(tmp_path / "g.vtm"), "--quiet"]) == 0
    assert counted == [["lshape.vtp", "lshape_blocks.vtp"]]


@pytest.fixture
def serving(monkeypatch):
    """This process reading by one long-lived child (:func:`childread.serve`), stopped after."""
    monkeypatch.setattr(childread, "_SERVER", [])
    childread.serve()
    yield childread._SERVER
    while childread._SERVER:
        childread._SERVER.pop().stop()


@pytest.mark.skipif(not Path("/proc/self").exists(), reason="POSIX's select on pipes")
def test_a_serving_child_reads_file_after_file_and_names_a_crash(counted, serving, tmp_path):
    """A batch worker's child: the files of several runs read by one child, each as a child
    of its own reads it; a file that crashes it is named, and the next read starts another."""
    first = serving[0]
    files = [EXAMPLES / "wavy.vtp", EXAMPLES / "fig2.vtp", EXAMPLES / "concave.vtp"]
    childread.prefetch(files[:2])
    served = [childread.read(path) for path in files]
    assert serving == [first] and all(problem is None for problem, _ in served)
    childread._READ.clear()
    alone = [childread._start([path]).finish()[childread._key(path)] for path in files]
    assert served == alone
    problem, data = childread.read(_damaged(tmp_path))
    assert data == b"" and problem.startswith(("VTK's reader crashed (SIGABRT)", "VTK: "))
    assert childread.read(EXAMPLES / "wavy_aux.vtp")[0] is None
