"""State-space radiation on the bench report's points that failed before: the hinge barge at tolerance 0.005 at
0.04, 0.02 and 0.01 s, and F3OF DT3 (the bench report's quick run, 900 s of decay from 1 deg) at every tolerance.

Each point runs in process without an error estimate and is scored by the bench report's own measure
(``wec_cosim.benchreport.cases``); with ``--roots`` the table also gives F3OF DT3's two free modes (period,
damping ratio) of the linear model with the kernel's continuous transform and with the state-space fit's, which
explain the F3OF errors without time stepping. Usage::

    python benchmarks/bench_state_space_points.py [--roots] [--out benchmarks/results/state_space_points.txt]
"""

from __future__ import annotations

import argparse
import time

from common import load, report_header, write_report

from wec_cosim.benchreport.cases import CASES
from wec_cosim.benchreport.points import Variant, quiet_threads, run_point

POINTS = (("hinge_barge", 0.005, 0.04), ("hinge_barge", 0.005, 0.02), ("hinge_barge", 0.005, 0.01),
          ("f3of_dt3", 0.1, 0.1), ("f3of_dt3", 0.02, 0.1), ("f3of_dt3", 0.005, 0.1), ("f3of_dt3", 0.005, 0.025))


def roots_rows(tolerances: tuple[float, ...]) -> list[str]:
    """F3OF DT3's same-way and mirror-wise modes: the kernel's against the fit's, per tolerance."""
    from orchestrator.scenario import apply_overrides, load_scenario
    from orchestrator.scene import load_scene
    from wec_cosim.benchreport.errors import _paired_roots, reference_roots

    case = next(c for c in CASES if c.name == "f3of_dt3")
    out = []
    for tol in tolerances:
        s = apply_overrides(load_scenario(case.base.scenario), [
            *case.base.overrides, "hydro.radiation_method=state_space", f"hydro.state_space_tolerance={tol:g}"])
        scene = load_scene(s, log=None)
        kernel = _paired_roots(scene, reference_roots(scene))
        fitted = _paired_roots(scene, reference_roots(scene, "state_space"))
        cells = [f"{k.period:.4f} s, {k.damping_ratio:.2e} / {f.period:.4f} s, {f.damping_ratio:.2e}"
                 for k, f in zip(kernel, fitted, strict=True)]
        out.append(f"| {tol:g} | {' | '.join(cells)} |")
        print(out[-1], flush=True)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--roots", action="store_true")
    parser.add_argument("--out", default=None)
    args = parser.parse_args()
    quiet_threads()
    lines = report_header("bench_state_space_points.py")
    lines += ["", "| case | state-space tolerance | step (s) | status | error (the bench report's measure) | RTF | "
              "the run's message |", "|---|---|---|---|---|---|---|"]
    start = time.perf_counter()
    cases = {c.name: c for c in CASES}
    for name, tol, h in POINTS:
        base = cases[name].variant(name == "f3of_dt3")
        v = Variant(base.scenario, base.overrides, in_process=True).with_(
            "hydro.radiation_method=state_space", f"hydro.state_space_tolerance={tol:g}", f"simulation.step={h:g}")
        p = run_point(v, cases[name].error, shadow=False)
        lines.append(f"| {name} | {tol:g} | {h:g} | {p.status} | {p.error:.3g} | {p.real_time_factor:.0f} | "
                     f"{p.message[:200]} |")
        print(lines[-1], flush=True)
    if args.roots:
        lines += ["", "F3OF DT3's free modes, the kernel's continuous transform / the state-space fit "
                  "(period, damping ratio):", "", "| tolerance | same-way mode | mirror-wise mode |", "|---|---|---|",
                  *roots_rows((0.1, 0.02, 0.005))]
    lines += ["", f"{time.perf_counter() - start:.0f} s; load average at the end {load()}"]
    write_report(lines, args.out)


if __name__ == "__main__":
    main()
