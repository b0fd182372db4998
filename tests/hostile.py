"""What the hostile-input generators share: a command run in a forked child (a segmentation fault or an abort
shows as a negative status instead of taking pytest down), the cylinder scene shortened to the least that still
exercises a path, and the check of one clean error."""

from __future__ import annotations

import contextlib
import copy
import io
import os
import select
import signal
import time
from pathlib import Path
from typing import Any

from .test_malformed_generated import Case, check
from .toml_text import bundled, dumps

TIMEOUT = 120  # s: a case that takes longer is a hang

__all__ = ["Case", "check", "cylinder", "dumps", "expect_clean_error", "run_forked"]


def cylinder(duration: float = 1.0, **sections: dict) -> dict:
    """The bundled heave cylinder (its database is cached), ``duration`` s long, with sections updated."""
    data = copy.deepcopy(bundled("cylinder_regular"))
    data["simulation"]["duration"] = duration
    for name, values in sections.items():
        if isinstance(values, dict) and isinstance(data.get(name), dict):
            data[name].update(values)
        else:
            data[name] = values
    return data


def run_forked(argv: list[str], timeout: float = TIMEOUT, call: Any = None) -> tuple[int, str, str]:
    """Exit status, stderr and stdout of ``wec-cosim ARGV`` (or of ``call()``, which returns an exit status) run
    in a forked copy of this process. A signal that ends the child is returned as its negative number; a child
    still running after ``timeout`` s is killed and reported as status -9 with ``hang`` in its stderr."""
    err_r, err_w = os.pipe()
    out_r, out_w = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: run, report through the pipes, never return into pytest
        code = 70
        try:
            os.close(err_r)
            os.close(out_r)
            err, out = io.StringIO(), io.StringIO()
            with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
                try:
                    if call is not None:
                        code = call()
                    else:
                        from wec_cosim.cli import main

                        code = main(argv)
                except SystemExit as exc:
                    code = exc.code if isinstance(exc.code, int) else 2
                except BaseException:  # noqa: BLE001 - shown to the test as a traceback
                    import traceback

                    err.write(traceback.format_exc())
                    code = 1
            os.write(err_w, err.getvalue().encode())
            os.write(out_w, out.getvalue().encode())
        finally:
            os._exit(code if isinstance(code, int) else 1)
    os.close(err_w)
    os.close(out_w)
    chunks: dict[int, list[bytes]] = {err_r: [], out_r: []}
    deadline = time.monotonic() + timeout
    open_fds = [err_r, out_r]
    hung = False
    while open_fds:
        left = deadline - time.monotonic()
        if left <= 0:
            hung = True
            os.kill(pid, signal.SIGKILL)
            break
        ready, _, _ = select.select(open_fds, [], [], left)
        for fd in ready:
            data = os.read(fd, 65536)
            if data:
                chunks[fd].append(data)
            else:
                open_fds.remove(fd)
    _, status = os.waitpid(pid, 0)
    os.close(err_r)
    os.close(out_r)
    err, out = (b"".join(chunks[fd]).decode(errors="replace") for fd in (err_r, out_r))
    if hung:
        return -9, f"hang: no answer within {timeout} s\n{err}", out
    code = os.waitstatus_to_exitcode(status)
    return code, err, out


def expect_clean_error(case: Case, folder: Path, code: int, stderr: str) -> None:
    """Exit status 2, one paragraph naming what the case expects, no traceback (the generated suite's check)."""
    check(case, code, stderr, folder)


def write_case_files(case: Case, folder: Path) -> list[str]:
    from .test_malformed_generated import _materialise

    return _materialise(case, folder)


def scenario_text(data: dict) -> str:
    return dumps(data)
