"""The family model: fit on members and their default grids, predict a member's grid, save
and load (docs/family.md).

A member's grid is its base (members.py) on its exact boundary nodes, plus a correction that
vanishes on the boundary: a combination of the family's correction modes (the principal
components of the training members' corrections, each zero on the boundary) whose
coefficients the network computes from the member's boundary encoding. For a four-sided
family the base is the family's linearised elliptic grid (physics.py: the Winslow system
frozen at the members' mean grid, solved with the member's boundary nodes), and where the
family's grids solve the Winslow equations, one more linearised solve at the predicted grid
takes it to second order towards the member's own. Where they are node optima (the default's
four-sided grids and bodies) the network is the linear map alone (network.fit_linear), and
the member's own node optimisation finishes the grid: a four-sided member's, from the
member's own elliptic grid as base, until it settles (at most ``POLISH_ITERATIONS``); a
body's needs none where its worst angle is certified, else its own run's optimisation
starts from the model's grid (mesh.py). A body's base is its elliptic grid (its own run's
start), and a second linear map predicts that grid's correction over its reference grid
(the rows its layout marches, from which its own run solves the elliptic grid): the model's
grid of a member whose elliptic grid is not solved is its reference grid plus both
corrections, so a certified grid costs the member its layout alone. A multi-block member's
base is its blocking's layout, and its grid (the network's) the start of its own run's
Winslow solve (mesh.BlocksStart).
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pinn_engine.errors import InputError
from pinn_engine.family.encoding import Encoding, boundary_vector
from pinn_engine.family.members import Member, block_corners, family_settings, realigned
from pinn_engine.family.network import fit_linear, forward
from pinn_engine.family.physics import FrozenWinslow, solves_winslow
from pinn_engine.quality import guard_figures
from pinn_engine.settings import Settings

# 2: a body's model maps its elliptic grid's correction over its reference grid too
# (start_modes, start_params); a model of 1 lacks that map and is refused
FORMAT = "pinn-mesh-family/2"
# The correction modes carry all but this share of the training corrections' energy
KEPT_ENERGY = 1e-8
EPOCHS = 1500  # Adam's full-batch epochs: about 1 s for 24 members on one core
# Iterations of the member's own node optimisation that finish a model's grid where the
# family's grids are node optima (the default's four-sided grids), at most, in each of its
# stages (mesh.POLISH_SHARPENING), stopped where it has settled (mesh.POLISH_SETTLE)
POLISH_ITERATIONS = 100
# A node-optimum family's member's elliptic grid by chord steps (FamilyModel._elliptic): they
# stop when no node moves more than ELLIPTIC_TOL of the extent (a grid that far from the
# converged one changes no angle by a thousandth of the ranking's 0.01-degree step; the
# classical solver's 1e-12 took the chord steps 18 to over 30 steps on the channels), and
# the classical solver takes over after ELLIPTIC_STEPS (the channels took 11 to 23, one more)
ELLIPTIC_TOL = 1e-9
ELLIPTIC_STEPS = 40
MIN_MEMBERS = 3  # fewer members span no family


def _describe(kind: str, topology: str, size: Sequence[int]) -> str:
    if kind == "blocks":
        return f"multi-block grids of {size[0]} nodes ({topology})"
    shape = {"o": "O-grids", "c": "C-grids"}.get(topology, "four-sided grids")
    return f"{shape} of {size[0]} x {size[1]} nodes"


@dataclass(eq=False)  # compared by identity: a route's setting holds one
class FamilyModel:
    """A fitted family model: its ``kind``, ``topology`` and ``size``, the members' shared
    ``settings`` (``FAMILY_KEYS``) and ``options``, and the fitted parts (``encoding``,
    ``mean_grid``, ``modes``, ``params``, ``winslow``, ``polish``) with the ``report`` of
    its fit; a body's ``start_modes`` and ``start_params``: the map to its elliptic grid's
    correction over its reference grid."""

    kind: str
    topology: str
    size: tuple[int, int]
    settings: dict
    options: str
    encoding: Encoding
    mean_grid: np.ndarray | None
    modes: np.ndarray
    params: dict[str, np.ndarray]
    winslow: bool
    report: dict = field(default_factory=dict)
    history: dict = field(default_factory=dict)
    path: str | None = None
    polish: int = 0  # iterations of the member's node optimisation that finish its grid
    start_modes: np.ndarray | None = None  # a body's elliptic grid over its reference grid
    start_params: dict[str, np.ndarray] | None = None
    corners: np.ndarray | None = None  # a multi-block family's blocks' corners (B, 4, 2)

    @classmethod
    def fit(
        cls,
        members: Sequence[Member],
        targets: Sequence[np.ndarray],
        options: str = "",
        epochs: int = EPOCHS,
        seed: int = 0,
        progress: Callable[[dict], object] | None = None,
    ) -> FamilyModel:
        """Fit on ``members`` and their default grids ``targets`` (each in its member's
        family frame); ``options``: the members' options as the user wrote them."""
        began = time.perf_counter()
        if len(members) < MIN_MEMBERS:
            raise InputError(f"a family needs at least {MIN_MEMBERS} members, not {len(members)}")
        first = members[0]
        corners = None
        if first.kind == "blocks":  # every member's blocks in the first's order and turn
            corners = np.array(block_corners(first))
            aligned = [realigned(m, corners) if m.kind == "blocks" else m for m in members]
            targets = [
                a.stacked(m.unique(t)) if m.kind == "blocks" else t
                for a, m, t in zip(aligned, members, targets)
            ]
            members, first = aligned, aligned[0]
        for m in members[1:]:
            if (m.kind, m.topology, m.size) != (first.kind, first.topology, first.size):
                raise InputError(
                    f"is one of {_describe(m.kind, m.topology, m.size)}, where the family's "
                    f"first member makes {_describe(first.kind, first.topology, first.size)}",
                    m.source,
                )
            other = [k for k in first.settings if m.settings.get(k) != first.settings[k]]
            if other:
                diff = ", ".join(f"{k} {m.settings[k]}" for k in other)
                shared = ", ".join(f"{k} {first.settings[k]}" for k in other)
                raise InputError(
                    f"asks for {diff}, where the family's first member asks for {shared}; "
                    "a family's members share their options",
                    m.source,
                )
        encoding = Encoding.fit(np.array([_vector(m) for m in members]))
        targets = [np.asarray(t, dtype=float) for t in targets]
        winslow = first.kind == "four-sided" and solves_winslow(targets)
        polish = 0
        if first.optimised and not winslow:  # a body: its own run's optimisation, its stop
            from pinn_engine.starts.quality_start import NODE_ITERATIONS

            polish = POLISH_ITERATIONS if first.kind == "four-sided" else NODE_ITERATIONS
        mean_grid = None
        if polish and first.kind == "four-sided":  # the base: each member's elliptic grid
            from pinn_engine.starts.warmstart import elliptic_start

            for m in members:
                m.elliptic = elliptic_start(m.boundary, *m.size)[1]
            mean_grid = np.mean([m.elliptic for m in members], axis=0)
        elif first.kind == "four-sided":
            mean_grid = np.mean(targets, axis=0)
        model = cls(
            first.kind, first.topology, first.size, first.settings, options,
            encoding, mean_grid, np.zeros((0, first.base.size)), {}, winslow,
        )  # fmt: skip
        model.polish, model.corners = polish, corners
        bases = [model.base(m) for m in members]
        corrections = np.array([(t - b).ravel() for t, b in zip(targets, bases)])
        model.modes = _modes(corrections)
        z = np.array([model.encoding.encode(_vector(m)) for m in members])
        start_fit = {}
        if first.kind == "body":  # the elliptic grid (the base) over the reference grid
            starts = np.array([(b - m.base).ravel() for m, b in zip(members, bases)])
            model.start_modes = _modes(starts)
            if len(model.start_modes):
                model.start_params, start_fit = fit_linear(z, starts @ model.start_modes.T)
        coeffs = corrections @ model.modes.T
        network = time.perf_counter()
        fitted = {}
        if len(model.modes) and model.linear:  # the linear map, finished by the member's own
            model.params, fitted = fit_linear(z, coeffs)
        elif len(model.modes):
            from pinn_engine.family.train import fit_network  # torch: imported only to fit

            model.params, model.history = fit_network(z, coeffs, epochs, seed, progress)
        network = time.perf_counter() - network
        errors = [float(np.abs(model.predict(m)[0] - t).max()) for m, t in zip(members, targets)]
        model.report = {
            "members": len(members),
            "kind": first.kind,
            "topology": first.topology,
            "size": list(first.size),
            "encoding_components": int(len(encoding.axes)),
            "correction_modes": int(len(model.modes)),
            "start_modes": 0 if model.start_modes is None else int(len(model.start_modes)),
            "start_map": start_fit,
            "epochs": epochs if len(model.modes) and not model.linear else 0,
            **fitted,
            "winslow_step": model.winslow,
            "polish_iterations": model.polish,
            "largest_training_error": max(errors),
            "worst_target": max(_worst(m, t) for m, t in zip(members, targets)),
            "network_seconds": network,
            "fit_seconds": time.perf_counter() - began,
        }
        return model

    @property
    def linear(self) -> bool:
        """Whether the map is linear (``network.fit_linear``) on the clamped encoding: where
        the member's own polish finishes the model's grid and corrects what a network would
        fit. A multi-block member's solve holds its sliding edge ends where the model puts
        them, which the network places nearer its own run's."""
        return bool(self.polish)

    def base(self, member: Member) -> np.ndarray:
        """The base grid of ``member`` (family frame): a body's elliptic grid (its start,
        solved once a member); a four-sided member's own elliptic grid where the family's
        grids are node optima (the grid its own run optimises from, solved once a member),
        else the linearised elliptic grid; a multi-block member's layout."""
        if member.kind == "blocks":
            return member.base
        if member.kind == "body":
            member.body_start()
            return member.elliptic
        if self.polish:
            if member.elliptic is None:
                member.elliptic = self._elliptic(member)
            return member.elliptic
        return self._linearised(member)

    def _linearised(self, member: Member) -> np.ndarray:
        """The family's linearised elliptic grid on ``member``'s boundary nodes: one step
        of the system frozen at the mean grid, from the mean grid's interior."""
        start = np.array(self.mean_grid)
        start[0], start[-1] = member.base[0], member.base[-1]
        start[:, 0], start[:, -1] = member.base[:, 0], member.base[:, -1]
        return self.frozen().advance(start)

    def _elliptic(self, member: Member) -> np.ndarray:
        """``member``'s elliptic grid: chord steps of its Winslow equations (the system
        frozen at the members' mean elliptic grid, factorised once) from the linearised
        grid, until no node moves more than ``ELLIPTIC_TOL`` of the extent; the classical
        solver where ``ELLIPTIC_STEPS`` do not get there."""
        grid = self._linearised(member)
        extent = float(np.ptp(grid.reshape(-1, 2), axis=0).max())
        for _ in range(ELLIPTIC_STEPS):
            new = self.frozen().advance(grid)
            moved = float(np.abs(new - grid).max())
            grid = new
            if moved <= ELLIPTIC_TOL * extent:
                return grid
        from pinn_engine.starts.warmstart import elliptic_start

        return elliptic_start(member.boundary, *member.size)[1]

    def frozen(self) -> FrozenWinslow:
        """The Winslow system frozen at the mean grid, factorised once per loaded model."""
        if getattr(self, "_frozen", None) is None:
            self._frozen = FrozenWinslow(self.mean_grid)
        return self._frozen

    def predict(self, member: Member) -> tuple[np.ndarray, dict]:
        """The model's grid of ``member`` (family frame) and what the guard needs to know:
        whether its encoding lies in the family's range. A body whose elliptic grid is not
        solved: its reference grid plus the predicted correction to its elliptic grid."""
        self.check(member)
        vector = _vector(member)
        z = self.encoding.clamped(vector) if self.linear else self.encoding.encode(vector)
        if member.kind == "body" and member.elliptic is None:
            grid = member.base + _correction(self.start_modes, self.start_params, z, member.base)
        else:
            grid = self.base(member)
        grid = grid + _correction(self.modes, self.params, z, grid)
        if member.kind == "body":
            grid = _held(grid, member, self.polish > 0)
        return grid, {"in_range": self.encoding.in_range(vector)}

    def check(self, member: Member, settings: Settings | None = None) -> None:
        """Refuse, in one line, a member outside the family: another kind, other counts or
        other settings that place its nodes."""
        where = self.path or "the family model"
        ours = (self.kind, self.topology, tuple(self.size))
        theirs = (member.kind, member.topology, tuple(member.size))
        if theirs != ours:
            raise InputError(
                f"outside the family of {where} ({_describe(*ours)}): this member makes "
                f"{_describe(*theirs)}; mesh it without the model, or fit a family of its "
                "kind and counts",
                member.source,
            )
        if settings is not None:
            asked = family_settings(settings)
            other = [k for k in self.settings if k != "size" and asked.get(k) != self.settings[k]]
            if other:
                diff = ", ".join(
                    f"{k} {asked[k]} (the family's: {self.settings[k]})" for k in other
                )
                raise InputError(
                    f"outside the family of {where}: {diff}; mesh it with the family's "
                    f"options ({self.options or 'the defaults'}) or without the model",
                    member.source,
                )

    def save(self, path: str | os.PathLike) -> Path:
        """Write the model to ``path`` (a torch file) atomically."""
        import torch

        from pinn_engine._version import __version__
        from pinn_engine.io.fileio import atomic_path

        def t(a):
            return torch.as_tensor(np.asarray(a, dtype=float))

        payload = {
            "format": FORMAT,
            "version": __version__,
            "kind": self.kind,
            "topology": self.topology,
            "size": list(self.size),
            "settings": self.settings,
            "options": self.options,
            "encoding": {
                k: t(v) if isinstance(v, np.ndarray) else v
                for k, v in self.encoding.state().items()
            },
            "mean_grid": None if self.mean_grid is None else t(self.mean_grid),
            "modes": t(self.modes),
            "params": {k: t(v) for k, v in self.params.items()},
            "winslow": self.winslow,
            "polish": self.polish,
            "start_modes": None if self.start_modes is None else t(self.start_modes),
            "start_params": None
            if self.start_params is None
            else {k: t(v) for k, v in self.start_params.items()},
            "corners": None if self.corners is None else t(self.corners),
            "report": self.report,
            "history": self.history,
        }
        with atomic_path(path) as tmp:
            torch.save(payload, tmp)
        return Path(path)


