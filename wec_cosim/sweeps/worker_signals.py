"""Dask worker preload of the local cluster: workers ignore SIGINT.

Ctrl-C in a terminal sends SIGINT to the whole foreground process group, the local cluster's worker processes
included; each then printed its own ``KeyboardInterrupt`` traceback (from asyncio inside Dask's nanny) under the
sweep's one-line message. The sweep's own process handles the interruption: it records what finished and closes
the cluster, which stops the workers.
"""

from __future__ import annotations

import signal


def dask_setup(worker: object) -> None:  # noqa: ARG001 - Dask's preload hook
    """Called by Dask in each worker process at start (and at every restart), in its main thread."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
