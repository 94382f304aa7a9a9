"""A trained model: feed-forward grids at any resolution, saved and loaded with its boundary."""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch

from pinn_engine._version import __version__
from pinn_engine.classical.pins import pinned_boundary
from pinn_engine.classical.warm import WarmStart
from pinn_engine.errors import InputError
from pinn_engine.geometry.boundary import Boundary, Frame
from pinn_engine.geometry.plane import Plane
from pinn_engine.io.fileio import atomic_path
from pinn_engine.kinds.four_sided.mapping import Mapping
from pinn_engine.neural.networks import CoordinateNet, load_checkpoint
from pinn_engine.settings import Settings, read_settings
from pinn_engine.starts.warmstart import lattice_for

FORMAT = "pinn-mesh-model/1"


@dataclass
class TrainedModel:
    """The trained map plus what produced it (settings, loss history, training info)."""

    mapping: Mapping
    settings: Settings
    history: dict[str, list[float]]
    info: dict

    def grid(self, ni: int, nj: int, params: np.ndarray | None = None) -> np.ndarray:
        """Grid (nj, ni, 2) in the working frame: one forward pass, no training; at node
        parameters ``params`` (nj, ni, 2) where given, else the uniform nodes."""
        return self.mapping.grid(ni, nj, params=params)

    def save(self, path: str | os.PathLike) -> Path:
        """Write the model (weights, settings, boundary, history) to ``path`` atomically."""
        b = self.mapping.boundary
        net = self.mapping.net
        payload = {
            "format": FORMAT,
            "version": __version__,
            "settings": self.settings.to_dict(),
            **network_payload(net),
            "boundary": {
                "ring": torch.as_tensor(b.ring),
                "corners": list(b.corners),
                "origin": torch.as_tensor(b.frame.origin),
                "scale": b.frame.scale,
                "plane_origin": torch.as_tensor(b.plane.origin),
                "plane_axes": torch.as_tensor(b.plane.axes),
                # the sides as trained: nodes on sharp vertices and followed lines' ends
                "knots": [(side, torch.as_tensor(a), torch.as_tensor(t)) for side, a, t in b.knots],
            },
            "history": self.history,
            "info": self.info,
            "warm": None
            if self.mapping.warm is None
            else torch.as_tensor(self.mapping.warm.correction),
            "warm_nodes": None
            if self.mapping.warm is None or self.mapping.warm.nodes is None
            else [torch.as_tensor(n) for n in self.mapping.warm.nodes],
        }
        with atomic_path(path) as tmp:
            torch.save(payload, tmp)
        return Path(path)

    @classmethod
    def load(cls, path: str | os.PathLike, boundary: Boundary | None = None) -> TrainedModel:
        """Read a model; if ``boundary`` is given it must be the one the model was trained on."""
        src = str(path)
        payload = read_payload(path, FORMAT)
        try:
            settings = _settings_of(payload["settings"])
            net = network_from(payload)
            bd = payload["boundary"]
            plane = (
                Plane(bd["plane_origin"].numpy(), bd["plane_axes"].numpy())
                if "plane_origin" in bd
                else Plane.horizontal()
            )  # models before planes
            saved = Boundary(
                ring=bd["ring"].numpy(),
                corners=tuple(bd["corners"]),
                frame=Frame(bd["origin"].numpy(), float(bd["scale"])),
                source=src,
                plane=plane,
            )
            warm = payload.get("warm")
            nodes = payload.get("warm_nodes")
            nodes = None if nodes is None else tuple(n.numpy() for n in nodes)
            warm = WarmStart(warm.numpy(), nodes) if warm is not None else None
            if payload.get("warm_walls"):
                raise InputError(
                    "a model of an older pinn-mesh with orthogonal sides, whose warm start "
                    "this version does not have; fit it again",
                    src,
                )
        except (KeyError, TypeError, RuntimeError, ValueError) as exc:
            raise InputError(f"damaged or incompatible model ({exc})", src) from None
        if boundary is not None:
            same = (
                saved.ring.shape == boundary.ring.shape
                and np.allclose(
                    saved.frame.to_user(saved.ring),
                    boundary.frame.to_user(boundary.ring),
                    rtol=1e-9,
                    atol=1e-12 * boundary.frame.scale,
                )
                and saved.corners == boundary.corners
            )
            if not same:
                raise InputError("model was trained for a different boundary", src)
            saved = dataclasses.replace(saved, source=boundary.source, plane=boundary.plane)
        # the sides as the model was trained on them (Mesher.fit); a model saved without
        # them had its sharp vertices alone pinned
        knots = bd.get("knots")
        saved = (
            pinned_boundary(saved, *lattice_for(*settings.lattice))
            if knots is None
            else dataclasses.replace(
                saved, knots=tuple((side, a.numpy(), t.numpy()) for side, a, t in knots)
            )
        )
        return cls(
            Mapping(net, saved, settings.boundary_mode, warm),
            settings,
            payload["history"],
            payload["info"],
        )


def network_payload(net: CoordinateNet) -> dict:
    """The network's part of a saved model: its shape and weights."""
    return {
        "network": {
            "kind": net.kind,
            "hidden_layers": net.hidden_layers,
            "neurons": net.neurons,
            "activation": net.activation,
            "outputs": net.outputs,
            "inputs": net.inputs,
        },
        "state": {k: v.detach().cpu() for k, v in net.state_dict().items()},
    }


def network_from(payload: dict) -> CoordinateNet:
    """The float64 network of a saved model's :func:`network_payload` (models written before
    3D name neither inputs nor outputs: two each)."""
    net = CoordinateNet(**payload["network"])
    net.load_state_dict(payload["state"])
    return net.to(torch.float64)


def read_payload(path: str | os.PathLike, fmt: str) -> dict:
    """The dictionary of a model file of format ``fmt``; a missing, unreadable or other
    file is a one-line :class:`InputError`."""
    src = str(path)
    if not Path(path).is_file():
        raise InputError("model file not found", src)
    try:
        payload = load_checkpoint(path)
    except Exception as exc:  # torch raises many types for a damaged file
        raise InputError(f"not a readable pinn-mesh model ({type(exc).__name__})", src) from None
    if not isinstance(payload, dict) or payload.get("format") != fmt:
        raise InputError(f"not a pinn-mesh model of format {fmt}", src)
    return payload


def _settings_of(saved: dict) -> Settings:
    """The settings of a saved model; files written before the renames name two differently."""
    saved = dict(saved)
    if "boundary" in saved:
        saved["boundary_mode"] = saved.pop("boundary")
    if "fast" in saved:
        saved["derivatives"] = "jets" if saved.pop("fast") else "autograd"
    return read_settings(saved)
