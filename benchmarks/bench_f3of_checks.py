"""F3OF database: the project's own checks, measured, on each of the four F3OF scenes.

For each bundled scenario ``scenarios/f3of_*.toml`` (all four share one 18 x 18 database) this reports
the worst value each check finds on the scene's degrees of freedom (``HydroDatabase.check_physics``
at tolerance 0, so that it names the worst place; the scenes load it at the default 5 %), the
change and spread of Ogilvie's A_inf, and the scaled error of A and B rebuilt from the truncated
impulse response the time-domain model convolves (the run's ``radiation.frequency_error``, from a
1 s in-process run). No BEM solve if the database is cached. Then, on the RAO scene (all nine DOFs), the
same rebuild error per DOF pair, separately for B and omega (A - A_inf), with the scenario's A_inf and B
continuation (``kramers_kronig``) and with Ogilvie's A_inf and the power law alone (``ogilvie``).

    python benchmarks/bench_f3of_checks.py --out benchmarks/results/f3of_checks.txt
"""

from __future__ import annotations

import argparse
import os
import platform
import tempfile
from pathlib import Path

import numpy as np
from common import write_report

from orchestrator.cosim.simulation import format_summary, run_scenario
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

ROOT = Path(__file__).resolve().parent.parent
NAMES = ("f3of_dt1", "f3of_dt2", "f3of_dt3", "f3of_rao")


def scene_checks(name: str, folder: Path) -> list[str]:
    """Report lines of one scene: worst asymmetry and B eigenvalue, A_inf fit, kernel rebuild error."""
    scenario = load_scenario(ROOT / "scenarios" / f"{name}.toml")
    messages: list[str] = []
    scene = load_scene(scenario, log=messages.append)
    index = np.asarray(scene.hydro_index())
    lines = [f"{name} (check tolerance {scenario.hydro.check_tolerance:g}; loads: yes)"]
    lines += [f"    worst: {m[len(scene.hdb.source) + 2:]}" for m in scene.hdb.check_physics(index, 0.0)]
    lines += [f"    {m}" for m in messages if "Ogilvie" in m or "Kramers-Kronig" in m]
    scenario.simulation.duration = 1.0
    result = run_scenario(scenario, folder / f"{name}.h5", in_process=True, log=None, progress=False)
    lines += [f"    {m}" for m in format_summary(result).splitlines() if m.startswith("radiation")]
    return lines


def pair_errors(added_mass_inf: str) -> list[str]:
    """Per DOF pair of the RAO scene: ||B_kernel - B|| and ||w (A_kernel - A)|| over the database frequencies,
    scaled as the run's frequency error (sqrt(s_i s_j), s_i from the database's B and w (A - A_inf))."""
    from hydro_fmu.hdb import DOF_NAMES
    from hydro_fmu.state_space import dof_scales
    from orchestrator.reference.frequency_domain import kernel_coefficients, scene_kernel

    scenario = load_scenario(ROOT / "scenarios" / "f3of_rao.toml")
    scenario.hydro.added_mass_inf = added_mass_inf
    scene = load_scene(scenario, log=None)
    idx = np.asarray(scene.hydro_index())
    hdb, w = scene.hdb, scene.hdb.omega
    a, b = hdb.added_mass[:, idx][:, :, idx], hdb.radiation_damping[:, idx][:, :, idx]
    a_inf = hdb.added_mass_inf[np.ix_(idx, idx)]
    t, k = scene_kernel(scene, scenario.simulation.step, scenario.hydro.irf_duration)
    ka, kb = kernel_coefficients(t, k, a_inf, w)
    ref = np.concatenate([b, w[:, None, None] * (a - a_inf)], axis=0)
    scale = np.sqrt(np.outer(*(2 * [dof_scales(ref)])))
    eb = np.sqrt(np.sum((kb - b) ** 2, axis=0)) / scale
    ea = np.sqrt(np.sum((w[:, None, None] * (ka - a)) ** 2, axis=0)) / scale
    names = [f"{scene.hydro_bodies[i // 6]}.{DOF_NAMES[i % 6]}" for i in idx]
    lines = [f"f3of_rao, added_mass_inf = {added_mass_inf}: kernel's B and w A against the database per DOF pair "
             f"(largest B {eb.max():.4f}, largest w A {ea.max():.4f})"]
    for i, name in enumerate(names):
        lines.append(f"    {name:12s} B  " + " ".join(f"{x:6.3f}" for x in eb[i]))
        lines.append(f"    {'':12s} wA " + " ".join(f"{x:6.3f}" for x in ea[i]))
    return lines


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out")
    a = parser.parse_args(argv)
    lines = [f"# command: python benchmarks/bench_f3of_checks.py{' --out ' + a.out if a.out else ''}",
             f"# python {platform.python_version()}, {os.cpu_count()} cores, load average at start "
             f"{' '.join(f'{x:.2f}' for x in os.getloadavg())}"]
    with tempfile.TemporaryDirectory() as tmp:
        for name in NAMES:
            lines += scene_checks(name, Path(tmp))
    for mode in ("kramers_kronig", "ogilvie"):
        lines += pair_errors(mode)
    lines.append(f"# load average at end {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    write_report(lines, a.out)


if __name__ == "__main__":
    main()
