"""The mesh checks' overlap search, before and after its vectorisation, side by side in one process.

Hulls: closed boxes 10 x 10 x 5 m centred on the waterline, each face cut into n x n squares of two triangles
(the wetted part has 6 n^2 triangles: its bottom and four half sides), with every panel coplanar with its
neighbours on a face (the case that made the earlier search slow: a Python loop clipped every touching pair). The
earlier implementation (``hydro_fmu/meshes.py`` at git revision REF, default ``main``) and this tree's are run
alternately, ``--repeat`` times each; medians and their ratio. The earlier search is skipped above
``--old-limit`` wetted panels (minutes). Also: ``check_mesh`` in full on each hull, and the refusal of a
two-million-triangle STL file by its header alone (``hydro_fmu.meshes.check_face_count``).

    python benchmarks/bench_mesh_checks.py --out benchmarks/results/mesh_checks.txt
"""

from __future__ import annotations

import argparse
import importlib.util
import statistics
import struct
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from common import ROOT, report_header, write_report

from hydro_fmu import meshes  # noqa: E402
from tests.test_hostile_meshes import box  # noqa: E402 - the tests' hull


def old_module(ref: str) -> object:
    """``hydro_fmu/meshes.py`` of revision ``ref``, imported as a module of the current package (its relative
    imports resolve to this tree's ``hydro_fmu``, which the overlap search does not use)."""
    source = subprocess.run(["git", "show", f"{ref}:hydro_fmu/meshes.py"], cwd=ROOT, capture_output=True, text=True,
                            check=True).stdout
    path = Path(tempfile.mkdtemp()) / "meshes_old.py"
    path.write_text(source)
    spec = importlib.util.spec_from_file_location("hydro_fmu.meshes_old", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def seconds(call, repeat: int) -> list[float]:  # noqa: ANN001
    out = []
    for _ in range(repeat):
        start = time.perf_counter()
        call()
        out.append(time.perf_counter() - start)
    return out


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--ref", default="main")
    parser.add_argument("--sizes", default="10,20,40,100", help="n of the n x n squares per box face")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--old-limit", type=int, default=10_000)
    parser.add_argument("--out")
    args = parser.parse_args()
    old = old_module(args.ref)
    lines = report_header("bench_mesh_checks.py", f"; earlier search from {args.ref}")
    lines.append(f"{'wetted panels':>14}{'earlier (s)':>14}{'now (s)':>10}{'ratio':>9}{'check_mesh (s)':>16}  pairs")
    for n in (int(x) for x in args.sizes.split(",")):
        hull = box(n)
        wet = hull.immersed_part()
        new_times, old_times = [], []
        for _ in range(args.repeat):  # alternating, so that the load of the machine weighs on both alike
            new_times += seconds(lambda wet=wet: meshes.overlapping_coplanar_pairs(wet), 1)
            if wet.n_faces <= args.old_limit:
                old_times += seconds(lambda wet=wet: old.overlapping_coplanar_pairs(wet), 1)
        found = len(meshes.overlapping_coplanar_pairs(wet))
        if old_times:
            assert len(old.overlapping_coplanar_pairs(wet)) == found
        check = statistics.median(seconds(lambda hull=hull: meshes.check_mesh(hull, "box", (0, 0, -1)),
                                          args.repeat))
        now = statistics.median(new_times)
        before = statistics.median(old_times) if old_times else float("nan")
        lines.append(f"{wet.n_faces:>14}{before:>14.3f}{now:>10.3f}{before / now:>9.1f}{check:>16.3f}  {found}")
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "two_million.stl"
        with open(path, "wb") as f:
            f.write(b"\0" * 80 + struct.pack("<I", 2_000_000))
            f.truncate(84 + 50 * 2_000_000)
        start = time.perf_counter()
        try:
            meshes.check_face_count(path)
        except meshes.HydroDatabaseError as exc:
            refused = f"refused in {1e3 * (time.perf_counter() - start):.2f} ms: {str(exc)[:90]}..."
        lines.append(f"two-million-triangle binary STL (100 MB): {refused}")
    lines.append(f"# load average at the end {__import__('common').load()}; numpy {np.__version__}")
    write_report(lines, args.out)


if __name__ == "__main__":
    main()
