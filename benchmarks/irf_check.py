"""The impulse-response check against the error it predicts: runs of the floating cylinder in regular waves with
shorter and shorter impulse responses (hydro.irf_duration), each run's steady heave error against the exact
frequency-domain answer beside the check's share of the inertia (hydro_fmu/radiation_check.py), and RM3 in
regular waves with the BEM's A_inf and with A_inf fitted (hydro.added_mass_inf = "kramers_kronig"), whose
impedance errors differ (0.596 and below) while the runs' errors do not.

    python benchmarks/irf_check.py --out benchmarks/results/irf_check.txt
"""

from __future__ import annotations

import argparse

from common import ROOT, report_header, write_report

from orchestrator.cosim.simulation import run_scenario
from orchestrator.scenario import apply_overrides, load_scenario


def one(scenario: str, items: list[str], out: str) -> tuple[float, float, float, str, list]:
    s = apply_overrides(load_scenario(ROOT / "scenarios" / scenario), items)
    result = run_scenario(s, out, in_process=True, progress=False, log=None)
    check = result.radiation
    from orchestrator.scene import load_scene

    c = load_scene(s, log=None).radiation_check()
    k = c.worst
    return (float(check["frequency_error"]), float(c.inertia_share[k]), float(c.at_omega[k]), c.labels[k],
            result.comparisons)


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--out")
    args = p.parse_args()
    lines = report_header("irf_check.py")
    lines.append("cylinder_regular (T = 5.6 s, near the heave resonance), in process; error of the steady heave "
                 "amplitude and phase against the exact frequency-domain answer")
    lines.append(f"{'irf_duration s':>15}{'impedance err':>15}{'inertia share':>15}{'heave err %':>13}"
                 f"{'phase err deg':>15}")
    for duration in (40.0, 10.0, 5.0, 3.0, 2.0, 1.0):
        err, share, _, _, comps = one("cylinder_regular.toml", [f"hydro.irf_duration={duration}"], "/tmp/irf_cyl.h5")
        heave = comps[0]
        lines.append(f"{duration:>15g}{err:>15.3g}{100 * share:>14.3g}%{100 * heave.amplitude_error:>+12.3f}%"
                     f"{heave.phase_error_deg:>+15.2f}")
    lines.append("")
    lines.append("rm3_regular (T = 8 s), in process, MoorDyn lines; errors of the steady motions against the exact "
                 "frequency-domain answer (the lines linearised quasi-statically there)")
    for label, items in (("A_inf from the BEM", []), ("A_inf fitted (kramers_kronig)",
                                                       ["hydro.added_mass_inf=kramers_kronig"])):
        err, share, at, dof, comps = one("rm3_regular.toml", items, "/tmp/irf_rm3.h5")
        lines.append(f"  {label}: impedance error {err:.3g}, largest share of the inertia {100 * share:.2g} % "
                     f"({dof} at {at:.3g} rad/s)")
        for c in comps:
            lines.append(f"    {c.label:<24}{100 * c.amplitude_error:>+9.3f}%"
                         + (f"{c.phase_error_deg:>+9.2f} deg" if c.phase_error_deg == c.phase_error_deg else ""))
    write_report(lines, args.out)


if __name__ == "__main__":
    main()
