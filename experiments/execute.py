"""Run the jobs of a plan, in-process or over worker processes, with a progress bar."""

from __future__ import annotations

import hashlib
import json
import multiprocessing as mp
import os
import pickle
import queue as queue_mod
import sys
import time
from collections.abc import Callable
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from pathlib import Path
from typing import TextIO

from .runs import Job, run_job


def clock(seconds: float) -> str:
    """``seconds`` as h:mm:ss (rounded, never negative)."""
    seconds = max(int(round(seconds)), 0)
    return f"{seconds // 3600:d}:{seconds // 60 % 60:02d}:{seconds % 60:02d}"


class ProgressBar:
    """A text bar on ``stream``: one updating line on a terminal, a line per 2 % otherwise."""

    def __init__(
        self, total: float, stream: TextIO | None = None, width: int = 30, enabled: bool = True
    ) -> None:
        self.total = max(float(total), 1e-9)
        self.stream = stream if stream is not None else sys.stderr
        self.width, self.enabled = width, enabled
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self.start = time.perf_counter()
        self.done, self.label = 0.0, ""
        self._last_draw, self._last_step = 0.0, -1

    def text(self) -> str:
        frac = min(max(self.done / self.total, 0.0), 1.0)
        filled = int(round(frac * self.width))
        elapsed = time.perf_counter() - self.start
        eta = elapsed * (1 - frac) / frac if frac > 0.01 else float("nan")
        eta_text = clock(eta) if eta == eta else "--:--:--"
        bar = "#" * filled + "." * (self.width - filled)
        return f"[{bar}] {100 * frac:5.1f}% {clock(elapsed)} eta {eta_text}  {self.label}"

    def update(self, done: float, label: str | None = None, force: bool = False) -> None:
        self.done = done
        if label is not None:
            self.label = label
        if not self.enabled:
            return
        now = time.perf_counter()
        if self.tty:
            if force or now - self._last_draw > 0.2:
                print("\r" + self.text().ljust(110), end="", file=self.stream, flush=True)
                self._last_draw = now
        else:
            step = int(50 * min(done / self.total, 1.0))
            if force or step != self._last_step:
                print(self.text(), file=self.stream, flush=True)
                self._last_step = step

    def close(self, message: str = "") -> None:
        if not self.enabled:
            return
        self.update(self.total, message or "done", force=True)
        if self.tty:
            print(file=self.stream, flush=True)


class _Tracker:
    """Per-job completed fractions, weighted by the jobs' costs, feeding a bar."""

    def __init__(self, jobs: list[Job], bar: ProgressBar) -> None:
        self.cost = {j.key: j.cost() for j in jobs}
        self.labels = {j.key: j.label for j in jobs}
        self.frac = dict.fromkeys(self.cost, 0.0)
        self.bar, self.running = bar, {}

    def set(self, key: str, frac: float) -> None:
        self.frac[key] = max(self.frac[key], min(frac, 1.0))
        self.bar.update(self.done(), self.describe())

    def start(self, key: str) -> None:
        self.running[key] = True
        self.bar.update(self.done(), self.describe())

    def finish(self, key: str) -> None:
        self.running.pop(key, None)
        self.set(key, 1.0)

    def done(self) -> float:
        return sum(self.cost[k] * f for k, f in self.frac.items())

    def describe(self) -> str:
        finished = sum(f >= 1.0 for f in self.frac.values())
        now = ", ".join(self.labels[k] for k in list(self.running)[:2])
        return f"{finished}/{len(self.frac)} runs" + (f" | {now}" if now else "")


_QUEUE = None


def _init_worker(q) -> None:
    global _QUEUE
    _QUEUE = q


def _worker(job: Job, example_dir: str) -> dict:
    q = _QUEUE

    def progress(frac: float) -> None:
        if q is not None:
            q.put((job.key, frac))

    if q is not None:
        q.put((job.key, 0.0))
    return run_job(job, example_dir, progress)


