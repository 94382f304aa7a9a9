"""The networks' jet in C++ (jet/native.py, kernels.cpp): as torch computes it, safe fallback."""

from __future__ import annotations

import logging
import os
import re
import shutil
import stat
import warnings
from pathlib import Path

import pytest
import torch
from helpers import needs_compiler

from pinn_engine.errors import JetKernelsWarning
from pinn_engine.neural.jet import layers, native
from pinn_engine.neural.jet.layers import ACTIVATIONS
from pinn_engine.neural.networks import CoordinateNet


def _run(net: CoordinateNet, x: torch.Tensor, extra: torch.Tensor) -> list[torch.Tensor]:
    """Jet, values and every parameter gradient of a loss that uses all of them."""
    net.zero_grad()
    jet, values = net.jet(x, extra)
    (jet.pow(2).sum() + values.pow(3).sum()).backward()
    return [jet.detach(), values.detach()] + [p.grad.clone() for p in net.parameters()]


@pytest.fixture
def fresh_kernels(monkeypatch, tmp_path):
    """kernels() rebuilt from scratch in an empty cache (the install's library hidden), and
    forgotten afterwards."""
    monkeypatch.setenv("PINN_MESH_CACHE", str(tmp_path))
    monkeypatch.setattr(native, "PACKAGED_DIR", tmp_path / "no-package")
    native.kernels.cache_clear()
    yield
    native.kernels.cache_clear()


@pytest.fixture(scope="session")
def built_library() -> Path:
    """The kernels library this machine already has (the install's, else the engine's
    cache; built there once if neither has it)."""
    assert native.kernels() is not None
    packaged = native.packaged_library(native.PACKAGED_DIR)
    return packaged if packaged.exists() else native._built(native._compiler())[0]


@pytest.fixture
def copied_build(built_library, monkeypatch) -> list[Path]:
    """``_compile`` copies ``built_library`` to its target (0700, as the compiler's output is
    left): the cache's choices with a real library to load, without compiling again (one
    test, ``test_the_build_is_cached_per_source_and_reused``, compiles for real)."""
    built = []

    def copy(compiler, folder, target, flags=native.FLAGS):
        shutil.copyfile(built_library, target)
        target.chmod(0o700)
        built.append(target)
        return target

    monkeypatch.setattr(native, "_compile", copy)
    return built


@needs_compiler
@pytest.mark.parametrize("dtype", [torch.float64, torch.float32])
@pytest.mark.parametrize("activation", sorted(ACTIVATIONS))
@pytest.mark.parametrize("kind", ["shortcut", "mlp"])
def test_fused_kernels_equal_the_torch_operations(kind, activation, dtype, monkeypatch):
    assert native.kernels() is not None, "the fused kernels did not build"
    torch.manual_seed(3)
    net = CoordinateNet(kind, 3, 9, activation).to(dtype)
    x, extra = torch.rand(17, 2, dtype=dtype), torch.rand(11, 2, dtype=dtype)
    fused = _run(net, x, extra)
    monkeypatch.setattr(native, "kernels", lambda: None)
    plain = _run(net, x, extra)
    tol = {"rtol": 1e-12, "atol": 1e-12} if dtype == torch.float64 else {"rtol": 2e-4, "atol": 2e-5}
    for a, b in zip(fused, plain):
        torch.testing.assert_close(a, b, **tol)


def test_no_extra_points_and_no_jet_points_are_both_fine():
    net = CoordinateNet("shortcut", 2, 5).double()
    x = torch.rand(4, 2, dtype=torch.float64)
    jet, values = net.jet(x)
    assert jet.shape == (6, 4, 2) and values.shape == (0, 2)
    jet, values = net.jet(x[:0], x)
    assert jet.shape == (6, 0, 2)
    torch.testing.assert_close(values, net(x))


