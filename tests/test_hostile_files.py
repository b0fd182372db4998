"""Files and disks, in real processes (a crash shows as a negative status): two writers on one results file, the
results file deleted, moved or replaced while a run writes it, and every writing command under file-size limits
(``ulimit -f``, writes failing with EFBIG as on a full disk), a full temporary folder and a full disk (a small
tmpfs, where the machine lets the test mount one).

Each case ends with exit status 2 and one paragraph, no traceback, no signal; or, where the limit leaves room, exit
0 and a file that opens. A second writer refuses and the first run completes; a file removed mid-run stops the run
with the rows copied next to it (``<name>.recovered.h5``, its times increasing), as the message says.
"""

from __future__ import annotations

import contextlib
import os
import resource
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

from .conftest import ROOT
from .hostile import cylinder, dumps

PY = [sys.executable, "-c", "import sys; from wec_cosim.cli import console; sys.argv[0] = 'wec-cosim'; console()"]


def start(args: list[str], *, limit: int | None = None, env: dict | None = None) -> subprocess.Popen:
    """``wec-cosim ARGS`` through the console script's function, in a new process (``limit``: RLIMIT_FSIZE bytes;
    the default SIGXFSZ action is left as a shell leaves it: the console script itself must cope)."""
    def limits() -> None:
        if limit is not None:
            resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    return subprocess.Popen([*PY, *args], cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=limits, env={**os.environ, **(env or {})})


def finish(proc: subprocess.Popen, timeout: float = 600) -> tuple[int, str]:
    _, err = proc.communicate(timeout=timeout)
    return proc.returncode, err


def one_clean_error(code: int, err: str, *fragments: str) -> None:
    assert code == 2, f"exit status {code}\n{err}"
    assert "Traceback" not in err and len([x for x in err.splitlines() if x.strip()]) == 1, err
    for fragment in fragments:
        assert fragment in err, f"{fragment!r} not in {err}"


@pytest.fixture(scope="module")
def scenario(tmp_path_factory) -> Path:
    """A 3000 s run that writes rows every 50 ms of wall time (long enough to be caught while it writes)."""
    folder = tmp_path_factory.mktemp("files")
    path = folder / "long.toml"
    path.write_text(dumps(cylinder(3000.0, simulation={"flush_seconds": 0.05, "checkpoint_every": 100.0})))
    short = folder / "short.toml"
    short.write_text(dumps(cylinder(20.0, simulation={"checkpoint_every": 5.0})))
    code, err = finish(start(["build-fmus", str(short), "--out", str(folder / "fmus")]))  # FMUs cached once
    assert code == 0, err
    return path


def wait_for_rows(path: Path, rows: int = 20, proc: subprocess.Popen | None = None, timeout: float = 300) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and (proc is None or proc.poll() is None):
        with contextlib.suppress(OSError, KeyError):
            with h5py.File(path, "r", swmr=True) as f:
                if len(f["time"]) >= rows:
                    return
        time.sleep(0.05)
    raise AssertionError(f"{path} did not reach {rows} rows")


# ------------------------------------------------------------------------------------------- two writers
@pytest.mark.parametrize("second", ["run", "resume"])
def test_a_second_writer_refuses_and_the_first_run_completes(tmp_path, scenario, second) -> None:
    out = tmp_path / "r.h5"
    short = scenario.with_name("short.toml")
    # 1500 s of the cylinder step in about 15 s at a load of 6 on 2 cores: the second process (its imports take
    # seconds) must meet the first still writing; 400 s were sometimes done before it arrived
    first = start(["run", str(scenario), "--quiet", "--out", str(out), "--duration", "1500"])
    wait_for_rows(out, rows=1, proc=first)
    args = ["run", str(short), "--quiet", "--out", str(out)] if second == "run" else ["resume", str(out), "--quiet"]
    code, err = finish(start(args))
    assert first.poll() is None, "the first run ended before the second was refused: the test proves nothing"
    one_clean_error(code, err, str(out), "being written by another wec-cosim process", f"process {first.pid}")
    code, err = finish(first)
    assert code == 0, err
    with h5py.File(out, "r") as f:
        assert f.attrs["status"] == "completed" and len(f["time"]) == 15001
    assert not Path(str(out) + ".lock").exists()


def test_the_lock_is_taken_in_a_results_folder_that_does_not_exist_yet(tmp_path) -> None:
    """``--out`` in folders still to be made: the lock file goes beside the results, the folders made first (the
    run wrote into new folders before the lock existed, and must still)."""
    from .test_malformed_generated import run_in_process

    (tmp_path / "s.toml").write_text(dumps(cylinder(1.0)))
    out = tmp_path / "new" / "deeper" / "r.h5"
    code, stderr = run_in_process(["run", str(tmp_path / "s.toml"), "--quiet", "--out", str(out)])
    assert code == 0, stderr
    with h5py.File(out, "r") as f:
        assert f.attrs["status"] == "completed" and len(f["time"]) == 11  # 1 s in steps of 0.1 s, both ends
    assert not Path(str(out) + ".lock").exists()


# ------------------------------------------------------------------------------------------- the file removed
def _delete(out: Path) -> None:
    out.unlink()


def _move(out: Path) -> None:
    out.rename(out.with_name("elsewhere.h5"))


def _replace_by_text(out: Path) -> None:
    tmp = out.with_name("new.txt")
    tmp.write_text("someone else's file\n")
    os.replace(tmp, out)


def _replace_by_copy(out: Path) -> None:
    tmp = out.with_name("copy.h5")
    shutil.copy(out, tmp)
    os.replace(tmp, out)


