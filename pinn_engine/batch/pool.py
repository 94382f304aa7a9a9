"""A small local batch on a warm process pool instead of a Dask cluster.

A local Dask cluster costs about 1 s of both cores to start (Dask's imports in this process
and in the workers' server, its scheduler, the dashboard's bokeh), a third of a batch of a
dozen small cases, and the cases wait for all of it. The pool's workers are forked from the
warm server (:mod:`.warm`) as soon as it has imported the engine, and this process imports
neither the engine nor Dask. As on Dask, a case whose worker dies (a crash, the kernel's
out-of-memory killer) is run again on a new worker, alone, and a case that kills
:data:`ALLOWED_FAILURES` workers gets an error row; the other cases go on.
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import signal
from collections import Counter
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool

from pinn_engine.batch import warm

# The most cases a local batch runs on the pool (more run on a Dask cluster, whose start
# is then a small share of the batch and whose dashboard shows its progress)
SMALL_BATCH = 24
ALLOWED_FAILURES = 3  # Dask's default for a task whose workers die (allowed-failures)
INTERRUPTED = 130  # a worker's exit status on Ctrl-C: the shell's 128 + SIGINT
Todo = list[tuple[str, argparse.Namespace]]
Task = Callable[[str, argparse.Namespace], dict]  # a case's work in a worker: its row

_started = None  # in a worker: the queue on which it names each case it starts


def small(cases: int, scheduler: str | None) -> bool:
    """Whether a batch of ``cases`` runs on the pool: a local one of at most
    :data:`SMALL_BATCH` cases."""
    return not scheduler and cases <= SMALL_BATCH


def _setup(started) -> None:
    """A pool worker's set-up: the queue it names its cases on, then as a Dask worker's. A
    Ctrl-C (which reaches every process of the terminal's group) ends it quietly: the batch
    stops, and says so, in its own process."""
    global _started
    _started = started
    signal.signal(signal.SIGINT, lambda signum, frame: os._exit(INTERRUPTED))
    warm.setup_worker()


def _mesh(name: str, args: argparse.Namespace, task: Task | None = None) -> dict:
    """One case in a worker (``task``, default :func:`.task.run_case`), its start named to
    the batch first."""
    from pinn_engine.batch.task import run_case

    _started.put(name)
    return (task or run_case)(name, args)


class WarmPool:
    """``workers`` local processes (default: one per core) forked from the warm server, whose
    start begins here; each case runs ``task`` (a module's function; default: the batch's
    :func:`.task.run_case`)."""

    def __init__(self, workers: int | None = None, task: Task | None = None) -> None:
        warm.start(dask=False)
        self.workers = workers or warm.default_workers()
        self.task = task
        self.context = multiprocessing.get_context(warm.start_method() or "spawn")

    def results(self, todo: Todo) -> Iterator[tuple[str, dict]]:
        """Each case's name and summary row, as the cases finish."""
        from pinn_engine.batch.task import DIED, error_row

        waiting, deaths = dict(todo), Counter()
        alone: list[str] = []  # cases running when a worker died: each is retried alone
        while waiting:
            batch = [alone.pop()] if alone else list(waiting)
            for name, row in self._round({n: waiting[n] for n in batch}, deaths):
                del waiting[name]
                yield name, row
            for name in [n for n in batch if n in waiting]:
                if deaths[name] >= ALLOWED_FAILURES:
                    del waiting[name]
                    yield name, error_row(name, DIED)
                elif deaths[name] and name not in alone:
                    alone.append(name)

    def _round(self, todo: dict, deaths: Counter) -> Iterator[tuple[str, dict]]:
        """The cases of ``todo`` on one pool, until it is done or a worker dies; a death
        counts against each case that had started and not finished (each case of ``todo``
        where none had: a worker that died before its first case)."""
        started = self.context.SimpleQueue()
        pool = ProcessPoolExecutor(min(self.workers, len(todo)), self.context, _setup, (started,))
        futures: dict[Future, str] = {
            pool.submit(_mesh, n, a, self.task): n for n, a in todo.items()
        }
        finished: set[str] = set()
        try:
            pending, broken = set(futures), False
            while pending and not broken:
                done, pending = wait(pending, return_when=FIRST_COMPLETED)
                for future in done:
                    name, error = futures[future], future.exception()
                    broken |= isinstance(error, BrokenProcessPool)
                    if error is None or not isinstance(error, BrokenProcessPool):
                        finished.add(name)
                        yield name, future.result() if error is None else _failure(name, error)
            if broken:  # charged to the cases that had started; all, where none had
                for future in pending:  # finished before the death, not yet asked for
                    if future.done() and future.exception() is None:
                        finished.add(futures[future])
                        yield futures[future], future.result()
                names = set()
                while not started.empty():
                    names.add(started.get())
                for name in (names or set(todo)) - finished:
                    deaths[name] += 1
        except BaseException:  # interrupted, or the caller stopped asking: drop the cases
            # the executor's processes: no public way to end them before Python 3.14
            for process in list((getattr(pool, "_processes", None) or {}).values()):
                process.kill()
            raise
        finally:
            pool.shutdown(wait=True, cancel_futures=True)
            started.close()


def _failure(name: str, error: BaseException) -> dict:
    """The row of a case whose task itself failed (its arguments could not be sent)."""
    from pinn_engine.batch.task import error_row

    return error_row(name, f"{type(error).__name__}: {error}")
