"""The shared numba cache locator (fmu_base/_jit.py), and the hydro model's independence of numba.

The locator keys each kernel module's cache on its content and on the content of the toolkit modules it imports
(a module that calls another's kernels compiles them into its own machine code); FMUs run their sources from a
fresh folder each time, so the same sources elsewhere must load the cache, not compile again. The hydro model runs on
the compiled C runtime (docs/runtime.md): without numba (or with ``WEC_COSIM_NO_JIT``) it gives the same forces,
bit for bit.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from fmu_base import _jit

ROOT = Path(__file__).resolve().parent.parent


def _package(folder: Path, files: dict[str, str]) -> None:
    for name, text in files.items():
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)


def test_cache_key_covers_the_package_modules_a_kernel_module_imports(tmp_path: Path, monkeypatch) -> None:
    """A kernel module's key changes with every toolkit module it imports (relative, ``from . import``, absolute,
    recursively), not with a module it does not import; modules outside the FMU packages get no locator."""
    files = {"hydro_fmu/kernels.py": "from fmu_base._jit import njit\nfrom .helper import f\nfrom . import other\n",
             "hydro_fmu/helper.py": "from hydro_fmu.deep import g\nf = 1\n",
             "hydro_fmu/deep.py": "g = 2\n", "hydro_fmu/other.py": "h = 3\n", "hydro_fmu/unrelated.py": "u = 4\n",
             "fmu_base/_jit.py": "njit = None\n", "elsewhere/kernels.py": "x = 1\n"}
    _package(tmp_path, files)
    kernels = tmp_path / "hydro_fmu" / "kernels.py"
    names = [str(p.relative_to(tmp_path.resolve())) for p in _jit.key_sources(kernels)]
    assert names[0] == "hydro_fmu/kernels.py"
    assert sorted(names[1:]) == ["fmu_base/_jit.py", "hydro_fmu/deep.py", "hydro_fmu/helper.py", "hydro_fmu/other.py"]
    stamp = _jit.source_stamp(kernels)
    for name in ("hydro_fmu/deep.py", "hydro_fmu/other.py", "fmu_base/_jit.py", "hydro_fmu/kernels.py"):
        with open(tmp_path / name, "a") as fh:
            fh.write("# changed\n")
        new = _jit.source_stamp(kernels)
        assert new != stamp, name
        stamp = new
    with open(tmp_path / "hydro_fmu" / "unrelated.py", "a") as fh:
        fh.write("# changed\n")
    assert _jit.source_stamp(kernels) == stamp
    if _jit.AVAILABLE:
        monkeypatch.setenv("WEC_COSIM_NUMBA_CACHE", str(tmp_path / "cache"))
        locator = _jit._ContentLocator.from_function(None, str(kernels))
        assert locator is not None and Path(locator.get_cache_path()).name == f"hydro_fmu.kernels-{stamp}"
        assert _jit._ContentLocator.from_function(None, str(tmp_path / "elsewhere" / "kernels.py")) is None


def test_kernels_are_reused_from_the_cache_by_sources_in_another_folder(tmp_path: Path) -> None:
    """mbd_fmu/kernels.py run from two extraction folders: the first compiles into a content-keyed cache entry,
    the second loads it (no new entries), and both give the same answer."""
    if not _jit.AVAILABLE:
        pytest.skip("numba not installed")
    cache = tmp_path / "cache"
    script = ("import numpy as np, sys; sys.path.insert(0, sys.argv[1]); import mbd_fmu.kernels as k;"
              "assert k.__file__.startswith(sys.argv[1]), k.__file__;"
              "import json; print(json.dumps(k._cross(np.array([1.0, 2.0, 3.0]), np.array([4.0, 5.0, 6.0])).tolist()))")
    env = dict(os.environ, WEC_COSIM_CACHE=str(cache))
    env.pop("WEC_COSIM_NO_JIT", None)
    env.pop("WEC_COSIM_NUMBA_CACHE", None)
    outputs, entries = [], []
    for name in ("first", "second"):
        folder = tmp_path / name
        for package in ("mbd_fmu", "fmu_base"):
            shutil.copytree(ROOT / package, folder / package, ignore=shutil.ignore_patterns("__pycache__"))
        proc = subprocess.run([sys.executable, "-c", script, str(folder)], capture_output=True, text=True, env=env,
                              timeout=600)
        assert proc.returncode == 0, proc.stderr
        outputs.append(proc.stdout)
        entries.append(sorted(str(p.relative_to(cache)) for p in (cache / "numba").rglob("*") if p.is_file()))
    assert json.loads(outputs[0]) == [-3.0, 6.0, -3.0]  # (1, 2, 3) x (4, 5, 6)
    assert outputs[0] == outputs[1]
    assert any(e.startswith("numba/mbd_fmu.kernels-") and e.endswith(".nbi") for e in entries[0])
    assert entries[1] == entries[0]


HYDRO_RUN = """
import sys
import numpy as np
if sys.argv[1] == "blocked":
    sys.modules["numba"] = None  # import numba raises ImportError, as when it is not installed
