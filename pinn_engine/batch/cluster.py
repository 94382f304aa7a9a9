"""The Dask client a batch runs on: a local cluster of worker processes, or the scheduler of
a cluster; each worker set up for meshing (one torch thread, the command's heap settings)."""

from __future__ import annotations

import contextlib
import importlib.util
from collections.abc import Iterator

from pinn_engine.batch import warm
from pinn_engine.errors import MissingExtraError

try:
    import dask
    from distributed import Client, LocalCluster
    from distributed.diagnostics.plugin import WorkerPlugin
except ModuleNotFoundError as exc:  # installed without the batch extra
    raise MissingExtraError(*warm.DASK_EXTRA) from exc

HOST = "127.0.0.1"  # a local cluster listens on this machine only
DASHBOARD = f"{HOST}:8787"  # Dask's usual dashboard port (another is taken when it is busy)
THREADS_PER_WORKER = 1  # one case at a time a process: cases run side by side in processes


class MeshingWorker(WorkerPlugin):
    """Set a worker process up for meshing (:func:`.warm.setup_worker`)."""

    def setup(self, worker) -> None:  # noqa: ARG002
        warm.setup_worker()


@contextlib.contextmanager
def connect(workers: int | None = None, scheduler: str | None = None) -> Iterator[Client]:
    """A client on the scheduler at ``scheduler``, or on a new local cluster of ``workers``
    processes (closed afterwards); its workers set up by :class:`MeshingWorker`."""
    if scheduler:
        with contextlib.closing(Client(scheduler)) as client:
            prepare(client)
            yield client
        return
    warm.start(dask=True)
    method = warm.start_method()
    # for the cluster's life: the nanny starts a worker that died by the same method
    with dask.config.set({"distributed.worker.multiprocessing-method": method} if method else {}):
        cluster = LocalCluster(
            n_workers=workers or warm.default_workers(),
            threads_per_worker=THREADS_PER_WORKER,
            processes=True,
            host=HOST,
            dashboard_address=DASHBOARD,
        )
        with contextlib.closing(cluster), contextlib.closing(Client(cluster)) as client:
            prepare(client)
            yield client


def prepare(client: Client) -> None:
    """Set up every worker, and those that join later, for meshing."""
    client.register_plugin(MeshingWorker(), name="pinn-mesh")


def _scheduler_has_bokeh() -> bool:
    return importlib.util.find_spec("bokeh") is not None


def dashboard(client: Client) -> str | None:
    """The address of the cluster's dashboard, when one runs: the scheduler serves its
    pages only with bokeh installed (without it the address answers with an apology)."""
    services = client.scheduler_info().get("services", {})
    if "dashboard" not in services or not client.run_on_scheduler(_scheduler_has_bokeh):
        return None
    return client.dashboard_link
