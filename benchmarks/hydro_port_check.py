"""Port check of the compiled hydrodynamics runtime against the numba/numpy hydro path it replaced (issue 29).

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

import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from common import ROOT, revision_tree

from fmu_base import native

REVISION = "9b4783a"
PATHS = ["fmu_base", "hydro_fmu", "mbd_fmu", "plain_mbd_fmu", "orchestrator", "sweeps", "benchreport", "benchmarks",
         "scenarios"]


def main() -> None:
    args = list(sys.argv[1:])
    if "--out" in args:  # the output where the caller means it, not in the temporary tree
        i = args.index("--out") + 1
        args[i] = str(Path(args[i]).resolve())
    library = native.library_path()
    if library is None:
        native.library()  # raises with the message saying how to build it
    with tempfile.TemporaryDirectory(prefix="wec_port_check_") as tmp:
        tree = revision_tree(REVISION, Path(tmp), PATHS)
        shutil.copy(library, tree / "fmu_base" / library.name)
        proc = subprocess.run([sys.executable, str(tree / "benchmarks" / "hydro_port_check.py"), *args],
                              cwd=tree / "benchmarks")
    sys.exit(proc.returncode)


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT))
    main()
