"""Generated checkpoints that lie: a real run's checkpoint changed after it was written (each number, bytes of each
FMU state and of the master memory, a radiation history scaled, the integrity attribute removed), the same changes
re-signed with a correct digest (rows 0, another scenario's fingerprint, another build), a checkpoint of another run
of the same scene (another wave height) and a results file replaced by another run's.

``wec-cosim resume`` must refuse each in one paragraph naming the checkpoint, exit status 2, and leave the results
file byte for byte as it was; the unchanged checkpoint resumes. (The digest is an integrity check, not a signature:
whoever recomputes it after changing a state's numbers is not detected; the re-signed cases here are those the
checkpoint's identity and its fit to the results file still catch.) MoorDyn states: a state cut short is refused before
MoorDyn reads it (it aborted the process), and the input file's text is never taken from a state.
"""

from __future__ import annotations

import hashlib
import random
import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest

from orchestrator.results.checkpoints import checkpoint_digest, checkpoint_path

from .hostile import Case, check, cylinder, run_forked
from .test_malformed_generated import _materialise, run_in_process

SEED = 35
BYTE_CASES = 4  # seeded byte changes per component state


def _run(folder: Path, height: float) -> Path:
    """A 20 s in-process run of the cylinder with a checkpoint every 5 s."""
    folder.mkdir(parents=True, exist_ok=True)
    data = cylinder(20.0, simulation={"checkpoint_every": 5.0, "flush_seconds": 0.05}, waves={"height": height})
    case = Case("base", ["run", "{dir}/s.toml", "--quiet", "--in-process", "--out", "{dir}/r.h5"], {"s.toml": data})
    code, stderr = run_in_process(_materialise(case, folder))
    assert code == 0, stderr
    return folder / "r.h5"


@pytest.fixture(scope="module")
def runs(tmp_path_factory) -> dict[str, Path]:
    base = tmp_path_factory.mktemp("checkpoint_runs")
    return {"one": _run(base / "one", 1.0), "two": _run(base / "two", 2.0)}


