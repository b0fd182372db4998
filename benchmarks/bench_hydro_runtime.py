"""Hydro step cost: the numba path of the Python hydro model against the compiled runtime, side by side.

The measurement drives, per scene (cylinder, hinge barge, F3OF DT3, 9N9LA), the Python model's step-time path
(``HydroModel.outputs``: the numba pass; ``HydroModel.affine``: numpy) and the runtime made from the same preparation
through the same input histories at the scene's macro step, alternating in one process: microseconds per macro step
(wall and CPU), medians and ratios, with and without the linearised interface. That Python path retired after
revision :data:`REVISION`; this script runs that revision's ``benchmarks/bench_hydro_runtime.py`` (which measured
both) against the current compiled library (:func:`common.run_with_current_library`) with the arguments given
(``--runs``, ``--out``). Not a timed assertion anywhere: the load is in the report's header and footer.

    python benchmarks/bench_hydro_runtime.py --out benchmarks/results/hydro_runtime.txt   (about 3 minutes)
"""

from __future__ import annotations

import sys

from common import run_with_current_library

REVISION = "3005162"  # the last revision with the numba/numpy hydro path

if __name__ == "__main__":
    sys.exit(run_with_current_library(REVISION, "bench_hydro_runtime.py", sys.argv[1:]))
