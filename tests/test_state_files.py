"""Checkpoints and FMU states are data, never code: no pickle is read (a crafted pickle payload in a
checkpoint does not execute), and a crafted, foreign or corrupt state gives one clean error (exit
status 2, the file named), through fmpy as in-process."""

from __future__ import annotations

import collections
import os
import pickle
import struct
import subprocess
import sys

import h5py
import numpy as np
import pytest

from fmu_base import state_codec
from fmu_base.state_codec import StateFormatError, decode, encode
from orchestrator.results.checkpoints import checkpoint_path

from .conftest import ROOT
from .toml_text import bundled, write


class _Node:  # a plain object of a test module: walked by encode, never constructed by decode
    def __init__(self) -> None:
        self.a = np.arange(3.0)
        self.b = self.a  # shared reference
        self.me = self  # cycle


class _Other:
    def __init__(self) -> None:
        self.x = 1.0


def test_round_trip_of_a_state_tree_keeps_values_types_and_sharing() -> None:
    shared = np.linspace(0, 1, 5)
    state = {"x": shared, "y": shared, "t": (1, 2.5, "s", None, True), "nan": float("nan"), "inf": -np.inf,
             "c": 1 + 2j, "i": np.int64(7), "f32": np.float32(0.5), "deque": collections.deque([1.0, 2.0], maxlen=3),
             3.5: "float key", "set": {1, 2}, "big": 2**70, "empty": np.zeros((0, 4)), "cplx": np.ones(2, complex),
             "bytes": (b"\x00raw\xff", b"")}
    back = decode(encode(state))
    assert back["x"] is back["y"] and np.array_equal(back["x"], shared)
    assert back["t"] == (1, 2.5, "s", None, True) and np.isnan(back["nan"]) and back["inf"] == -np.inf
    assert back["c"] == 1 + 2j and back["i"] == 7 and back["i"].dtype == np.int64 and back["f32"].dtype == np.float32
    assert back["deque"] == collections.deque([1.0, 2.0]) and back["deque"].maxlen == 3
    assert back[3.5] == "float key" and back["set"] == {1, 2} and back["big"] == 2**70
    assert back["empty"].shape == (0, 4) and back["cplx"].dtype == complex
    assert back["bytes"] == (b"\x00raw\xff", b"")


def test_objects_are_restored_into_the_live_template_with_shared_references_and_cycles() -> None:
    saved = _Node()
    saved.a[:] = [7.0, 8.0, 9.0]
    saved.extra = "only in the saved state"
    live = _Node()
    live.cache = "only in the live object"
    out = decode(encode(saved), live)
    assert out is live and out.me is live and out.b is out.a
    assert list(out.a) == [7.0, 8.0, 9.0] and out.extra == "only in the saved state"
    assert not hasattr(out, "cache"), "attributes the saved object did not have are removed (deep-copy semantics)"


def _object_state(name: str, attrs: dict | None = None) -> bytes:
    return _layout({"tree": {"$": "object", "id": 0, "class": name, "attrs": attrs or {}}, "arrays": []})


def _datasource_name() -> str:
    from numpy.lib import _datasource

    return f"{_datasource.DataSource.__module__}:DataSource"


@pytest.mark.parametrize("name", ["subprocess:Popen", "os:_wrap_close", "builtins:object", "numpy:ndarray",
                                  "orchestrator.results.results_file:ResultsWriter",
                                  "mbd_fmu.linear_system:LinearMultibodySystem",
                                  "tests.test_state_files:_Node", "orchestrator.nothing_here:Evil"])
def test_a_state_cannot_pick_a_class_outside_the_allow_list(name) -> None:
    """Importable classes, the project's own included, are refused when neither the template holds one nor
    the allow-list of classes a model creates as it runs (RESTORABLE) names it."""
    with pytest.raises(StateFormatError, match="not a class of this model"):
        decode(_object_state(name))
    with pytest.raises(StateFormatError, match="not a class of this model"):
        decode(_object_state(name), [_Other()])  # a template of another class does not help


def test_a_numpy_class_whose_finaliser_deletes_a_folder_is_refused(tmp_path) -> None:
    """numpy's DataSource removes its ``_destpath`` folder when collected if ``_istmpdest``: a state that
    could instantiate it (as any numpy class could, before the allow-list) deleted a folder of its choice."""
    import gc

    victim = tmp_path / "precious"
    victim.mkdir()
    (victim / "data.txt").write_text("keep me")
    with pytest.raises(StateFormatError, match="not a class of this model"):
        decode(_object_state(_datasource_name(), {"_istmpdest": True, "_destpath": str(victim)}))
    gc.collect()
    assert (victim / "data.txt").read_text() == "keep me"


