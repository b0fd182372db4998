"""F3OF database: mesh convergence of A, B and the excitation at a few frequencies, three resolutions.

The scenarios' database (``scenarios/f3of_*.toml``) is solved on the repaired meshes
``scenarios/data/f3of/*_repaired<SUFFIX>.obj``; this script solves the same three-body problem
(same settings, half meshes) on the other resolutions at a handful of frequencies and reports, per
resolution and frequency, the largest difference of A, B and X on the scenes' degrees of freedom
(surge, heave, pitch of the three bodies) against the finest mesh, each entry scaled like the
database check (s_ij = sqrt(s_i s_j), s_i the largest |X_ii| over the frequencies). Databases are
cached in ``scenarios/hydro_cache`` (the coarse ones are a few tens of kB).

Run (BEM cost per frequency about 1 : 4 : 16 for the three resolutions; the finest only on request):

    python benchmarks/bench_f3of_mesh.py --out benchmarks/results/f3of_mesh.txt      # original and _x2
    python benchmarks/bench_f3of_mesh.py --only "" _x2 _x4                            # all three
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import platform
import time
from pathlib import Path

import numpy as np
from common import write_report

from hydro_fmu.bem import cached_database
from orchestrator.scenario import load_scenario
from orchestrator.scene.database import bem_inputs

ROOT = Path(__file__).resolve().parent.parent
SCENARIO = ROOT / "scenarios" / "f3of_dt3.toml"
OMEGA = (0.2, 0.4, 0.6, 0.8, 1.0, 1.25, 1.5, 2.0, 2.5)  # rad/s: periods 31-2.5 s
RESOLUTIONS = {"": "original panels (repaired)", "_x2": "each panel halved", "_x4": "each panel quartered"}
DOFS = [6 * b + d for b in range(3) for d in (0, 2, 4)]  # surge, heave, pitch of base, flap1, flap2


def database(suffix: str, log=print):
    """The three-body database on the meshes of resolution ``suffix`` at OMEGA, and its wall time (s)."""
    scenario = load_scenario(SCENARIO)
    bodies, settings = bem_inputs(scenario)
    bodies = [dataclasses.replace(b, geometry=dataclasses.replace(
        b.geometry, mesh_file=b.geometry.mesh_file.replace("_repaired_x4.obj", f"_repaired{suffix}.obj")
        .replace("_repaired_x2.obj", f"_repaired{suffix}.obj").replace("_repaired.obj", f"_repaired{suffix}.obj")))
        for b in bodies]
    settings = dataclasses.replace(settings, omega=OMEGA)
    start = time.perf_counter()
    hdb, path, computed = cached_database(bodies, settings, ROOT / "scenarios" / "hydro_cache", log=log)
    return hdb, path, (time.perf_counter() - start) if computed else float("nan")


def scaled(values: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """(Nw, n, n) on DOFS -> entries divided by sqrt(s_i s_j), s_i the largest |reference_ii| over omega."""
    v = values[:, DOFS][:, :, DOFS]
    s = np.abs(np.einsum("wii->wi", reference[:, DOFS][:, :, DOFS])).max(axis=0)
    return v / np.sqrt(np.outer(s, s))[None]


def richardson(coarse: np.ndarray, middle: np.ndarray) -> list[str]:
    """Observed order and the middle mesh's error from three resolutions (panel count 1 : 2 : 4, so the panel
    size h goes as 1 : 2^-1/2 : 1/2). With e = C h^p and D the difference against the finest mesh,
    D_coarse / D_middle = 2^(p/2) + 1, and the middle mesh's own error is D_middle / (1 - 2^(-p/2)).
    ``coarse``, ``middle``: (Nw, 3) differences of A, B, X per frequency. Returns report lines."""
    ratio = np.median(coarse / middle, axis=0)
    order = 2 * np.log2(np.maximum(ratio - 1, 1e-12))
    error = middle.max(axis=0) / (1 - 2.0 ** (-order / 2))
    return [f"Richardson over the three resolutions (h ~ panel count^-1/2): median ratio of the differences "
            f"orig/_x2 A {ratio[0]:.2f}, B {ratio[1]:.2f}, X {ratio[2]:.2f} -> observed order in h "
            f"A {order[0]:.2f}, B {order[1]:.2f}, X {order[2]:.2f}",
            f"estimated error of the _x2 mesh (the scenarios' database) against the converged answer, largest over "
            f"omega: A {error[0]:.3f}, B {error[1]:.3f}, X {error[2]:.3f} (of the check scales); _x4's: "
            f"A {error[0] * 2 ** (-order[0] / 2):.3f}, B {error[1] * 2 ** (-order[1] / 2):.3f}, "
            f"X {error[2] * 2 ** (-order[2] / 2):.3f}"]


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", nargs="*", help="resolution suffixes to compute ('' '_x2' '_x4')")
    parser.add_argument("--out")
    a = parser.parse_args(argv)
    lines = [f"# command: python benchmarks/bench_f3of_mesh.py{' --only ' + ' '.join(a.only) if a.only else ''}",
             f"# python {platform.python_version()}, {os.cpu_count()} cores, load average at start "
             f"{' '.join(f'{x:.2f}' for x in os.getloadavg())}"]
    results = {}
    for suffix, what in RESOLUTIONS.items():
        if (a.only is None and suffix == "_x4") or (a.only is not None and suffix not in a.only):
            continue  # the finest only on request: 16 times the original's cost per frequency
        hdb, path, wall = database(suffix, log=lambda m: None)
        results[suffix] = hdb
        lines.append(f"{suffix or '(none)':<8} {what:<28} {hdb.source}; {path.name}; BEM wall time "
                     + (f"{wall:.0f} s" if wall == wall else "cached"))
    if len(results) > 1:
        finest = results[list(results)[-1]]
        lines.append("largest difference against the finest mesh computed, on surge, heave, pitch of the three bodies, "
                     "scaled as the database check scales (A, B) or by the largest |X| per DOF (X)")
        asym = [float(np.max(np.abs(scaled(h.radiation_damping, h.radiation_damping)
                                    - scaled(h.radiation_damping, h.radiation_damping).transpose(0, 2, 1))))
                for h in results.values()]
        lines.append("largest asymmetry of B (the check's measure, 5 % allowed): "
                     + ", ".join(f"{s or 'orig'} {100 * v:.1f} %" for s, v in zip(results, asym, strict=True)))
        lines.append(f"{'omega':>7} " + " ".join(f"{(s or 'orig') + ' ' + q:>10}" for s in list(results)[:-1]
                                                for q in ("A", "B", "X")))
        ref_a = scaled(finest.added_mass, finest.added_mass)
        ref_b = scaled(finest.radiation_damping, finest.radiation_damping)
        x_ref = finest.excitation[0][:, DOFS]
        sx = np.abs(x_ref).max(axis=0)
        diff = {s: np.array([[np.abs(scaled(results[s].added_mass, finest.added_mass)[k] - ref_a[k]).max(),
                               np.abs(scaled(results[s].radiation_damping, finest.radiation_damping)[k]
                                      - ref_b[k]).max(),
                               (np.abs(results[s].excitation[0][k, DOFS] - x_ref[k]) / sx).max()]
                              for k in range(len(OMEGA))]) for s in list(results)[:-1]}
        for k, w in enumerate(OMEGA):
            lines.append(f"{w:7.2f} " + " ".join(f"{diff[s][k, q]:10.4f}" for s in diff for q in range(3)))
        if list(results) == list(RESOLUTIONS):
            lines += richardson(diff[""], diff["_x2"])
    lines.append(f"# load average at end {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    write_report(lines, a.out)


if __name__ == "__main__":
    main()
