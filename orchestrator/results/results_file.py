"""Results files (HDF5), written while the run goes.

Layout (every dataset has a first axis of N samples; see ``docs/results.md``):

* ``/time`` (N,), s;
* ``/bodies/<name>/displacement``, ``velocity`` (N, 6) from equilibrium, world frame, surge..yaw
  (m, rad; m/s, rad/s); ``/bodies/<name>/hydro_force`` (N, 6), N and N m;
* ``/ptos/<name>/force`` (N,) and ``power`` (N,) (N or N m; W, absorbed);
* ``/wave/elevation`` (N,), m, incident elevation at the world origin;
* root attributes: ``scenario`` (the file's text), ``scenario_file``, ``versions`` (JSON),
  ``settings`` (JSON: master, step, extrapolation...), and when the run ends ``status``
  (``completed`` or ``failed: ...``) and ``wall_time`` (s). ``status`` is ``running`` while the run
  goes or if it was killed.

One writer per file: the run holds a lock on ``<file>.lock`` while it writes (a second run on the same
file refuses); a file deleted or replaced while it is written stops the run, its rows copied to
``<file stem>.recovered.h5`` (:mod:`.file_guard`).

Crash safety: datasets are chunked and extendable; rows are buffered in memory and appended at
least every ``flush_seconds`` of wall time, the file being in HDF5's single-writer/multiple-reader
(SWMR) mode, which keeps it consistent on disk at every moment. A killed run leaves a file that
opens and holds every row up to the last flush. A kill during a flush can leave some series
one flush longer than others (each dataset's new size becomes visible on its own):
:func:`read_results` returns the rows present in every series.
"""

from __future__ import annotations

import contextlib
import json
import time
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from orchestrator.scenario.input_checks import require_room

from .file_guard import FileWatch, ResultsFileLost, ResultsLock, rescue


