"""The hydrodynamics acceptance figures in one report (the tests assert them; this prints the numbers).

* floating hemisphere: heave added mass and damping of our Capytaine databases against Hulme's
  multipole solution, K a = 0.2 .. 2, two panel sizes;
* two cylinders: reciprocity of the interaction blocks, and the co-simulated two-body heave decay
  (FMUs through fmpy) against the exact frequency-domain decay, two macro steps;
* state space against the convolution (disc and cylinder heave decays) by tolerance;
* excitation: superposition against convolution on an imported record, by kernel length;
* 3-hour JONSWAP record: Hs, Tp, power.

Run from the repository root:

    python benchmarks/hydro_acceptance.py [--out benchmarks/results/hydro_acceptance.txt]
"""

from __future__ import annotations

import argparse
import platform
import sys
import tempfile
from datetime import date
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from common import write_report  # noqa: E402

from hydro_fmu import spectra  # noqa: E402
from hydro_fmu.bemio import read_bemio  # noqa: E402
from orchestrator.scenario import load_scenario  # noqa: E402
from orchestrator.scene import load_scene  # noqa: E402
from tests import test_excitation, test_hemisphere, test_multibody, test_state_space, test_waves  # noqa: E402
from tests.multipole_hemisphere import hemisphere_heave  # noqa: E402


def hemisphere() -> list[str]:
    ref = np.array([hemisphere_heave(ka)[:2] for ka in test_hemisphere.KA])
    lines = ["## Floating hemisphere, heave (reference: Hulme's multipole method, tests/multipole_hemisphere.py)", "",
             "| K a | mu_33 ref | lambda_33 ref | " + " | ".join(
                 f"mu err % (panel {p} m) | lambda err % (panel {p} m)" for p in test_hemisphere.PANELS) + " |",
             "|---" * (3 + 2 * len(test_hemisphere.PANELS)) + "|"]
    errors = [100 * (test_hemisphere.hemisphere_database(p) / ref - 1) for p in test_hemisphere.PANELS]
    for i, ka in enumerate(test_hemisphere.KA):
        cells = " | ".join(f"{e[i, 0]:+.2f} | {e[i, 1]:+.2f}" for e in errors)
        lines.append(f"| {ka} | {ref[i, 0]:.4f} | {ref[i, 1]:.4f} | {cells} |")
    for p, e in zip(test_hemisphere.PANELS, errors, strict=True):
        lines.append(f"max |error| panel {p} m: added mass {np.abs(e[:, 0]).max():.2f} %, damping "
                     f"{np.abs(e[:, 1]).max():.2f} %")
    return lines + [""]


def two_bodies(tmp: Path) -> list[str]:
    scenario = load_scenario(ROOT / "scenarios" / "two_cylinders_decay.toml")
    scene = load_scene(scenario, log=None)
    hdb = read_bemio(scene.hdb_file)
    lines = ["## Two cylinders (12 x 12 interaction database)", ""]
    for name, table in (("A", hdb.added_mass), ("B", hdb.radiation_damping), ("A_inf", hdb.added_mass_inf[None])):
        scale = np.sqrt(np.abs(np.einsum("wii->wi", table)).max(axis=0))
        scale[scale == 0] = 1
        diff = np.abs(table[:, :6, 6:] - np.transpose(table[:, 6:, :6], (0, 2, 1))) / np.outer(scale[:6], scale[6:])
        lines.append(f"reciprocity |{name}_12 - {name}_21^T| / scale: max {100 * diff.max():.2f} %")
    k = np.argmin(np.abs(hdb.omega - 1.6))
    lines.append(f"heave-heave interaction at 1.6 rad/s: B_fore,aft / B_fore,fore = "
                 f"{hdb.radiation_damping[k, 2, 8] / hdb.radiation_damping[k, 2, 2]:.3f}, A ratio "
                 f"{hdb.added_mass[k, 2, 8] / hdb.added_mass[k, 2, 2]:.3f}")
    errors = {}
    for step in (0.1, 0.05, 0.025):
        errors[step] = test_multibody.decay_error(scenario, load_scene(scenario, log=None), step, tmp)
    lines.append("two-body heave decay (co-simulation through fmpy) against the exact FD decay, max |error| / x0: "
                 + ", ".join(f"h = {h} s: {100 * e:.3f} %" for h, e in errors.items()))
    steps = list(errors)
    lines.append("observed orders: " + ", ".join(
        f"{np.log2(errors[a] / errors[b]):.2f}" for a, b in zip(steps, steps[1:], strict=False)))
    return lines + [""]


