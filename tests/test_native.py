"""The networks' jet in C++ (jet/native.py, kernels.cpp): as torch computes it, safe fallback."""

from __future__ import annotations

import logging

import pytest
import torch
from conftest import needs_compiler

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
    """kernels() rebuilt from scratch in an empty cache, and forgotten afterwards."""
    monkeypatch.setenv("PINN_MESH_CACHE", str(tmp_path))
    native.kernels.cache_clear()
    yield
    native.kernels.cache_clear()


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


@pytest.mark.slow  # compiles the kernels afresh (about 30 s)
@needs_compiler
def test_an_unusable_cache_directory_builds_in_the_temporary_directory(
    fresh_kernels, monkeypatch, tmp_path
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
    with caplog.at_level(logging.WARNING, logger="pinn_engine.native"):
        assert native.kernels() is None
    assert "simulated" in caplog.text
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
        with pytest.raises(AssertionError, match="fused loss"):
            fused.loss(target, ends, sets, grads)
