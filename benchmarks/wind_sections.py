"""Wind-turbine blade sections for the real-airfoil benchmark (``airfoil_set.py``).

Extracts, from snapshots of the IEA Wind Task 37 reference turbines' repositories (git
directories, as the project's ``fetch`` tool leaves them: ``fetch
github:IEAWindTask37/IEA-15-240-RWT`` and likewise IEA-10.0-198-RWT, IEA-3.4-130-RWT,
IEA-22-280-RWT), every blade section:

- the OpenFAST (AeroDyn) airfoil files ``*_Coords.txt``, copied as they are (``N NumCoords``,
  ``!`` comments, the reference point, then the coordinates; pinn-mesh reads the format):
  ``<turbine>_AFnn.dat``, every ``EVERY``-th along the span (default 2: the files
  interpolate between the masters, so neighbours differ little);
- the windIO ontology's airfoils (``airfoils: - name, coordinates: {x: [...], y: [...]}``),
  written as Selig-style files in the ontology's point order: ``<turbine>_<name>.dat``.

The files are not committed (about 1.5 MB); this script makes them again::

    python benchmarks/wind_sections.py OUT_FOLDER [MIRROR_ROOT] [EVERY]

``MIRROR_ROOT`` (default ``/work/.mirror``) holds ``IEAWindTask37+<repo>/repo``.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import yaml

TURBINES = {  # repository: (short name, windIO ontology inside it)
    "IEA-15-240-RWT": ("iea15", "WT_Ontology/IEA-15-240-RWT.yaml"),
    "IEA-10.0-198-RWT": ("iea10", "yaml/IEA-10-198-RWT.yaml"),
    "IEA-3.4-130-RWT": ("iea3p4", "yaml/IEA-3.4-130-RWT.yaml"),
    "IEA-22-280-RWT": ("iea22", "windIO/IEA-22-280-RWT.yaml"),
}


def _git(repo: Path, *args: str) -> str:
    return subprocess.run(
        ["git", "-C", str(repo), *args], capture_output=True, text=True, check=True
    ).stdout


def extract(out: Path, mirrors: Path, every: int = 2) -> list[Path]:
    """The sections of every turbine found under ``mirrors`` (every ``every``-th OpenFAST
    file, every windIO airfoil), written into ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for repo, (short, ontology) in TURBINES.items():
        git = mirrors / f"IEAWindTask37+{repo}" / "repo"
        if not git.exists():
            print(f"{git}: missing (fetch github:IEAWindTask37/{repo})", file=sys.stderr)
            continue
        files = _git(git, "ls-tree", "-r", "--name-only", "HEAD").splitlines()
        coords: dict[str, str] = {}  # one file a section number (some repositories hold two)
        for name in sorted(f for f in files if f.endswith("_Coords.txt")):
            coords.setdefault(re.search(r"AF(\d+)_Coords", name)[1], name)
        for number in sorted(coords)[::every]:
            target = out / f"{short}_AF{number}.dat"
            target.write_text(_git(git, "show", f"HEAD:{coords[number]}"))
            written.append(target)
        if ontology in files:
            # some ontologies repeat an anchor name (YAML refuses that): anchors dropped,
            # aliases read as null (no airfoil coordinate is an alias)
            text = _git(git, "show", f"HEAD:{ontology}")
            text = re.sub(r"\*id\d+", "null", re.sub(r"&id\d+", "", text))
            data = yaml.safe_load(text)
            for foil in data.get("airfoils", []):
                xy = foil["coordinates"]
                stem = re.sub(r"[^A-Za-z0-9]+", "_", foil["name"]).strip("_")
                target = out / f"{short}_{stem}.dat"
                rows = "".join(
                    f"{float(x):.10g} {float(y):.10g}\n" for x, y in zip(xy["x"], xy["y"])
                )
                target.write_text(f"{foil['name']}\n{rows}")
                written.append(target)
    return written


if __name__ == "__main__":
    args = sys.argv[1:]
    mirrors = Path(args[1] if len(args) > 1 else "/work/.mirror")
    found = extract(Path(args[0]), mirrors, int(args[2]) if len(args) > 2 else 2)
    print(f"{len(found)} sections written to {sys.argv[1]}")