from fmu_base import _jit
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene
assert _jit.AVAILABLE == (sys.argv[1] == "numba")
model = load_scene(load_scenario(sys.argv[2]), log=None).hydro_model()
rows = np.arange(5, dtype=np.int64); out = np.zeros((5, model.n)); p = np.zeros(4); e = np.zeros(4)
seen = []
for k in range(100):
    t = 0.02 * k
    v = 0.2 * np.sin(0.9 * t + np.arange(model.n)); x = 0.1 * np.cos(0.4 * t + np.arange(model.n))
    eta = model.outputs(t, x, v, rows, out, p, e)
    seen.append(np.concatenate([out.ravel(), p, e, [eta]]))
    model.commit_work(t, x, v); model.advance(t, 0.02, v)
print(np.array(seen).tobytes().hex())
"""


def test_the_hydro_model_needs_no_numba() -> None:
    """numba not installed (its import blocked) or WEC_COSIM_NO_JIT set: the hinge barge's hydro model gives the
    same forces, powers, work and elevation over 100 points as with numba, bit for bit."""
    results = {}
    for how in ("numba", "blocked", "environment"):
        env = dict(os.environ)
        env.pop("WEC_COSIM_NO_JIT", None)
        if how == "environment":
            env["WEC_COSIM_NO_JIT"] = "1"
        if how == "numba" and not _jit.AVAILABLE:
            continue
        proc = subprocess.run([sys.executable, "-c", HYDRO_RUN, how, str(ROOT / "scenarios" / "hinge_barge.toml")],
                              capture_output=True, text=True, env=env, timeout=600, cwd=ROOT)
        assert proc.returncode == 0, proc.stderr
        results[how] = proc.stdout
    assert len(set(results.values())) == 1 and len(results["blocked"]) > 1000


@pytest.mark.skipif(not _jit.AVAILABLE, reason="numba not installed: no compiled kernels, no cache to prune")
def test_caches_of_other_source_versions_unused_for_30_days_are_removed(tmp_path: Path) -> None:
    """Other versions of the same module (this naming and the earlier one without the package) go once unused for
    30 days; recent ones (another process may run that version) and other modules' stay."""
    import time

    old = time.time() - 31 * 86400
    names = {"hydro_fmu.kernels-aaa": None, "hydro_fmu.kernels-bbb": old, "hydro_fmu.kernels-ccc": time.time(),
             "kernels-ddd": old, "kernels-eee": time.time(), "mbd_fmu.kernels-fff": old, "hydro_fmu.other-ggg": old}
    for name, mtime in names.items():
        (tmp_path / name).mkdir()
        if mtime is not None:
            os.utime(tmp_path / name, (mtime, mtime))
    _jit._prune(tmp_path / "hydro_fmu.kernels-aaa")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["hydro_fmu.kernels-aaa", "hydro_fmu.kernels-ccc",
                                                          "hydro_fmu.other-ggg", "kernels-eee", "mbd_fmu.kernels-fff"]