class ResultsWriter:
    """Append-only writer of time series with periodic flushes.

    Args:
        path: file to create (its folder is created too).
        series: dataset path -> shape of one row (``()`` for scalars).
        attrs: root attributes written at creation (strings or numbers; dicts become JSON).
        flush_seconds: longest wall time between two flushes.
        buffer_rows: rows kept in memory before a flush at the latest.
        lock: the :class:`~.file_guard.ResultsLock` the caller took on the file the rows are for (released when
            the writer is closed).
    """

    def __init__(
        self,
        path: str | Path,
        series: dict[str, tuple[int, ...]],
        attrs: dict[str, Any],
        flush_seconds: float = 2.0,
        buffer_rows: int = 2048,
        lock: ResultsLock | None = None,
    ) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.flush_seconds = flush_seconds
        self.lock = lock
        self.rows = self.written = 0
        self._room(0)  # HDF5 cannot close a file after a failed write: refuse a full disk before creating it
        self.file = h5py.File(self.path, "w", libver="latest")
        self.watch = FileWatch(self.path)
        for key, value in attrs.items():
            self.file.attrs[key] = json.dumps(value) if isinstance(value, (dict, list)) else value
        self.file.attrs["status"] = "running"
        self.file.attrs["wall_time"] = np.nan
        self.datasets = {}
        self.columns = row_layout(series)
        for name, shape in series.items():
            chunk = (max(1, min(buffer_rows, 1024)),) + tuple(shape)
            self.datasets[name] = self.file.create_dataset(
                name, shape=(0,) + tuple(shape), maxshape=(None,) + tuple(shape), chunks=chunk, dtype="f8")
        # One row of every series side by side (row_layout): a row is one copy, a flush one slice per series.
        self.buffer = np.zeros((buffer_rows, sum(c.stop - c.start for c, _ in self.columns.values())))
        self.rows = 0  # rows in the buffer
        self.written = 0  # rows on disk
        self.file.swmr_mode = True
        self._last_flush = time.monotonic()

    def append(self, row: dict[str, np.ndarray | float]) -> None:
        """Add one sample of every series (missing series get NaN)."""
        line = self.buffer[self.rows]
        for name, (columns, _) in self.columns.items():
            line[columns] = np.ravel(row.get(name, np.nan))
        self._next_row()

    def append_values(self, values: np.ndarray, extra: dict[str, np.ndarray | float] | None = None) -> None:
        """Add one sample given as the leading columns of a row (:func:`row_layout` of the series, in order;
        ``values`` may cover only the first series), the others from ``extra`` by name (missing: NaN)."""
        k = len(values)
        self.buffer[self.rows, :k] = values
        self.commit_line(k, extra)

    def next_line(self) -> np.ndarray:
        """The buffer row the next sample goes into: write its leading columns in place, then
        :meth:`commit_line` (what :meth:`append_values` does without the copy of a row)."""
        return self.buffer[self.rows]

    def commit_line(self, filled: int, extra: dict[str, np.ndarray | float] | None = None) -> None:
        """Add the row of :meth:`next_line`, its first ``filled`` columns written; the others from ``extra`` by
        name (missing: NaN)."""
        line = self.buffer[self.rows]
        k = filled
        if k < len(line):
            line[k:] = np.nan
            for name, value in (extra or {}).items():
                if name in self.columns:
                    line[self.columns[name][0]] = np.ravel(value)
        self._next_row()

    def _next_row(self) -> None:
        self.rows += 1
        if self.rows == len(self.buffer) or time.monotonic() - self._last_flush > self.flush_seconds:
            self.flush()

    def append_block(self, data: dict[str, np.ndarray]) -> None:
        """Write many rows at once (every series, same length), e.g. the rows kept on a resume."""
        self.flush()
        n = len(next(iter(data.values()))) if data else 0
        n0, n1 = self.written, self.written + n
        for name, ds in self.datasets.items():
            ds.resize(n1, axis=0)
            ds[n0:n1] = data[name]
        self.written = n1

    def flush(self) -> None:
        """Append the buffered rows to the file and flush it to disk (a refused write is an ``OSError``)."""
        try:
            self._flush()
        except RuntimeError as exc:  # h5py reports a failed write (disk full, file-size limit) this way
            raise write_error(exc, self.path) from None

    def _room(self, nbytes: int) -> None:
        """Refuse a write that the disk or the file-size limit would cut half-way: HDF5 cannot close a file
        after a failed write (and its library may crash at exit), so stop while the file is still whole."""
        need = 2 * nbytes + 256 * 1024  # data, chunk and metadata overhead, the final attributes
        require_room(self.path, need)

    def _check_file(self) -> None:
        """Stop (:class:`ResultsFileLost`) if the file was deleted or replaced; its rows copied where they can be
        read (:func:`.file_guard.rescue`)."""
        problem = self.watch.problem()
        if problem is None:
            return
        last = ""
        if "time" in self.columns and (self.rows or self.written):
            t = self.buffer[self.rows - 1, self.columns["time"][0]] if self.rows else self.datasets["time"][-1]
            last = f" up to t = {float(np.ravel(t)[0]):g} s"
        n = self.written
        try:
            self._flush_rows()
            n = self.written
            self.file.attrs["status"] = f"failed: the results file {self.path} was {problem} during the run"
        except Exception:  # noqa: BLE001 - the unlinked file may not take more: the rows already in it are copied
            pass
        target = rescue(self.file, self.path)
        with contextlib.suppress(Exception):
            self.file.close()
        self.release()
        where = (f"the {n} rows written{last} are saved in {target}" if target
                 else f"the {n} rows written{last} went into the {problem} file and are lost")
        raise ResultsFileLost(
            f"the results file {self.path} was {problem} while the run was writing it: {where}; the run stopped. "
            "Do not delete, move or replace a results file before its run ends (another run on the same file is "
            "refused by its lock); run the simulation again")

    def _flush(self) -> None:
        self._check_file()
        self._flush_rows()
        self.file.flush()
        self._last_flush = time.monotonic()

    def _flush_rows(self) -> None:
        if self.rows:
            self._room(self.buffer[: self.rows].nbytes)
            n0, n1 = self.written, self.written + self.rows
            memory = h5py.h5s.create_simple((self.rows,))
            for name, ds in self.datasets.items():
                columns, shape = self.columns[name]
                ds.resize(n1, axis=0)
                block = np.ascontiguousarray(self.buffer[: self.rows, columns]).reshape((self.rows,) + shape)
                _write_rows(ds, n0, block, memory if not shape else None)
                ds.flush()
            self.written, self.rows = n1, 0

    def close(self, status: str = "completed", wall_time: float | None = None,
              attrs: dict[str, Any] | None = None) -> None:
        """Flush, close, and record the final status and wall time; release the lock."""
        try:
            if self.file.id.valid:
                self.flush()
                self.file.close()
            self._check_file()
            with h5py.File(self.path, "a") as f:
                f.attrs["status"] = status
                if wall_time is not None:
                    f.attrs["wall_time"] = wall_time
                for key, value in (attrs or {}).items():
                    f.attrs[key] = json.dumps(value) if isinstance(value, (dict, list)) else value
        finally:
            if status != "running":
                self.release()

    def release(self) -> None:
        """Drop the lock on the results file (idempotent)."""
        if self.lock is not None:
            self.lock.release()
            self.lock = None


    def fail(self, status: str, wall_time: float | None = None, attrs: dict[str, Any] | None = None) -> bool:
        """After a write error (disk full): drop the unwritten rows, close, record ``status`` if the file
        system still allows it. Returns whether the status was recorded; never raises."""
        self.rows = 0
        try:
            if self.file.id.valid:
                self.file.close()
        except Exception:  # noqa: BLE001 - the file system refused; the rows on disk stay readable
            pass
        try:
            self.close(status=status, wall_time=wall_time, attrs=attrs)
            return True
        except Exception:  # noqa: BLE001
            try:
                with h5py.File(self.path, "a") as f:
                    f.attrs["status"] = status
                return True
            except Exception:  # noqa: BLE001
                return False
        finally:
            self.release()


