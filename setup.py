"""Builds the compiled runtime (``native/``: C11, standard library and libm only) into ``fmu_base/_wecrt.so``.

The project's metadata is in pyproject.toml; this file adds the one compiled piece: the step-time physics that
the Python models call through :mod:`ctypes` (``fmu_base/native.py``) and that the FMUs carry inside ``fmu_base``.
It is a plain shared library, not a Python extension module (no Python headers or symbols are used), so its name
carries no Python ABI tag. ``pip install -e .`` puts it beside the sources (``fmu_base/_wecrt.so``), ``pip install
.`` into the installed package. After editing ``native/``, rebuild with ``pip install -e .`` again or
``python setup.py build_ext --inplace``.
"""

from __future__ import annotations

import os
import shutil
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent
SOURCES = sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "native" / "src").rglob("*.c"))
HEADERS = sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "native").rglob("*.h"))
GCC_FLAGS = ["-std=c11", "-O2", "-Wall", "-Wextra", "-fvisibility=hidden", "-g0"]
MSVC_FLAGS = ["/std:c11", "/O2", "/W3"]
NO_COMPILER = """
wec-cosim: cannot build its compiled runtime: no C compiler ({compiler!r} {why}).

The step-time hydrodynamics (native/, C11, standard library only) is compiled when the package is installed.
Install a C compiler, then run the install again:
  Debian/Ubuntu:  sudo apt-get install gcc        (or build-essential)
  Fedora/RHEL:    sudo dnf install gcc
  macOS:          xcode-select --install
  Windows:        Microsoft C++ Build Tools (https://visualstudio.microsoft.com/visual-cpp-build-tools/)
A compiler other than the default is chosen with the CC environment variable.
"""


class BuildRuntime(build_ext):
    """build_ext for the runtime library: our flags, a plain library name, one clear message without a compiler."""

    def get_ext_filename(self, fullname: str) -> str:
        suffix = {"win32": ".dll", "darwin": ".dylib"}.get(sys.platform, ".so")
        return os.path.join(*fullname.split(".")) + suffix

    def get_export_symbols(self, ext: Extension) -> list[str]:
        return []  # the API is exported by WEC_API in native/include; there is no PyInit_ function

    def build_extension(self, ext: Extension) -> None:
        msvc = self.compiler.compiler_type == "msvc"
        ext.extra_compile_args = MSVC_FLAGS if msvc else GCC_FLAGS
        executable = getattr(self.compiler, "compiler_so", None)
        if executable and shutil.which(executable[0]) is None:
            raise SystemExit(NO_COMPILER.format(compiler=executable[0], why="is not on PATH"))
        try:
            super().build_extension(ext)
        except Exception as exc:  # distutils' CompileError, LinkError, DistutilsExecError...
            if executable and shutil.which(executable[0]) is None or "command not found" in str(exc) \
                    or isinstance(exc, FileNotFoundError):
                raise SystemExit(NO_COMPILER.format(compiler=executable[0] if executable else "cc",
                                                    why=f"failed: {exc}")) from None
            raise


setup(
    ext_modules=[Extension("fmu_base._wecrt", sources=SOURCES, depends=HEADERS, include_dirs=["native/include"],
                           libraries=[] if sys.platform == "win32" else ["m"])],
    cmdclass={"build_ext": BuildRuntime},
)
