"""The compiled runtime's build and loading: where the install puts the library, that it is the build of the current
sources, that only the API is exported, and the one clear message without a compiler or without the library."""

from __future__ import annotations

import ctypes
import importlib.util
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from fmu_base import native

ROOT = Path(__file__).resolve().parent.parent


def test_the_install_put_the_library_where_the_loader_finds_it() -> None:
    path = native.library_path()
    assert path is not None and path.parent == Path(native.__file__).resolve().parent
    lib = native.library()
    assert lib.wec_data_format_version() == 1
    assert lib.wec_runtime_version() >= 100


def test_the_library_is_built_from_the_current_sources() -> None:
    """In a source checkout (editable install) the library must be newer than every file of native/: after editing
    the C sources, rebuild with ``pip install -e .`` (or ``python setup.py build_ext --inplace``)."""
    sources = list((ROOT / "native").rglob("*.[ch]"))
    path = native.library_path()
    if not sources or path is None or ROOT not in path.parents:
        pytest.skip("not a source checkout with an in-place build")
    stale = [s.relative_to(ROOT).as_posix() for s in sources if s.stat().st_mtime > path.stat().st_mtime]
    assert not stale, f"fmu_base/{path.name} is older than {stale}: rebuild it with pip install -e ."


def test_only_the_api_is_exported() -> None:
    lib = native.library()
    for name in ("wec_hydro_create", "wec_hydro_outputs", "wec_status_name"):
        assert hasattr(lib, name)
    for internal in ("hydro_evaluate", "wec_data_open", "wec_expm", "conv_memory_force"):
        with pytest.raises(AttributeError):
            getattr(lib, internal)
    lib.wec_status_name.restype = ctypes.c_char_p
    assert lib.wec_status_name(3) == b"WEC_ERR_DATA"


@pytest.mark.skipif(importlib.util.find_spec("setuptools") is None, reason="setuptools is not installed here")
def test_building_without_a_compiler_says_what_to_install(tmp_path: Path) -> None:
    """setup.py's build of the runtime with CC naming no compiler, in a copy of setup.py and native/ with minimal
    metadata (this environment's setuptools, no download): one message saying what to install, no traceback."""
    shutil.copy(ROOT / "setup.py", tmp_path)
    shutil.copytree(ROOT / "native", tmp_path / "native")
    (tmp_path / "pyproject.toml").write_text('[project]\nname = "wec-cosim-build-check"\nversion = "0"\n\n'
                                             "[tool.setuptools]\npackages = []\n")
    env = {**os.environ, "CC": "wec-cosim-no-such-compiler"}
    proc = subprocess.run([sys.executable, "setup.py", "-q", "build_ext", "--build-lib", str(tmp_path / "lib"),
                           "--build-temp", str(tmp_path / "tmp")], cwd=tmp_path, env=env, capture_output=True,
                          text=True, timeout=300)
    text = proc.stdout + proc.stderr
    assert proc.returncode != 0
    assert "no C compiler ('wec-cosim-no-such-compiler' is not on PATH)" in text, text
    assert "sudo apt-get install gcc" in text and "xcode-select --install" in text
    assert "Traceback" not in text


def test_a_missing_library_is_one_message_with_the_fix(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.setattr(native, "HERE", tmp_path)
    native.library.cache_clear()
    try:
        with pytest.raises(native.RuntimeMissingError, match=r"is not built: it is compiled by `pip install -e \.`"):
            native.library()
    finally:
        monkeypatch.undo()
        native.library.cache_clear()
    assert native.library() is not None
