"""The cylinder's power matrix in irregular seas (docs/sweeps.md) against the exact frequency domain.

Reads three sweep files made from the repository root by

    wec-cosim sweep scenarios/cylinder_irregular.toml --out results/cylinder_power.h5
    wec-cosim sweep scenarios/cylinder_irregular.toml --method frequency_domain --out results/cylinder_power_fd.h5
    wec-cosim sweep scenarios/cylinder_irregular.toml --out results/cylinder_linear.h5 \\
        --grid waves.hs=2 --grid waves.tp=6,8,10,12 --grid hydro.viscous=false --seeds 12
    wec-cosim sweep scenarios/cylinder_irregular.toml --out results/cylinder_linear_paired.h5 \
        --grid waves.hs=2 --grid waves.tp=6 --grid hydro.viscous=false --seeds 12 \
        --grid hydro.radiation_method=state_space,convolution --grid simulation.step=0.1,0.05

(time domain with quadratic drag; frequency domain, linear, no drag; time domain without the viscous
forces, the linear model the frequency domain solves; the same at Tp 6 s with the radiation model
and the time step changed, on the same seeds), and solves ``wec-cosim rao``'s irregular-sea
statistics (``/irregular/`` of the RAO file) for a few cells. Prints:

1. the linear time-domain cells against the frequency domain, with the seeds' standard error: the
   co-simulation and the matrix machinery reproduce the exact answer within the sampling error;
   The paired runs (same seeds) separate the time-domain model's own discretisation error from the
   sampling error of the seeds;
2. ``wec-cosim rao``'s mean power for a few cells against the frequency-domain sweep's (same physics,
   two code paths);
3. every cell of the time-domain matrix (with drag) over the frequency-domain one: the effect of the
   quadratic drag that the linear method leaves out.

    python benchmarks/power_matrix_check.py [--out benchmarks/results/power_matrix.txt]
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np
from common import write_report

from orchestrator.reference.response_files import write_rao_file
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene
from wec_cosim.sweeps.matrices import read_matrices

ROOT = Path(__file__).resolve().parent.parent
RAO_CELLS = [(1.0, 6.0), (3.0, 8.0), (5.0, 12.0)]


def matrices(path: Path):
    with h5py.File(path) as f:
        return read_matrices(f), dict(f.attrs)


def rao_power(hs: float, tp: float) -> tuple[float, float]:
    """Mean power (W) and significant heave (m) of ``wec-cosim rao`` in the sea (hs, tp)."""
    s = load_scenario(ROOT / "scenarios" / "cylinder_irregular.toml")
    s.waves.hs, s.waves.tp = hs, tp
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "rao.h5"
        write_rao_file(load_scene(s, log=None), out)
        with h5py.File(out) as f:
            return float(f["irregular/ptos/pto/mean_power"][()]), float(
                f["irregular/bodies/float/significant_response"][0])


def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--results", default=str(ROOT / "results"))
    p.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "power_matrix.txt"))
    a = p.parse_args(argv)
    folder = Path(a.results)
    td, td_attrs = matrices(folder / "cylinder_power.h5")
    fd, _ = matrices(folder / "cylinder_power_fd.h5")
    lin, _ = matrices(folder / "cylinder_linear.h5")
    hs, tp = list(td.values[0]), list(td.values[1])
    lines = [f"# {' '.join(['python', *sys.argv])}",
             f"# load average {' '.join(f'{x:.2f}' for x in os.getloadavg())}",
             f"# time domain: {td_attrs['seeds']} seeds per cell, sweep status {td_attrs['status']!r}",
             "", "1. linear time domain (hydro.viscous = false) against the frequency domain, Hs 2 m",
             f"{'Tp s':>6}{'TD kW':>10}{'+- s.e.':>9}{'FD kW':>10}{'TD/FD-1':>9}{'in s.e.':>9}"
             f"{'Hs,heave TD':>13}{'FD m':>8}"]
    i = hs.index(2.0)
    for k, t in enumerate(lin.values[1]):
        j = tp.index(float(t))
        p_td = lin.data["mean_power"][0, k, 0] / 1e3
        se = lin.data["mean_power_std"][0, k, 0] / 1e3 / np.sqrt(lin.data["seeds_done"][0, k, 0])
        p_fd = fd.data["mean_power"][i, j] / 1e3
        z_td = lin.data["bodies/float/significant"][0, k, 0, 2]
        z_fd = fd.data["bodies/float/significant"][i, j, 2]
        lines.append(f"{t:>6g}{p_td:>10.3f}{se:>9.3f}{p_fd:>10.3f}{p_td / p_fd - 1:>+9.2%}{(p_td - p_fd) / se:>+9.2f}"
                     f"{z_td:>13.3f}{z_fd:>8.3f}")
    lines += ["", "1b. Tp 6 s, the same 12 seeds: time-domain model settings against state space at dt 0.1 s "
              "(paired differences: no sampling error between them)",
              f"{'radiation':<14}{'dt s':>6}{'TD kW':>10}{'paired diff':>13}{'+- s.e.':>9}"]
    with h5py.File(folder / "cylinder_linear_paired.h5") as f:
        runs: dict[tuple, dict[int, float]] = {}
        for g in f["cases"].values():
            params = dict(json.loads(g.attrs["params"]))
            key = (params["hydro.radiation_method"], params["simulation.step"])
            runs.setdefault(key, {})[int(g.attrs["seed_index"])] = float(g["ptos/pto/mean_power"][()])
    reference = np.array([runs[("state_space", 0.1)][k] for k in sorted(runs[("state_space", 0.1)])])
    for key in sorted(runs):
        power = np.array([runs[key][k] for k in sorted(runs[key])])
        diff = power / reference - 1
        lines.append(f"{key[0]:<14}{key[1]:>6g}{power.mean() / 1e3:>10.3f}{diff.mean():>+13.3%}"
                     f"{diff.std(ddof=1) / np.sqrt(len(diff)):>9.3%}")
    lines += ["", "2. `wec-cosim rao` irregular-sea statistics against the frequency-domain sweep",
              f"{'Hs m':>6}{'Tp s':>6}{'rao kW':>10}{'sweep kW':>10}{'rel. diff':>11}"]
    for h, t in RAO_CELLS:
        power, _ = rao_power(h, t)
        sweep = fd.data["mean_power"][hs.index(h), tp.index(t)]
        lines.append(f"{h:>6g}{t:>6g}{power / 1e3:>10.3f}{sweep / 1e3:>10.3f}{power / sweep - 1:>11.1e}")
    lines += ["", "3. time domain with quadratic drag over the frequency domain (no drag): TD/FD - 1",
              f"{'Hs / Tp':>8}" + "".join(f"{t:>8g}" for t in tp)]
    ratio = td.data["mean_power"] / fd.data["mean_power"] - 1
    rel_se = td.data["mean_power_std"] / np.sqrt(td.data["seeds_done"]) / td.data["mean_power"]
    for r, h in enumerate(hs):
        lines.append(f"{h:>8g}" + "".join(f"{x:>+8.1%}" for x in ratio[r]))
    lines.append(f"standard error of the time-domain cells over the seeds: median {np.median(rel_se):.1%}, "
                 f"largest {np.max(rel_se):.1%}")
    write_report(lines, a.out)


if __name__ == "__main__":
    main()
