"""``pinn-mesh fit MANIFEST -o FAMILY.pt [--workers N | --scheduler ADDRESS]`` (SPEC 16): one
family model fitted on a manifest's members (SPEC 12's CSV), their default grids computed on
the batch's workers. Exit status 0 when every member gave a grid, 1 when some failed (the
model is fitted on the others), 2 for a bad manifest or when no model could be fitted."""

from __future__ import annotations

import argparse
import sys

from pinn_engine.batch import pool, warm
from pinn_engine.batch.cli import EXIT_FAILED, manifest_parser, read_cases
from pinn_engine.errors import PinnMeshError
from pinn_engine.routes.cli.parser import EXIT_ERROR, EXIT_INTERRUPTED


def build_parser() -> argparse.ArgumentParser:
    p = manifest_parser(
        "pinn-mesh fit",
        "Fit one family model on the members of a manifest (CSV: "
        "name,input,aux,options; the same options for every member): each member meshed by "
        "its own default run, then the network; pinn-mesh BOUNDARY --model FAMILY.pt meshes "
        "a new member in a forward pass.",
        "FAMILY.pt",
        "the model file",
    )
    p.add_argument("--epochs", type=int, metavar="N", help="the network's training epochs")
    p.add_argument("--seed", type=int, default=0, metavar="N", help="the network's seed")
    return p


def main(argv: list[str]) -> int:
    """Fit the family model; returns the exit status."""
    from pinn_engine.batch.family import fit_manifest

    parser = build_parser()
    args = parser.parse_args(argv)
    if args.epochs is not None and args.epochs < 1:
        parser.error(f"--epochs {args.epochs}: give at least 1")
    cases = read_cases(parser, args)
    if cases is None:
        return EXIT_ERROR
    if not args.scheduler:  # the local workers' server imports while this process does
        warm.start(dask=not pool.small(len(cases), args.scheduler))
    try:
        model, failed = fit_manifest(
            cases,
            args.output,
            workers=args.workers,
            scheduler=args.scheduler,
            epochs=args.epochs,
            seed=args.seed,
            stream=sys.stderr,
        )
    except KeyboardInterrupt:
        print("pinn-mesh fit: interrupted; no model written", file=sys.stderr)
        return EXIT_INTERRUPTED
    except (OSError, TimeoutError, PinnMeshError) as exc:
        print(f"pinn-mesh fit: error: {exc}", file=sys.stderr)
        return EXIT_ERROR
    r = model.report
    counts = f"{r['size'][0]} x {r['size'][1]}" if r["kind"] != "blocks" else r["topology"]
    print(
        f"wrote {args.output}: a family of {r['members']} {model_kind(r)} "
        f"({counts}), fitted in {r['targets_seconds']:.1f} s "
        f"(members' grids) + {r['fit_seconds']:.1f} s (model); encoding "
        f"{r['encoding_components']} components, {r['correction_modes']} correction modes"
    )
    for row in failed:
        print(f"pinn-mesh fit: member {row['name']} failed: {row['message']}", file=sys.stderr)
    return EXIT_FAILED if failed else 0


def model_kind(report: dict) -> str:
    """The members' kind in words."""
    if report["kind"] == "blocks":
        return "multi-block grids"
    return {"o": "O-grids", "c": "C-grids"}.get(report["topology"], "four-sided grids")
