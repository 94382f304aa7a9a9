"""Run a batch: skip the cases done by an earlier run, submit the others to the cluster, turn
each finished future into its summary row and keep ``summary.csv`` up to date."""

from __future__ import annotations

import os
import sys
import time
import uuid
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import TextIO

from pinn_engine.batch import summary
from pinn_engine.batch.manifest import Case, cases_of, read_manifest
from pinn_engine.batch.progress import Bar
from pinn_engine.batch.task import error_row, prepared, run_case

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
        return error_row(name, "the worker meshing it died each time it was tried")
    return error_row(name, f"{type(exc).__name__}: {exc}")


def run(
    client,
    cases: list[Case],
    outdir: str | os.PathLike,
    force: bool = False,
    stream: TextIO | None = None,
) -> list[dict]:
    """Mesh ``cases`` on ``client``'s workers into ``outdir``; the summary rows in the cases'
    order. A case whose grid exists and whose earlier row is done is skipped unless
    ``force``; ``stream`` gets the progress line (None: no progress)."""
    from distributed import as_completed

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
    token = uuid.uuid4().hex[:8]  # this run's task keys differ from an earlier run's
    futures = {
        client.submit(run_case, name, args, key=f"pinn-mesh-{name}-{token}"): name
        for name, args in todo
    }
    written = time.perf_counter()
    try:
        for future in as_completed(futures):
            name = futures[future]
            try:
                rows[name] = future.result()
            except Exception as exc:  # the task, not the case, failed
                rows[name] = _failure(name, exc)
            if bar:
                bar.update(rows[name]["status"] == "error")
            if time.perf_counter() - written > SUMMARY_EVERY:
                write()
                written = time.perf_counter()
    finally:
        client.cancel([f for f in futures if not f.done()])
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
    without one, a local cluster of ``workers`` processes (default: one per core) or the
    scheduler at ``scheduler`` is used for this call. ``force`` redoes cases done by an
    earlier call; ``progress`` draws the progress line on stderr.
    """
    from pinn_engine.batch.cluster import connect, prepare

    todo = as_cases(cases)
    stream = sys.stderr if progress else None
    if client is not None:
        prepare(client)
        return _table(run(client, todo, outdir, force, stream))
    with connect(workers, scheduler) as own:
        return _table(run(own, todo, outdir, force, stream))