@pytest.mark.slow  # compiles the kernels afresh (about 30 s)
@needs_compiler
def test_the_build_is_cached_per_source_and_reused(fresh_kernels, tmp_path):
    assert native.kernels() is not None
    built = list(tmp_path.glob("jet_kernels-*.so"))
    assert len(built) == 1
    stamp = built[0].stat().st_mtime_ns
    native.kernels.cache_clear()
    assert native.kernels() is not None
    assert [p.stat().st_mtime_ns for p in tmp_path.glob("jet_kernels-*.so")] == [stamp]
    assert not list(tmp_path.glob("*.tmp*")) and len(list(tmp_path.iterdir())) == 1


@needs_compiler
def test_an_unusable_cache_directory_builds_in_the_temporary_directory(
    fresh_kernels, copied_build, monkeypatch, tmp_path
):
    blocker = tmp_path / "a-file"
    blocker.write_text("not a directory")
    monkeypatch.setenv("PINN_MESH_CACHE", str(blocker / "cache"))
    monkeypatch.setattr(native.tempfile, "gettempdir", lambda: str(tmp_path / "tmp"))
    assert native.kernels() is not None
    assert len(list((tmp_path / "tmp").glob("pinn-mesh-*/jet_kernels-*.so"))) == 1


def test_a_failing_compiler_falls_back_to_torch_with_a_warning(
    fresh_kernels, monkeypatch, tmp_path, caplog
):
    broken = tmp_path / "broken-c++"
    broken.write_text("#!/bin/sh\necho 'fatal error: simulated' >&2\nexit 1\n")
    broken.chmod(0o755)
    monkeypatch.setenv("CXX", str(broken))
    with pytest.warns(JetKernelsWarning, match="simulated"):
        assert native.kernels() is None
    assert list(tmp_path.glob("*.so")) == []  # no half-written library left behind
    net = CoordinateNet("shortcut", 2, 5).double()
    x = torch.rand(6, 2, dtype=torch.float64)
    assert net.jet(x)[0].shape == (6, 6, 2)  # still works, through torch operations


def test_native_kernels_can_be_switched_off(fresh_kernels, monkeypatch):
    monkeypatch.setenv("PINN_MESH_NATIVE", "0")
    assert native.kernels() is None


@needs_compiler
def test_two_threads_give_the_same_numbers(monkeypatch):
    torch.manual_seed(5)
    net = CoordinateNet("shortcut", 4, 30).float()
    x, extra = torch.rand(37, 2), torch.rand(23, 2)
    one = _run(net, x, extra)
    monkeypatch.setenv("PINN_MESH_JET_THREADS", "2")
    for a, b in zip(_run(net, x, extra), one):
        torch.testing.assert_close(a, b, rtol=0, atol=0)


@needs_compiler
def test_backward_without_a_workspace_recomputes_the_same_numbers(monkeypatch):
    torch.manual_seed(6)
    net = CoordinateNet("shortcut", 4, 30).float()
    x, extra = torch.rand(53, 2), torch.rand(71, 2)
    stored = _run(net, x, extra)
    monkeypatch.setattr(layers, "WORKSPACE_BYTES", 0)
    for a, b in zip(_run(net, x, extra), stored):
        torch.testing.assert_close(a, b, rtol=0, atol=0)


@needs_compiler
def test_the_fused_loss_refuses_groups_that_do_not_fit():
    torch.manual_seed(7)
    net = CoordinateNet("shortcut", 2, 5).double()
    x, extra = torch.rand(3, 2, dtype=torch.float64), torch.rand(4, 2, dtype=torch.float64)
    params = net.jet_params()
    fused = layers.native_jet(x, extra, net.kind, net.activation, params)
    grads = [[torch.empty_like(p) for p in params] for _ in range(2)]
    target = net(extra).detach()  # the values themselves: no distance
    assert fused.loss(target, [4], [1], grads)[1] < 1e-28
    for ends, sets in (([5], [1]), ([3, 2], [1, 1]), ([4], [2])):
        with pytest.raises(layers.NativeCallError, match="fused loss"):
            fused.loss(target, ends, sets, grads)


# ---------------------------------------------------------------- the cache: only this user's


