"""Base class shared by the toolkit's PythonFMU slaves (FMI 2.0 co-simulation).

PythonFMU 0.7 handles one scalar at a time, saves only registered variables as state,
serialises state with JSON and writes an incomplete ``ModelStructure``. This base class adds:

* vector variables backed by numpy arrays, registered with FMI structured names
  (``float.F[3]``), read and written in bulk by overridden ``get_real``/``set_real``;
* lazy outputs: setting an input marks the outputs stale, the next ``get_real`` of an output
  recomputes them once through :meth:`VectorSlave.update_outputs`;
* full state (physics objects, integrator history) through deep copies, serialised as data only
  (:mod:`fmu_base.state_codec`: JSON and raw arrays, never pickle), so rollback and checkpoints
  restore everything, not only the registered variables, and a crafted state cannot run code;
* every exception raised in an FMI call is logged with its message before the host sees the
  error status, so the user reads the FMU's own message whatever the host;
* a complete ``ModelStructure`` (``Outputs`` with their true input dependencies and every
  ``InitialUnknown``) and units with ``UnitDefinitions``, so ``fmpy validate`` reports nothing.

Physics lives in plain Python packages (``hydro_fmu``, ``mbd_fmu``); a slave only maps
variables onto a physics object.
"""

from __future__ import annotations

import copy
import json
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any
from xml.etree.ElementTree import Element, SubElement

import numpy as np
from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real
from pythonfmu.default_experiment import DefaultExperiment
from pythonfmu.enums import Fmi2Initial, Fmi2Status

from . import state_codec

SPEC_FILE = "scene_spec.json"

# PythonFMU 0.7's C++ instantiation (its ``findClass`` step) releases one reference to the FMU
# script module's __dict__ that it never owned, once per instance; without compensation the
# module's globals are freed while the module is still in sys.modules and the host process
# crashes later. The script takes one reference when it is imported (for the first instance) and
# every instance takes one more (for the next); they are kept for the life of the process.
_SCRIPT_DICT_REFERENCES: list[dict] = []


def hold_module_globals(module_name: str) -> None:
    """Keep one extra reference to the globals of ``module_name`` (see above)."""
    module = sys.modules.get(module_name)
    if module is not None:
        _SCRIPT_DICT_REFERENCES.append(vars(module))

# SI base-unit exponents (kg, m, s, rad) of every unit used on our interfaces.
_BASE_UNITS: dict[str, dict[str, int]] = {
    "1": {},
    "s": {"s": 1},
    "Hz": {"s": -1},
    "m": {"m": 1},
    "m/s": {"m": 1, "s": -1},
    "m/s2": {"m": 1, "s": -2},
    "rad": {"rad": 1},
    "rad/s": {"rad": 1, "s": -1},
    "rad/s2": {"rad": 1, "s": -2},
    "kg": {"kg": 1},
    "kg.m": {"kg": 1, "m": 1},
    "kg.m2": {"kg": 1, "m": 2},
    "kg/m3": {"kg": 1, "m": -3},
    "N": {"kg": 1, "m": 1, "s": -2},
    "N.m": {"kg": 1, "m": 2, "s": -2},
    "N/m": {"kg": 1, "s": -2},
    "N.s/m": {"kg": 1, "s": -1},
    "N.m/rad": {"kg": 1, "m": 2, "s": -2, "rad": -1},
    "N.m.s/rad": {"kg": 1, "m": 2, "s": -1, "rad": -1},
    "N/rad": {"kg": 1, "m": 1, "s": -2, "rad": -1},
    "N.s/rad": {"kg": 1, "m": 1, "s": -1, "rad": -1},
    "N.s": {"kg": 1, "m": 1, "s": -1},
    "N/s": {"kg": 1, "m": 1, "s": -3},
    "N.m/s": {"kg": 1, "m": 2, "s": -3},
    "W": {"kg": 1, "m": 2, "s": -3},
    "J": {"kg": 1, "m": 2, "s": -2},
}

