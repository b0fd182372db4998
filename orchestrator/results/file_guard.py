"""One writer per results file, and a results file that disappears while it is written.

* :class:`ResultsLock`: a run holds an exclusive lock (``flock``) on ``<results>.lock`` from before it
  creates the results file until it closes it, so a second run (or a resume) on the same file refuses
  at once, naming the process that holds it, instead of truncating the file under the first. The
  kernel drops the lock when a process ends, however it ends: a lock file left by a killed run is
  taken over. The file holds the holder's process id, host and start time, for the message.
* :class:`FileWatch`: the results file is identified by its device and inode when it is created; at
  every flush (and at the end) the path is checked to still name that file. A file deleted or
  replaced while the run goes would take the rows written since into a file nobody can reach (HDF5
  keeps writing into the open, unlinked inode); instead the run stops with a message saying where the
  rows went: they are copied from the open file into ``<results>.recovered.h5`` next to it (or said
  lost if even that cannot be written).
"""

from __future__ import annotations

import contextlib
import fcntl
import os
import socket
import time
from pathlib import Path

import h5py

from orchestrator.errors import WecCosimError


class ResultsFileLost(WecCosimError):
    """The results file was deleted or replaced while the run wrote it."""


def lock_path(results: str | Path) -> Path:
    results = Path(results)
    return results.with_name(results.name + ".lock")


class ResultsLock:
    """An exclusive lock on a results file (module docstring); :meth:`release` when the file is closed."""

    def __init__(self, results: str | Path, what: str = "run") -> None:
        self.results = Path(results)
        self.path = lock_path(results)
        self.fd: int | None = None
        while True:  # the lock file may be removed by the holder between our open and our lock: try again
            try:
                self.path.parent.mkdir(parents=True, exist_ok=True)  # the results' folder, as the writer makes it
                fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
            except OSError as exc:
                raise WecCosimError(f"cannot create the lock file {self.path} of {self.results} ({exc.strerror}); "
                                    "give an output file in a folder you can write (--out)") from None
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                holder = _read(fd)
                os.close(fd)
                raise WecCosimError(
                    f"{self.results} is being written by another wec-cosim process ({holder or 'unknown'}; lock "
                    f"{self.path}): two runs on one results file would destroy it; wait for that run to finish, "
                    "or give another output file (--out)") from None
            try:
                same = os.fstat(fd).st_ino == os.stat(self.path).st_ino
            except FileNotFoundError:
                same = False
            if same:
                break
            os.close(fd)
        with contextlib.suppress(OSError):  # who holds it, for the message of another run (a full disk: unsaid)
            os.ftruncate(fd, 0)
            os.write(fd, f"{what} by process {os.getpid()} on {socket.gethostname()} since "
                         f"{time.strftime('%Y-%m-%d %H:%M:%S')}".encode())
        self.fd = fd

    def release(self) -> None:
        """Remove the lock file and drop the lock (idempotent)."""
        if self.fd is None:
            return
        with contextlib.suppress(OSError):
            os.unlink(self.path)
        with contextlib.suppress(OSError):
            os.close(self.fd)
        self.fd = None


def _read(fd: int) -> str:
    with contextlib.suppress(OSError):
        return os.pread(fd, 400, 0).decode(errors="replace").strip()
    return ""


class FileWatch:
    """Whether a path still names the file it named when the watch was made (module docstring)."""

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        st = os.stat(self.path)
        self.identity = (st.st_dev, st.st_ino)

    def moved_to(self, path: str | Path) -> None:
        """The file was renamed on purpose (a resume's new file put in place): watch it under ``path``."""
        self.path = Path(path)

    def problem(self) -> str | None:
        """"deleted" or "replaced by another file" if the path no longer names the watched file, else None."""
        try:
            st = os.stat(self.path)
        except FileNotFoundError:
            return "deleted"
        except OSError:
            return None  # cannot tell (a network file system's hiccup): keep writing
        return None if (st.st_dev, st.st_ino) == self.identity else "replaced by another file"


def rescue(f: h5py.File, results: Path) -> Path | None:
    """Copy everything the open (deleted or replaced) file ``f`` holds into ``<results stem>.recovered.h5``
    next to ``results``; the path written, or None if it could not be written."""
    target = results.with_name(results.stem + ".recovered.h5")
    try:
        f.flush()
        with h5py.File(target, "w") as out:
            for key, value in f.attrs.items():
                out.attrs[key] = value
            for name in f:
                f.copy(f[name], out, name=name)
        return target
    except Exception:  # noqa: BLE001 - the folder may be gone too; the message then says the rows are lost
        with contextlib.suppress(OSError):
            target.unlink()
        return None
