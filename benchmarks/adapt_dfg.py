"""DFG 2D-1 in simpleFoam on a grid adapted to its own first solution (SPEC 14): drag, lift
and pressure difference against the published values, before and after, beside the
unadapted grid with twice the cells (docs/adaptation.md).

    .venv/bin/python benchmarks/adapt_dfg.py [--size 0.01] [--array U]     # minutes

Rows, each one ``examples/openfoam_dfg/run.sh`` in ``out/adapt_dfg/<row>``:
- ``plain``: the unadapted grid at cell size ``--size``, solved; its result is the field;
- ``adapted``: the same command with ``--adapt plain/case.foam:ARRAY`` (the route as a user
  runs it: the grid is kept unadapted where no strength lowers the field's interpolation
  error);
- ``adapted, kept``: the same, with the adapted grid kept whatever its interpolation error
  (the best of the strengths tried): the field was solved on the unadapted grid, so that
  grid interpolates it exactly (its error is the field's resampling error alone) and the
  rule cannot judge it; this row shows what the adapted grid gives in the solver;
- ``twice``: the unadapted grid with about twice the cells (cell size over sqrt 2).

``--mesh-kept ARGS`` is the pinn-mesh command of the third row (run.sh's PINN_MESH).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

from dfg_openfoam import markdown, run  # noqa: E402

OUT = ROOT / "out" / "adapt_dfg"


def mesh_kept(args: list[str]) -> int:
    """pinn-mesh with ``args``, the unadapted grid's interpolation error taken as infinite
    (so the best adapted try is kept)."""
    import pinn_engine.adapt.grids as grids
    from pinn_engine.command import main

    measured = grids.interpolation_error
    calls = []

    def unadapted_worst(points, cells, sample):
        calls.append(1)
        return math.inf if len(calls) == 1 else measured(points, cells, sample)

    grids.interpolation_error = unadapted_worst
    sys.argv = ["pinn-mesh", *args]
    return main()


def main() -> None:
    if len(sys.argv) > 1 and sys.argv[1] == "--mesh-kept":
        sys.exit(mesh_kept(sys.argv[2:]))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=float, default=0.01)
    parser.add_argument("--array", default="U")
    args = parser.parse_args()
    h = args.size
    field = str(OUT / "plain" / "case.foam") + f":{args.array}"
    kept = OUT / "mesh_kept.sh"
    OUT.mkdir(parents=True, exist_ok=True)
    kept.write_text(f'#!/bin/sh\nexec "{sys.executable}" "{Path(__file__)}" --mesh-kept "$@"\n')
    kept.chmod(0o755)
    rows = []
    for name, size, extra in (
        ("unadapted", h, {}),
        (f"adapted to {args.array}", h, {"ADAPT": field}),
        (f"adapted to {args.array}, kept", h, {"ADAPT": field, "PINN_MESH": str(kept)}),
        ("unadapted, twice the cells", h / math.sqrt(2), {}),
    ):
        case = OUT / ("plain" if not extra else name.replace(" ", "_").replace(",", ""))
        if not extra and size != h:
            case = OUT / "twice"
        rows.append((name, size, run("pinn-mesh", size, case=case, extra=extra)))
        print(markdown(rows[-1:]).splitlines()[-2], flush=True)
    print(markdown(rows), end="")


if __name__ == "__main__":
    main()