@pytest.fixture
def no_build(monkeypatch, tmp_path):
    """``_compile`` stubbed (writes a file, records its target), the temporary directory in
    ``tmp_path/tmp``: the cache's choices without a compiler."""
    built = []

    def fake_compile(compiler, folder, target, flags=native.FLAGS):
        target.write_bytes(b"built")
        target.chmod(0o700)
        built.append(target)
        return target

    monkeypatch.setattr(native, "_compile", fake_compile)
    monkeypatch.setattr(native.tempfile, "gettempdir", lambda: str(tmp_path / "tmp"))
    monkeypatch.setattr(native, "PACKAGED_DIR", tmp_path / "package")
    (tmp_path / "tmp").mkdir()
    monkeypatch.setenv("PINN_MESH_CACHE", str(tmp_path / "cache"))
    return built


def _plant(folder: Path, mode: int = 0o700) -> Path:
    """A library of the expected name in ``folder``, as another user would plant it."""
    folder.mkdir(exist_ok=True)
    planted = folder / f"jet_kernels-{native.build_key('c++')}.so"
    planted.write_bytes(b"planted")
    planted.chmod(mode)
    return planted


@pytest.mark.skipif(os.name == "nt", reason="POSIX owners and modes")
def test_a_new_cache_folder_is_private(no_build, tmp_path):
    path, fresh = native._built("c++")
    assert fresh is None and path.parent == tmp_path / "cache" and path.read_bytes() == b"built"
    assert stat.S_IMODE((tmp_path / "cache").stat().st_mode) == 0o700


@pytest.mark.skipif(os.name == "nt", reason="POSIX owners and modes")
def test_a_library_in_a_group_writable_cache_is_not_loaded(no_build, tmp_path, caplog):
    planted = _plant(tmp_path / "cache")
    (tmp_path / "cache").chmod(0o775)
    with caplog.at_level(logging.WARNING):
        path, fresh = native._built("c++")
    assert path != planted and planted.read_bytes() == b"planted"
    assert path.parent == tmp_path / "tmp" / f"pinn-mesh-{os.getuid()}" and fresh is None
    assert "is writable by others (mode 775)" in caplog.text


@pytest.mark.skipif(os.name == "nt", reason="POSIX owners and modes")
def test_a_group_writable_library_is_built_again(no_build, tmp_path, caplog):
    planted = _plant(tmp_path / "cache", mode=0o664)
    (tmp_path / "cache").chmod(0o700)
    with caplog.at_level(logging.WARNING):
        path, _ = native._built("c++")
    assert path == planted and path.read_bytes() == b"built"  # replaced, not loaded
    assert "not loading" in caplog.text


@pytest.mark.skipif(os.name == "nt", reason="POSIX owners and modes")
def test_folders_and_libraries_of_another_user_are_not_used(no_build, tmp_path, monkeypatch):
    for folder in (tmp_path / "cache", tmp_path / "tmp" / f"pinn-mesh-{os.getuid()}"):
        _plant(folder)
    real = os.getuid()
    monkeypatch.setattr(native.os, "getuid", lambda: real + 1)  # everything is foreign now
    path, fresh = native._built("c++")
    assert fresh is not None and path.parent == fresh and path.read_bytes() == b"built"
    assert fresh.parent == tmp_path / "tmp"


@pytest.mark.skipif(os.name == "nt", reason="POSIX owners and modes")
def test_a_library_owned_by_another_user_is_not_loaded(no_build, tmp_path, monkeypatch):
    planted = _plant(tmp_path / "cache")
    real_lstat, real_uid = os.lstat, os.getuid()

    class Foreign:
        def __init__(self, info):
            self.st_mode, self.st_uid = info.st_mode, real_uid + 1

    def lstat(path, *args, **kwargs):
        info = real_lstat(path, *args, **kwargs)
        return Foreign(info) if Path(path) == planted else info

    monkeypatch.setattr(native.os, "lstat", lstat)
    path, _ = native._built("c++")
    assert path == planted and planted.read_bytes() == b"built"  # built again over it


