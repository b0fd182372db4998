"""numba's ``njit`` with an on-disk cache that survives the FMU's extraction folder (shared by every FMU package).

An FMU runs its Python sources from a fresh temporary folder every time it is instantiated; numba's
own cache locators key the cache on the source file's *directory*, so every run would recompile
the kernels (several seconds). The locator below keys it on the source file's *content* instead,
in ``$WEC_COSIM_CACHE/numba`` (default ``~/.cache/wec-cosim/numba``): the same sources, wherever they
are, load the compiled machine code in tens of milliseconds.

Which modules: any module of the toolkit's FMU packages (:data:`PACKAGES`: ``mbd_fmu``, ``hydro_fmu``, ...)
that compiles functions with :func:`njit`. Its key covers its own content and the content of every module of
those packages it imports, followed recursively (:func:`key_sources`): a kernel module that calls another
module's kernels (``mbd_fmu/nullspace_kernels.py`` calls ``mbd_fmu/kernels.py``) compiles them into its own
machine code, so its cache must follow them. Caches of other source versions unused for 30 days are removed.
If numba is not installed, ``WEC_COSIM_NO_JIT`` is set, or the cache folder cannot be written,
:data:`AVAILABLE` tells the callers (the models then run on their Python paths, or numba compiles in memory).
"""

from __future__ import annotations

import ast
import functools
import hashlib
import os
from collections.abc import Callable
from pathlib import Path

# Packages whose kernel modules get the content-keyed cache (each is bundled into its FMU with fmu_base).
PACKAGES = ("mbd_fmu", "hydro_fmu", "fmu_base", "plain_mbd_fmu")


@functools.lru_cache(maxsize=256)
def _import_nodes(source: bytes, filename: str) -> tuple[ast.ImportFrom | ast.Import, ...]:
    """The import statements of a module's source. Memoised on the content: every compiled function of a kernel
    module asks for its module's key when numba sets up its cache, and parsing the module and the package modules
    it imports each time cost seconds per import of the module (7 s for ``mbd_fmu/kernels.py``)."""
    return tuple(node for node in ast.walk(ast.parse(source, filename=filename))
                 if isinstance(node, (ast.ImportFrom, ast.Import)))


def _imported_files(path: Path) -> list[Path]:
    """Files of :data:`PACKAGES` that the module at ``path`` imports (relative imports within its package, and
    absolute ``package.module`` imports resolved beside its package folder); those that do not exist are left
    out."""
    package = path.parent
    found = []
    for node in _import_nodes(path.read_bytes(), str(path)):
        if isinstance(node, ast.ImportFrom):
            if node.level == 1:
                base = package
                parts = node.module.split(".") if node.module else []
            elif node.level == 0 and node.module and node.module.split(".")[0] in PACKAGES:
                base = package.parent
                parts = node.module.split(".")
            else:
                continue
            stems = [parts] if parts else []
            stems += [parts + [alias.name] for alias in node.names]  # ``from . import kernels``
        elif isinstance(node, ast.Import):
            base = package.parent
            stems = [a.name.split(".") for a in node.names if a.name.split(".")[0] in PACKAGES]
        else:
            continue
        for stem in stems:
            candidate = base.joinpath(*stem).with_suffix(".py") if stem else None
            if candidate is not None and candidate.is_file():
                found.append(candidate.resolve())
    return found


def key_sources(py_file: str | Path) -> list[Path]:
    """The module at ``py_file`` and every module of :data:`PACKAGES` it imports, recursively, in a fixed order
    (the module first, then by path relative to its package's parent): what its cache key covers."""
    first = Path(py_file).resolve()
    seen, todo = {first}, [first]
    while todo:
        for other in _imported_files(todo.pop()):
            if other not in seen:
                seen.add(other)
                todo.append(other)
    root = first.parent.parent
    rest = sorted(seen - {first}, key=lambda p: str(p.relative_to(root)) if p.is_relative_to(root) else str(p))
    return [first, *rest]


def source_stamp(py_file: str | Path) -> str:
    """Hash of the content of :func:`key_sources` (each file's package-relative name and bytes)."""
    digest = hashlib.sha256()
    for path in key_sources(py_file):
        digest.update(f"{path.parent.name}/{path.name}\0".encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:20]