_CAUSALITY = {
    "parameter": Fmi2Causality.parameter,
    "calculatedParameter": Fmi2Causality.calculatedParameter,
    "input": Fmi2Causality.input,
    "output": Fmi2Causality.output,
    "local": Fmi2Causality.local,
}


def load_spec(resources: str | Path | None) -> dict[str, Any]:
    """Read the scene specification JSON that the builder placed in the FMU's resources."""
    if resources is None:
        raise RuntimeError("FMU instantiated without a resources folder; cannot find its scene spec")
    path = Path(resources) / SPEC_FILE
    if not path.is_file():
        raise RuntimeError(f"scene specification {path} is missing from the FMU resources")
    return json.loads(path.read_text())


class SerializedState:
    """An FMU state read by ``fmi2DeSerializeFMUstate``: checked bytes, applied by ``fmi2SetFMUstate``."""

    def __init__(self, data: bytes) -> None:
        self.data = data


# FMI entry points whose exceptions are logged (with the exception's own message) before PythonFMU
# turns them into an error status; do_step failures become a plain error return (not fatal).
_LOGGED_CALLS = ("setup_experiment", "enter_initialization_mode", "exit_initialization_mode", "terminate",
                 "_get_fmu_state", "_set_fmu_state")


def _logged(name: str, method):  # noqa: ANN001, ANN202
    import functools

    @functools.wraps(method)
    def call(self, *args, **kwargs):  # noqa: ANN001, ANN002, ANN003, ANN202
        try:
            return method(self, *args, **kwargs)
        except Exception as exc:  # noqa: BLE001 - reported to the host, then raised
            self.log(_describe_failure(name, exc), Fmi2Status.error)
            raise
    return call


def _logged_step(method):  # noqa: ANN001, ANN202
    import functools

    @functools.wraps(method)
    def call(self, current_time: float, step_size: float) -> bool:
        try:
            return method(self, current_time, step_size)
        except Exception as exc:  # noqa: BLE001 - a failed step is an error status, not a crash
            self.log(_describe_failure(f"do_step at t = {current_time:g} s", exc), Fmi2Status.error)
            return False
    return call


def _describe_failure(what: str, exc: BaseException) -> str:
    text = str(exc) or type(exc).__name__
    if isinstance(exc, state_codec.StateFormatError):
        return f"invalid FMU state: {text}"
    if isinstance(exc, (ValueError, RuntimeError, OSError, np.linalg.LinAlgError)):
        return text
    return f"{what}: {type(exc).__name__}: {text}"


def _positions(positions: list[int]) -> slice | np.ndarray:
    """Positions in a block as a slice when they are consecutive (a view: gather and scatter without an index
    array, about half the time for a dozen values), else as an index array."""
    first = positions[0]
    if positions == list(range(first, first + len(positions))):
        return slice(first, first + len(positions))
    return np.array(positions, dtype=np.intp)


