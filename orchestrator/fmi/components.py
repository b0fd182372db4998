"""Co-simulation components: an FMU run through fmpy, or the same slave called in-process.

Both expose one small interface to the masters (names resolved to value references once):

* ``setup(t0)``, ``enter_initialization()``, ``exit_initialization()``, ``terminate()``;
* ``set_reals(port, values)`` / ``get_reals(port)`` for a :class:`Port` made by ``port(names)``;
* ``do_step(t, h)``; ``get_state()`` / ``set_state(s)`` / ``free_state(s)``, and
  ``serialize_state(s)`` / ``deserialize_state(b)``;
* ``feedthrough``: True if some output depends directly on some input (from the FMU's
  ``ModelStructure``), which decides the order in which a master reads outputs.

:class:`FmuComponent` goes through fmpy's ``FMU2Slave`` and the PythonFMU binary, exactly what a
third-party FMI host does; :class:`InProcessComponent` calls the same slave object directly, so
the difference between the two is the cost of the FMI interface itself.
"""

from __future__ import annotations

import ctypes
import itertools
import shutil
import tempfile
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
    fmi2Real,
    fmi2ValueReference,
)

from orchestrator.errors import MasterError


@dataclass
class Port:
    """A fixed list of Real variables of one component, with buffers ready for bulk transfer."""

    names: list[str]
    vrs: list[int]
    c_vrs: Any = None
    c_values: Any = None
    values: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def __post_init__(self) -> None:
        n = len(self.vrs)
        self.c_vrs = (fmi2ValueReference * n)(*self.vrs)
        self.c_values = (fmi2Real * n)()
        self.values = np.ctypeslib.as_array(self.c_values) if n else np.zeros(0)


@dataclass
class VariableInfo:
    name: str
    value_reference: int
    causality: str
    unit: str = ""


# fmpy's native logger proxy keeps a single Python logger for the whole process, so one logger
# serves every FMU instance and files each message under the instance name it comes with.
_LOGS: dict[str, deque] = {}
_WARNINGS: dict[str, list[str]] = {}  # messages logged with status fmi2Warning, by instance name
_INSTANCE_IDS = itertools.count(1)
_CALLBACKS: list[fmi2CallbackFunctions] = []


def _callbacks() -> fmi2CallbackFunctions:
    if not _CALLBACKS:
        from fmpy import calloc, free
        from fmpy.logging import addLoggerProxy

        def logger(component, instance, status, category, message):  # noqa: ANN001
            name = instance.decode("utf-8", "replace") if instance else ""
            text = message.decode("utf-8", "replace")
            _LOGS.setdefault(name, deque(maxlen=50)).append(text)
            if status == 1 and len(_WARNINGS.setdefault(name, [])) < 100:  # fmi2Warning
                _WARNINGS[name].append(text.replace("%%", "%"))

        cb = fmi2CallbackFunctions()
        cb.logger = fmi2CallbackLoggerTYPE(logger)
        cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        addLoggerProxy(ctypes.byref(cb))
        _CALLBACKS.append(cb)
    return _CALLBACKS[0]


class _Base:
    """Model description, variables and unpacked files shared by both kinds of component."""

    def __init__(self, name: str, fmu_path: str | Path) -> None:
        self.name = name
        self.path = Path(fmu_path)
        md = read_model_description(str(self.path))
        self.model_description = md
        self.variables = {
            v.name: VariableInfo(v.name, v.valueReference, v.causality, getattr(v, "unit", "") or "")
            for v in md.modelVariables
        }
        # An output without a dependency list depends on every input (FMI 2.0, section 2.2.8).
        self.feedthrough = any(u.dependencies is None or len(u.dependencies) > 0 for u in md.outputs)
        self._unzip = extract(str(self.path), unzipdir=tempfile.mkdtemp(prefix=f"wec_{name}_"))

    def port(self, names: Sequence[str]) -> Port:
        missing = [n for n in names if n not in self.variables]
        if missing:
            raise MasterError(f"component {self.name!r} has no variable {missing[0]!r}")
        return Port(list(names), [self.variables[n].value_reference for n in names])

    def names(self, causality: str) -> list[str]:
        return [v.name for v in self.variables.values() if v.causality == causality]