def execute(
    jobs: list[Job],
    example_dir: Path,
    processes: int = 1,
    bar: ProgressBar | None = None,
    extra_cost: float = 0.0,
    done: dict[str, dict] | None = None,
    on_result: Callable[[Job, dict], None] | None = None,
) -> dict[str, dict]:
    """Run ``jobs`` (longest first over ``processes`` workers); results by job key.

    ``extra_cost`` reserves room at the end of the bar for work after the runs (figures);
    ``done`` holds results to reuse instead of running those jobs; ``on_result(job, result)``
    is called as each run finishes.
    """
    total = sum(j.cost() for j in jobs)
    bar = bar or ProgressBar(total + extra_cost)
    tracker = _Tracker(jobs, bar)
    results: dict[str, dict] = {}
    for job in jobs:
        if done and job.key in done:
            results[job.key] = done[job.key]
            tracker.finish(job.key)
    ordered = sorted((j for j in jobs if j.key not in results), key=lambda j: -j.cost())

    def finished(job: Job, result: dict) -> None:
        results[job.key] = result
        if on_result is not None:
            on_result(job, result)
        tracker.finish(job.key)

    if processes <= 1:
        for job in ordered:
            tracker.start(job.key)
            finished(job, run_job(job, example_dir, lambda f, k=job.key: tracker.set(k, f)))
        return results
    if not ordered:
        return results
    ctx = mp.get_context("spawn")  # torch and fork do not mix
    q = ctx.Queue()
    with ProcessPoolExecutor(
        max_workers=processes, mp_context=ctx, initializer=_init_worker, initargs=(q,)
    ) as pool:
        futures = {pool.submit(_worker, job, str(example_dir)): job for job in ordered}
        pending = set(futures)
        while pending:
            ready, pending = wait(pending, timeout=0.5, return_when=FIRST_COMPLETED)
            _drain(q, tracker)
            for fut in ready:
                job = futures[fut]
                try:
                    result = fut.result()
                except Exception as exc:  # noqa: BLE001 - a crashed worker is a failed run
                    result = job.record(f"{type(exc).__name__}: {exc}")
                finished(job, result)
        _drain(q, tracker)
    return results


def _drain(q, tracker: _Tracker) -> None:
    while True:
        try:
            key, frac = q.get_nowait()
        except queue_mod.Empty:
            return
        if key in tracker.frac:
            if key not in tracker.running and tracker.frac[key] < 1.0:
                tracker.running[key] = True
            tracker.set(key, frac)


class RunCache:
    """Finished runs on disk, one pickle per job (keyed by a hash of the job key)."""

    def __init__(self, folder: str | os.PathLike) -> None:
        self.folder = Path(folder)

    def path(self, job) -> Path:
        return self.folder / (hashlib.sha1(job.key.encode()).hexdigest()[:16] + ".pkl")

    def save(self, job, result: dict) -> None:
        self.folder.mkdir(parents=True, exist_ok=True)
        tmp = self.path(job).with_suffix(".tmp")
        with tmp.open("wb") as fh:
            pickle.dump(result, fh, protocol=pickle.HIGHEST_PROTOCOL)
        tmp.replace(self.path(job))

    def load(self, jobs) -> dict[str, dict]:
        """The successful cached runs of ``jobs``, by key."""
        found = {}
        for job in jobs:
            path = self.path(job)
            if path.is_file():
                with path.open("rb") as fh:
                    result = pickle.load(fh)  # noqa: S301 - our own cache files
                if result.get("ok") and result.get("key") == job.key:
                    found[job.key] = result
        return found

    def sessions(self) -> list[dict]:
        """The invocations that ran jobs into this cache: date, wall seconds, runs executed."""
        path = self.folder / "sessions.json"
        return json.loads(path.read_text()) if path.is_file() else []

    def add_session(self, entry: dict) -> list[dict]:
        sessions = self.sessions() + [entry]
        self.folder.mkdir(parents=True, exist_ok=True)
        (self.folder / "sessions.json").write_text(json.dumps(sessions, indent=1) + "\n")
        return sessions