def row_layout(series: dict[str, tuple[int, ...]]) -> dict[str, tuple[slice, tuple[int, ...]]]:
    """Columns of each series in a flat row of all series side by side, in the dict's order: name -> (columns,
    shape of one sample)."""
    out, start = {}, 0
    for name, shape in series.items():
        size = int(np.prod(shape, dtype=np.int64))
        out[name] = (slice(start, start + size), tuple(shape))
        start += size
    return out


def write_error(exc: BaseException, path: Path) -> OSError:
    """An ``OSError`` with the operating system's reason from an HDF5 write failure's long message."""
    import errno
    import re

    text = str(exc)
    code = re.search(r"errno = (\d+)", text)
    reason = re.search(r"error message = '([^']*)'", text)
    number = int(code.group(1)) if code else errno.EIO
    return OSError(number, reason.group(1) if reason else text.split("(")[0].strip(), str(path))


def read_results(path: str | Path) -> dict[str, Any]:
    """All datasets of a results file as numpy arrays, plus ``attrs`` (JSON attributes decoded).

    The time series (the extendable datasets) are cut to the rows every one of them holds: a run killed
    during a flush leaves the later series one flush short (module docstring)."""
    out: dict[str, Any] = {}
    series: list[str] = []
    with h5py.File(path, "r", swmr=True) as f:
        def visit(name: str, obj: Any) -> None:
            if isinstance(obj, h5py.Dataset):
                out[name] = obj[()]
                if obj.maxshape and obj.maxshape[0] is None:
                    series.append(name)
        f.visititems(visit)
        if series:
            rows = min(len(out[name]) for name in series)
            for name in series:
                out[name] = out[name][:rows]
        attrs = {}
        for k, v in f.attrs.items():
            if isinstance(v, str) and v[:1] in "[{":
                try:
                    v = json.loads(v)
                except ValueError:
                    pass
            attrs[k] = v
        out["attrs"] = attrs
    return out


def _write_rows(ds: h5py.Dataset, start: int, block: np.ndarray, memory: h5py.h5s.SpaceID | None) -> None:
    """``ds[start : start + len(block)] = block`` through HDF5's own write call (``block`` C-contiguous, float64):
    h5py's slice assignment costs about three times as much for the few-column blocks of a flush."""
    space = ds.id.get_space()
    space.select_hyperslab((start,) + (0,) * (block.ndim - 1), block.shape)
    ds.id.write(memory if memory is not None else h5py.h5s.create_simple(block.shape), space, block)
