"""Accuracy of our FMUs under a plain fixed-step host: the force interface against the linearised one.

A plain host (fmpy's SSP runner, libcosim fixedStep, tests/c_host/jacobi_host.c) reads every
output right after the step and holds it over the next one (zero-order hold, Jacobi, no
iteration). Emulated here by our ``SimpleJacobiMaster`` (``resolve_feedthrough = false``), which
``tests/test_ssp.py`` and ``tests/test_plain_hosts.py`` check against those hosts to 1e-10. Rows:

* two_floats (20 s, transient included): error against the Richardson-extrapolated monolithic
  reference (``orchestrator.cosim.study``) at four steps, observed orders, stepping wall time, for the
  plain host with the force (``force``, p = 0) and with the linearised interface, and for our
  resolving Jacobi with p = 2 (the project's default master) for comparison;
* cylinder_regular (200 s): steady heave amplitude and phase against the exact frequency-domain
  answer, plain host, force and linearised, at several steps;
* hinge_barge (40 s, the scenario's own length): every DOF at the exported step 0.02 s, plain host
  linearised and our default Jacobi (p = 2, force).

In-process components (the FMUs' own slave classes, ``--fmpy`` to go through fmpy). Run from the
repository root:

    python benchmarks/bench_plain_hosts.py [--fmpy] [--skip-hinge] [--out benchmarks/results/plain_hosts.txt]
"""

from __future__ import annotations

import argparse
import copy
import os
import platform
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from common import write_report  # noqa: E402

from orchestrator.cosim import study  # noqa: E402
from orchestrator.cosim.simulation import run_scenario  # noqa: E402
from orchestrator.scenario import load_scenario  # noqa: E402
from orchestrator.scene import load_scene  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
STEPS = [0.2, 0.1, 0.05, 0.025]
VARIANTS = {  # label: study.variant keyword arguments (master jacobi)
    "plain host, force (p = 0)": dict(extrapolation=0, plain_host=True),
    "plain host, linearised": dict(extrapolation=0, plain_host=True, interface="linearised"),
    "our jacobi, force, p = 2": dict(extrapolation=2),
}


def two_floats(in_process: bool) -> list[str]:
    s = load_scenario(ROOT / "scenarios" / "two_floats.toml")
    s.simulation.duration = 20.0
    scene = load_scene(s, log=None)
    ref = study.reference(s, 0.0125, scene)
    lines = ["two_floats, 20 s: error against the monolithic reference (relative to the largest heave)",
             f"  {'variant':<28}" + "".join(f"{'h = ' + str(h):>12}" for h in STEPS) + "   orders             us/step"]
    for label, kw in VARIANTS.items():
        runs = [study.run_series(study.variant(s, "jacobi", h, **kw), scene=scene, in_process=in_process)
                for h in STEPS]
        errors = [study.error(r, ref) for r in runs]
        per_step = runs[-1].wall_time / (len(runs[-1].time) - 1) * 1e6
        orders = " ".join(f"{o:.2f}" for o in study.orders(STEPS, errors))
        lines.append(f"  {label:<28}" + "".join(f"{e:12.3e}" for e in errors) + f"   {orders:<18} {per_step:7.0f}")
    return lines


def steady(name: str, steps: list[float], variants: dict, in_process: bool, duration: float | None = None) -> list[str]:
    base = load_scenario(ROOT / "scenarios" / f"{name}.toml")
    lines = [f"{name}: steady amplitude error / phase error against the exact frequency-domain answer"]
    for label, kw in variants.items():
        for h in steps:
            s = copy.deepcopy(base)
            s.simulation.step = h
            if duration:
                s.simulation.duration = duration
            s.simulation.extrapolation = kw["extrapolation"]
            s.simulation.interface = kw.get("interface", "force")
            s.simulation.resolve_feedthrough = not kw.get("plain_host", False)
            start = time.perf_counter()
            try:
                r = run_scenario(s, Path("/tmp") / f"bench_plain_{name}_{os.getpid()}.h5", in_process=in_process,
                                 log=None, progress=False)
                text = ", ".join(f"{c.label} {100 * c.amplitude_error:+.3f} %" + (
                    f" {c.phase_error_deg:+.2f} deg" if c.unit != "W" else "") for c in r.comparisons)
            except Exception as exc:  # noqa: BLE001 - an unstable run is a result here
                text = f"failed: {str(exc)[:160]}"
            lines.append(f"  {label:<28} h = {h:<6g} {text}   ({time.perf_counter() - start:.1f} s)")
    return lines


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--fmpy", action="store_true", help="FMUs through fmpy instead of in-process slaves")
    p.add_argument("--skip-hinge", action="store_true")
    p.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "plain_hosts.txt"))
    a = p.parse_args()
    in_process = not a.fmpy
    lines = [f"command: python {' '.join(sys.argv)}", f"machine: {platform.node()} {platform.processor()} "
             f"{os.cpu_count()} cores; load average at start {os.getloadavg()}",
             f"components: {'in-process slaves' if in_process else 'FMUs through fmpy'}", ""]
    lines += two_floats(in_process) + [""]
    lines += steady("cylinder_regular", [0.2, 0.1, 0.05], {k: v for k, v in VARIANTS.items() if "plain" in k},
                    in_process) + [""]
    if not a.skip_hinge:
        lines += steady("hinge_barge", [0.02], {k: v for k, v in VARIANTS.items() if "force, p" not in k
                                                 or "our" in k}, in_process)
    lines.append(f"load average at the end {os.getloadavg()}")
    write_report(lines, a.out)


if __name__ == "__main__":
    main()