class FmuComponent(_Base):
    """An FMU loaded with fmpy (FMI 2.0 co-simulation)."""

    def __init__(self, name: str, fmu_path: str | Path) -> None:
        super().__init__(name, fmu_path)
        md = self.model_description
        self.dead = False
        self.instance_name = f"{name}#{next(_INSTANCE_IDS)}"
        self.messages = _LOGS.setdefault(self.instance_name, deque(maxlen=50))
        self.fmu = FMU2Slave(
            guid=md.guid, unzipDirectory=self._unzip,
            modelIdentifier=md.coSimulation.modelIdentifier, instanceName=self.instance_name,
        )
        self._call("instantiate", self.fmu.instantiate, callbacks=_callbacks(), loggingOn=True)
        # All categories on: PythonFMU forwards a slave's log messages (our error reports) only then.
        self._call("setDebugLogging", self.fmu.setDebugLogging, True, [])
        # The per-step calls go to the C functions fmpy loaded (argument types set by fmpy) without fmpy's
        # Python wrapper (a few microseconds per call, six calls per macro step); the status is checked here.
        self._c = self.fmu.component
        self._set = self.fmu.dll.fmi2SetReal
        self._get = self.fmu.dll.fmi2GetReal
        self._step = self.fmu.dll.fmi2DoStep

    def _call(self, what: str, fn, *args: Any, **kwargs: Any) -> Any:  # noqa: ANN001
        seen = len(self.messages)
        try:
            return fn(*args, **kwargs)
        except (FMICallException, Exception) as exc:  # fmpy raises a bare Exception on instantiate
            self._failed(exc.status if isinstance(exc, FMICallException) else 4)
            raise MasterError(f"{self.name} FMU: {what} failed: {self._detail(seen, str(exc))}") from None

    def _failed(self, status: int) -> None:
        """After fmi2Fatal (PythonFMU's status for an exception in the slave) the FMI standard allows no
        further call, not even fmi2Terminate or fmi2FreeInstance: PythonFMU's binary crashes on them."""
        if status >= 4:
            self.dead = True

    def _detail(self, seen: int, fallback: str) -> str:
        """The FMU's own messages logged during the failed call (PythonFMU's generic wrapper text dropped)."""
        new = list(self.messages)[seen:] if len(self.messages) >= seen else list(self.messages)
        out: list[str] = []
        for m in new:
            if m.startswith("Fatal py exception encountered") or m in out:
                continue
            out.append(m)
        return " | ".join(out[-3:]) if out else (fallback or "no message from the FMU")

    def warnings(self) -> list[str]:
        """The messages the FMU logged with status warning so far (the first 100)."""
        return list(_WARNINGS.get(self.instance_name, []))

    def setup(self, start_time: float, stop_time: float | None = None) -> None:
        self._call("setupExperiment", self.fmu.setupExperiment, startTime=start_time, stopTime=stop_time)

    def enter_initialization(self) -> None:
        self._call("enterInitializationMode", self.fmu.enterInitializationMode)

    def exit_initialization(self) -> None:
        self._call("exitInitializationMode", self.fmu.exitInitializationMode)

    # Status worse than fmi2Warning (1): discard, error, fatal -- fmpy's wrappers would raise FMICallException.
    def set_reals(self, port: Port, values: np.ndarray) -> None:
        port.values[:] = values
        seen = len(self.messages)
        status = self._set(self._c, port.c_vrs, len(port.vrs), port.c_values)
        if status > 1:
            self._raise("fmi2SetReal", status, seen)

    def get_reals(self, port: Port) -> np.ndarray:
        seen = len(self.messages)
        status = self._get(self._c, port.c_vrs, len(port.vrs), port.c_values)
        if status > 1:
            self._raise("fmi2GetReal", status, seen)
        return port.values.copy()

    def do_step(self, t: float, h: float) -> None:
        seen = len(self.messages)
        status = self._step(self._c, t, h, 1)
        if status > 1:
            self._raise(f"doStep at t = {t:g} s", status, seen)

    def _raise(self, what: str, status: int, seen: int) -> None:
        self._failed(status)
        raise MasterError(f"{self.name} FMU: {what} failed: {self._detail(seen, '')}") from None

    def get_state(self) -> Any:
        return self._call("getFMUstate", self.fmu.getFMUstate)

    def set_state(self, state: Any) -> None:
        self._call("setFMUstate", self.fmu.setFMUstate, state)

    def free_state(self, state: Any) -> None:
        self._call("freeFMUstate", self.fmu.freeFMUstate, state)

    def serialize_state(self, state: Any) -> bytes:
        return bytes(self._call("serializeFMUstate", self.fmu.serializeFMUstate, state))

    def deserialize_state(self, data: bytes) -> Any:
        return self._call("deSerializeFMUstate", self.fmu.deSerializeFMUstate, data)

    def terminate(self) -> None:
        if not self.dead:
            try:
                self.fmu.terminate()
                self.fmu.freeInstance()
            except Exception:  # noqa: BLE001 - best effort on shutdown
                pass
            self.dead = True
        _forget_path(Path(self._unzip) / "resources")  # PythonFMU put it on sys.path
        _LOGS.pop(self.instance_name, None)
        _WARNINGS.pop(self.instance_name, None)
        shutil.rmtree(self._unzip, ignore_errors=True)


