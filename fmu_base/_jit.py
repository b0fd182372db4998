"""numba's ``njit`` with an on-disk cache that survives the FMU's extraction folder.

An FMU runs its Python sources from a fresh temporary folder every time it is instantiated; numba's
own cache locators key the cache on the source file's *directory*, so every run would recompile
the kernels (several seconds). The locator below keys it on the source file's *content* instead,
in ``$WEC_COSIM_CACHE/numba`` (default ``~/.cache/wec-cosim/numba``): the same sources, wherever they
are, load the compiled machine code in tens of milliseconds. A kernel module other than ``kernels.py``
(``nullspace_kernels.py``) compiles ``kernels.py``'s functions into its own machine code, so its key
covers both files' content. Caches of other source versions unused for
30 days are removed. If numba is not installed, or the cache
folder cannot be written, :data:`AVAILABLE` tells the callers (the model then runs on its Python path,
or numba compiles in memory).
"""

from __future__ import annotations

import hashlib
import os
from collections.abc import Callable
from pathlib import Path


def cache_root() -> Path:
    """Folder of the compiled kernels: ``$WEC_COSIM_NUMBA_CACHE`` if set (the test suite shares one across its
    processes while each session builds its FMUs into a private cache), else beside the FMU cache."""
    if os.environ.get("WEC_COSIM_NUMBA_CACHE"):
        return Path(os.environ["WEC_COSIM_NUMBA_CACHE"])
    base = os.environ.get("WEC_COSIM_CACHE") or os.path.join(
        os.environ.get("XDG_CACHE_HOME", os.path.expanduser("~/.cache")), "wec-cosim")
    return Path(base) / "numba"


try:
    if os.environ.get("WEC_COSIM_NO_JIT"):
        raise ImportError("disabled by WEC_COSIM_NO_JIT")
    import numba
    from numba.core import caching

    class _ContentLocator(caching._CacheLocator):
        """Cache keyed on the kernel module's file content, not its location."""

        def __init__(self, py_file: str) -> None:
            data = Path(py_file).read_bytes()
            base = Path(py_file).with_name("kernels.py")
            if base != Path(py_file) and base.is_file():  # another module's kernels call these: their machine code
                data += base.read_bytes()  # is compiled into that module's cache, which must follow them
            self._stamp = hashlib.sha256(data).hexdigest()[:20]
            self._path = str(cache_root() / f"{Path(py_file).stem}-{self._stamp}")

        def get_cache_path(self) -> str:
            return self._path

        def get_source_stamp(self) -> str:
            return self._stamp

        def get_disambiguator(self) -> str:
            return self._stamp[:8]

        @classmethod
        def from_function(cls, py_func, py_file):
            if Path(py_file).parent.name != "mbd_fmu" or not os.path.isfile(py_file):
                return None
            try:
                locator = cls(py_file)
                locator.ensure_cache_path()
                _prune(Path(locator._path))
            except OSError:
                return None
            return locator

    _PRUNED: set = set()

    def _prune(current: Path, days: float = 30.0) -> None:
        """Remove other versions' caches (same module, other source content) unused for ``days`` (about 15 MB
        each), once per process."""
        if current in _PRUNED:
            return
        _PRUNED.add(current)
        os.utime(current)  # in use: the age below is the time since a process last used a version
        import shutil
        import time

        stem = current.name.rsplit("-", 1)[0]
        for other in current.parent.glob(f"{stem}-*"):
            if other != current and other.is_dir() and time.time() - other.stat().st_mtime > days * 86400:
                shutil.rmtree(other, ignore_errors=True)

    if _ContentLocator.__name__ not in {c.__name__ for c in caching.CacheImpl._locator_classes}:
        caching.CacheImpl._locator_classes.insert(0, _ContentLocator)

    def njit(func: Callable) -> Callable:
        """Compiled, cached, numpy error semantics (division by zero gives inf/nan as in the Python path)."""
        return numba.njit(cache=True, error_model="numpy")(func)

    AVAILABLE = True
except ImportError:  # pragma: no cover - numba is a dependency; this keeps the Python path usable without it
    AVAILABLE = False

    def njit(func: Callable) -> Callable:
        return func
