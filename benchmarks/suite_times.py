"""How long the test tiers take: `make check`'s (not slow, not paraview) and the slow one.

Usage: ``.venv/bin/python benchmarks/suite_times.py [--tier fast|slow|both] [--top 15]``,
from the repository root. Each tier runs in a Python of its own (pytest.main); for each
test the wall seconds and the CPU seconds of that process and its children are recorded, so
that a machine shared with other work can still compare tests with each other (CPU), while
the wall total is the figure the bounds are about (docs/testing.md).
"""

from __future__ import annotations

import argparse
import resource
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

TIERS = {"fast": "not slow and not paraview", "slow": "slow and not paraview"}


def _cpu() -> float:
    """CPU seconds of this process and of its children that have ended."""
    used = [resource.getrusage(who) for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)]
    return sum(u.ru_utime + u.ru_stime for u in used)


class Timer:
    """A pytest plugin: (CPU seconds, wall seconds) of each test, setup to teardown."""

    def __init__(self) -> None:
        self.rows: dict[str, tuple[float, float]] = {}

    @pytest.hookimpl(hookwrapper=True)
    def pytest_runtest_protocol(self, item, nextitem):
        cpu, wall = _cpu(), time.perf_counter()
        yield
        self.rows[item.nodeid] = (_cpu() - cpu, time.perf_counter() - wall)


def run(tier: str, top: int) -> int:
    sys.path.insert(0, str(ROOT))  # as ``python -m pytest`` from the root: ``experiments``
    timer = Timer()
    began = time.perf_counter()
    status = pytest.main(["-q", "-p", "no:cacheprovider", "-m", TIERS[tier]], plugins=[timer])
    wall = time.perf_counter() - began
    cpu = sum(c for c, _ in timer.rows.values())
    print(f"\n{tier} tier: {len(timer.rows)} tests, {wall:.0f} s wall in all, {cpu:.0f} s CPU")
    for nodeid, (c, w) in sorted(timer.rows.items(), key=lambda r: -r[1][0])[:top]:
        print(f"  {w:6.1f} s wall {c:6.1f} s CPU  {nodeid}")
    return int(status)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tier", choices=[*TIERS, "both"], default="both")
    parser.add_argument("--top", type=int, default=15, help="the tests of most CPU seconds to list")
    args = parser.parse_args()
    if args.tier != "both":
        return run(args.tier, args.top)
    command = [sys.executable, __file__, "--top", str(args.top), "--tier"]
    return max(subprocess.run([*command, tier]).returncode for tier in TIERS)


if __name__ == "__main__":
    sys.exit(main())