@needs_compiler
@pytest.mark.skipif(os.name == "nt", reason="POSIX owners and modes")
def test_the_engine_never_loads_a_planted_library(
    fresh_kernels, copied_build, tmp_path, monkeypatch
):
    planted = _plant(tmp_path)
    tmp_path.chmod(0o777)
    monkeypatch.setattr(native.tempfile, "gettempdir", lambda: str(tmp_path / "tmp"))
    loaded = []
    real = native.ctypes.CDLL
    monkeypatch.setattr(native.ctypes, "CDLL", lambda path: loaded.append(path) or real(path))
    try:
        assert native.kernels() is not None
    finally:
        tmp_path.chmod(0o700)
    assert len(loaded) == 1 and Path(loaded[0]).name == planted.name  # the name it wanted
    assert loaded[0] != str(planted) and planted.read_bytes() == b"planted"
    assert stat.S_IMODE(Path(loaded[0]).stat().st_mode) == 0o700


# ---------------------------------------------------------------- the install's library


def test_the_install_step_builds_the_library_that_runs_load(no_build, tmp_path, monkeypatch):
    package = tmp_path / "package"
    package.mkdir()
    (package / "jet_kernels-0123456789abcdef.so").write_bytes(b"an older source's")
    built = native.build_packaged(package)
    assert built == native.packaged_library(package) and no_build == [built]
    assert list(package.iterdir()) == [built]  # the older source's library is gone
    loaded = []
    monkeypatch.setattr(native.ctypes, "CDLL", lambda path: loaded.append(path) or path)
    monkeypatch.setattr(native, "_bind", lambda lib: lib)
    native.kernels.cache_clear()
    try:
        assert native.kernels() == str(built)
    finally:
        native.kernels.cache_clear()
    assert loaded == [str(built)] and no_build == [built]  # nothing compiled at run time
    monkeypatch.setattr(native, "_cpu_id", lambda: "another CPU")
    assert native.packaged_library(package) != built  # never loaded on another CPU


def test_without_a_compiler_the_install_goes_on_and_a_run_warns_once(
    no_build, monkeypatch, capsys, caplog
):
    monkeypatch.setattr(native, "_compiler", lambda: None)
    assert native.build_packaged(native.PACKAGED_DIR) is None and no_build == []
    assert "built at first use" in capsys.readouterr().out
    native.kernels.cache_clear()
    try:
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            with caplog.at_level(logging.INFO, logger=native.log.name):
                assert native.kernels() is None
    finally:
        native.kernels.cache_clear()
    assert [(w.category, str(w.message).count("\n")) for w in said] == [(JetKernelsWarning, 0)]
    assert "no C++ compiler found" in str(said[0].message) and not caplog.records
    native.kernels.cache_clear()
    try:  # Python's filters reach it: quiet, as the command line's --quiet makes it
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            warnings.simplefilter("ignore", JetKernelsWarning)
            assert native.kernels() is None
    finally:
        native.kernels.cache_clear()
    assert said == []


def test_a_second_install_reuses_the_first_ones_library(no_build, tmp_path, capsys):
    """pip builds the package anew for each extra installed after the core: the library of
    the same source and CPU is compiled once and copied from the user's cache after."""
    first, second = tmp_path / "first", tmp_path / "second"
    first.mkdir(), second.mkdir()
    built = native.build_packaged(first)
    again = native.build_packaged(second)
    assert no_build == [built] and again.name == built.name  # compiled once
    assert again.read_bytes() == built.read_bytes()
    assert "built before" in capsys.readouterr().out


