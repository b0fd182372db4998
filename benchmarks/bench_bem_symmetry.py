"""Capytaine on full against half meshes (``hydro.bem_symmetry = "xOz"``): cost per frequency and agreement.

The two barges of seed 003's hinge barge (``scenarios/hinge_barge.toml``) at a chosen panel size, solved
by :func:`hydro_fmu.bem.compute_database` without and with the mirror symmetry about y = 0, each over two
and over ``2 + extra`` frequencies (a database needs two at least) around 7.85 rad/s. The marginal cost
per frequency (difference of the two runs over ``extra``) excludes the fixed cost (meshing, lids, the
infinite-frequency solve, the Green function's set-up), which single-frequency timings mix in.
Agreement: largest difference of A and B between the two, relative to the largest entry (the meshes
differ by the split row of panels on y = 0 and the lids: a discretisation difference, not round-off).
Run from the repository root:

    python benchmarks/bench_bem_symmetry.py [--panel 0.03] [--extra 4] [--out benchmarks/results/bem_symmetry.txt]
"""

from __future__ import annotations

import argparse
import dataclasses
import platform
import sys
import time
from pathlib import Path

import numpy as np
from common import write_report

from hydro_fmu.bem import compute_database
from orchestrator.scenario import load_scenario
from orchestrator.scene.database import bem_inputs

ROOT = Path(__file__).resolve().parent.parent


def timed(bodies, settings) -> tuple[float, object]:
    start = time.perf_counter()
    hdb = compute_database(bodies, settings)
    return time.perf_counter() - start, hdb


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--panel", type=float, default=0.03, help="panel size (m)")
    parser.add_argument("--extra", type=int, default=4, help="frequencies added to the two-frequency run")
    parser.add_argument("--out", default=None)
    args = parser.parse_args(argv)

    bodies, settings = bem_inputs(load_scenario(ROOT / "scenarios" / "hinge_barge.toml"))
    bodies = [dataclasses.replace(b, geometry=dataclasses.replace(b.geometry, panel_size=args.panel))
              for b in bodies]
    many = tuple(round(7.85 + 0.05 * k, 4) for k in range(args.extra + 2))
    two = many[:2]
    rows, results = [], {}
    for symmetry in ("none", "xOz"):
        t1, _ = timed(bodies, dataclasses.replace(settings, omega=two, symmetry=symmetry))
        tn, hdb = timed(bodies, dataclasses.replace(settings, omega=many, symmetry=symmetry))
        results[symmetry] = hdb
        rows.append((symmetry, hdb.source.split("(")[-1].rstrip(")"), t1, tn, (tn - t1) / args.extra))
    full, half = results["none"], results["xOz"]
    diff = {name: float(np.abs(getattr(half, name) - getattr(full, name)).max() / np.abs(getattr(full, name)).max())
            for name in ("added_mass", "radiation_damping")}
    lines = [
        f"# command: python benchmarks/bench_bem_symmetry.py --panel {args.panel} --extra {args.extra}"
        + (f" --out {args.out}" if args.out else ""),
        f"# python {sys.version.split()[0]}, numpy {np.__version__}, {platform.machine()}; hinge barge, "
        f"panel {args.panel} m, frequencies {many[0]}-{many[-1]} rad/s",
        f"{'symmetry':>8}  {'mesh':<55} {'2 freqs s':>9} {f'{len(many)} freqs s':>10} {'s/freq':>7}",
    ]
    lines += [f"{s:>8}  {m:<55} {a:9.1f} {b:10.1f} {c:7.1f}" for s, m, a, b, c in rows]
    lines.append(f"# marginal cost per frequency, full / half: {rows[0][4] / rows[1][4]:.2f}; "
                 f"two-frequency run: {rows[0][2] / rows[1][2]:.2f}")
    lines.append("# largest difference half - full, relative to the largest entry: "
                 + ", ".join(f"{k} {v:.2e}" for k, v in diff.items()))
    write_report(lines, args.out)


if __name__ == "__main__":
    main()
