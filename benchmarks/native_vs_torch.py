"""The C++ fused loss against torch.func and torch.compile: one loss + gradient evaluation.

Usage: ``.venv/bin/python benchmarks/native_vs_torch.py [--repeats 20] [--no-compile]``

What is timed is what the paper preset's training does at each L-BFGS evaluation
(``kinds.four_sided.problem._FusedLoss``): the default network
(``CoordinateNet("shortcut", 4, 30, "tanh")``,
both sub-networks), 1000 collocation points where the Winslow residual needs the map's first
and second derivatives (L_eqns, paper eq. 11 and 13), 1000 boundary points (250 a side) with
their targets (L_bcs), and the gradient of L_eqns + lambda1 L_bcs with respect to all 6182
parameters. One torch thread (as training runs). Each way, in float64 and float32:

- ``C++ kernel``: ``NativeJet.loss`` (``neural/jet/kernels.cpp``), one call;
- ``torch jet``: the same jets as torch operations (``neural/jet/layers.py``, ``_TorchLayers``,
  hand-written backward; the path without a compiler), loss and ``torch.autograd.grad``;
- ``torch.func jacfwd``: per point, ``jacfwd`` of ``jacfwd`` (value, first and second derivatives
  in one forward-over-forward pass), ``vmap`` over the points, ``torch.func.grad_and_value``
  of the loss;
- ``torch.func hessian``: the same with ``torch.func.hessian`` (forward over reverse);
- ``torch.func jvp (batched)``: no vmap; nested ``jvp`` on the whole batch with the tangent
  (1, 0) or (0, 1) at every point (each output depends on its own point only): three
  forward-over-forward passes give the five derivatives;
- ``torch.compile(...)``: the torch jet path and the torch.func ways, compiled (inductor,
  default mode, an empty compile cache each time); the compilation (the first call) is
  timed apart.

Each way runs in its own process (a crash is reported, compiled code is not shared). Its
loss and gradient are checked against the C++ kernel's (largest gradient difference relative
to the largest gradient entry). Printed: the median and the range of ``--repeats``
evaluations after three warm-up calls, and the first call (with torch.compile: the
compilation), in ms.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import time

import torch
from torch.func import functional_call, hessian, jacfwd, jvp, vmap

from pinn_engine.neural.jet import ETA, ETAETA, XI, XIETA, XIXI, layers, native
from pinn_engine.neural.losses import loss_eqns, loss_points
from pinn_engine.neural.networks import CoordinateNet

N_JET, N_SIDE, LAMBDA1 = 1000, 250, 1.7


def problem(dtype: torch.dtype):
    torch.manual_seed(0)
    net = CoordinateNet("shortcut", 4, 30, "tanh").to(dtype)
    x = torch.rand(N_JET, 2, dtype=dtype)
    t = torch.rand(4, N_SIDE, dtype=dtype)
    sides = [
        torch.stack([t[0], torch.zeros_like(t[0])], 1),
        torch.stack([torch.ones_like(t[1]), t[1]], 1),
        torch.stack([t[2], torch.ones_like(t[2])], 1),
        torch.stack([torch.zeros_like(t[3]), t[3]], 1),
    ]
    bx = torch.cat(sides)
    by = bx * 2.0 + 0.1 * torch.sin(3 * bx)  # some target shape
    return net, x, bx, by


def flat(grads) -> torch.Tensor:
    return torch.cat([g.reshape(-1) for g in grads])


# ---------------------------------------------------------------- the ways


def cpp_way(net, x, bx, by):
    params = net.jet_params()
    grads = [[torch.empty_like(p) for p in params] for _ in range(2)]
    ends = [N_SIDE * (k + 1) for k in range(4)]

    def run():
        fused = layers.native_jet(x, bx, net.kind, net.activation, params)
        terms = fused.loss(by, ends, [1, 1, 1, 1], grads)
        loss = terms[0] + LAMBDA1 * terms[1:].sum()
        return loss, [a + LAMBDA1 * b for a, b in zip(*grads)]

    return run


def torch_jet_loss(net, x, bx, by):
    jet, values = net.jet(x, bx)
    bcs = loss_points(values.reshape(4, N_SIDE, 2), by.reshape(4, N_SIDE, 2)).sum()
    return loss_eqns(jet) + LAMBDA1 * bcs


def torch_jet_way(net, x, bx, by, compiled: bool = False):
    params = net.jet_params()
    loss_of = torch.compile(torch_jet_loss) if compiled else torch_jet_loss

    def run():
        loss = loss_of(net, x, bx, by)
        return loss.detach(), torch.autograd.grad(loss, params)

    return run


def func_loss_of(net, derivatives: str):
    """The loss as a function of the parameters (a dict), through torch.func transforms."""

    def point(params, p):  # one point (2,) -> the two outputs (2,)
        return functional_call(net, params, (p[None],))[0]

    if derivatives == "jacfwd":

        def first(params, p):
            j = jacfwd(point, argnums=1)(params, p)
            return j, j

        both = jacfwd(first, argnums=1, has_aux=True)  # (hessian, jacobian) in one pass

        def jet_parts(params, p):
            return both(params, p)

    elif derivatives == "hessian":

        def jet_parts(params, p):
            return hessian(point, argnums=1)(params, p), jacfwd(point, argnums=1)(params, p)

    def jvp_jet(params, x):
        """The derivatives at all points at once: each output depends on its own point
        only, so a jvp with the tangent (1, 0) at every point is d/dxi everywhere."""
        e_xi, e_eta = torch.zeros_like(x), torch.zeros_like(x)
        e_xi[:, 0], e_eta[:, 1] = 1, 1

        def along(u):
            return lambda y: jvp(lambda z: functional_call(net, params, (z,)), (y,), (u,))[1]

        r_xi, r_xixi = jvp(along(e_xi), (x,), (e_xi,))
        r_eta, r_etaeta = jvp(along(e_eta), (x,), (e_eta,))
        r_xieta = jvp(along(e_xi), (x,), (e_eta,))[1]
        return torch.stack([torch.zeros_like(r_xi), r_xi, r_eta, r_xixi, r_xieta, r_etaeta])

    def loss(params, x, bx, by):
        if derivatives == "jvp":
            jet = jvp_jet(params, x)
            values = functional_call(net, params, (bx,))
            bcs = loss_points(values.reshape(4, N_SIDE, 2), by.reshape(4, N_SIDE, 2)).sum()
            return loss_eqns(jet) + LAMBDA1 * bcs
        h, j = vmap(jet_parts, in_dims=(None, 0))(params, x)  # (B, 2, 2, 2), (B, 2, 2)
        zero = torch.zeros_like(j[:, :, 0])  # the values: L_eqns does not use them
        parts = {XI: j[:, :, 0], ETA: j[:, :, 1], XIXI: h[:, :, 0, 0], XIETA: h[:, :, 0, 1]}
        parts[ETAETA] = h[:, :, 1, 1]
        jet = torch.stack([zero] + [parts[c] for c in range(1, 6)])
        values = functional_call(net, params, (bx,))
        bcs = loss_points(values.reshape(4, N_SIDE, 2), by.reshape(4, N_SIDE, 2)).sum()
        return loss_eqns(jet) + LAMBDA1 * bcs

    return loss


def func_way(net, x, bx, by, derivatives: str = "jacfwd", compiled: bool = False):
    params = {k: v.detach() for k, v in net.named_parameters()}
    names = {id(p): name for name, p in net.named_parameters()}
    order = [names[id(p)] for p in net.jet_params()]  # the C++ kernel's order
    value_and_grad = torch.func.grad_and_value(func_loss_of(net, derivatives))
    if compiled:
        value_and_grad = torch.compile(value_and_grad)

    def run():
        g, loss = value_and_grad(params, x, bx, by)
        return loss, [g[name] for name in order]

    return run


# ---------------------------------------------------------------- timing


WAYS = {  # name: (factory, its extra arguments)
    "C++ kernel": (cpp_way, ()),
    "torch jet": (torch_jet_way, ()),
    "torch.func jacfwd": (func_way, ("jacfwd",)),
    "torch.func hessian": (func_way, ("hessian",)),
    "torch.func jvp (batched)": (func_way, ("jvp",)),
    "torch.compile(torch jet)": (torch_jet_way, (True,)),
    "torch.compile(torch.func jacfwd)": (func_way, ("jacfwd", True)),
    "torch.compile(torch.func jvp)": (func_way, ("jvp", True)),
}


def measure(name: str, dtype_name: str, repeats: int) -> dict:
    """One way in one precision (in its own process: a crash or a compiler's state stays
    there): its first call (compilation included), then ``repeats`` timed calls after three
    warm-up calls, in ms; its loss and gradient against the C++ kernel's."""
    torch.set_num_threads(1)
    assert native.kernels() is not None, "the C++ kernels did not build (no compiler?)"
    net, x, bx, by = problem(getattr(torch, dtype_name))
    ref_loss, ref_grad = cpp_way(net, x, bx, by)()
    ref_grad = flat(ref_grad)
    if name != "C++ kernel":  # the torch jet path: NetworkJet without the C++ kernels
        native.kernels = lambda: None
    factory, extra = WAYS[name]
    run = factory(net, x, bx, by, *extra)
    start = time.perf_counter()
    loss, g = run()
    first = time.perf_counter() - start
    g = flat(g)
    for _ in range(3):
        run()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return {
        "first": 1000 * first,
        "median": 1000 * statistics.median(times),
        "min": 1000 * min(times),
        "max": 1000 * max(times),
        "loss": float(ref_loss),
        "loss_rel": abs(float(loss) / float(ref_loss) - 1),
        "grad_rel": float((g - ref_grad).abs().max() / ref_grad.abs().max()),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=20)
    parser.add_argument("--no-compile", action="store_true", help="skip torch.compile")
    parser.add_argument("--one", nargs=2, metavar=("WAY", "DTYPE"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one:
        print(json.dumps(measure(*args.one, args.repeats)))
        return
    print(f"torch {torch.__version__}, 1 thread; {N_JET} jet points, {4 * N_SIDE} boundary points")
    print("each way in its own process; ms per loss + gradient evaluation")
    for dtype in ("float64", "float32"):
        print(f"\n{dtype}")
        print(f"  {'way':34s} {'median':>8s} {'range':>17s} {'first call':>11s}  against C++")
        for name in WAYS:
            if args.no_compile and name.startswith("torch.compile"):
                continue
            command = [sys.executable, __file__, "--one", name, dtype]
            command += ["--repeats", str(args.repeats)]
            with tempfile.TemporaryDirectory() as cache:  # compiled cold, every time
                env = dict(os.environ, TORCHINDUCTOR_CACHE_DIR=cache)
                done = subprocess.run(command, capture_output=True, text=True, env=env)
            if done.returncode < 0:  # its stderr: compiler warnings, not the cause
                print(f"  {name:34s} crashed ({signal.Signals(-done.returncode).name})")
                continue
            if done.returncode != 0:
                last = (done.stderr.strip().splitlines() or [""])[-1]
                print(f"  {name:34s} failed: {last[:200]}")
                continue
            r = json.loads(done.stdout.strip().splitlines()[-1])
            check = f"loss {r['loss_rel']:.0e}, gradient {r['grad_rel']:.0e}"
            span = f"{r['min']:.2f}-{r['max']:.2f}"
            print(f"  {name:34s} {r['median']:8.2f} {span:>17s} {r['first']:11.1f}  {check}")


if __name__ == "__main__":
    main()
