"""What an FMU does when the Python running it lacks a package: a readable error, not silence.

Our FMUs carry their Python sources but not numpy, scipy or h5py: those come from the host's
Python (a Python host's own, or, in a C host, the one preloaded with the environment of
``wec-cosim host-env``). When an import fails, the FMU script falls back to
:func:`missing_package_slave`: a slave class whose construction fails with a message naming the
missing package, the Python that lacks it and the fix. ``fmi2Instantiate`` then returns NULL (the
FMI error status of instantiation) and PythonFMU passes the message to the host's logger when
logging is on (``Fatal py exception encountered: [ctor] ... RuntimeError('wec-cosim hydro FMU:
...')``); it is also written to the process's standard error, which PythonFMU does not silence,
so a host that instantiates with logging off still shows why. This module imports only the
standard library and PythonFMU (bundled in every FMU).
"""

from __future__ import annotations

import sys
from typing import Any

from pythonfmu import Fmi2Slave

REQUIRED = ("numpy", "scipy", "h5py")


def missing_package_message(error: ImportError, kind: str) -> str:
    """The message for an ImportError raised while importing the ``kind`` FMU's sources."""
    name = getattr(error, "name", None) or "a package"
    return (f"wec-cosim {kind} FMU: the Python running this FMU (prefix {sys.prefix}, Python "
            f"{sys.version.split()[0]}) cannot import {name!r} ({error}). The FMU runs in its host's Python and "
            f"needs {', '.join(REQUIRED)} there: install them into that Python (pip install {' '.join(REQUIRED)}); "
            "in a C or C++ host, run it with the environment `wec-cosim host-env` prints (LD_PRELOAD of "
            "libpython, PYTHONHOME, PYTHONPATH with the packages; docs/hosts/c.md)")


def missing_package_slave(error: ImportError, kind: str) -> tuple[type, Any]:
    """``(slave class, hold_module_globals)`` standing in for the real ones after ``error``."""
    message = missing_package_message(error, kind)
    held: list[dict] = []

    def hold_module_globals(module_name: str) -> None:
        # Same compensation as fmu_base.slave.hold_module_globals (PythonFMU releases a reference to the
        # script module's globals per instantiation), without numpy.
        module = sys.modules.get(module_name)
        if module is not None:
            held.append(vars(module))

    class MissingPackageSlave(Fmi2Slave):
        """Fails to instantiate, with the message above."""

        def __init__(self, **kwargs: Any) -> None:
            hold_module_globals(type(self).__module__)
            print(message, file=sys.stderr, flush=True)
            raise RuntimeError(message)

        def do_step(self, current_time: float, step_size: float) -> bool:  # pragma: no cover - never built
            return False

    return MissingPackageSlave, hold_module_globals