def _worst(member: Member, grid: np.ndarray) -> float:
    """The worst MaxIncludedAngle of ``member``'s ``grid`` (a multi-block member's stacked
    nodes: over its blocks)."""
    if member.kind == "blocks":
        return max(guard_figures(b)["worst_max_angle"] for b in member.blocks_of(grid))
    return guard_figures(grid)["worst_max_angle"]


def _vector(member: Member) -> np.ndarray:
    """``member``'s boundary nodes as the encoding reads them."""
    return boundary_vector(member.base, member.kind, member.drawn)


def _modes(corrections: np.ndarray) -> np.ndarray:
    """The principal components of ``corrections`` (one member a row) that carry all but
    ``KEPT_ENERGY`` of their energy (none where every correction is zero)."""
    _, s, vt = np.linalg.svd(corrections, full_matrices=False)
    energy = s**2
    kept = int((np.cumsum(energy) < (1 - KEPT_ENERGY) * energy.sum()).sum() + 1)
    return vt[:kept] if energy.sum() > 0 else vt[:0]


def _correction(
    modes: np.ndarray | None, params: dict | None, z: np.ndarray, like: np.ndarray
) -> np.ndarray | float:
    """The correction the map ``params`` makes of the encoding ``z`` on ``modes``, shaped
    ``like`` a grid (0 without modes)."""
    if modes is None or not len(modes):
        return 0.0
    return (forward(params, z) @ modes).reshape(like.shape)