class InProcessComponent(_Base):
    """The slave class of an FMU called directly in this process (no fmpy, no PythonFMU binary).

    The FMU is unpacked and its slave instantiated with the FMU's own resources, so the physics,
    the variables and their value references are exactly those of :class:`FmuComponent`.
    """

    def __init__(self, name: str, fmu_path: str | Path) -> None:
        import importlib
        import sys

        super().__init__(name, fmu_path)
        md = self.model_description
        resources = Path(self._unzip) / "resources"
        module_name = (resources / "slavemodule.txt").read_text().strip()
        sys.path.insert(0, str(resources))
        try:
            module = importlib.import_module(module_name)
        finally:
            sys.path.remove(str(resources))
        cls = getattr(module, md.modelName)
        self.slave = cls(instance_name=name, resources=str(resources))

    def _call(self, what: str, fn, *args: Any) -> Any:  # noqa: ANN001
        """Call the slave; an exception becomes the same error as through fmpy: the FMU's own message."""
        seen = len(self.slave.log_queue)
        try:
            return fn(*args)
        except Exception as exc:  # noqa: BLE001 - the slave logged its message (fmu_base.slave)
            raise MasterError(f"{self.name} FMU: {what} failed: {self._detail(seen, str(exc))}") from None

    def _detail(self, seen: int, fallback: str) -> str:
        out: list[str] = []
        for record in list(self.slave.log_queue)[seen:]:
            if record.msg not in out:
                out.append(record.msg)
        return " | ".join(m.replace("%%", "%") for m in out[-3:]) if out else (fallback or "no message from the FMU")

    def warnings(self) -> list[str]:
        """The messages the slave logged with status warning so far."""
        from pythonfmu.enums import Fmi2Status

        return [r.msg.replace("%%", "%") for r in self.slave.log_queue if r.status == Fmi2Status.warning]

    def setup(self, start_time: float, stop_time: float | None = None) -> None:
        self._call("setupExperiment", self.slave.setup_experiment, start_time, stop_time, None)

    def enter_initialization(self) -> None:
        self._call("enterInitializationMode", self.slave.enter_initialization_mode)

    def exit_initialization(self) -> None:
        self._call("exitInitializationMode", self.slave.exit_initialization_mode)

    def set_reals(self, port: Port, values: np.ndarray) -> None:
        self.slave.set_real(port.vrs, values.tolist())

    def get_reals(self, port: Port) -> np.ndarray:
        return np.array(self.slave.get_real(port.vrs))

    def do_step(self, t: float, h: float) -> None:
        seen = len(self.slave.log_queue)
        if not self.slave.do_step(t, h):
            raise MasterError(f"{self.name} FMU: doStep at t = {t:g} s failed: {self._detail(seen, '')}")

    def get_state(self) -> Any:
        return self.slave._get_fmu_state()

    def set_state(self, state: Any) -> None:
        self._call("setFMUstate", self.slave._set_fmu_state, state)

    def free_state(self, state: Any) -> None:
        pass

    def serialize_state(self, state: Any) -> bytes:
        return self._call("serializeFMUstate", self.slave._fmu_state_to_bytes, state)

    def deserialize_state(self, data: bytes) -> Any:
        return self._call("deSerializeFMUstate", self.slave._fmu_state_from_bytes, data)

    def terminate(self) -> None:
        self.slave.terminate()
        shutil.rmtree(self._unzip, ignore_errors=True)


def _forget_path(folder: Path) -> None:
    import sys

    while str(folder) in sys.path:
        sys.path.remove(str(folder))
