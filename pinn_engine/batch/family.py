"""Family models in Python (SPEC 16): ``fit_family(boundaries, **options)`` in the shape of
scikit-learn's estimators (configure, ``fit`` once, then ``mesh`` any member, fast), and
``fit_manifest``, the command's fit of a manifest's members."""

from __future__ import annotations

import os
import shlex
import sys
import tempfile
import time
from collections.abc import Callable, Iterable
from pathlib import Path

from pinn_engine.batch.api import Cases, as_cases
from pinn_engine.batch.members import member_rows
from pinn_engine.errors import PinnMeshError

# What FamilyMesher takes besides the single run's options: how the fit runs
FIT_OPTIONS = ("workers", "scheduler", "client", "epochs", "seed")
REPORT_SHARE = 0.1  # a progress line each time this share of the epochs is done


def fit_manifest(
    cases: Cases,
    output: str | os.PathLike | None = None,
    *,
    client=None,
    workers: int | None = None,
    scheduler: str | None = None,
    epochs: int | None = None,
    seed: int = 0,
    stream=None,
):
    """Fit a family model on the members of ``cases`` (a manifest's path or records): their
    default grids on the batch's workers, then the network; saved at ``output`` when given.
    Returns the model (``job.load_family``'s kind) and the failed members' rows; raises
    ``PinnMeshError`` when fewer than three members gave a grid."""
    from pinn_engine import job

    cases = as_cases(cases)
    began = time.perf_counter()
    if stream:
        print(f"the members' default grids ({len(cases)} members):", file=stream, flush=True)
    rows = member_rows(cases, client, workers, scheduler, stream)
    failed = [row for row in rows if row["status"] == "error"]
    good = [row for row in rows if row["status"] == "ok"]
    if len(good) < 3:
        first = f"; {failed[0]['name']}: {failed[0]['message']}" if failed else ""
        raise PinnMeshError(
            f"{len(good)} of {len(rows)} members gave a grid; a family needs at least 3{first}"
        )
    targets_seconds = time.perf_counter() - began
    options = shlex.join(_options_of(cases[0]))
    model = job.fit_family_model(
        [row["member"] for row in good],
        [row["target"] for row in good],
        options,
        epochs,
        seed,
        _fit_progress(stream) if stream else None,
    )
    model.report.update(
        failed_members=[row["name"] for row in failed],
        targets_seconds=targets_seconds,
        member_seconds=sorted(row["seconds"] for row in good),
    )
    if output is not None:
        model.save(output)
        model.path = str(output)
    return model, failed


def _options_of(case) -> list[str]:
    """The options of a member's row that make its family, as the command line writes them."""
    args = case.args
    words = ["--size", *map(str, args.size)] if args.size else []
    for flag, value in (("--topology", args.topology), ("--farfield", args.farfield)):
        if value is not None:
            words += [flag, str(value)]
    interfaces = ("--interfaces", getattr(args, "interfaces", None))
    for flag, value in (("--method", args.method), ("--objective", args.objective), interfaces):
        if value is not None:
            words += [flag, str(value)]
    return words


def _fit_progress(stream) -> Callable[[dict], None]:
    """The network's training as a line per tenth of its epochs."""
    shown = [-1]

    def progress(info: dict) -> None:
        step = int(info["epoch"] / info["total"] / REPORT_SHARE)
        if step != shown[0] or info["epoch"] == info["total"]:
            shown[0] = step
            print(
                f"fitting the network: epoch {info['epoch']}/{info['total']}, "
                f"loss {info['loss']:.3g}, {info['seconds']:.1f} s",
                file=stream,
                flush=True,
            )

    return progress


def _flag(name: str, value) -> list[str]:
    """A keyword option as the command line's words (``size=(41, 21)`` is ``--size 41 21``)."""
    flag = "--" + name.replace("_", "-")
    if isinstance(value, bool):
        return [flag] if value else []
    if isinstance(value, dict):
        return [flag, ",".join(f"{k}={v}" for k, v in value.items())]
    if isinstance(value, (list, tuple)):
        return [flag, *map(str, value)]
    return [flag, str(value)]


