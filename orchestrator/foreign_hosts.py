"""Run an exported SSP archive in other FMI hosts: fmpy's SSP simulator and libcosim (libcosimpy).

Meant to run in a separate process (a crash in a foreign host must not take ours down):

    python -m orchestrator.foreign_hosts {fmpy,libcosim,libcosim-osp} ARCHIVE.ssp --steps N --out F.npz VAR...

``VAR`` is ``component.variable`` (e.g. ``mbd.fore.x[3]``). The output holds ``time`` (the
communication points after each step) and one array per variable.

What each host does (read from their sources, 2026): fmpy 0.3's ``simulate_ssp`` starts every
connector at 0, then per step sets each component's inputs from the connector values, calls
``doStep`` and reads the outputs; connections are applied after all components stepped (Jacobi,
zero-order hold); it labels a row with the step's start time, so we add the step. It ignores the
SSD's parameter bindings unless given ``parameter_set`` (we pass ``resources/parameters.ssv``).
libcosim's fixed-step algorithm does the same exchange (outputs read after ``doStep``, before
new inputs are set) and applies the component-level parameter bindings itself.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import zipfile
from pathlib import Path

import numpy as np


def run_fmpy(archive: Path, steps: int, step: float, variables: list[str]) -> dict[str, np.ndarray]:
    from fmpy.ssp.simulation import simulate_ssp
    from fmpy.ssp.ssd import read_ssv

    params = read_ssv(str(archive), resource="resources/parameters.ssv")
    # stop slightly before the last point: fmpy accumulates time += step and runs while time < stop.
    rows = simulate_ssp(str(archive), start_time=0.0, stop_time=(steps - 0.5) * step, step_size=step,
                        parameter_set=params)
    out = {"time": np.arange(1, len(rows) + 1) * step}
    for v in variables:
        out[v] = np.asarray(rows[v], dtype=float)
    return out


def _libcosim_values(execution, steps: int, step: float, variables: list[str]) -> dict[str, np.ndarray]:
    from libcosimpy.CosimObserver import CosimObserver

    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    refs = []
    for v in variables:
        comp, name = v.split(".", 1)
        index = execution.slave_index_from_instance_name(comp)
        if index is None:
            raise SystemExit(f"libcosim: no component {comp!r}")
        table = {var.name.decode(): var.reference for var in execution.slave_variables(index)}
        refs.append((index, table[name]))
    out = {v: np.empty(steps) for v in variables}
    for k in range(steps):
        execution.step(1)
        for v, (index, ref) in zip(variables, refs, strict=True):
            out[v][k] = observer.last_real_values(index, [ref])[0]
    out["time"] = np.arange(1, steps + 1) * step
    return out


def run_libcosim(archive: Path, steps: int, step: float, variables: list[str], osp: bool = False) -> dict:
    from libcosimpy.CosimExecution import CosimExecution

    with tempfile.TemporaryDirectory(prefix="wec_libcosim_") as tmp:
        with zipfile.ZipFile(archive) as z:
            z.extractall(tmp)
        if osp:
            execution = CosimExecution.from_osp_config_file(str(Path(tmp) / "OspSystemStructure.xml"))
        else:
            execution = CosimExecution.from_ssp_file(str(tmp))
        return _libcosim_values(execution, steps, step, variables)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("host", choices=("fmpy", "libcosim", "libcosim-osp"))
    p.add_argument("archive", type=Path)
    p.add_argument("--steps", type=int, required=True)
    p.add_argument("--step", type=float, required=True)
    p.add_argument("--out", type=Path, required=True)
    p.add_argument("variables", nargs="+")
    a = p.parse_args(argv)
    if a.host == "fmpy":
        data = run_fmpy(a.archive, a.steps, a.step, a.variables)
    else:
        data = run_libcosim(a.archive, a.steps, a.step, a.variables, osp=a.host == "libcosim-osp")
    np.savez(a.out, **{k.replace("/", "_"): v for k, v in data.items()})
    return 0


if __name__ == "__main__":
    sys.exit(main())