@pytest.mark.parametrize("change, problem", [(_delete, "deleted"), (_move, "deleted"),
                                             (_replace_by_text, "replaced"), (_replace_by_copy, "replaced")],
                         ids=["deleted", "moved away", "replaced by a text file", "replaced by a copy"])
def test_a_results_file_removed_mid_run_stops_the_run_and_says_where_the_rows_are(tmp_path, scenario, change,
                                                                                   problem) -> None:
    out = tmp_path / "r.h5"
    proc = start(["run", str(scenario), "--quiet", "--out", str(out)])
    wait_for_rows(out, proc=proc)
    change(out)
    code, err = finish(proc)
    recovered = tmp_path / "r.recovered.h5"
    one_clean_error(code, err, str(out), problem, f"saved in {recovered}")
    with h5py.File(recovered, "r") as f:
        t = f["time"][()]
        assert len(t) >= 20 and np.all(np.diff(t) > 0) and str(f.attrs["status"]).startswith("failed")
        assert len(f["bodies/float/displacement"]) == len(t)
    if change is _replace_by_text:
        assert out.read_text() == "someone else's file\n"  # the other file is left alone


# ------------------------------------------------------------------------------------------- limits and full disks
LIMITS = (0, 4096, 150_000)  # bytes: nothing, a header, less than the run's rows and FMU data


def _commands(folder: Path, short: Path) -> dict[str, list[str]]:
    return {"run": ["run", str(short), "--quiet", "--out", str(folder / "r.h5")],
            "resume": ["resume", str(folder / "done.h5"), "--quiet"],
            "rao": ["rao", str(short), "--out", str(folder / "rao.h5")],
            "steady": ["steady", str(short), "--out", str(folder / "steady.h5")],
            "export-ssp": ["export-ssp", str(short), str(folder / "x.ssp")]}


@pytest.fixture(scope="module")
def finished_run(scenario) -> Path:
    """A completed 20 s run with checkpoints, for the resumes."""
    out = scenario.with_name("done.h5")
    code, err = finish(start(["run", str(scenario.with_name("short.toml")), "--quiet", "--out", str(out)]))
    assert code == 0, err
    return out


@pytest.mark.parametrize("limit", LIMITS)
@pytest.mark.parametrize("command", ["run", "resume", "rao", "steady", "export-ssp"])
def test_every_writing_command_under_a_file_size_limit(tmp_path, scenario, finished_run, command, limit) -> None:
    shutil.copy(finished_run, tmp_path / "done.h5")
    shutil.copy(finished_run.with_name("done.checkpoint.h5"), tmp_path / "done.checkpoint.h5")
    args = _commands(tmp_path, scenario.with_name("short.toml"))[command]
    before = (tmp_path / "done.h5").read_bytes()
    code, err = finish(start(args, limit=limit))
    assert code in (0, 2), f"{command} under {limit} bytes: status {code}\n{err}"
    if code == 2:
        one_clean_error(code, err)
        if limit == 0:
            assert "ulimit -f" in err, err
        assert (tmp_path / "done.h5").read_bytes() == before  # a failed resume leaves the file as it was
        return
    written = Path(args[-1] if command in ("export-ssp",) else
                   (args[args.index("--out") + 1] if "--out" in args else args[1]))
    assert written.is_file()
    if written.suffix == ".h5":
        with h5py.File(written, "r"):
            pass


@contextlib.contextmanager
def tmpfs(folder: Path, size: str):
    """A tmpfs of ``size`` mounted on ``folder`` (the test's own, unmounted after)."""
    folder.mkdir()
    if os.geteuid() != 0 or shutil.which("mount") is None:
        pytest.skip("mounting a small tmpfs needs root; the file-size-limit cases cover the same failures")
    done = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(folder)], capture_output=True)
    if done.returncode:
        pytest.skip(f"cannot mount a tmpfs here ({done.stderr.decode().strip()})")
    try:
        yield folder
    finally:
        subprocess.run(["umount", str(folder)], check=False)


def _fill(folder: Path, leave: int) -> None:
    """Fill a file system but ``leave`` bytes."""
    free = shutil.disk_usage(folder).free
    with open(folder / "filler", "wb") as f:
        f.write(b"\0" * max(0, free - leave))


@pytest.mark.parametrize("leave", [0, 12 * 1024, 400 * 1024])
def test_a_full_temporary_folder_is_one_clean_error(tmp_path, scenario, leave) -> None:
    with tmpfs(tmp_path / "tmp", "1m") as tmp:
        _fill(tmp, leave)
        env = {"TMPDIR": str(tmp), "WEC_COSIM_CACHE": str(tmp_path / "cache")}  # the FMUs are built there
        code, err = finish(start(["run", str(scenario.with_name("short.toml")), "--quiet", "--out",
                                  str(tmp_path / "r.h5")], env=env))
        assert code in (0, 2) and code != -signal.SIGSEGV, f"status {code}\n{err}"
        if code == 2:
            one_clean_error(code, err)


@pytest.mark.parametrize("command", ["run", "resume"])
def test_a_full_disk_under_the_results_is_one_clean_error(tmp_path, scenario, finished_run, command) -> None:
    with tmpfs(tmp_path / "disk", "2m") as disk:
        shutil.copy(finished_run, disk / "done.h5")
        shutil.copy(finished_run.with_name("done.checkpoint.h5"), disk / "done.checkpoint.h5")
        _fill(disk, 100 * 1024)
        before = (disk / "done.h5").read_bytes()
        code, err = finish(start(_commands(disk, scenario.with_name("short.toml"))[command]))
        one_clean_error(code, err, str(disk))
        assert (disk / "done.h5").read_bytes() == before  # a failed resume leaves the file as it was
