"""Python binding of the compiled hydrodynamics runtime (``native/src/hydro``, API ``native/include/wec_hydro.h``).

:class:`HydroRuntime` owns one runtime model (a C handle) made from the runtime input
(:func:`hydro_fmu.runtime_input.runtime_input`). Every call checks its sizes here and in C; a failed call raises
:class:`fmu_base.native.RuntimeCallError` (a ``ValueError``) with the runtime's message. Copies (``copy.copy``,
``copy.deepcopy``, :meth:`HydroRuntime.clone`) are independent models sharing the read-only data; the state
(everything that changes as the model runs) is saved and loaded as bytes (:meth:`HydroRuntime.state`,
:meth:`HydroRuntime.load_state`), which is also what :mod:`fmu_base.state_codec` stores for it.
"""

from __future__ import annotations

import ctypes

import numpy as np

from fmu_base import native
from fmu_base.native import RuntimeCallError

_P = ctypes.c_void_p
_D = ctypes.c_double
_S = ctypes.c_size_t
_I = ctypes.c_int
SIGNATURES = {
    "wec_hydro_create": (_P, [ctypes.c_char_p, _S]),
    "wec_hydro_create_error": (ctypes.c_char_p, []),
    "wec_hydro_last_error": (ctypes.c_char_p, [_P]),
    "wec_hydro_clone": (_P, [_P]),
    "wec_hydro_free": (None, [_P]),
    "wec_hydro_dofs": (_I, [_P, ctypes.POINTER(_S)]),
    "wec_hydro_added_mass_inf": (_I, [_P, _P, _S]),
    "wec_hydro_set_start_time": (_I, [_P, _D]),
    "wec_hydro_outputs": (_I, [_P, _D, _P, _P, _S, _P, _S, _P, _P, _P, _P]),
    "wec_hydro_elevation": (_I, [_P, _D, _P]),
    "wec_hydro_linearise": (_I, [_P, _D, _P, _P, _S, _P, _P, _P, _P, _P, _P]),
    "wec_hydro_advance": (_I, [_P, _D, _D, _P, _S]),
    "wec_hydro_commit_work": (_I, [_P, _D, _P, _P, _S]),
    "wec_hydro_do_step": (_I, [_P, _D, _D, _P, _P, _S]),
    "wec_hydro_state_size": (_I, [_P, ctypes.POINTER(_S)]),
    "wec_hydro_state_save": (_I, [_P, _P, _S]),
    "wec_hydro_state_load": (_I, [_P, ctypes.c_char_p, _S]),
    "wec_hydro_copy_state": (_I, [_P, _P]),
}
ROWS = 5  # total, excitation, radiation, hydrostatic, viscous
COMPONENTS = 4


def _library() -> ctypes.CDLL:
    lib = native.library()
    if not getattr(lib, "_hydro_declared", False):
        native.declare(lib, SIGNATURES)
        lib._hydro_declared = True
    return lib


def _address(a: np.ndarray) -> int:
    return a.__array_interface__["data"][0]