def test_classes_of_the_template_and_of_the_allow_list_are_restored() -> None:
    import mbd_fmu.simulator  # noqa: F401 - RESTORABLE's classes count once their modules are imported
    from mbd_fmu.formulations import Factorized

    # A second _Node where the template (one _Node) has none: the template's own class, so it is built.
    saved = [_Node(), _Node()]
    back = decode(encode(saved), [_Node()])
    assert len(back) == 2 and all(type(x) is _Node and x.me is x for x in back)
    # A factorised Newton matrix, created as a model runs (not in a freshly built model): on RESTORABLE.
    matrix = np.array([[4.0, 1.0], [1.0, 3.0]])
    lu = decode(encode(Factorized(matrix)))
    assert type(lu) is Factorized and np.allclose(lu.solve(np.array([1.0, 2.0])), np.linalg.solve(matrix, [1.0, 2.0]))
    chain = 4 * np.eye(60) + np.eye(60, k=1) + np.eye(60, k=-1)  # large and sparse: SuperLU, kept as its matrix
    lu = decode(encode(Factorized(chain)))
    assert lu.kind == "sparse" and np.allclose(chain @ lu.solve(np.ones(60)), 1.0)
    assert set(state_codec.RESTORABLE) <= set(state_codec.allowed_classes(None))


def test_dunder_attribute_names_are_refused() -> None:
    live = _Node()
    state = {"$": "object", "id": 0, "class": "tests.test_state_files:_Node", "attrs": {"__class__": 1}}
    with pytest.raises(StateFormatError, match="'__class__' is not one of a state"):
        decode(_layout({"tree": state, "arrays": []}), live)
    assert type(live) is _Node


def _layout(header: dict, body: bytes = b"", version: int = 1, magic: bytes = b"WECSTATE") -> bytes:
    import json

    text = json.dumps(header).encode()
    return struct.pack("<8sIIQ", magic, version, 0, len(text)) + text + body


CORRUPT = {
    "empty": b"",
    "pickle": pickle.dumps({"a": 1}),
    "wrong magic": _layout({"tree": 1, "arrays": []}, magic=b"NOTSTATE"),
    "future version": _layout({"tree": 1, "arrays": []}, version=99),
    "truncated header": _layout({"tree": 1, "arrays": []})[:-3],
    "header not JSON": struct.pack("<8sIIQ", b"WECSTATE", 1, 0, 3) + b"\xff\xfe{",
    "no tree": _layout({"arrays": []}),
    "object dtype": _layout({"tree": {"$": "array", "i": 0}, "arrays": [
        {"dtype": "|O", "shape": [1], "offset": 0, "nbytes": 8}]}, b"\0" * 8),
    "array past the end": _layout({"tree": {"$": "array", "i": 0}, "arrays": [
        {"dtype": "<f8", "shape": [100], "offset": 0, "nbytes": 800}]}, b"\0" * 8),
    "negative shape": _layout({"tree": {"$": "array", "i": 0}, "arrays": [
        {"dtype": "<f8", "shape": [-1], "offset": 0, "nbytes": -8}]}),
    "missing array": _layout({"tree": {"$": "array", "i": 3}, "arrays": []}),
    "dangling reference": _layout({"tree": {"$": "ref", "id": 9}, "arrays": []}),
    "unknown kind": _layout({"tree": {"$": "pickle", "data": "gASV"}, "arrays": []}),
    "function without a model": _layout({"tree": {"$": "code"}, "arrays": []}),
    "deep nesting": struct.pack("<8sIIQ", b"WECSTATE", 1, 0, 200_015) + b'{"arrays":[],"tree":'
                    + b"[" * 100_000 + b"]" * 100_000 + b"}",
}


@pytest.mark.parametrize("case", list(CORRUPT))
def test_corrupt_or_crafted_state_bytes_raise_a_state_format_error(case) -> None:
    with pytest.raises(StateFormatError):
        decode(CORRUPT[case])


# ----------------------------------------------------------------------------- checkpoints of real runs
class _Payload:
    """A pickle that would create ``marker`` when loaded (the attack a pickle-based reader allows)."""

    def __init__(self, marker: str) -> None:
        self.marker = marker

    def __reduce__(self):  # noqa: ANN204
        return (os.system, (f"touch {self.marker}",))