def cache_base() -> Path:
    """The toolkit's cache folder: ``$WEC_COSIM_CACHE``, default ``$XDG_CACHE_HOME/wec-cosim`` or
    ``~/.cache/wec-cosim`` (built FMUs in ``fmus/``, compiled kernels in ``numba/``, fits in ``fits/``)."""
    return Path(os.environ.get("WEC_COSIM_CACHE") or os.path.join(
        os.environ.get("XDG_CACHE_HOME", os.path.expanduser("~/.cache")), "wec-cosim"))


def cache_root() -> Path:
    """Folder of the compiled kernels: ``$WEC_COSIM_NUMBA_CACHE`` if set (the test suite shares one across its
    processes while each session builds its FMUs into a private cache), else beside the FMU cache."""
    if os.environ.get("WEC_COSIM_NUMBA_CACHE"):
        return Path(os.environ["WEC_COSIM_NUMBA_CACHE"])
    return cache_base() / "numba"


try:
    if os.environ.get("WEC_COSIM_NO_JIT"):
        raise ImportError("disabled by WEC_COSIM_NO_JIT")
    import numba
    from numba.core import caching

    class _ContentLocator(caching._CacheLocator):
        """Cache keyed on the kernel module's file content, not its location."""

        def __init__(self, py_file: str) -> None:
            self._stamp = source_stamp(py_file)  # the module and the package modules it imports (their kernels)
            self._path = str(cache_root() / f"{Path(py_file).parent.name}.{Path(py_file).stem}-{self._stamp}")

        def get_cache_path(self) -> str:
            return self._path

        def get_source_stamp(self) -> str:
            return self._stamp

        def get_disambiguator(self) -> str:
            return self._stamp[:8]

        @classmethod
        def from_function(cls, py_func, py_file):
            if Path(py_file).parent.name not in PACKAGES or not os.path.isfile(py_file):
                return None
            try:
                locator = cls(py_file)
                locator.ensure_cache_path()
                _prune(Path(locator._path))
            except (OSError, SyntaxError, ValueError):
                return None
            return locator

    _PRUNED: set = set()

    def _prune(current: Path, days: float = 30.0) -> None:
        """Remove other versions' caches (same module, other source content, under this naming or the earlier
        one without the package) unused for ``days`` (about 15 MB each), once per process."""
        if current in _PRUNED:
            return
        _PRUNED.add(current)
        os.utime(current)  # in use: the age below is the time since a process last used a version
        import shutil
        import time

        stem = current.name.rsplit("-", 1)[0]  # package.module
        legacy = stem.split(".", 1)[-1]  # the folders' names until 2026-11-24: module-stamp, no package
        for pattern in {f"{stem}-*", f"{legacy}-*"}:
            for other in current.parent.glob(pattern):
                if other != current and other.is_dir() and time.time() - other.stat().st_mtime > days * 86400:
                    shutil.rmtree(other, ignore_errors=True)

    if _ContentLocator.__name__ not in {c.__name__ for c in caching.CacheImpl._locator_classes}:
        caching.CacheImpl._locator_classes.insert(0, _ContentLocator)

    def njit(func: Callable | None = None, *, reassociate: bool = False) -> Callable:
        """Compiled, cached, numpy error semantics (division by zero gives inf/nan as in the Python path).
        ``reassociate``: let the compiler reorder floating-point sums (vectorised reductions; NaN and inf keep
        their meaning, the result changes at round-off). Use as ``@njit`` or ``@njit(reassociate=True)``."""
        options = {"fastmath": {"reassoc", "contract"}} if reassociate else {}
        if func is None:
            return lambda f: numba.njit(cache=True, error_model="numpy", **options)(f)
        return numba.njit(cache=True, error_model="numpy", **options)(func)

    AVAILABLE = True
except ImportError:  # pragma: no cover - numba is a dependency; this keeps the Python path usable without it
    AVAILABLE = False

    def njit(func: Callable | None = None, *, reassociate: bool = False) -> Callable:
        return func if func is not None else (lambda f: f)