class HydroRuntime:
    """A runtime model made from runtime input ``data`` (bytes); :class:`fmu_base.native.RuntimeCallError` with the
    runtime's message if the data are refused."""

    def __init__(self, data: bytes) -> None:
        lib = _library()
        handle = lib.wec_hydro_create(data, len(data))
        if not handle:
            raise RuntimeCallError(lib.wec_hydro_create_error().decode("utf-8", "replace"), native.ERR_DATA)
        self._adopt(lib, handle)

    def _adopt(self, lib: ctypes.CDLL, handle: int) -> None:
        self._lib, self._handle = lib, handle
        count = _S()
        self._check(lib.wec_hydro_dofs(handle, ctypes.byref(count)))
        self.n = count.value
        self._block = np.zeros((ROWS, self.n))
        self._power = np.zeros(COMPONENTS)
        self._work = np.zeros(COMPONENTS)
        self._eta = np.zeros(1)
        self._addresses = (_address(self._block), _address(self._power), _address(self._work), _address(self._eta))
        self._slots: dict[str, tuple[np.ndarray, tuple[int, ...], int]] = {}
        self._last_outputs: tuple | None = None
        self._last_inputs: tuple | None = None

    def _pointer(self, key: str, a: np.ndarray, shape: tuple[int, ...], output: bool = False,
                 dtype: type = np.float64) -> tuple[int, np.ndarray]:
        """(address, array) of the argument ``key``: the same array object as the last call's costs a dictionary
        look-up (FMU value stores and model buffers are passed at every point; taking an address from numpy costs
        microseconds); another is checked (shape, dtype, C order: inputs converted, outputs refused) and kept."""
        slot = self._slots.get(key)
        if slot is not None and slot[0] is a and a.shape == shape:
            return slot[2], a
        if not (isinstance(a, np.ndarray) and a.dtype == dtype and a.flags.c_contiguous and a.shape == shape):
            if output:
                raise ValueError(f"hydro runtime: {key} must be a C-contiguous {np.dtype(dtype)} array of shape "
                                 f"{shape}, not {getattr(a, 'dtype', type(a).__name__)} {np.shape(a)}")
            converted = np.ascontiguousarray(a, dtype=dtype)
            if converted.shape != shape:
                raise ValueError(f"hydro runtime: {key} has shape {converted.shape}, expected {shape}")
            return _address(converted), converted  # a temporary: not kept
        address = _address(a)
        self._slots[key] = (a, shape, address)
        return address, a

    def _inputs(self, x: np.ndarray, v: np.ndarray) -> tuple[int, int]:
        """Addresses of the inputs ``x``, ``v``; the same two arrays as the last call cost two identity checks (only
        arrays used as they are are remembered: a converted copy is made again at every call)."""
        last = self._last_inputs
        if last is not None and x is last[0] and v is last[1]:
            return last[2], last[3]
        n = self.n
        px, x_used = self._pointer("x", x, (n,))
        pv, v_used = self._pointer("v", v, (n,))
        self._last_inputs = (x, v, px, pv) if (x_used is x and v_used is v) else None
        self._keep = (x_used, v_used)  # alive until the call is made
        return px, pv

    def __del__(self) -> None:
        handle, self._handle = getattr(self, "_handle", None), None
        if handle:
            self._lib.wec_hydro_free(handle)

    def _check(self, status: int) -> None:
        if status != 0:
            message = self._lib.wec_hydro_last_error(self._handle).decode("utf-8", "replace")
            raise RuntimeCallError(message or native.status_name(status), status)

    # ------------------------------------------------------------------ copies and state
    def clone(self) -> HydroRuntime:
        """An independent model with the same data (shared) and state."""
        handle = self._lib.wec_hydro_clone(self._handle)
        if not handle:
            raise RuntimeCallError(self._lib.wec_hydro_create_error().decode("utf-8", "replace"), native.ERR_MEMORY)
        new = object.__new__(type(self))
        new._adopt(self._lib, handle)
        return new

    def __copy__(self) -> HydroRuntime:
        return self.clone()

    def __deepcopy__(self, memo: dict) -> HydroRuntime:
        return self.clone()

    def state(self) -> bytes:
        """The model state as bytes (native/src/hydro/state.c)."""
        size = _S()
        self._check(self._lib.wec_hydro_state_size(self._handle, ctypes.byref(size)))
        buffer = ctypes.create_string_buffer(size.value)
        self._check(self._lib.wec_hydro_state_save(self._handle, buffer, size.value))
        return buffer.raw

    def load_state(self, data: bytes) -> None:
        """Load a state saved by a model of the same data (refused, model unchanged, otherwise)."""
        data = bytes(data)
        self._check(self._lib.wec_hydro_state_load(self._handle, data, len(data)))

    def copy_state_from(self, other: HydroRuntime) -> None:
        self._check(self._lib.wec_hydro_copy_state(self._handle, other._handle))

    def __getstate__(self) -> dict:
        return {"state": self.state()}

    def __setstate__(self, state: dict) -> None:
        if not getattr(self, "_handle", None):
            raise ValueError("a hydro runtime state is restored into a model built from the same data, not on its own")
        self.load_state(state["state"])

    # ------------------------------------------------------------------ step-time calls
    def added_mass_inf(self) -> np.ndarray:
        out = np.zeros((self.n, self.n))
        self._check(self._lib.wec_hydro_added_mass_inf(self._handle, _address(out), out.size))
        return out

    def set_start_time(self, t: float) -> None:
        self._check(self._lib.wec_hydro_set_start_time(self._handle, float(t)))

    def evaluate(self, t: float, x: np.ndarray, v: np.ndarray, block: np.ndarray | None = None) -> float:
        """The force rows (5, n) at time ``t`` for ``x``, ``v`` into ``block`` (default: :attr:`block`); returns the
        elevation at the origin (m). Powers and work of the point are then in :attr:`power` and :attr:`work`."""
        n = self.n
        px, pv = self._inputs(x, v)
        pb, _ = self._pointer("block", self._block if block is None else block, (ROWS, n), output=True)
        _, power, work, eta = self._addresses
        self._check(self._lib.wec_hydro_outputs(self._handle, t, px, pv, n, None, ROWS, pb, power, work, eta))
        return float(self._eta[0])

    def outputs(self, t: float, x: np.ndarray, v: np.ndarray, rows: np.ndarray, out: np.ndarray, power: np.ndarray,
                work: np.ndarray) -> float:
        """The force rows ``rows`` (int64, values 0..4) into the rows of ``out`` (len(rows), n), the power and work of
        each component into ``power`` and ``work`` (4 each); returns the elevation at the origin (m). One call; the
        same six arrays as the last call (an FMU's value store) cost one identity check each."""
        last = self._last_outputs
        if last is not None and x is last[0] and v is last[1] and rows is last[2] and out is last[3] \
                and power is last[4] and work is last[5]:
            status = self._lib.wec_hydro_outputs(self._handle, t, *last[6])
        else:
            n = self.n
            px, x = self._pointer("x", x, (n,))
            pv, v = self._pointer("v", v, (n,))
            pr, rows = self._pointer("rows", rows, (len(rows),), dtype=np.int64)
            po, _ = self._pointer("out", out, (len(rows), n), output=True)
            pp, _ = self._pointer("power", power, (COMPONENTS,), output=True)
            pw, _ = self._pointer("work", work, (COMPONENTS,), output=True)
            args = (px, pv, n, pr, len(rows), po, pp, pw, self._addresses[3])
            self._last_outputs = (x, v, rows, out, power, work, args)
            status = self._lib.wec_hydro_outputs(self._handle, t, *args)
        if status:
            self._check(status)
        return self._eta[0].item()

    @property
    def block(self) -> np.ndarray:
        """The force rows of the last :meth:`evaluate` into the default block."""
        return self._block

    @property
    def power(self) -> np.ndarray:
        return self._power

    @property
    def work(self) -> np.ndarray:
        return self._work

    def elevation(self, t: float) -> float:
        self._check(self._lib.wec_hydro_elevation(self._handle, float(t), self._addresses[3]))
        return float(self._eta[0])

    def linearise(self, t: float, x: np.ndarray, v: np.ndarray, stiffness_mask: np.ndarray | None = None,
                  damping_mask: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(F0, F0_rate, dF_dx, dF_dv) about (t, x, v) with the matrices restricted to the masks (n, n bool; None:
        every entry)."""
        n = self.n
        px, pv = self._inputs(x, v)
        masks = []
        for mask in (stiffness_mask, damping_mask):
            if mask is None:
                masks.append(None)
                continue
            mask = np.ascontiguousarray(mask, dtype=np.uint8)
            if mask.shape != (n, n):
                raise ValueError(f"hydro runtime: a mask has shape {mask.shape}, expected ({n}, {n})")
            masks.append(mask)
        f0, rate, dfdx, dfdv = np.zeros(n), np.zeros(n), np.zeros((n, n)), np.zeros((n, n))
        self._check(self._lib.wec_hydro_linearise(
            self._handle, float(t), px, pv, n, None if masks[0] is None else _address(masks[0]),
            None if masks[1] is None else _address(masks[1]), _address(f0), _address(rate), _address(dfdx),
            _address(dfdv)))
        return f0, rate, dfdx, dfdv

    def advance(self, t: float, h: float, v: np.ndarray) -> None:
        """Commit ``v`` at the current point ``t`` to the radiation memory and move on by ``h`` (s)."""
        pv, v = self._pointer("v", v, (self.n,))
        status = self._lib.wec_hydro_advance(self._handle, t, h, pv, self.n)
        if status:
            self._check(status)

    def commit_work(self, t: float, x: np.ndarray, v: np.ndarray) -> None:
        """Accept the point ``t`` (inputs ``x``, ``v``) into the work account."""
        px, pv = self._inputs(x, v)
        status = self._lib.wec_hydro_commit_work(self._handle, t, px, pv, self.n)
        if status:
            self._check(status)

    def do_step(self, t: float, h: float, x: np.ndarray, v: np.ndarray) -> None:
        """The FMU's step: the work at the point ``t`` committed, then :meth:`advance`."""
        px, pv = self._inputs(x, v)
        status = self._lib.wec_hydro_do_step(self._handle, t, h, px, pv, self.n)
        if status:
            self._check(status)