@pytest.fixture(scope="module")
def checkpointed_run(tmp_path_factory):
    """A short run of the cylinder with a checkpoint before its end (scenario, results file)."""
    folder = tmp_path_factory.mktemp("ckpt")
    data = bundled("cylinder_regular")
    data["simulation"].update(duration=2.0, checkpoint_every=1.0)
    path = write(folder / "cyl.toml", data)
    out = folder / "cyl.h5"
    proc = subprocess.run([sys.executable, "-m", "wec_cosim.cli", "run", str(path), "--out", str(out), "--quiet"],
                          capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert proc.returncode == 0, proc.stderr
    return path, out


def _resume_copy(tmp_path, run, edit, in_process: bool = False) -> tuple[subprocess.CompletedProcess, object]:
    """Copy the run's results and checkpoint, apply ``edit`` to the checkpoint, resume the copy."""
    import shutil

    _, out = run
    results = tmp_path / "r.h5"
    shutil.copy(out, results)
    ckpt = checkpoint_path(results)
    shutil.copy(checkpoint_path(out), ckpt)
    if in_process:
        with h5py.File(results, "a") as f:
            import json

            settings = json.loads(f.attrs["settings"])
            settings["fmi"] = "in-process"
            f.attrs["settings"] = json.dumps(settings)
    with h5py.File(ckpt, "a") as f:
        edit(f)
    proc = subprocess.run([sys.executable, "-m", "wec_cosim.cli", "resume", str(results), "--quiet"],
                          capture_output=True, text=True, cwd=ROOT, timeout=600)
    return proc, ckpt


def _replace(f: h5py.File, name: str, data: bytes) -> None:
    del f[name]
    f.create_dataset(name, data=np.void(data))


@pytest.mark.parametrize("where", ["master", "states/hydro", "states/mbd"])
def test_a_pickle_payload_in_a_checkpoint_does_not_execute(tmp_path, checkpointed_run, where) -> None:
    marker = tmp_path / "pwned"
    payload = pickle.dumps(_Payload(str(marker)))
    proc, ckpt = _resume_copy(tmp_path, checkpointed_run, lambda f: _replace(f, where, payload))
    assert proc.returncode == 2, proc.stderr
    assert not marker.exists(), "the pickle payload ran"
    assert "Traceback" not in proc.stderr and proc.stderr.count("\n") == 1, proc.stderr
    assert str(ckpt) in proc.stderr and "pickle" in proc.stderr


@pytest.mark.parametrize("in_process", [False, True], ids=["fmpy", "in-process"])
def test_a_crafted_fmu_state_is_a_clean_error_from_the_fmu(tmp_path, checkpointed_run, in_process) -> None:
    """A well-formed state of the wrong FMU, re-signed with a correct digest (a careful forger: the digest is an
    integrity check, not a signature), passes the checkpoint's checks and reaches the hydro FMU, which refuses it
    with its own message: exit 2 and that message, under fmpy as in-process (no crash)."""
    from orchestrator.results.checkpoints import checkpoint_digest

    def swap(f: h5py.File) -> None:
        mbd = f["states/mbd"][()].tobytes()
        _replace(f, "states/hydro", mbd)
        states = {name: f[f"states/{name}"][()].tobytes() for name in f["states"]}
        numbers = {k: f.attrs[k].item() for k in ("time", "rows", "steps")}
        identity = {k: str(f.attrs[k]) for k in ("scenario", "build")}
        f.attrs["sha256"] = checkpoint_digest(states, f["master"][()].tobytes(), numbers, identity)

    proc, _ = _resume_copy(tmp_path, checkpointed_run, swap, in_process=in_process)
    assert proc.returncode == 2, proc.stderr
    assert "Traceback" not in proc.stderr and proc.stderr.count("\n") == 1, proc.stderr
    assert "hydro FMU: setFMUstate failed: invalid FMU state: the state is not a state of this FMU" in proc.stderr


@pytest.mark.parametrize("case", ["truncated", "no format", "negative rows"])
def test_a_corrupt_checkpoint_is_a_clean_error(tmp_path, checkpointed_run, case) -> None:
    def edit(f: h5py.File) -> None:
        if case == "truncated":
            _replace(f, "master", f["master"][()].tobytes()[:100])
        elif case == "no format":
            del f.attrs["format"]
        else:
            f.attrs["rows"] = -4

    proc, ckpt = _resume_copy(tmp_path, checkpointed_run, edit)
    assert proc.returncode == 2, proc.stderr
    assert "Traceback" not in proc.stderr and str(ckpt) in proc.stderr, proc.stderr


def test_no_pickle_in_any_state_reader() -> None:
    """The modules that read files a user may receive import no pickle (the codec is the only reader)."""
    for module in ("fmu_base/slave.py", "fmu_base/state_codec.py", "orchestrator/results/checkpoints.py",
                   "orchestrator/cosim/monolithic.py", "orchestrator/cosim/simulation.py"):
        text = (ROOT / module).read_text()
        assert "import pickle" not in text and "pickle.load" not in text, module
    assert state_codec.VERSION == 1
