"""Port check of the compiled hydrodynamics runtime against the numba/numpy hydro path it replaced.

The check compares, side by side on the same input histories over 100 s of every bundled scenario with
hydrodynamics and variants of what none uses, the Python model's step-time path (``HydroModel.outputs``: the numba
pass; ``HydroModel.affine``: numpy) with the runtime made from the same preparation: force rows, linearised outputs,
work and elevation, relative differences (acceptance <= 1e-12). That Python path retired after revision
:data:`REVISION`, where the check was run (``benchmarks/results/hydro_port_check.txt``: 2.5e-14 on the bundled
scenarios). This script runs that revision's check again against the current runtime: it extracts the revision's
packages, scenarios and benchmarks into a temporary folder, puts the current compiled library (``fmu_base/_wecrt.so``)
beside its ``fmu_base`` (the revision's binding calls only functions the library still has, with the same
signatures, and writes the same data format) and runs its ``benchmarks/hydro_port_check.py`` there with the arguments
given (``--only``, ``--duration``, ``--out``).

    python benchmarks/hydro_port_check.py --out benchmarks/results/hydro_port_check.txt   (about 25 minutes)
"""

from __future__ import annotations

import sys

from common import run_with_current_library

REVISION = "3005162"  # the last revision with the numba/numpy hydro path

if __name__ == "__main__":
    sys.exit(run_with_current_library(REVISION, "hydro_port_check.py", sys.argv[1:]))
