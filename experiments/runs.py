"""What the experiments run (budgets, jobs) and how: one job is one meshing run.

A job is picklable and runs in a worker process (or in-process) through :func:`run_job`, which
returns plain data: the quality figures, the loss history, the grid and its cell angles.
"""

from __future__ import annotations

import math
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pinn_engine.settings import METHODS, NEURAL

CASES = ("wavy", "fig2", "concave")
PRESETS = ("paper", "default")
LOSS_CASE = "wavy"  # the paper's first case: loss curves and meshes of the two neural methods
FOUR_METHOD_CASES = ("fig2", "concave")  # the paper's Fig. 2 geometry, and a concave one
LABELS = {
    "pinn": "Proposed (PINN)",
    "mgnet": "MGNet",
    "tfi": "Algebraic (TFI)",
    "elliptic": "PDE (elliptic)",
}
SHORT = {"pinn": "proposed", "mgnet": "MGNet", "tfi": "TFI", "elliptic": "PDE"}


@dataclass(frozen=True)
class Budget:
    """The sizes of one experiment mode. ``None`` epochs mean the preset's (paper: 5000/500)."""

    mode: str
    adam_epochs: int | None
    lbfgs_iterations: int | None
    size: tuple[int, int]
    loss_seeds: tuple[int, ...]  # seeds of the neural runs on LOSS_CASE (seed 0 is pictured)
    sweep_adam_epochs: int
    sweep_lbfgs_iterations: int
    sweep_layers: tuple[int, ...]
    sweep_neurons: tuple[int, ...]
    sweep_seeds: tuple[int, ...]
    sweep_fixed_neurons: int = 30  # paper Fig. 9a: layers varied at 30 neurons
    sweep_fixed_layers: int = 4  # paper Fig. 9b: neurons varied at 4 layers
    sweep_case: str = LOSS_CASE
    sweep_preset: str = "paper"
    lbfgs_points: int | None = None  # None: the preset's (1000)

    def to_dict(self) -> dict:
        return {k: (list(v) if isinstance(v, tuple) else v) for k, v in self.__dict__.items()}


BUDGETS = {
    "full": Budget(
        "full",
        None,
        None,
        (61, 31),
        (0, 1, 2),
        2000,
        200,
        (1, 2, 3, 4, 5, 6, 7),
        (10, 20, 30, 40, 50, 60),
        (0, 1, 2),
    ),
    "quick": Budget(
        "quick", 40, 5, (21, 11), (0, 1), 40, 5, (1, 4), (10, 30), (0, 1), lbfgs_points=200
    ),
}


@dataclass(frozen=True)
class Job:
    """One meshing run: ``group`` is "compare" (method comparison) or "sweep" (architecture)."""

    group: str
    case: str
    method: str
    preset: str
    seed: int = 0
    overrides: tuple[tuple[str, object], ...] = ()
    size: tuple[int, int] = (61, 31)
    device: str = "cpu"

    def record(self, error: str = "") -> dict:
        """The start of this run's result: what it is, not yet ok."""
        return {
            "key": self.key,
            "group": self.group,
            "case": self.case,
            "method": self.method,
            "preset": self.preset,
            "seed": self.seed,
            "ok": False,
            "error": error,
        }

    @property
    def key(self) -> str:
        extra = "".join(f"/{k}={v}" for k, v in self.overrides)
        return f"{self.group}/{self.case}/{self.preset}/{self.method}/seed{self.seed}{extra}"

    @property
    def label(self) -> str:
        """Short text for the progress bar."""
        over = dict(self.overrides)
        arch = f" {over['hidden_layers']}x{over['neurons']}" if "neurons" in over else ""
        return f"{self.case} {self.preset} {self.method}{arch} s{self.seed}"

    def settings(self):
        from pinn_engine.settings import make_settings

        return make_settings(
            self.method,
            self.preset,
            seed=self.seed,
            device=self.device,
            lattice=self.size,
            **dict(self.overrides),
        )

    def cost(self) -> float:
        """A rough relative run time, to weigh the progress bar and order the work."""
        if self.method not in NEURAL:
            return 0.1
        s = self.settings()
        # measured on 2 cores: time grows with depth and faster with width; the shortcut
        # network of the proposed method costs about twice MGNet's plain one
        size = max(0.3, 1 + 0.33 * (s.hidden_layers / 4 - 1) + 0.88 * (s.neurons / 30 - 1))
        per_epoch = 1.6 if self.method == "pinn" else 0.8
        return (s.adam_epochs * per_epoch + _lbfgs_weight(s)) * size / 100.0


@dataclass
class Plan:
    budget: Budget
    jobs: list[Job] = field(default_factory=list)