class RealStore:
    """The values of every Real variable of a slave in a few flat float64 blocks, with one numpy gather or
    scatter per FMI call.

    Each :meth:`allocate` returns a view into the current block (a new block when it is full; a block is never
    reallocated, so the views stay valid for the life of the slave). The value references of a call are mapped
    to (block, positions) once per distinct list of references (hosts read and write the same lists at every
    step) and cached (consecutive positions as a slice); a list spanning several blocks falls back to one read per
    value.
    """

    BLOCK = 4096  # floats per block (32 kB); a larger variable gets a block of its own
    PLANS = 64  # distinct value-reference lists remembered (a host uses a handful)

    def __init__(self) -> None:
        self._blocks: list[np.ndarray] = []
        self._used = 0  # floats used in the last small block
        self._small: np.ndarray | None = None
        self._where: dict[int, tuple[int, int]] = {}  # vr -> (block number, position)
        self._plans: dict[tuple[int, ...], tuple[np.ndarray, np.ndarray] | None] = {}

    def allocate(self, values: np.ndarray) -> np.ndarray:
        """A view of ``len(values)`` new floats in the store, initialised to ``values``."""
        n = len(values)
        if n > self.BLOCK // 4:
            block = np.empty(n)
            self._blocks.append(block)
            view = block
        else:
            if self._small is None or self._used + n > len(self._small):
                self._small = np.zeros(self.BLOCK)
                self._blocks.append(self._small)
                self._used = 0
            view = self._small[self._used : self._used + n]
            self._used += n
        view[:] = values
        return view

    def bind(self, vr: int, view: np.ndarray, index: int) -> None:
        """Value reference ``vr`` is element ``index`` of ``view`` (returned by :meth:`allocate`)."""
        base = view.base if view.base is not None else view
        number = next(k for k, b in enumerate(self._blocks) if b is base)
        offset = (view.__array_interface__["data"][0] - base.__array_interface__["data"][0]) // view.itemsize
        self._where[vr] = (number, offset + index)
        self._plans.clear()

    def _plan(self, vrs: list[int]) -> tuple[np.ndarray, np.ndarray] | None:
        key = tuple(vrs)
        plan = self._plans.get(key, False)
        if plan is False:
            where = [self._where[vr] for vr in key]  # KeyError for an unknown reference, as before
            blocks = {b for b, _ in where}
            plan = None if len(blocks) != 1 else (self._blocks[blocks.pop()], _positions([p for _, p in where]))
            if len(self._plans) >= self.PLANS:
                self._plans.clear()
            self._plans[key] = plan
        return plan

    def gather(self, vrs: list[int]) -> list[float]:
        """The values of ``vrs`` (a list of Python floats, what PythonFMU hands to the host)."""
        plan = self._plans.get(tuple(vrs), False)
        if plan:
            return plan[0][plan[1]].tolist()
        if plan is False and self._plan(vrs) is not None:
            return self.gather(vrs)
        return [self._blocks[b].item(p) for b, p in (self._where[vr] for vr in vrs)]

    def scatter(self, vrs: list[int], values: list[float]) -> None:
        """Write ``values`` into ``vrs`` (same length)."""
        if len(vrs) != len(values):
            raise ValueError(f"{len(vrs)} value references but {len(values)} values")
        plan = self._plans.get(tuple(vrs), False)
        if plan:
            plan[0][plan[1]] = values
            return
        plan = self._plan(vrs)
        if plan is None:
            for vr, value in zip(vrs, values, strict=True):
                b, p = self._where[vr]
                self._blocks[b][p] = value
        else:
            plan[0][plan[1]] = values


class RollbackState:
    """A state attribute saved as its object's rollback state: the live ``owner`` and what its steps change
    (``owner.rollback_state()``). Set back onto the same owner by ``owner.restore_rollback_state(data)``; anywhere
    else (another instance, serialisation) as :meth:`materialise`, a deep copy of the owner as it was then."""

    __slots__ = ("owner", "data")

    def __init__(self, owner: Any, data: Any) -> None:
        self.owner = owner
        self.data = data

    def materialise(self) -> Any:
        """A deep copy of the owner as it was when saved (the owner itself is left as it is now: set back to the
        saved state for the copy, then forward again)."""
        now = self.owner.rollback_state()
        self.owner.restore_rollback_state(self.data)
        try:
            return copy.deepcopy(self.owner)
        finally:
            self.owner.restore_rollback_state(now)


