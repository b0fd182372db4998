"""Running cases on Dask's distributed scheduler: a local cluster by default, or a running one.

A local cluster has one single-threaded worker process per core (``dask.system.CPU_COUNT``, which
respects CPU affinity and container limits); each worker runs one case at a time with its own
FMU instances. ``--scheduler ADDRESS`` (or Dask's ``scheduler-address`` setting, e.g. the
``DASK_SCHEDULER_ADDRESS`` environment variable) connects to a cluster started elsewhere
(``dask scheduler`` and ``dask worker`` on the machines, or a job-queue or Kubernetes deployment):
its workers need this package and its dependencies installed and must see the scenario file and its
data (hydrodynamic database, meshes) at the same paths (a shared file system).

Failures: a case that raises is a result (:func:`wec_cosim.sweeps.case.run_case`); a worker that dies (killed,
out of memory, a crash in native code) has its cases rescheduled on the others by the scheduler;
a case whose worker died ``distributed.scheduler.allowed-failures`` + 1 times is recorded as failed.
Results come back to this process, the only writer of the sweep file.
"""

from __future__ import annotations

import logging
import uuid
from collections.abc import Iterable, Iterator
from contextlib import contextmanager

from orchestrator.errors import WecCosimError

from .case import CaseResult, CaseTask, run_case

CONNECT_TIMEOUT = "60s"
CLOSE_TIMEOUT = 20.0  # s: closing the client after a Ctrl-C (the cluster is closed after it in any case)


@contextmanager
def dask_client(address: str | None = None, workers: int = 0, log=print) -> Iterator:
    """A Dask client on the cluster at ``address``, or on a new local cluster of ``workers`` processes
    (0: one per core), closed on exit. Prints the dashboard's address when there is one."""
    import dask
    from distributed import Client

    address = address or dask.config.get("scheduler-address", None)
    if address:
        try:
            client = Client(address, timeout=CONNECT_TIMEOUT)
        except (OSError, TimeoutError) as exc:
            raise WecCosimError(f"cannot reach the Dask scheduler at {address} ({exc}); start one with `dask "
                                "scheduler` and workers with `dask worker ADDRESS`, or omit --scheduler for a "
                                "local cluster") from None
        cluster = None
        if log:
            log(f"Dask scheduler {address}: {len(client.scheduler_info()['workers'])} workers")
    else:
        n = workers or dask.system.CPU_COUNT
        cluster = local_cluster(n)
        client = Client(cluster, timeout=CONNECT_TIMEOUT)
        if log:
            log(f"local Dask cluster: {n} worker process{'es' if n > 1 else ''}")
    try:
        if log and _has_dashboard() and "dashboard" in client.scheduler_info().get("services", {}):
            log(f"Dask dashboard: {client.dashboard_link}")
        yield client
    finally:
        with deaf_to_ctrl_c():  # a second Ctrl-C while the cluster closes must not break the closing
            try:
                client.close(timeout=CLOSE_TIMEOUT)
            except (OSError, TimeoutError):
                # A Ctrl-C that lands inside one of the client's calls can leave it unable to close cleanly (it
                # then waited twice the connect timeout, 120 s, and its TimeoutError replaced the interruption the
                # user asked for); the cluster's processes are closed below all the same.
                pass
            if cluster is not None:
                close_quietly(cluster)


@contextmanager
def ctrl_c_interrupts() -> Iterator[None]:
    """Inside the block every SIGINT raises KeyboardInterrupt in the main thread, also where Python's own handler
    would not reach the sweep's code. The shutdown that follows (thousands of futures released, the cluster
    closed, the file recorded) runs in :func:`deaf_to_ctrl_c` blocks, so a second Ctrl-C does not cut it. The
    process does not start ignoring SIGINT at the first press: an interrupt raised inside a garbage-collector
    callback or a ``__del__`` (Dask has both) is swallowed by Python ("Exception ignored in ..." and its traceback),
    and a sweep that then ignored every later Ctrl-C ran on; a press that lands there is sent again 50 ms later
    instead. Outside the main thread nothing changes."""
    import os
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def interrupt(signum: int, frame) -> None:  # noqa: ANN001
        f = frame
        while f is not None:  # inside a gc callback or a __del__ Python would swallow it: signal again shortly
            if f.f_code.co_name == "__del__" or f.f_code.co_filename.replace("\\", "/").endswith("distributed/gc.py"):
                threading.Timer(0.05, os.kill, (os.getpid(), signal.SIGINT)).start()
                return
            f = f.f_back
        raise KeyboardInterrupt

    old = signal.signal(signal.SIGINT, interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old)


