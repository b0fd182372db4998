"""Loads the compiled runtime (``native/``: the step-time physics in C) and turns its status codes into exceptions.

The runtime is one shared library inside this package, ``fmu_base/_wecrt.so`` (``.dylib``, ``.dll`` elsewhere),
built by ``pip install`` (``setup.py``; a C11 compiler is needed) and bundled with ``fmu_base`` into every FMU. It
is plain C with a flat API (``native/include/``), loaded here with :mod:`ctypes`: the library is not a Python
extension and links nothing of Python. Each runtime's binding declares its functions (``hydro_fmu/runtime.py``);
this module finds and loads the library once per process and holds what the bindings share.
"""

from __future__ import annotations

import ctypes
import functools
from pathlib import Path

from . import runtime_data

HERE = Path(__file__).resolve().parent
NAMES = ("_wecrt.so", "_wecrt.dylib", "_wecrt.dll")
STATUS = {0: "WEC_OK", 1: "WEC_ERR_HANDLE", 2: "WEC_ERR_ARGUMENT", 3: "WEC_ERR_DATA", 4: "WEC_ERR_STATE",
          5: "WEC_ERR_STEP", 6: "WEC_ERR_MEMORY"}
ERR_HANDLE, ERR_ARGUMENT, ERR_DATA, ERR_STATE, ERR_STEP, ERR_MEMORY = 1, 2, 3, 4, 5, 6
_INSTALL_HINT = ("it is compiled by `pip install -e .` (or `pip install .`) from the repository, which needs a C11 "
                 "compiler: Debian/Ubuntu `sudo apt-get install gcc`, Fedora/RHEL `sudo dnf install gcc`, macOS "
                 "`xcode-select --install`, Windows the Microsoft C++ Build Tools")


class RuntimeMissingError(ImportError):
    """The compiled runtime library is not built or cannot be loaded; the message says how to build it."""


class RuntimeCallError(ValueError):
    """A runtime call failed; ``status`` is its code, the message the runtime's explanation."""

    def __init__(self, message: str, status: int) -> None:
        super().__init__(message)
        self.status = status


def library_path() -> Path | None:
    """The runtime library beside this module, if it is there."""
    for name in NAMES:
        path = HERE / name
        if path.is_file():
            return path
    return None


@functools.cache
def library() -> ctypes.CDLL:
    """The loaded runtime (once per process); :class:`RuntimeMissingError` if it is not built."""
    path = library_path()
    if path is None:
        raise RuntimeMissingError(f"the compiled wec-cosim runtime ({HERE / NAMES[0]}) is not built: "
                                  f"{_INSTALL_HINT}")
    try:
        lib = ctypes.CDLL(str(path))
    except OSError as exc:
        raise RuntimeMissingError(f"the compiled wec-cosim runtime {path} cannot be loaded ({exc}); rebuild it: "
                                  f"{_INSTALL_HINT}") from None
    lib.wec_runtime_version.restype = ctypes.c_int
    lib.wec_data_format_version.restype = ctypes.c_int
    if lib.wec_data_format_version() != runtime_data.VERSION:
        raise RuntimeMissingError(f"the compiled runtime {path} reads data format {lib.wec_data_format_version()}, "
                                  f"this Python code writes {runtime_data.VERSION}: rebuild it ({_INSTALL_HINT})")
    return lib


def declare(lib: ctypes.CDLL, signatures: dict[str, tuple[object, list]]) -> None:
    """Set restype and argtypes of the library's functions: name -> (restype, [argtypes])."""
    for name, (restype, argtypes) in signatures.items():
        function = getattr(lib, name)
        function.restype = restype
        function.argtypes = argtypes


def status_name(status: int) -> str:
    return STATUS.get(status, f"status {status}")
