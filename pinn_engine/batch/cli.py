"""``pinn-mesh batch MANIFEST -o OUTDIR [--workers N | --scheduler ADDRESS] [--force]``
(SPEC 12): exit status 0 when every case gave a grid, 1 when some failed, 2 for a bad
manifest (or a scheduler that cannot be reached, an OUTDIR that cannot be written)."""

from __future__ import annotations

import argparse
import sys

from pinn_engine.batch import pool, warm
from pinn_engine.batch.manifest import ManifestError, read_manifest
from pinn_engine.errors import MissingExtraError, PinnMeshError
from pinn_engine.routes.cli.parser import EXIT_ERROR, EXIT_INTERRUPTED, OneLineParser

EXIT_FAILED = 1  # some cases got an error row; the others were meshed
# why a cluster shows no dashboard: its scheduler runs without one, or without bokeh
NO_DASHBOARD = (
    "none (the scheduler serves no pages: started without a dashboard, or without bokeh; "
    "pip install 'pinn-mesh[batch]' where it runs)"
)
# why a small local batch shows none
POOL_DASHBOARD = f"none (up to {pool.SMALL_BATCH} cases run on local processes, without Dask)"


def manifest_parser(prog: str, description: str, output: str, output_help: str) -> OneLineParser:
    """The arguments every manifest command takes: the manifest, ``-o`` and where it runs."""
    p = OneLineParser(prog=prog, description=description)
    p.add_argument("manifest", help="CSV with the header name,input,aux,options")
    p.add_argument("-o", "--output", required=True, metavar=output, help=output_help)
    where = p.add_mutually_exclusive_group()
    where.add_argument(
        "--workers", type=int, metavar="N", help="local worker processes (default: the cores)"
    )
    where.add_argument(
        "--scheduler", metavar="ADDRESS", help="run on the Dask scheduler at tcp://host:port"
    )
    return p


def read_cases(parser: argparse.ArgumentParser, args: argparse.Namespace) -> list | None:
    """The manifest's cases once the worker count is checked and Dask is there; None after a
    one-line error (exit status ``EXIT_ERROR``)."""
    if args.workers is not None and args.workers < 1:
        parser.error(f"--workers {args.workers}: give at least 1")
    try:
        cases = read_manifest(args.manifest)
        warm.require_dask()
    except (ManifestError, MissingExtraError) as exc:
        print(f"{parser.prog}: error: {exc}", file=sys.stderr)
        return None
    return cases


def build_parser() -> argparse.ArgumentParser:
    p = manifest_parser(
        "pinn-mesh batch",
        "Mesh every case of a manifest (CSV: name,input,aux,options) on a Dask "
        "cluster; each case as the single-run command would mesh it.",
        "OUTDIR",
        "the grids and summary.csv",
    )
    p.add_argument("--force", action="store_true", help="redo the cases an earlier run did")
    return p


def main(argv: list[str]) -> int:
    """Run the batch; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    cases = read_cases(parser, args)
    if cases is None:
        return EXIT_ERROR
    small = pool.small(len(cases), args.scheduler)
    if not args.scheduler:  # the local workers' server imports while this process does
        warm.start(dask=not small)
    from pinn_engine.batch.api import run

    try:
        if small:
            print(f"Dask dashboard: {POOL_DASHBOARD}", file=sys.stderr, flush=True)
            rows = run(pool.WarmPool(args.workers), cases, args.output, args.force, sys.stderr)
        else:
            from pinn_engine.batch.cluster import connect, dashboard

            with connect(args.workers, args.scheduler) as client:
                link = dashboard(client) or NO_DASHBOARD
                print(f"Dask dashboard: {link}", file=sys.stderr, flush=True)
                rows = run(client, cases, args.output, args.force, sys.stderr)
    except KeyboardInterrupt:
        print(
            f"pinn-mesh batch: interrupted; the cases done are in {args.output}/summary.csv",
            file=sys.stderr,
        )
        return EXIT_INTERRUPTED
    except (OSError, TimeoutError, PinnMeshError) as exc:  # no scheduler, OUTDIR not writable
        print(f"pinn-mesh batch: error: {exc}", file=sys.stderr)
        return EXIT_ERROR
    failed = sum(row["status"] == "error" for row in rows)
    warned = sum(row["status"] == "warning" for row in rows)
    print(
        f"wrote {args.output}/summary.csv: {len(rows) - failed - warned} ok, "
        f"{warned} with a warning, {failed} failed"
    )
    if failed:
        print(
            f"pinn-mesh batch: {failed} of {len(rows)} cases failed (their messages are in "
            f"{args.output}/summary.csv)",
            file=sys.stderr,
        )
        return EXIT_FAILED
    return 0