def test_a_portable_build_is_loaded_where_no_build_for_this_cpu_is(no_build, monkeypatch):
    """PINN_MESH_PORTABLE=1 at the install (a wheel for other machines): the library is
    compiled for any CPU of the platform and named by the source and flags alone."""
    package = native.PACKAGED_DIR
    package.mkdir()
    monkeypatch.setenv("PINN_MESH_PORTABLE", "1")
    built = native.build_packaged(package)
    assert built == native.packaged_library(package, portable=True)
    monkeypatch.setattr(native, "_cpu_id", lambda: "another CPU")
    assert native.packaged_library(package, portable=True) == built  # any CPU's
    loaded = []
    monkeypatch.setattr(native.ctypes, "CDLL", lambda path: loaded.append(path) or path)
    monkeypatch.setattr(native, "_bind", lambda lib: lib)
    native.kernels.cache_clear()
    try:
        assert native.kernels() == str(built)
    finally:
        native.kernels.cache_clear()
    assert "-march=native" not in native.PORTABLE_FLAGS and "-O3" in native.PORTABLE_FLAGS


# ---------------------------------------------------------------- the build key


def test_the_build_key_names_the_cpu(monkeypatch):
    key = native.build_key("c++")
    assert re.fullmatch(r"[0-9a-f]{16}", key)
    monkeypatch.setattr(native, "_cpu_id", lambda: "x86_64 Linux model name=CPU A")
    a = native.build_key("c++")
    monkeypatch.setattr(native, "_cpu_id", lambda: "x86_64 Linux model name=CPU B")
    assert native.build_key("c++") != a


def test_the_cpu_is_identified_on_each_platform(monkeypatch, tmp_path):
    cpuinfo = tmp_path / "cpuinfo"
    cpuinfo.write_text(
        "processor\t: 0\nvendor_id\t: GenuineIntel\nmodel name\t: Intel(R) Xeon(R) X\n"
        "flags\t\t: fpu sse2 avx2\n\nprocessor\t: 1\nmodel name\t: other\n"
    )
    monkeypatch.setattr(native, "CPUINFO", cpuinfo)
    monkeypatch.setattr(native.platform, "machine", lambda: "x86_64")
    monkeypatch.setattr(native.platform, "system", lambda: "Linux")
    linux = native._cpu_id()
    assert "model name=Intel(R) Xeon(R) X" in linux and "avx2" in linux and "other" not in linux
    sysctl = {"machdep.cpu.brand_string": "Apple M2", "machdep.cpu.features": ""}
    monkeypatch.setattr(native, "_output", lambda command: sysctl.get(command[-1], ""))
    monkeypatch.setattr(native.platform, "system", lambda: "Darwin")
    monkeypatch.setattr(native.platform, "machine", lambda: "arm64")
    assert native._cpu_id() == "arm64 Darwin Apple M2"
    monkeypatch.setattr(native.platform, "system", lambda: "Windows")
    monkeypatch.setattr(native.platform, "machine", lambda: "AMD64")
    monkeypatch.setattr(native.platform, "processor", lambda: "Intel64 Family 6 Model 85")
    assert native._cpu_id() == "AMD64 Windows Intel64 Family 6 Model 85"
    monkeypatch.setattr(native.platform, "processor", lambda: "")
    monkeypatch.setattr(native.platform, "machine", lambda: "")
    monkeypatch.setattr(native.platform, "node", lambda: "box7")
    assert native._cpu_id() == "unknown machine Windows unidentified CPU of host box7"


# ---------------------------------------------------------------- a failing build


@pytest.mark.skipif(not shutil.which("false"), reason="no `false` command")
def test_a_failing_compile_raises_and_the_engine_falls_back(
    fresh_kernels, monkeypatch, tmp_path, caplog
):
    compiler = shutil.which("false")
    with pytest.raises(native.NativeBuildError, match=r"`.*false -O3 .*kernels\.cpp` failed"):
        native._compile(compiler, tmp_path, tmp_path / "lib.so")
    assert list(tmp_path.iterdir()) == []  # no temporary file left
    monkeypatch.setenv("CXX", compiler)
    with pytest.warns(JetKernelsWarning, match="could not build the fused jet kernels.*false"):
        assert native.kernels() is None
    net = CoordinateNet("shortcut", 2, 5).double()
    x = torch.rand(6, 2, dtype=torch.float64)
    torch.testing.assert_close(net.jet(x)[0][0], net(x))  # through torch operations
