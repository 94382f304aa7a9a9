"""Run a batch: skip the cases done by an earlier run, submit the others to the cluster, turn
each finished future into its summary row and keep ``summary.csv`` up to date."""

from __future__ import annotations

import os
import sys
import time
import uuid
from collections.abc import Iterable, Iterator, Mapping
from pathlib import Path
from typing import TextIO

from pinn_engine.batch import pool, summary, warm
from pinn_engine.batch.manifest import Case, cases_of, read_manifest
from pinn_engine.batch.pool import Todo, WarmPool
from pinn_engine.batch.progress import Bar
from pinn_engine.batch.task import DIED, error_row, prepared, run_case

SUMMARY_EVERY = 2.0  # seconds between rewrites of summary.csv while cases finish
Cases = str | os.PathLike | Iterable[Case | Mapping[str, str]]


def as_cases(cases: Cases) -> list[Case]:
    """The cases of a manifest path, or of records ``{name, input, aux, options}`` (paths
    relative to the working folder; ``aux`` a list or a ``;``-separated string)."""
    if isinstance(cases, (str, os.PathLike)):
        return read_manifest(cases)
    items = list(cases)
    records = [
        (k, {**c, "aux": ";".join(c["aux"]) if isinstance(c.get("aux"), list) else c.get("aux")})
        for k, c in enumerate(items, start=1)
        if not isinstance(c, Case)
    ]
    if not records:
        return items
    if len(records) != len(items):
        raise TypeError("give either Case objects or records, not both")
    return cases_of(records, Path(), "cases")


def _failure(name: str, exc: BaseException) -> dict:
    """The row of a case whose task itself failed (its worker died too often, mostly)."""
    from distributed import KilledWorker

    if isinstance(exc, KilledWorker):
        return error_row(name, DIED)
    return error_row(name, f"{type(exc).__name__}: {exc}")


def dask_results(client, todo: Todo, task=run_case) -> Iterator[tuple[str, dict]]:
    """Each case's name and row (``task``'s, default the summary row of
    :func:`.task.run_case`) from ``client``'s workers, as the cases finish; the cases left
    are cancelled when the caller stops asking."""
    from distributed import as_completed

    token = uuid.uuid4().hex[:8]  # this run's task keys differ from an earlier run's
    futures = {
        client.submit(task, name, args, key=f"pinn-mesh-{name}-{token}"): name
        for name, args in todo
    }
    try:
        for future in as_completed(futures):
            name = futures[future]
            try:
                yield name, future.result()
            except Exception as exc:  # the task, not the case, failed
                yield name, _failure(name, exc)
    finally:
        client.cancel([f for f in futures if not f.done()])


def run(
    client,
    cases: list[Case],
    outdir: str | os.PathLike,
    force: bool = False,
    stream: TextIO | None = None,
) -> list[dict]:
    """Mesh ``cases`` on ``client``'s workers (a Dask client, or a :class:`.pool.WarmPool`)
    into ``outdir``; the summary rows in the cases' order. A case whose grid exists and whose
    earlier row is done is skipped unless ``force``; ``stream`` gets the progress line (None:
    no progress)."""
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    earlier = summary.read_rows(outdir)
    rows: dict[str, dict] = {}
    todo = []
    for case in cases:
        args, before = prepared(case, outdir), earlier.get(case.name)
        if not force and before and before["status"] in summary.DONE:
            if Path(args.output).exists():
                rows[case.name] = before
                continue
        todo.append((case.name, args))

    def write() -> None:
        summary.write_rows(outdir, [rows[c.name] for c in cases if c.name in rows])

    bar = Bar(len(cases), len(cases) - len(todo), stream) if stream else None
    results = client.results(todo) if isinstance(client, WarmPool) else dask_results(client, todo)
    written = time.perf_counter()
    try:
        for name, row in results:
            rows[name] = row
            if bar:
                bar.update(row["status"] == "error")
            if time.perf_counter() - written > SUMMARY_EVERY:
                write()
                written = time.perf_counter()
    finally:
        results.close()
        write()
        if bar:
            bar.close()
    return [rows[c.name] for c in cases]


def _table(rows: list[dict]):
    """The rows as a pandas DataFrame when pandas is installed, else as they are."""
    try:
        import pandas as pd
    except ImportError:
        return rows
    return pd.DataFrame(rows, columns=summary.COLUMNS)


def mesh_many(
    cases: Cases,
    client=None,
    outdir: str | os.PathLike = "out/batch",
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    force: bool = False,
    progress: bool = False,
):
    """Mesh many cases (a manifest path or records, see :func:`as_cases`) into ``outdir``,
    each as the single-run command would, and return the summary: a list of row dicts, or
    a pandas DataFrame when pandas is installed.

    ``client``: a ``distributed.Client`` to run on (its workers are set up for meshing);
    without one, ``workers`` local processes (default: one per core; a warm process pool for
    at most ``pool.SMALL_BATCH`` cases, a local Dask cluster for more) or the scheduler at
    ``scheduler`` is used for this call. ``force`` redoes cases done by an
    earlier call; ``progress`` draws the progress line on stderr.
    """
    todo = as_cases(cases)
    stream = sys.stderr if progress else None
    if client is None and pool.small(len(todo), scheduler):
        warm.require_dask()
        return _table(run(WarmPool(workers), todo, outdir, force, stream))
    from pinn_engine.batch.cluster import connect, prepare

    if client is not None:
        prepare(client)
        return _table(run(client, todo, outdir, force, stream))
    with connect(workers, scheduler) as own:
        return _table(run(own, todo, outdir, force, stream))