class VectorSlave(Fmi2Slave):
    """PythonFMU slave whose Real variables are views of numpy arrays.

    Subclasses register variables with :meth:`add_reals`, implement :meth:`update_outputs`
    (fill the output arrays from the current inputs and state) and :meth:`do_step`, and list
    in ``state_attributes`` every attribute that holds simulation state.
    """

    state_attributes: tuple[str, ...] = ()

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        cls._wrap_fmi_calls()

    @classmethod
    def _wrap_fmi_calls(cls) -> None:
        """Log the message of any exception raised in this class's own FMI entry points (see above)."""
        for name in _LOGGED_CALLS:
            if name in vars(cls) and not getattr(vars(cls)[name], "_fmi_logged", False):
                setattr(cls, name, _logged(name, vars(cls)[name]))
                getattr(cls, name)._fmi_logged = True
        if "do_step" in vars(cls) and not getattr(vars(cls)["do_step"], "_fmi_logged", False):
            cls.do_step = _logged_step(vars(cls)["do_step"])
            cls.do_step._fmi_logged = True

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        hold_module_globals(type(self).__module__)
        self._slot: dict[int, tuple[np.ndarray, int]] = {}
        self._values = RealStore()
        self._input_vrs: list[int] = []
        self._output_deps: dict[int, Sequence[str] | None] = {}
        self._units: dict[str, str] = {}
        self._arrays: dict[str, np.ndarray] = {}
        self._outputs_stale = True
        self._ready = False  # set by subclasses once the physics model exists

    # ------------------------------------------------------------------ registration
    def add_reals(
        self,
        key: str,
        names: Sequence[str],
        causality: str,
        start: Sequence[float] | np.ndarray,
        *,
        unit: str | Sequence[str] = "1",
        description: str = "",
        depends_on: Sequence[str] | None = (),
    ) -> np.ndarray:
        """Register scalar Reals ``names`` backed by one array, returned (and kept under ``key``).

        ``depends_on`` applies to outputs: the keys of the input arrays whose values feed the
        outputs directly (direct feedthrough); ``()`` means none, ``None`` means all inputs.
        ``unit`` is one unit for all names or one per name.
        """
        units = [unit] * len(names) if isinstance(unit, str) else list(unit)
        for u in units:
            if u not in _BASE_UNITS:
                raise ValueError(f"unit {u!r} of {key} is not in the unit table")
        values = self._values.allocate(np.array(start, dtype=float).reshape(len(names)))
        variability = {
            "parameter": Fmi2Variability.fixed,
            "calculatedParameter": Fmi2Variability.fixed,
        }.get(causality, Fmi2Variability.continuous)
        # FMI 2.0 (table of section 2.2.7): a parameter is "exact" (the default), an input takes no initial
        # attribute at all (its start value is required and written); libcosim rejects initial="exact" there.
        initial = Fmi2Initial.exact if causality == "parameter" else None
        for i, name in enumerate(names):
            var = Real(
                name,
                causality=_CAUSALITY[causality],
                variability=variability,
                initial=initial,
                description=description or None,
                getter=(lambda a=values, j=i: float(a[j])),
                setter=(lambda v, a=values, j=i: a.__setitem__(j, v)),
            )
            self.register_variable(var)
            self._slot[var.value_reference] = (values, i)
            self._values.bind(var.value_reference, values, i)
            self._units[name] = units[i]
            if causality == "input":
                self._input_vrs.append(var.value_reference)
            if causality == "output":
                self._output_deps[var.value_reference] = depends_on
        self._arrays[key] = values
        return values

    def set_default_experiment(self, spec: dict[str, Any]) -> None:
        """``DefaultExperiment`` from the scene specification's ``experiment`` (start, stop, step in s): what
        ``fmpy.simulate_fmu(fmu)`` and other hosts use when not told otherwise."""
        e = spec.get("experiment")
        if e:
            self.default_experiment = DefaultExperiment(start_time=e["start"], stop_time=e["stop"], step_size=e["step"])

    def array(self, key: str) -> np.ndarray:
        return self._arrays[key]

    def stacked(self, keys: Sequence[str]) -> np.ndarray | None:
        """The arrays of ``keys`` (equal lengths n) as rows of one (len(keys), n) view, if they were registered
        one after the other (adjacent in the value store); None otherwise."""
        arrays = [self._arrays[k] for k in keys]
        first = arrays[0]
        base = first.base if first.base is not None else first
        start = (first.__array_interface__["data"][0] - base.__array_interface__["data"][0]) // first.itemsize
        n = len(first)
        view = base[start : start + n * len(arrays)]
        if len(view) != n * len(arrays) or not all(
                len(a) == n and np.shares_memory(a, view[i * n : (i + 1) * n])
                and a.__array_interface__["data"][0] == view[i * n :].__array_interface__["data"][0]
                for i, a in enumerate(arrays)):
            return None
        return view.reshape(len(arrays), n)

    def log(self, msg: str, status: Any = None, category: str | None = None, debug: Any = None) -> None:
        """PythonFMU's log with "%" escaped: FMI hosts treat the message as a printf format string
        (an unescaped "11% of" prints as "11" followed by an octal conversion)."""
        kwargs = {} if status is None else {"status": status}
        super().log(msg.replace("%", "%%"), category=category, **kwargs)

    # ------------------------------------------------------------------ physics hooks
    def update_outputs(self) -> None:  # pragma: no cover - overridden
        """Recompute every output array from the current inputs and state."""

    # ------------------------------------------------------------------ bulk access
    def refresh_outputs(self) -> None:
        """Recompute the outputs if an input changed since they were last computed (and the model is ready)."""
        if self._outputs_stale and self._ready:
            self.update_outputs()
            self._outputs_stale = False

    def get_real(self, vrs: list[int]) -> list[float]:
        self.refresh_outputs()
        return self._values.gather(vrs)

    def set_real(self, vrs: list[int], values: list[float]) -> None:
        self._values.scatter(vrs, values)
        self._outputs_stale = True

    def mark_outputs_stale(self) -> None:
        self._outputs_stale = True

    # ------------------------------------------------------------------ state
    def _get_fmu_state(self) -> dict[str, Any]:
        """The registered arrays and a copy of each state attribute; an attribute whose object offers a rollback
        state (``rollback_state()`` / ``restore_rollback_state(data)``: only what its steps change, e.g. the linear
        multibody model's positions and velocities) is saved as that (:class:`RollbackState`), the rest deep-copied.
        Setting the state back onto the same live object is then a few array copies, not a deep copy of the model
        (an iterative master does it at every iteration)."""
        attributes = {}
        previous = self.__dict__.setdefault("_rollback_previous", {})  # the last rollback state per attribute
        for k in self.state_attributes:
            value = getattr(self, k)
            last = previous.get(k)
            data = value.rollback_state(last.data if last is not None and last.owner is value else None) \
                if hasattr(value, "rollback_state") else None
            if data is not None:
                attributes[k] = previous[k] = RollbackState(value, data)
            else:
                attributes[k] = copy.deepcopy(value)
        return {"slave": type(self).__name__, "arrays": {k: a.copy() for k, a in self._arrays.items()},
                "attributes": attributes, "_owner": self}

    def _set_fmu_state(self, state: dict[str, Any] | SerializedState) -> None:
        if isinstance(state, SerializedState):
            state = self._decode_state(state.data)
            for key, value in state["attributes"].items():
                setattr(self, key, value)
            state = {"arrays": state["arrays"], "attributes": {}}
        for key, values in state["arrays"].items():
            self._arrays[key][:] = values
        for key, value in state["attributes"].items():
            if isinstance(value, RollbackState):
                if getattr(self, key) is value.owner:
                    value.owner.restore_rollback_state(value.data)
                else:
                    setattr(self, key, value.materialise())
            else:
                setattr(self, key, copy.deepcopy(value))
        self._outputs_stale = True

    # PythonFMU's binary calls these two on the class (static methods): the state carries a reference to
    # its slave ("_owner", not serialised) so that a failure is logged where the host can read it.
    @staticmethod
    def _fmu_state_to_bytes(state: dict[str, Any]) -> bytes:
        """The state in :mod:`fmu_base.state_codec`'s data-only layout (never pickle)."""
        owner = state.get("_owner")
        try:
            plain = {k: v for k, v in state.items() if k != "_owner"}
            plain["attributes"] = {k: v.materialise() if isinstance(v, RollbackState) else v
                                   for k, v in state["attributes"].items()}
            return state_codec.encode(plain)
        except Exception as exc:
            if owner is not None:
                owner.log(_describe_failure("serialising the FMU state", exc), Fmi2Status.error)
            raise

    @staticmethod
    def _fmu_state_from_bytes(data: bytes) -> SerializedState:
        """Kept as bytes: checked and applied onto the live model by ``_set_fmu_state`` (which logs)."""
        return SerializedState(bytes(data))

    def _decode_state(self, data: bytes) -> dict[str, Any]:
        """A serialised state decoded onto a copy of the live model (the live one is untouched if the
        data do not fit it)."""
        saved_by = state_codec.peek(data, "slave")
        if saved_by != type(self).__name__:  # refused before any of its objects is read
            raise state_codec.StateFormatError(
                f"the state is not a state of this FMU ({type(self).__name__}; got {saved_by!r})")
        template = {"slave": type(self).__name__, "arrays": {},
                    "attributes": {k: copy.deepcopy(getattr(self, k)) for k in self.state_attributes}}
        state = state_codec.decode(data, template)
        if not isinstance(state, dict) or state.get("slave") != type(self).__name__:
            raise state_codec.StateFormatError(
                f"the state is not a state of this FMU ({type(self).__name__}; got "
                f"{state.get('slave') if isinstance(state, dict) else type(state).__name__!r})")
        arrays, attributes = state.get("arrays"), state.get("attributes")
        if not isinstance(arrays, dict) or not isinstance(attributes, dict) or \
                set(arrays) != set(self._arrays) or set(attributes) != set(self.state_attributes):
            raise state_codec.StateFormatError("the state's variables do not match this FMU's")
        for key, values in arrays.items():
            if not isinstance(values, np.ndarray) or values.shape != self._arrays[key].shape:
                raise state_codec.StateFormatError(f"the state's variable {key!r} has the wrong size")
        return {"arrays": arrays, "attributes": attributes}

    # ------------------------------------------------------------------ model description
    def to_xml(self, model_options: dict[str, str] | None = None) -> Element:
        root = super().to_xml(model_options or {})
        self._add_units(root)
        self._write_model_structure(root)
        return root

    def _add_units(self, root: Element) -> None:
        used = sorted(set(self._units.values()) - {"1"})
        if used:
            defs = Element("UnitDefinitions")
            for unit in used:
                node = SubElement(defs, "Unit", {"name": unit})
                SubElement(node, "BaseUnit", {k: str(v) for k, v in _BASE_UNITS[unit].items()})
            position = [child.tag for child in root].index("CoSimulation") + 1
            root.insert(position, defs)
        for node in root.find("ModelVariables"):
            unit = self._units.get(node.get("name"), "1")
            real = node.find("Real")
            if unit != "1" and real is not None:
                real.set("unit", unit)

    def _write_model_structure(self, root: Element) -> None:
        old = root.find("ModelStructure")
        if old is not None:
            root.remove(old)
        structure = SubElement(root, "ModelStructure")
        index_of = {vr: i + 1 for i, vr in enumerate(self.vars)}
        inputs_by_key = {
            key: [vr for vr in self._input_vrs if self._slot[vr][0] is array]
            for key, array in self._arrays.items()
        }

        def deps(vr: int) -> str | None:
            keys = self._output_deps[vr]
            if keys is None:
                return None
            return " ".join(str(index_of[i]) for k in keys for i in inputs_by_key[k])

        outputs = [vr for vr, v in self.vars.items() if v.causality == Fmi2Causality.output]
        if outputs:
            node = SubElement(structure, "Outputs")
            for vr in outputs:
                attrib = {"index": str(index_of[vr])}
                d = deps(vr)
                if d is not None:
                    attrib["dependencies"] = d
                SubElement(node, "Unknown", attrib)
        initial = [
            vr
            for vr, v in self.vars.items()
            if v.causality in (Fmi2Causality.output, Fmi2Causality.calculatedParameter)
        ]
        if initial:
            node = SubElement(structure, "InitialUnknowns")
            for vr in initial:
                SubElement(node, "Unknown", {"index": str(index_of[vr])})


VectorSlave._wrap_fmi_calls()


def indexed_names(prefix: str, indices: Sequence[int]) -> list[str]:
    """FMI structured names ``prefix[i]`` for the given 1-based indices."""
    return [f"{prefix}[{i}]" for i in indices]


def matrix_names(prefix: str, rows: Sequence[int], cols: Sequence[int]) -> list[str]:
    """FMI structured names ``prefix[i,j]`` (row-major) for 1-based row and column indices."""
    return [f"{prefix}[{i},{j}]" for i in rows for j in cols]

