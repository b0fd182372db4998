"""``simulation.error_tolerance`` at 1 % and 0.1 %: the step the run chooses from its own error estimate, the true
error it reaches, and its wall time beside the fastest fixed step that meets the same error.

Cases: the hinge barge as bundled (regular waves H 0.02 m, T 2 s), F3OF in regular waves at 9 s (the bundled
RAO scenario at the period where the base's heave resonance makes the step matter: 21 % off at its 0.1 s step), and
the two floats in the bench report's JONSWAP sea. True errors against independent answers: the hinge barge's and
the floats' as the bench report measures them (``wec_cosim.benchreport.errors``); F3OF's as its acceptance test
measures it (``tests/test_f3of.py``: the steady first harmonic of surge, heave and pitch of the three bodies fitted
together with the base's ringing heave mode over [3 T + 60 s, end], against the exact frequency-domain answer on
the database; the run's own summary fits the plain harmonic, which that mode still disturbs after 600 s).

The comparison: fixed steps run without an estimate (the stepping loop's wall time, as the bench report's points),
the fastest whose true error meets the tolerance. FMU slaves in process (the same physics as through fmpy).

    python benchmarks/bench_error_tolerance.py [--cases hinge_barge,f3of_rao_9s,two_floats_irregular]
        [--out benchmarks/results/error_tolerance.txt]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from common import load, report_header, write_report

from wec_cosim.benchreport import errors
from wec_cosim.benchreport.cases import IRREGULAR_SEA
from wec_cosim.benchreport.points import Variant, quiet_threads, run_point

TOLERANCES = (0.01, 0.001)


def f3of_rao_error(scene, data: dict, result) -> float:  # noqa: ANN001
    """Largest complex relative error of surge, heave and pitch of the three bodies (tests/test_f3of.py's fit)."""
    from orchestrator.reference import frequency_domain
    from orchestrator.reference.decay import fit_forced
    from orchestrator.scenario import DOFS

    s = scene.scenario
    period = s.waves.period
    omega = 2 * math.pi / period
    t = np.asarray(data["time"])
    every = max(1, round(0.1 / float(t[1] - t[0])))  # the fit on samples 0.1 s apart, as the test's
    t = t[::every]
    fd = frequency_domain.solve(scene, np.array([omega]))
    labels, measured, exact = [], [], []
    series = []
    for b in s.bodies:
        for d in ("surge", "heave", "pitch"):
            j = DOFS.index(d)
            series.append(np.asarray(data[f"bodies/{b.name}/displacement"])[::every, j])
            exact.append(complex(fd.body_rao(b.name)[0][j]) * s.waves.height / 2)
            labels.append(f"{b.name} {d}")
    amplitudes, _ = fit_forced(t, np.column_stack(series), omega, 1, (3 * period + 60.0, float(t[-1])))
    measured = np.asarray(amplitudes)
    return float(np.max(np.abs(measured - np.array(exact)) / np.abs(np.array(exact))))


CASES = {
    "hinge_barge": (Variant("scenarios/hinge_barge.toml", in_process=True), errors.regular_wave_error,
                    (0.08, 0.04, 0.02, 0.01, 0.005)),
    "f3of_rao_9s": (Variant("scenarios/f3of_rao.toml", ("waves.period=9.0",), in_process=True), f3of_rao_error,
                    (0.1, 0.05, 0.025, 0.0125)),
    "two_floats_irregular": (Variant("scenarios/two_floats.toml", (*IRREGULAR_SEA, "simulation.duration=400"),
                                     in_process=True), errors.irregular_error, (0.2, 0.1, 0.05, 0.025, 0.0125)),
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", default=",".join(CASES))
    parser.add_argument("--out", default=None)
    args = parser.parse_args()
    quiet_threads()
    lines = report_header("bench_error_tolerance.py")
    start = time.perf_counter()
    rows = []
    for name in args.cases.split(","):
        base, error, steps = CASES[name]
        fixed = []
        for h in steps:
            p = run_point(base.with_(f"simulation.step={h:g}", "simulation.error_tolerance=0"), error, shadow=False)
            fixed.append((h, p))
            print(f"{name} fixed {h:g}: {p.status} error {p.error:.3g} wall {p.wall_time:.2f} s", flush=True)
        for tol in TOLERANCES:
            kept: dict = {}

            def keep(scene, data, result, into=kept) -> dict:  # noqa: ANN001
                into["choice"] = result.step_choice
                return {}

            p = run_point(base.with_(f"simulation.error_tolerance={tol:g}"), error,
                          estimate=errors.run_estimate, measures=keep)
            c = kept.get("choice")
            best = min((q for h, q in fixed if q.stable and q.error <= tol), key=lambda q: q.wall_time, default=None)
            best_text = (f"{float(best.variant.overrides[-2].split('=')[1]):g} s: {100 * best.error:.3g} %, "
                         f"{best.wall_time:.2f} s" if best else "none of " + ", ".join(f"{h:g}" for h, _ in fixed))
            if c is None or not p.stable:
                rows.append(f"| {name} | {100 * tol:g} % | {p.status}: {p.message[:100]} | | | | {best_text} |")
            else:
                tried = ", ".join(f"{a.step:.4g} s: " + (f"{100 * a.estimate:.3g} %" if math.isfinite(a.estimate)
                                                         else "did not finish") for a in c.attempts)
                total = sum(a.wall_time for a in c.attempts)
                met = "met" if p.error <= tol else "**not met**"
                note = "" if c.met else " (estimate not met)"
                rows.append(f"| {name} | {100 * tol:g} % | {c.step:.4g} s ({tried}){note} | {100 * p.error:.3g} % "
                            f"({met}) | {100 * p.estimate:.3g} % | {total:.1f} s ({p.wall_time:.2f} s) | {best_text} |")
            print(rows[-1], flush=True)
    lines += ["", "| case | tolerance | step chosen (steps tried: estimate) | true error | estimate | wall time: all "
              "runs with shadows (run kept, stepping) | fastest fixed step within it: true error, stepping wall time |",
              "|---|---|---|---|---|---|---|", *rows, "",
              f"{time.perf_counter() - start:.0f} s; load average at the end {load()}"]
    write_report(lines, args.out)


if __name__ == "__main__":
    main()