def _held(grid: np.ndarray, member: Member, optimised: bool) -> np.ndarray:
    """A body's model ``grid`` with the nodes its own run never moves set to its base's
    exactly (the modes vanish there to rounding; its reference grid's, which its elliptic
    grid holds): the wall, the far field and a C-grid's outflow columns, and where its own
    run optimises its nodes (``optimised``) the first layer too
    (``kinds.body.untrained.BODY_HELD_ROWS``; a trained network's correction moves it); an
    O-grid's column ni - 1 repeats its column 0 (the seam)."""
    from pinn_engine.kinds.body.untrained import BODY_HELD_ROWS

    base, held = member.base, BODY_HELD_ROWS if optimised else 1
    grid[:held], grid[-1] = base[:held], base[-1]
    if member.topology == "o":
        grid[:, -1] = grid[:, 0]
    else:
        grid[:, 0], grid[:, -1] = base[:, 0], base[:, -1]
    return grid


def load_family(path: str | os.PathLike) -> FamilyModel:
    """The family model saved at ``path``; a missing, damaged or other file is one line."""
    from pinn_engine.neural.networks import load_checkpoint  # torch: only to read a model

    src = str(path)
    if not Path(path).is_file():
        raise InputError("family model file not found", src)
    try:
        payload = load_checkpoint(path)
    except Exception as exc:  # torch raises many types for a damaged file
        raise InputError(f"not a readable family model ({type(exc).__name__})", src) from None
    if not isinstance(payload, dict) or payload.get("format") != FORMAT:
        raise InputError(
            f"not a family model (format {FORMAT}): give a file written by pinn-mesh fit", src
        )

    def n(v):
        return v.numpy() if hasattr(v, "numpy") else v

    enc = Encoding(**{k: n(v) for k, v in payload["encoding"].items()})
    mean = payload["mean_grid"]
    start_modes, start_params = payload.get("start_modes"), payload.get("start_params")
    corners = payload.get("corners")
    return FamilyModel(
        payload["kind"], payload["topology"], tuple(payload["size"]), payload["settings"],
        payload["options"], enc, None if mean is None else mean.numpy(),
        payload["modes"].numpy(), {k: v.numpy() for k, v in payload["params"].items()},
        bool(payload["winslow"]), payload["report"], payload["history"], src,
        int(payload.get("polish", 0)),
        None if start_modes is None else start_modes.numpy(),
        None if start_params is None else {k: v.numpy() for k, v in start_params.items()},
        None if corners is None else corners.numpy(),
    )  # fmt: skip
