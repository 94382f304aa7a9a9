"""Where ``pinn-mesh DICT --format openfoam`` spends its CPU time, stage by stage (SPEC 15).

    .venv/bin/python benchmarks/blockmesh3d_stages.py              # example_data/blockmesh
    .venv/bin/python benchmarks/blockmesh3d_stages.py --runs 5 pipe
    .venv/bin/python benchmarks/blockmesh3d_stages.py CASE/system/blockMeshDict   # any other

Each run is a fresh process (first-touched memory is part of a stage's cost, as in the
command) that imports what the command imports, reads and places the dictionary, finds its
faces, computes checkMesh's figures of blockMesh's placement, solves the Winslow grid (as
the command: a swept section's slab), computes the figures of that grid (as the command: a
swept grid's on its slab, ``mesh.measure_of``), optimises the swept
section from it and computes the figures of that grid, SPEC 6's angles of the report, and
writes the polyMesh files (the dictionaries of ``example_data/blockmesh`` that are solved
are swept sections; a dictionary that is none stops after the Winslow grid's figures; the
default's second search, from blockMesh's placement, is not timed). Printed per
dictionary: each stage's CPU seconds (user and system of the process,
``time.process_time``), the medians of ``--runs``, and the load average.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OWN = ROOT / "example_data" / "blockmesh"

# one run, in its own process: the stages' CPU seconds as JSON on stdout
STAGES = """
import json, os, sys, tempfile, time
from pathlib import Path
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # as the pinn-mesh command
clock, out = time.process_time, {}
start = clock()
import numpy as np
import scipy.sparse
from pinn_engine import heap
from pinn_engine.blocks3d import checks, placement, section, winslow
from pinn_engine.blocks3d.dictionary import read
from pinn_engine.blocks3d.mesh import measure_of, winslow_grid
from pinn_engine.geometry.faces import topology
from pinn_engine.hexa.quality import included_angles
from pinn_engine.io.export.openfoam import write_hex_polymesh
heap.tune_process()
out["imports"] = clock() - start

def stage(name, work):
    began = clock()
    done = work()
    out[name] = clock() - began
    return done

placed = stage("place", lambda: placement.place(read(sys.argv[1])))
cells = np.vstack([checks.hexes(ids) for ids in placed.ids])
faces = stage("faces", lambda: topology(cells))
stage("figures (placement)", lambda: checks.figures(placed.points, cells, faces))
sec = section.section(placed, winslow.boundary_held(placed)[1])
points, _ = stage("Winslow solve", lambda: winslow_grid(placed, sec))
measure = measure_of(placed, sec, True, cells, faces)
solved = stage("figures (solved)", lambda: measure(points))
if sec is None:
    print(json.dumps(out))
    sys.exit()


def optimised():
    xy = section.least_non_orthogonal(section.start_of(points, sec), sec, solved.max_skewness)
    return section.swept(points, sec, xy)


points = stage("section", optimised)
stage("figures (section)", lambda: measure(points))
stage("angles", lambda: [included_angles(points[ids]) for ids in placed.ids])
with tempfile.TemporaryDirectory() as case:
    stage("write", lambda: write_hex_polymesh(points, faces, placed.patches, Path(case)))
print(json.dumps(out))
"""


def dictionary(name: str) -> Path:
    """A dictionary's path: one of ``example_data/blockmesh``'s by name, or a file."""
    return Path(name) if Path(name).is_file() else OWN / name / "system" / "blockMeshDict"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "names", nargs="*", default=["pipe", "bend", "dfg3d"], help="names or dictionary files"
    )
    parser.add_argument("--runs", type=int, default=3, help="fresh processes (their medians)")
    opts = parser.parse_args()
    before = os.getloadavg()[0]
    for name in opts.names:
        runs = [
            json.loads(
                subprocess.run(
                    [sys.executable, "-c", STAGES, str(dictionary(name))],
                    capture_output=True,
                    text=True,
                    check=True,
                ).stdout
            )
            for _ in range(opts.runs)
        ]
        medians = {k: statistics.median(r[k] for r in runs) for k in runs[0]}
        cells = ", ".join(f"{k} {v:.3f}" for k, v in medians.items())
        print(f"{name}: {cells}; sum {sum(medians.values()):.3f} s", flush=True)
    print(
        f"CPU seconds, medians of {opts.runs} fresh processes; load average {before:.1f} "
        f"before, {os.getloadavg()[0]:.1f} after"
    )


if __name__ == "__main__":
    main()
