"""Runs an unpacked SSP in libcosim (libcosimpy) and prints `time x` of the component `body` after each step.

Run with `python -I` (isolated: no PYTHONPATH, no user site, not our package): the process imports libcosimpy only,
and says on stderr whether numpy, scipy or our hydro package were loaded (they must not be).

    python -I run_libcosim_ssp.py FOLDER STEPS STEP
"""

import sys

from libcosimpy.CosimExecution import CosimExecution
from libcosimpy.CosimObserver import CosimObserver

folder, steps, step = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
execution = CosimExecution.from_ssp_file(folder)
observer = CosimObserver.create_last_value()
execution.add_observer(observer)
index = execution.slave_index_from_instance_name("body")
reference = {v.name.decode(): v.reference for v in execution.slave_variables(index)}["x"]
for k in range(steps):
    execution.step(1)
    print(f"@ {(k + 1) * step!r} {observer.last_real_values(index, [reference])[0]!r}")
loaded = [name for name in ("numpy", "scipy", "hydro_fmu", "fmu_base") if name in sys.modules]
print(f"loaded: {' '.join(loaded) or 'none'}", file=sys.stderr)