def _sha(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _edit(path: Path, change, resign: bool = False) -> None:  # noqa: ANN001
    """Apply ``change(f)`` to a checkpoint; ``resign``: write the digest of the changed data (a careful forger)."""
    with h5py.File(path, "a") as f:
        change(f)
        if resign:
            states = {name: f[f"states/{name}"][()].tobytes() for name in f["states"]}
            numbers = {k: f.attrs[k].item() for k in ("time", "rows", "steps")}
            identity = {k: str(f.attrs[k]) for k in ("scenario", "build")}
            f.attrs["sha256"] = checkpoint_digest(states, f["master"][()].tobytes(), numbers, identity)


def _set_attr(key: str, value) -> callable:  # noqa: ANN001
    def change(f: h5py.File) -> None:
        f.attrs[key] = value
    return change


def _flip(name: str, offset: int, value: int) -> callable:
    def change(f: h5py.File) -> None:
        raw = bytearray(f[name][()].tobytes())
        raw[offset % len(raw)] ^= value
        del f[name]
        f.create_dataset(name, data=np.void(bytes(raw)))
    return change


def _scale_radiation_history(f: h5py.File) -> None:
    """The hydro state's long float arrays (the radiation history: velocity samples the convolution holds) times
    1000, written back in place in the state's binary layout (:mod:`fmu_base.state_codec`: a 24-byte head whose
    last 8 bytes give the JSON header's length, then the header, then the arrays at their offsets)."""
    import json

    raw = f["states/hydro"][()].tobytes()
    length = int.from_bytes(raw[16:24], "little")
    header = json.loads(raw[24:24 + length])
    data_start = 24 + length
    blob = bytearray(raw)
    scaled = 0
    for entry in header["arrays"]:
        count = int(np.prod(entry["shape"]))
        start = data_start + entry["offset"]
        if np.dtype(entry["dtype"]).kind == "f" and count > 100:
            values = np.frombuffer(raw, dtype=entry["dtype"], count=count, offset=start)
            blob[start:start + entry["nbytes"]] = (values * 1000.0).astype(entry["dtype"]).tobytes()
            scaled += 1
        elif np.dtype(entry["dtype"]) == np.uint8 and count > 800:  # the compiled runtime's state: float64 inside
            values = np.frombuffer(raw, dtype="<f8", count=count // 8, offset=start).copy()
            history = np.isfinite(values) & (np.abs(values) > 1e-12) & (np.abs(values) < 1e6)
            values[history] *= 1000.0
            blob[start:start + 8 * (count // 8)] = values.tobytes()
            scaled += int(history.any())
    assert scaled, "no array to scale in the hydro state"
    del f["states/hydro"]
    f.create_dataset("states/hydro", data=np.void(bytes(blob)))


def lying_checkpoints(runs: dict[str, Path]) -> list[tuple[str, callable, list[str]]]:
    """(label, prepare(folder) -> results path, fragments of the message)."""
    rng = random.Random(SEED)
    with h5py.File(checkpoint_path(runs["one"]), "r") as f:
        names = [f"states/{n}" for n in f["states"]] + ["master"]
        sizes = {n: len(f[n][()].tobytes()) for n in names}
        rows, t, steps = (f.attrs[k].item() for k in ("rows", "time", "steps"))
    changed = "changed after it was written"
    edits: list[tuple[str, callable, bool, list[str]]] = []
    for key, values in (("rows", (0, rows - 1, rows + 1, 10 * rows)), ("time", (0.0, t - 0.1, t + 0.1, 1e9)),
                        ("steps", (0, steps - 1, steps + 7))):
        for v in values:
            edits.append((f"{key} = {v}", _set_attr(key, v), False, [changed]))
    for name in names:
        for _ in range(BYTE_CASES):
            offset, bit = rng.randrange(sizes[name]), 1 << rng.randrange(8)
            edits.append((f"{name} byte {offset} ^ {bit}", _flip(name, offset, bit), False, [changed]))
    edits.append(("radiation history times 1000", _scale_radiation_history, False, [changed]))
    edits.append(("integrity attribute removed", lambda f: f.attrs.__delitem__("sha256"), False, [changed]))
    edits.append(("format version 1", _set_attr("format_version", 1), False, ["format version 1"]))
    # re-signed: the digest matches, the content still does not belong here
    edits.append(("re-signed rows = 0", _set_attr("rows", 0), True, ["does not fit"]))
    edits.append((f"re-signed rows = {rows - 7}", _set_attr("rows", rows - 7), True, ["does not fit"]))
    edits.append(("re-signed time + 1 s", _set_attr("time", t + 1.0), True, ["does not fit"]))
    edits.append(("re-signed scenario of another run", _set_attr("scenario", "0" * 64), True, ["another run"]))
    edits.append(("re-signed other build", _set_attr("build", "hydro=x.fmu,mbd=y.fmu"), True, ["another build"]))

    def edited(change, resign: bool):  # noqa: ANN001, ANN202
        def prepare(folder: Path) -> Path:
            results = folder / "r.h5"
            shutil.copy(runs["one"], results)
            shutil.copy(checkpoint_path(runs["one"]), checkpoint_path(results))
            _edit(checkpoint_path(results), change, resign)
            return results
        return prepare

    out = [(label, edited(change, resign), fragments) for label, change, resign, fragments in edits]

    def foreign_checkpoint(folder: Path) -> Path:
        results = folder / "r.h5"
        shutil.copy(runs["one"], results)
        shutil.copy(checkpoint_path(runs["two"]), checkpoint_path(results))
        return results

    def foreign_results(folder: Path) -> Path:
        results = folder / "r.h5"
        shutil.copy(runs["two"], results)
        shutil.copy(checkpoint_path(runs["one"]), checkpoint_path(results))
        return results

    out.append(("checkpoint of a run with another wave height", foreign_checkpoint, ["another run"]))
    out.append(("results file of a run with another wave height", foreign_results, ["another run"]))
    return out


def test_a_lying_checkpoint_is_refused_and_the_results_file_is_unchanged(tmp_path, runs) -> None:
    cases = lying_checkpoints(runs)
    assert len(cases) >= 30
    for k, (label, prepare, fragments) in enumerate(cases):
        folder = tmp_path / f"case{k}"
        folder.mkdir()
        results = prepare(folder)
        before = _sha(results)
        case = Case(label, ["resume", str(results), "--quiet"], {}, [str(checkpoint_path(results)), *fragments])
        code, stderr, _ = run_forked(case.argv)
        check(case, code, stderr, folder)
        assert _sha(results) == before, f"{label}: the results file changed"


def test_the_unchanged_checkpoint_resumes_to_the_same_rows(tmp_path, runs) -> None:
    results = tmp_path / "r.h5"
    shutil.copy(runs["one"], results)
    shutil.copy(checkpoint_path(runs["one"]), checkpoint_path(results))
    code, stderr = run_in_process(["resume", str(results), "--quiet"])
    assert code == 0, stderr
    with h5py.File(results, "r") as a, h5py.File(runs["one"], "r") as b:
        assert a.attrs["status"] == "completed"
        np.testing.assert_array_equal(a["time"][()], b["time"][()])
        np.testing.assert_array_equal(a["bodies/float/displacement"][()], b["bodies/float/displacement"][()])


# ------------------------------------------------------------------------------------------------ MoorDyn states
def _moordyn_system():  # noqa: ANN202
    """The MoorDyn tests' three RM3 lines on a buoy, stepped 1 s."""
    from mbd_fmu.spec import build_simulator

    from .test_moordyn_lines import spec, system_of

    sim = build_simulator(spec(0.05, time_step=0.004))
    sim.advance(1.0)
    return system_of(sim), sim


def test_a_moordyn_state_cut_short_is_refused_before_moordyn_reads_it() -> None:
    """Cut at seeded lengths (MoorDyn's own reader aborted the process on them): each is a MoorDynError, in a
    forked child so that an abort would show as SIGABRT instead of ending the test run."""
    from mbd_fmu.moordyn_lines import MoorDynError

    rng = random.Random(SEED)
    system, sim = _moordyn_system()
    full = system.__getstate__()
    size = full["moordyn_state"].size
    for cut in sorted({0, 1, size // 2, size - 8, size - 1, rng.randrange(1, size)}):
        state = dict(full)
        state["moordyn_state"] = full["moordyn_state"][:cut].copy()

        def restore(state: dict = state) -> int:
            import copy

            other = copy.deepcopy(system)
            other.__setstate__(state)
            try:
                other._active()
            except MoorDynError as exc:
                print(exc)
                return 2 if "bytes" in str(exc) else 4
            return 0

        code, _, out = run_forked([], call=restore)
        assert code == 2 and f"{cut} bytes" in out, f"cut at {cut} of {size}: status {code} {out}"


def test_a_moordyn_state_never_chooses_the_input_file() -> None:
    """A state whose text names other options (output to a file elsewhere) or whose lines differ: the text is
    ignored (written again from the lines), lines that differ from the live model's are refused."""
    import copy

    from mbd_fmu.moordyn_lines import MoorDynError, moordyn_input

    system, _ = _moordyn_system()
    state = system.__getstate__()
    assert "text" not in state
    hostile = dict(state, text="1 writeLog\n0 disableOutput\n/etc/passwd\n")
    other = copy.deepcopy(system)
    other.__setstate__(hostile)
    assert other.text == moordyn_input(system.lines, system.settings, system.start_fairleads)
    lines = [dict(d) for d in state["lines"]]
    lines[0]["length"] = lines[0]["length"] * 2
    with pytest.raises(MoorDynError, match="other lines"):
        copy.deepcopy(system).__setstate__(dict(state, lines=lines))