def state_space() -> list[str]:
    lines = ["## State space against convolution (heave decay from 0.2 m, h = 0.02 s, same coupling)", "",
             "| scene | tolerance | order | fit error | max |x_ss - x_conv| / x0 % |", "|---|---|---|---|---|"]
    for name in ("disc_decay", "cylinder_regular"):
        s = load_scenario(ROOT / "scenarios" / f"{name}.toml")
        s.waves.kind, s.ptos = "still", []
        s.bodies[0].initial_displacement = [0, 0, 0.2, 0, 0, 0]
        scene = load_scene(s, log=None)
        reference = test_state_space.decay(scene, "convolution")
        for tol in (0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001):
            x = test_state_space.decay(scene, "state_space", tol)
            model = scene.hydro_model(dt=0.02)
            lines.append(f"| {name} | {tol} | {model.report.order} | {model.report.kernel_error:.2g} | "
                         f"{100 * np.abs(x - reference).max() / 0.2:.3f} |")
    return lines + [""]


def excitation(tmp: Path) -> list[str]:
    from hydro_fmu.sea import SeaSpec, build_sea

    sea = build_sea(SeaSpec(kind="irregular", hs=2.0, tp=7.0, discretisation="equal_energy", n_components=300, seed=3))
    t = np.arange(0.0, 600.0, 0.1)
    path = tmp / "eta.csv"
    path.write_text("t,eta\n" + "\n".join(f"{a:.17g},{b:.17g}" for a, b in zip(t, sea.elevation(t), strict=True)))
    hdb = read_bemio(test_excitation.CYLINDER_DB)
    lines = ["## Excitation: superposition against impulse-response convolution (imported 600 s record)", "",
             "| kernel half-length s | RMS difference surge % | heave % | pitch % |", "|---|---|---|---|"]
    for duration in (10.0, 20.0, 40.0, 60.0):
        e = 100 * test_excitation.excitation_pair(hdb, path, duration)[[0, 2, 4]]
        lines.append(f"| {duration:g} | {e[0]:.3f} | {e[1]:.3f} | {e[2]:.3f} |")
    return lines + [""]


def jonswap() -> list[str]:
    lines = ["## 3-hour JONSWAP record (Hs 2 m, Tp 8 s, gamma 3.3, sampled at 0.5 s)", ""]
    for method in ("equal_frequency", "equal_energy"):
        spec, sea, t, eta = test_waves.three_hour_record(method)
        st = spectra.record_statistics(t, eta)
        power = spectra.deep_water_power(st["hs"], st["te"])
        flux = spectra.component_power(sea.components)
        m_1 = spectra.moment(spectra.jonswap(spec.hs, spec.tp, spec.gamma), -1, 1e-3, 60.0)
        continuous = 1025 * 9.81**2 * m_1 / 2
        lines.append(
            f"{method}: {len(sea.components.omega)} components; Hs {st['hs']:.4f} m "
            f"({100 * (st['hs'] / 2 - 1):+.3f} %), Tp {st['tp']:.4f} s ({100 * (st['tp'] / 8 - 1):+.3f} %), "
            f"Te {st['te']:.4f} s; rho g^2 Hs^2 Te / (64 pi) = {power:.1f} W/m, component flux {flux:.1f} W/m "
            f"({100 * (power / flux - 1):+.3f} %), continuous spectrum rho g^2 m_-1 / 2 = {continuous:.1f} W/m "
            f"({100 * (power / continuous - 1):+.3f} %)")
    return lines + [""]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", help="also write the report to this file")
    args = parser.parse_args()
    lines = ["# command: python benchmarks/hydro_acceptance.py",
             f"# date: {date.today()}  machine: {platform.machine()} python {platform.python_version()}", ""]
    with tempfile.TemporaryDirectory() as tmp:
        for section in (hemisphere, lambda: two_bodies(Path(tmp)), state_space, lambda: excitation(Path(tmp)), jonswap):
            lines += section()
    write_report(lines, args.out)


if __name__ == "__main__":
    sys.exit(main())
