"""The environment our FMUs need in a host that is not a Python program (``wec-cosim host-env``).

A PythonFMU 0.7 FMU carries Python sources, not an interpreter: its shared library calls the
Python C API but is not linked to libpython, and the sources import numpy, scipy and h5py from
the Python that runs them. A Python host (fmpy, libcosimpy) provides both. A C or C++ host (a
plain C program, libcosim's ``cosim`` command, a Modelica or Simulink tool) needs

* ``LD_PRELOAD`` of the shared libpython the packages were installed for (without it dlopen
  fails with ``undefined symbol: _Py_NoneStruct``);
* ``PYTHONHOME``: the installation's prefix, so the embedded interpreter finds its standard
  library whatever the host executable's location;
* ``PYTHONPATH``: the site-packages folders holding numpy, scipy and h5py (a virtual
  environment's are not found from the prefix alone).

``wec-cosim host-env`` prints these as shell ``export`` lines (``eval "$(wec-cosim host-env)"``),
as JSON, or runs a command with them set (``wec-cosim host-env -- ./my_host ...``). Only
Linux is covered (PythonFMU ships linux64 and win64 binaries; on Windows the Python DLL is found
through PATH instead).
"""

from __future__ import annotations

import json
import os
import shlex
import sys
import sysconfig
from pathlib import Path

from orchestrator.errors import WecCosimError

# Packages the FMUs import from the host's Python (see fmu_builder: the FMUs bundle our sources).
REQUIRED_PACKAGES = ("numpy", "scipy", "h5py")


def libpython() -> Path:
    """The shared libpython of this interpreter (WecCosimError if there is none)."""
    libdir = sysconfig.get_config_var("LIBDIR") or ""
    name = sysconfig.get_config_var("LDLIBRARY") or ""
    candidates = [Path(libdir) / name]
    instsoname = sysconfig.get_config_var("INSTSONAME")
    if instsoname:
        candidates.append(Path(libdir) / instsoname)
    for path in candidates:
        if path.suffix.startswith(".so") or ".so." in path.name:
            if path.is_file():
                return path
    raise WecCosimError(
        f"this Python ({sys.executable}) has no shared libpython (LDLIBRARY = {name!r} in {libdir}): a C host "
        "cannot run PythonFMU FMUs with it; use a Python built with --enable-shared (distribution packages, "
        "pyenv with PYTHON_CONFIGURE_OPTS=--enable-shared, conda)")


def package_paths() -> list[str]:
    """Folders that hold the packages the FMUs import, in this interpreter's search order."""
    out: list[str] = []
    for name in REQUIRED_PACKAGES:
        try:
            module = __import__(name)
        except ImportError:
            raise WecCosimError(f"package {name!r} is not installed in {sys.executable}; the FMUs import it "
                                f"(pip install {name})") from None
        folder = str(Path(module.__file__).resolve().parent.parent)
        if folder not in out:
            out.append(folder)
    for key in ("purelib", "platlib"):
        folder = sysconfig.get_paths()[key]
        if folder not in out:
            out.append(folder)
    return out


def fmu_environment(base: dict[str, str] | None = None) -> dict[str, str]:
    """The variables to add to ``base`` (default: this process's environment) for a C host."""
    base = dict(os.environ if base is None else base)
    preload = str(libpython())
    if base.get("LD_PRELOAD"):
        preload = f"{preload} {base['LD_PRELOAD']}" if preload not in base["LD_PRELOAD"].split() else base["LD_PRELOAD"]
    paths = package_paths()
    if base.get("PYTHONPATH"):
        paths += [p for p in base["PYTHONPATH"].split(os.pathsep) if p and p not in paths]
    return {"LD_PRELOAD": preload, "PYTHONHOME": sys.base_prefix, "PYTHONPATH": os.pathsep.join(paths)}


def shell_exports(env: dict[str, str]) -> str:
    """``export NAME=value`` lines (POSIX shell quoting)."""
    return "\n".join(f"export {k}={shlex.quote(v)}" for k, v in env.items())


def main_host_env(command: list[str], form: str = "shell") -> int:
    """``wec-cosim host-env``: print the environment, or run ``command`` with it (exec)."""
    env = fmu_environment()
    if command:
        os.execvpe(command[0], command, {**os.environ, **env})
    print(json.dumps(env, indent=1) if form == "json" else shell_exports(env))
    return 0
