"""Make ``rm3.h5``, the RM3 scenarios' hydrodynamic database, from Capytaine's solve of their geometry.

    python scenarios/data/rm3/make_database.py

1. ``wec-cosim hydro scenarios/rm3_regular.toml`` solved the bodies' geometry (the file in
   ``scenarios/hydro_cache/`` whose name carries the hash of the geometry and the frequency grid;
   computed again here if it is missing: about 10 CPU minutes).
2. Frequencies above 2.5 rad/s are dropped: there the float's heave damping turns negative (-2.8e4 N s/m
   at 3.1 rad/s against a peak of 6e5), the 0.2 m heave plate being meshed with 1 m panels. The
   scenarios continue B above 2.5 rad/s with ``hydro.damping_tail`` and cut the irregular sea there.
3. A and B are made symmetric and B positive semi-definite on the scenarios' degrees of freedom
   (surge, heave, pitch of both bodies; ``hydro_fmu.hdb_repair``); the changes are printed and
   recorded in ``docs/scenarios.md``.
"""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
sys.path.insert(0, str(ROOT))

import dataclasses  # noqa: E402

import numpy as np  # noqa: E402

from hydro_fmu.bemio import write_bemio  # noqa: E402
from hydro_fmu.hdb_repair import reciprocal_passive, truncated  # noqa: E402
from orchestrator.scenario import load_scenario  # noqa: E402
from orchestrator.scene.database import bem_inputs  # noqa: E402

OMEGA_MAX = 2.5


def main() -> None:
    from hydro_fmu.bem import cached_database

    scenario = load_scenario(ROOT / "scenarios" / "rm3_regular.toml")
    bodies, settings = bem_inputs(scenario)
    raw, path, computed = cached_database(bodies, settings, ROOT / "scenarios" / "hydro_cache")
    print(f"{'computed' if computed else 'cached'} Capytaine database {path.relative_to(ROOT)}: {raw.source}")
    planar = np.array([0, 2, 4, 6, 8, 10])  # surge, heave, pitch of both bodies: what the scenarios use
    raw = dataclasses.replace(raw, source=raw.source.replace(f"{ROOT}/", ""))  # no machine paths in the file
    hdb, report = reciprocal_passive(truncated(raw, OMEGA_MAX), planar)
    for key, value in report.items():
        print(f"  largest change, {key.replace('_', ' ')}: {100 * value:.3g} % of sqrt(max |M_ii| max |M_jj|)")
    target = write_bemio(hdb, HERE / "rm3.h5", code=hdb.source)
    print(f"wrote {target.relative_to(ROOT)} ({len(hdb.omega)} frequencies {hdb.omega[0]:g}..{hdb.omega[-1]:g} rad/s)")


if __name__ == "__main__":
    main()
