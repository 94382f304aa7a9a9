"""A family's members on the batch's workers (SPEC 16): each member's default grid, the one
its own ``pinn-mesh`` run gives, and what the family model reads of it."""

from __future__ import annotations

import argparse
import copy
import time
from collections.abc import Iterator
from typing import TextIO

from pinn_engine.batch import pool
from pinn_engine.batch.manifest import Case
from pinn_engine.batch.pool import WarmPool
from pinn_engine.batch.progress import Bar
from pinn_engine.batch.task import error_row
from pinn_engine.errors import PinnMeshError
from pinn_engine.settings import DEFAULT_SIZE

FAMILY_KINDS = ("four-sided", "body", "blocks")  # the kinds a family model meshes in this build


def member_inputs(args: argparse.Namespace):
    """The settings and geometry of a member's single-run arguments, checked as the single
    run checks them; a kind no family model meshes is refused in one line."""
    from pinn_engine import job
    from pinn_engine.routes.cli.four_sided import check_inputs
    from pinn_engine.routes.cli.options import check_options, settings_from

    args = copy.deepcopy(args)
    kind = job.kind_of(args.boundary, bool(args.blocks), body=bool(args.topology or args.naca))
    if kind not in FAMILY_KINDS:
        raise PinnMeshError(
            f"a family model meshes four-sided domains, O- and C-grids and multi-block "
            f"domains in this build, not {kind} domains; fit without this member"
        )
    if args.model or args.load_model:
        raise PinnMeshError("a member to fit on is meshed by its own run: drop --model")
    if kind == "blocks":
        from pinn_engine.routes.cli.multiblock import blocks_inputs, check_blocks

        check_blocks(args)
        return blocks_inputs(args)
    args.method = args.method or "pinn"
    args.size = args.size or DEFAULT_SIZE
    check_inputs(args, kind == "body")
    check_options(args)
    settings = settings_from(args, tuple(args.size))
    geometry = job.geometry_from_files(
        settings, args.boundary, args.aux, args.corners, args.farfield is not None
    )
    return settings, geometry


def member_task(name: str, args: argparse.Namespace) -> dict:
    """One member in a worker: its default grid (``job.run``) and its family member, as a row
    (``status`` ok, ``member``, ``target``, ``seconds``), or an error row."""
    from pinn_engine import job

    began = time.perf_counter()
    try:
        settings, geometry = member_inputs(args)
        outcome, member = job.member_run(settings, geometry)
        target = job.member_target(member, outcome)
    except PinnMeshError as exc:
        return error_row(name, str(exc), time.perf_counter() - began)
    except Exception as exc:  # a bug or a failed run: the member's row, not the fit's end
        return error_row(name, f"{type(exc).__name__}: {exc}", time.perf_counter() - began)
    return {
        "name": name,
        "status": "ok",
        "member": member,
        "target": target,
        "quality": outcome.quality,
        "seconds": round(time.perf_counter() - began, 3),
    }


def member_rows(
    cases: list[Case],
    client=None,
    workers: int | None = None,
    scheduler: str | None = None,
    stream: TextIO | None = None,
) -> list[dict]:
    """Each case's member row (:func:`member_task`) in the cases' order, on ``client``, a
    local pool of ``workers`` (a small batch), a local Dask cluster or ``scheduler``'s;
    ``stream`` gets the progress line."""
    todo = [(case.name, case.args) for case in cases]
    bar = Bar(len(todo), 0, stream) if stream else None
    rows: dict[str, dict] = {}

    def collect(results: Iterator[tuple[str, dict]]) -> None:
        for name, row in results:
            rows[name] = row
            if bar:
                bar.update(row["status"] == "error")

    from pinn_engine.batch.api import dask_results

    if client is not None:
        collect(dask_results(client, todo, member_task))
    elif pool.small(len(todo), scheduler):
        collect(WarmPool(workers, member_task).results(todo))
    else:
        from pinn_engine.batch.cluster import connect

        with connect(workers, scheduler) as own:
            collect(dask_results(own, todo, member_task))
    if bar:
        bar.close()
    return [rows[case.name] for case in cases]