class FamilyMesher:
    """One model for a family of shapes (SPEC 16), in scikit-learn's shape.

    ``FamilyMesher(size=(41, 21), topology=None, ..., workers=None, epochs=None, seed=0)``
    takes the single run's options as keywords (the same for every member) and how to fit;
    :meth:`fit` meshes each member by its own default run (on local worker processes, or a
    Dask cluster: ``workers``, ``scheduler``, ``client``) and fits the model; :meth:`mesh`
    meshes a new member in a forward pass. Fitted attributes: ``model_``, ``failed_`` (the
    members that gave no grid, their rows), ``fit_seconds_``.

    >>> family = fit_family(["a.vtp", "b.vtp", "c.vtp"], size=(41, 21))
    >>> grid = family.mesh("d.vtp")                  # a pyvista.StructuredGrid
    >>> family.save("channels.pt")
    """

    def __init__(self, **options) -> None:
        self.options = options

    def _run_options(self) -> dict:
        return {k: v for k, v in self.options.items() if k not in FIT_OPTIONS}

    def fit(self, boundaries: Iterable, progress: bool = False) -> FamilyMesher:
        """Fit on ``boundaries``: files (a four-sided boundary, an airfoil ``.dat``, ...) or
        pyvista/VTK polydata; ``progress`` prints the fit's progress on stderr."""
        began = time.perf_counter()
        fit = {k: v for k, v in self.options.items() if k in FIT_OPTIONS}
        words = [w for k, v in self._run_options().items() for w in _flag(k, v)]
        with tempfile.TemporaryDirectory(prefix="pinn-mesh-family-") as scratch:
            records = [
                {"name": f"member{k:03d}", "input": _as_file(b, Path(scratch), k), "aux": "",
                 "options": shlex.join(words)}
                for k, b in enumerate(boundaries)
            ]  # fmt: skip
            self.model_, self.failed_ = fit_manifest(
                records, stream=sys.stderr if progress else None, **fit
            )
        self.fit_seconds_ = time.perf_counter() - began
        return self

    def mesh(self, boundary, **options):
        """The grid of a member (polydata, points or a file) by the model: a
        ``pyvista.StructuredGrid`` (SPEC 3), its field data ``NetworkResult`` ``family``
        (``start`` where the guard kept the member's own start, with a warning)."""
        from pinn_engine.routes.pyvista_accessor import pinn_mesh

        self._check_fitted()
        run = {**self._run_options(), **options}
        run.setdefault("size", tuple(self.model_.size))
        if isinstance(boundary, (str, os.PathLike)) and run.get("topology") in (None, "none"):
            import pyvista as pv

            boundary = pv.read(boundary)
        return pinn_mesh(boundary, model=self.model_, **run)

    def save(self, path: str | os.PathLike) -> Path:
        """Write the model (``pinn-mesh BOUNDARY --model PATH`` meshes with it)."""
        self._check_fitted()
        out = self.model_.save(path)
        self.model_.path = str(path)
        return out

    @classmethod
    def load(cls, path: str | os.PathLike, **options) -> FamilyMesher:
        """A fitted FamilyMesher from a saved model (``options``: the members' run options,
        when meshing needs them, such as ``topology``)."""
        from pinn_engine import job

        mesher = cls(**options)
        mesher.model_ = job.load_family(path)
        mesher.failed_, mesher.fit_seconds_ = [], 0.0
        if mesher.model_.topology != "none":
            mesher.options.setdefault("topology", mesher.model_.topology)
        return mesher

    def _check_fitted(self) -> None:
        if not hasattr(self, "model_"):
            raise PinnMeshError("this FamilyMesher is not fitted yet: call fit(boundaries) first")


def _as_file(boundary, folder: Path, k: int) -> str:
    """A member's input as a file path: a path as it is, polydata written into ``folder``."""
    if isinstance(boundary, (str, os.PathLike)):
        return str(Path(boundary).resolve())
    import pyvista as pv

    path = folder / f"member{k:03d}.vtp"
    pv.wrap(boundary).save(path)
    return str(path)


def fit_family(boundaries: Iterable, progress: bool = False, **options) -> FamilyMesher:
    """``FamilyMesher(**options).fit(boundaries)``: one model for the family of
    ``boundaries`` (SPEC 16)."""
    return FamilyMesher(**options).fit(boundaries, progress)


def load_family(path: str | os.PathLike, **options) -> FamilyMesher:
    """The :class:`FamilyMesher` of a model saved by ``pinn-mesh fit`` or :meth:`save`."""
    return FamilyMesher.load(path, **options)