@contextmanager
def deaf_to_ctrl_c() -> Iterator[None]:
    """SIGINT ignored inside the block (in the main thread; elsewhere nothing changes): the last words of an
    interrupted sweep (closing the cluster, recording what finished) are not cut by a second Ctrl-C."""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old)


def close_quietly(cluster) -> None:  # noqa: ANN001
    """Close a local cluster without its shutdown chatter (a worker busy with a case is killed after a
    few seconds: that is the intent, not a warning for the user)."""
    logger = logging.getLogger("distributed")
    level = logger.level
    logger.setLevel(logging.CRITICAL)
    try:
        cluster.close(timeout=CLOSE_TIMEOUT)
    except (OSError, TimeoutError):  # workers that do not stop in time are killed at the interpreter's exit
        pass
    finally:
        logger.setLevel(level)


def local_cluster(workers: int, dashboard: bool = True):
    """A local cluster of ``workers`` single-threaded processes, patient with a loaded machine; its
    dashboard on port 8787 (or a free one) when bokeh is installed and ``dashboard`` is true."""
    import dask
    from distributed import LocalCluster

    # Logs of the scheduler and workers stay quiet (a cluster closed while a case runs logs broken
    # connections); what matters reaches the user as a case's result or an error here.
    try:
        with dask.config.set({"distributed.comm.timeouts.connect": CONNECT_TIMEOUT}):
            return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                silence_logs=logging.CRITICAL, preload=["wec_cosim.sweeps.worker_signals"],
                                dashboard_address=":8787" if dashboard and _has_dashboard() else ":0")
    except (OSError, TimeoutError) as exc:
        raise WecCosimError(f"the local Dask cluster of {workers} workers did not start ({exc})") from None


def _has_dashboard() -> bool:
    """Dask's dashboard needs bokeh (``pip install 'wec-cosim[dashboard]'``)."""
    import importlib.util

    return importlib.util.find_spec("bokeh") is not None


class SchedulerLost(WecCosimError):
    """The client lost its connection to the Dask scheduler: the cases still running or waiting have no result."""


def results_on_dask(client, tasks: Iterable[CaseTask]) -> Iterator[CaseResult]:
    """Submit every task and yield the results as they finish (in any order). A lost connection to the
    scheduler cancels every pending case at once: that is :class:`SchedulerLost`, not one failure per case."""
    from concurrent.futures import CancelledError

    from distributed import as_completed
    from distributed.scheduler import KilledWorker

    session = uuid.uuid4().hex[:8]
    futures = {client.submit(run_case, t, key=f"wec-case-{t.case.id}-{session}", pure=False): t for t in tasks}
    try:
        for future in as_completed(futures):
            task = futures[future]
            try:
                yield future.result()
            except KilledWorker as exc:
                yield CaseResult(task.case.id, "failed", error=f"the worker process running this case died "
                                 f"repeatedly (a crash or out of memory): {exc}")
            except CancelledError as exc:  # the scheduler is gone (or cancelled the work): no case result
                raise SchedulerLost(f"the connection to the Dask scheduler was lost ({' '.join(str(exc).split())})"
                                    ) from None
            except Exception as exc:  # noqa: BLE001 - e.g. a worker without this package: that case's result
                yield CaseResult(task.case.id, "failed", error=f"{type(exc).__name__}: {exc}")
            future.release()
    finally:
        # the generator may be closed (garbage-collected) after an interrupt has already closed the client
        # and its event loop: nothing is left to cancel then
        pending = [f for f in futures if not f.done()]
        if pending and client.status == "running":
            try:
                client.cancel(pending)
            except (RuntimeError, OSError):
                pass


def results_in_process(tasks: Iterable[CaseTask]) -> Iterator[CaseResult]:
    """The same results computed one after another in this process (no Dask)."""
    for task in tasks:
        yield run_case(task)