def make_plan(budget: Budget, device: str = "cpu") -> Plan:
    """Every run of a mode: the method comparisons, then the architecture sweep."""
    jobs: list[Job] = []
    points = (("lbfgs_points", budget.lbfgs_points),) if budget.lbfgs_points else ()
    train = (
        tuple(
            (k, v)
            for k, v in (
                ("adam_epochs", budget.adam_epochs),
                ("lbfgs_iterations", budget.lbfgs_iterations),
            )
            if v is not None
        )
        + points
    )
    for case in CASES:
        for preset in PRESETS:
            for method in METHODS:
                neural = method in NEURAL
                seeds = budget.loss_seeds if (neural and case == LOSS_CASE) else (0,)
                for seed in seeds:
                    jobs.append(
                        Job(
                            "compare",
                            case,
                            method,
                            preset,
                            seed,
                            train if neural else (),
                            budget.size,
                            device,
                        )
                    )
    configs = [(n, budget.sweep_fixed_neurons) for n in budget.sweep_layers]
    configs += [(budget.sweep_fixed_layers, w) for w in budget.sweep_neurons]
    for layers, neurons in dict.fromkeys(configs):
        for seed in budget.sweep_seeds:
            over = (
                ("adam_epochs", budget.sweep_adam_epochs),
                ("lbfgs_iterations", budget.sweep_lbfgs_iterations),
                ("hidden_layers", layers),
                ("neurons", neurons),
            ) + points
            jobs.append(
                Job(
                    "sweep",
                    budget.sweep_case,
                    "pinn",
                    budget.sweep_preset,
                    seed,
                    over,
                    budget.size,
                    device,
                )
            )
    return Plan(budget, jobs)


def case_files(example_dir: Path, case: str) -> tuple[Path, Path]:
    return example_dir / f"{case}.vtp", example_dir / f"{case}_aux.vtp"


def run_job(
    job: Job, example_dir: str | Path, progress: Callable[[float], None] | None = None
) -> dict:
    """Run ``job``; ``progress(fraction)`` is called during training. Never raises."""
    from pinn_engine.io.pipeline import load_aux, load_boundary
    from pinn_engine.kinds.four_sided.mesher import Mesher
    from pinn_engine.quality import included_angles

    out: dict = job.record()
    start = time.perf_counter()
    try:
        settings = job.settings()
        out["settings"] = settings.to_dict()
        out.update(
            hidden_layers=settings.hidden_layers,
            neurons=settings.neurons,
            boundary_mode=settings.boundary_mode,
            boundary_fit=settings.boundary_fit,
            elliptic_iterations=settings.elliptic_iterations,
        )
        if job.method in NEURAL:
            out.update(adam_epochs=settings.adam_epochs, lbfgs_iterations=settings.lbfgs_iterations)
        bpath, apath = case_files(Path(example_dir), job.case)
        boundary = load_boundary(bpath)
        aux = load_aux([apath], boundary)
        callback = _training_callback(settings, progress) if job.method in NEURAL else None
        mesher = Mesher(settings).fit(boundary, aux, callback)
        result = mesher.predict(*job.size, on_boundary=False)
    except Exception as exc:  # noqa: BLE001 - a failed run is a result, recorded and reported
        out["error"] = f"{type(exc).__name__}: {exc}"
        out["traceback"] = traceback.format_exc(limit=4)
        out["run_seconds"] = time.perf_counter() - start
        return out
    points = np.asarray(result.points, dtype=float)
    max_a, min_a = included_angles(points)
    report = result.report
    info = report.get("training", {})
    history = {k: [float(x) for x in v] for k, v in (result.history or {}).items()}
    n_total = len(history.get("total", []))
    n_adam = min(
        n_total,
        max(
            0,
            int(info.get("adam_epochs", out.get("adam_epochs", 0)))
            - int(info.get("recoveries", 0)),
        ),
    )
    out.update(
        ok=True,
        quality=dict(report["quality"]),
        train_seconds=float(report.get("train_seconds", 0.0)),
        mesh_seconds=float(report.get("mesh_seconds", 0.0)),
        run_seconds=time.perf_counter() - start,
        history=history,
        n_adam=n_adam,
        final={k: v[-1] for k, v in history.items() if v},
        lbfgs_accepted=info.get("lbfgs_accepted"),
        recoveries=info.get("recoveries", 0),
        points=points,
        max_angle=max_a,
        min_angle=min_a,
        boundary_ring=boundary.frame.to_user(boundary.ring),
        aux_lines=[boundary.frame.to_user(a.xy) for a in mesher.aux_lines_],
    )
    return out


def _lbfgs_weight(settings) -> float:
    """L-BFGS work in Adam epochs: up to 1.25 evaluations per iteration, each on more points."""
    return 1.25 * settings.lbfgs_iterations * (0.5 + 7.0 * settings.lbfgs_points / 1000)


def _training_callback(settings, progress: Callable[[float], None] | None):
    """Turn the trainer's ``info`` (phase, step, total) into a 0..1 fraction for ``progress``."""
    if progress is None:
        return None
    adam, lbfgs = settings.adam_epochs, _lbfgs_weight(settings)
    whole = max(adam + lbfgs, 1.0)

    def callback(info: dict) -> None:
        step, total = float(info.get("step", 0)), max(float(info.get("total", 1)), 1.0)
        part = min(step / total, 1.0)
        done = part * adam if info.get("phase") == "adam" else adam + part * lbfgs
        if math.isfinite(done):
            progress(min(done / whole, 0.99))

    return callback
