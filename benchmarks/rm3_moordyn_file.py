"""RM3 moored by a MoorDyn input file (scenarios/data/rm3/rm3_moordyn.txt: six lines, three subsurface buoys):
static tensions against MoorDyn's own static solve, the surge decay with MoorDyn's line dynamics against the same
lines as their linearised quasi-static stiffness (and the frequency-domain roots of that linear scene), and the
irregular sea at the bundled step.

    python benchmarks/rm3_moordyn_file.py --out benchmarks/results/rm3_moordyn_file.txt
"""

from __future__ import annotations

import argparse
import time

import h5py
import numpy as np
from bench_rm3_mooring import crossings, peaks
from common import ROOT, report_header, write_report

from mbd_fmu.moordyn_files import read_moordyn_file, run_text, static_solve
from orchestrator.cosim.simulation import run_scenario
from orchestrator.scenario import apply_overrides, load_scenario
from orchestrator.scene import load_scene
from wec_cosim.benchreport.errors import linear_irregular_response

ZERO = "[0.0, 0.0, 0.0, 0.0, 0.0, 0.0]"


def run(scenario: str, items: list[str], out: str) -> tuple[float, dict]:
    s = apply_overrides(load_scenario(ROOT / "scenarios" / scenario), items)
    start = time.perf_counter()
    result = run_scenario(s, out, in_process=True, progress=False, log=None)
    with h5py.File(out, "r", swmr=True) as f:
        data = {k: f[k][()] for k in ("time", "bodies/spar/displacement", "bodies/float/displacement")}
    return time.perf_counter() - start, {"data": data, "result": result}


def surge_period(scene) -> float:
    """Undamped period of the linearised scene's slowest mode (surge on the soft buoyed legs): where det Re Z(omega)
    changes sign, scanned from 0.01 rad/s (bench_rm3_mooring.linear_periods starts at 0.05)."""
    from orchestrator.reference.frequency_domain import linear_model

    omega = np.arange(0.01, 0.2, 1e-4)
    det = np.array([np.linalg.det(z.real) for z in linear_model(scene, omega).impedance])
    i = int(np.flatnonzero(np.sign(det[:-1]) != np.sign(det[1:]))[0])
    w = omega[i] - det[i] * (omega[i + 1] - omega[i]) / (det[i + 1] - det[i])
    return 2 * np.pi / w


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--out")
    args = p.parse_args()
    lines = report_header("rm3_moordyn_file.py")
    md = read_moordyn_file(ROOT / "scenarios/data/rm3/rm3_moordyn.txt")
    static = static_solve(run_text(md, 1000.0, 9.81), np.array([x for _, x in md.coupled]))
    wall, rest = run("rm3_moordyn_decay.toml", [f"bodies.float.initial_displacement={ZERO}",
                                                 f"bodies.spar.initial_displacement={ZERO}", "simulation.duration=60"],
                     "/tmp/rm3_md_rest.h5")
    with h5py.File("/tmp/rm3_md_rest.h5", "r", swmr=True) as f:
        tensions = np.stack([f[f"mooring/line{i}/tension"][()] for i in md.line_ids], axis=1)
    lines.append("static tensions (N) at end A / end B of each line: MoorDyn's static solve of the file, and the "
                 "largest deviation over 60 s of the coupled run at rest")
    for k, lid in enumerate(md.line_ids):
        dev = np.abs(tensions[:, k] / static.end_tensions[k] - 1).max(axis=0)
        lines.append(f"  line {lid}: {static.end_tensions[k, 0]:10.0f} / {static.end_tensions[k, 1]:10.0f}   "
                     f"deviation {100 * dev[0]:.3f} % / {100 * dev[1]:.3f} %")
    lines.append("")
    lines.append("surge decay from 5 m (and from 1 m) in still water, 600 s: the spar's mean zero-crossing period "
                 "and logarithmic decrement (bench_rm3_mooring's measures), against the undamped natural period "
                 "of the scene linearised at rest with the file's lines as their quasi-static stiffness")
    scene = load_scene(apply_overrides(load_scenario(ROOT / "scenarios/rm3_moordyn_decay.toml"),
                                       ["mooring_lines.model=quasi_static"]), log=None)
    natural = surge_period(scene)
    lines.append(f"  linearised scene: surge mode {natural:.2f} s")
    cases = (("MoorDyn (line dynamics)", "moordyn", 5.0), ("quasi-static (linearised)", "quasi_static", 5.0),
             ("MoorDyn, from 1 m", "moordyn", 1.0))
    for label, model, start in cases:
        offset = f"[{start}, 0.0, 0.0, 0.0, 0.0, 0.0]"
        wall, out = run("rm3_moordyn_decay.toml", [f"mooring_lines.model={model}", "simulation.duration=600",
                                                    f"bodies.float.initial_displacement={offset}",
                                                    f"bodies.spar.initial_displacement={offset}"],
                        f"/tmp/rm3_md_{model}_{start:g}.h5")
        d = out["data"]
        t, x = d["time"], d["bodies/spar/displacement"][:, 0]
        p = peaks(x)
        p = p[p > 0]
        period = float(np.mean(np.diff(crossings(t, x))))
        decrement = float(np.mean(np.log(p[:-1] / p[1:])))
        lines.append(f"  {label:<28} spar surge: period {period:.2f} s ({100 * (period / natural - 1):+.2f} % of the "
                     f"linearised scene's surge mode), logarithmic decrement {decrement:.3f} over {len(p)} peaks; "
                     f"wall {wall:.0f} s")
    lines.append("")
    wall, out = run("rm3_moordyn_irregular.toml", [], "/tmp/rm3_md_irregular.h5")
    d = out["data"]
    lines.append(f"irregular sea (rm3_moordyn_irregular.toml, 600 s at the bundled 0.1 s step): wall {wall:.0f} s; "
                 f"spar surge std {np.std(d['bodies/spar/displacement'][:, 0]):.3f} m, float heave std "
                 f"{np.std(d['bodies/float/displacement'][:, 2]):.3f} m")
    s = load_scenario(ROOT / "scenarios/rm3_moordyn_irregular.toml")
    linear = load_scene(apply_overrides(s, ["mooring_lines.model=quasi_static"]), log=None)
    t = d["time"]
    mask = t >= s.ramp_time + s.hydro.irf_duration
    coordinates, exact = linear_irregular_response(linear, t[mask])
    deviations = []
    for j, (body, dof) in enumerate(coordinates):
        x = d[f"bodies/{body}/displacement"][mask, dof]
        rms = float(np.sqrt(np.mean(exact[:, j] ** 2)))
        deviations.append(f"{body} {'xyz'[dof] if dof < 3 else 'rpy'[dof - 3]} "
                          f"{100 * np.sqrt(np.mean((x - exact[:, j]) ** 2)) / rms:.1f} %")
    lines.append("  RMS deviation from the exact linear response of the same realised sea (the scene with the lines' "
                 f"linearised stiffness), after {t[mask][0]:.0f} s, relative to that response's "
                 "RMS: " + ", ".join(deviations))
    write_report(lines, args.out)


if __name__ == "__main__":
    main()
