"""Run an exported SSP archive in other FMI hosts: fmpy's SSP simulator, libcosim (libcosimpy) and
a plain C host (``tests/c_host/jacobi_host.c``, compiled by the caller).

Meant to run in a separate process (a crash in a foreign host must not take ours down):

    python -m orchestrator.fmi.foreign_hosts {fmpy,libcosim,libcosim-osp,c} ARCHIVE.ssp --steps N --out F.npz VAR...

(``c`` needs ``--executable`` and runs it in a further process with the environment of
:mod:`orchestrator.fmi.host_environment`; its exit status and messages are checked here.)

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
import os
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

import numpy as np

from .host_environment import fmu_environment


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


def c_host_plan(archive: Path, folder: Path, steps: int, step: float, variables: list[str]) -> Path:
    """Write the plan file of ``jacobi_host`` for the SSP ``archive`` unpacked in ``folder`` (FMUs unpacked
    beside it): its components, the parameter set ``resources/parameters.ssv``, its connections, and
    ``variables`` recorded."""
    from fmpy import extract, read_model_description
    from fmpy.ssp.ssd import read_ssd, read_ssv

    ssd = read_ssd(str(archive))
    components = {c.name: c for c in ssd.system.elements}
    lines, refs = [], {}
    for name, comp in components.items():
        fmu = folder / comp.source
        md = read_model_description(str(fmu))
        unzipped = extract(str(fmu), unzipdir=str(folder / f"{name}_fmu"))
        refs[name] = {v.name: v.valueReference for v in md.modelVariables}
        lines.append(f"fmu {name} {unzipped} {md.coSimulation.modelIdentifier} {md.guid}")
    parameters = read_ssv(str(folder / "resources" / "parameters.ssv"))
    for p in parameters.parameters:
        comp, var = p.name.split(".", 1)
        lines.append(f"param {comp} {refs[comp][var]} {float(p.value)!r}")
    for c in ssd.system.connections:
        lines.append(f"connect {c.startElement} {refs[c.startElement][c.startConnector]} {c.endElement} "
                     f"{refs[c.endElement][c.endConnector]}")
    for v in variables:
        comp, var = v.split(".", 1)
        lines.append(f"record {comp} {refs[comp][var]}")
    lines += [f"step {step!r}", f"steps {steps}"]
    plan = folder / "plan.txt"
    plan.write_text("\n".join(lines) + "\n")
    return plan


def run_c(archive: Path, steps: int, step: float, variables: list[str], executable: Path,
          timeout: float = 3600.0) -> dict[str, np.ndarray]:
    """Run the compiled C host on the archive in its own process; SystemExit with its messages if it fails."""
    with tempfile.TemporaryDirectory(prefix="wec_c_host_") as tmp:
        folder = Path(tmp)
        with zipfile.ZipFile(archive) as z:
            z.extractall(folder)
        plan = c_host_plan(archive, folder, steps, step, variables)
        out = folder / "out.txt"
        proc = subprocess.run([str(executable), str(plan), str(out)], capture_output=True, text=True,
                              env={**os.environ, **fmu_environment()}, timeout=timeout)
        if proc.returncode != 0:
            raise SystemExit(f"C host exited with status {proc.returncode}:\n{proc.stderr[-4000:]}")
        table = np.loadtxt(out, ndmin=2)
    data = {"time": table[:, 0]}
    for k, v in enumerate(variables):
        data[v] = table[:, k + 1]
    return data


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("host", choices=("fmpy", "libcosim", "libcosim-osp", "c"))
    p.add_argument("archive", type=Path)
    p.add_argument("--steps", type=int, required=True)
    p.add_argument("--step", type=float, required=True)
    p.add_argument("--out", type=Path, required=True)
    p.add_argument("--executable", type=Path, help="the compiled C host (host c)")
    p.add_argument("variables", nargs="+")
    a = p.parse_args(argv)
    if a.host == "fmpy":
        data = run_fmpy(a.archive, a.steps, a.step, a.variables)
    elif a.host == "c":
        if a.executable is None:
            p.error("host c needs --executable")
        data = run_c(a.archive, a.steps, a.step, a.variables, a.executable)
    else:
        data = run_libcosim(a.archive, a.steps, a.step, a.variables, osp=a.host == "libcosim-osp")
    np.savez(a.out, **{k.replace("/", "_"): v for k, v in data.items()})
    return 0


if __name__ == "__main__":
    sys.exit(main())
