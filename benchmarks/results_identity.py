"""Are two source trees' runs of every bundled scenario bit-identical?

For a restructuring that must not change behaviour (moves and splits of modules), run every bundled scenario
with the command line of one tree, hash every dataset of each results file (dtype, shape and bytes) and keep its
attributes; then compare two such records. Attributes that record the run rather than its physics (wall time,
dates, versions, the command line) are listed apart from the data.

    python benchmarks/results_identity.py record --tree /path/to/old/checkout --out old.json
    python benchmarks/results_identity.py record --tree . --out new.json
    python benchmarks/results_identity.py compare old.json new.json

``record`` runs ``wec-cosim run`` of the tree given (its own packages first on ``sys.path``) in a subprocess per
scenario, so the installed copy of the project is not the one measured. ``--set`` items apply to every scenario
(for example ``--set simulation.duration=20``).
"""

from __future__ import annotations

import argparse
import ast
import hashlib
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parent.parent
# Attributes that record the run (its wall time, when and where it ran), not what it computed.
RUN_ATTRIBUTES = ("wall_time", "fmus", "created", "finished", "python", "versions", "command", "host", "started",
                  "setup_time", "stepping_time", "revision")

# The command-line entry of a tree: today's package, else the one before the layout of issue 28.
ENTRY = """
import sys
try:
    from wec_cosim.cli import main
except ImportError:
    from orchestrator.cli import main
import orchestrator
print("tree:", orchestrator.__file__, file=sys.stderr)
sys.exit(main())
"""


def record(tree: Path, out: Path, scenarios: list[Path], overrides: list[str]) -> None:
    tree = tree.resolve()
    env = dict(os.environ, PYTHONPATH=str(tree), OPENBLAS_NUM_THREADS="1")
    records: dict[str, dict] = {}
    with tempfile.TemporaryDirectory(prefix="wec_identity_") as tmp:
        for scenario in scenarios:
            h5 = Path(tmp) / f"{scenario.stem}.h5"
            cmd = [sys.executable, "-c", ENTRY, "run", str(scenario.resolve()), "--out", str(h5), "--quiet"]
            for item in overrides:
                cmd += ["--set", item]
            started = time.perf_counter()
            proc = subprocess.run(cmd, cwd=tree, env=env, capture_output=True, text=True)
            wall = time.perf_counter() - started
            entry = {"exit": proc.returncode, "wall": round(wall, 1)}
            used = [line for line in proc.stderr.splitlines() if line.startswith("tree:")]
            entry["tree"] = used[0][6:] if used else "?"
            if proc.returncode == 0 and h5.is_file():
                entry.update(_file_record(h5))
            else:
                entry["error"] = (proc.stderr or proc.stdout)[-2000:]
            records[scenario.stem] = entry
            print(f"{scenario.stem:24s} exit {proc.returncode} {wall:7.1f} s "
                  f"{len(entry.get('datasets', {}))} datasets ({entry['tree']})", flush=True)
    out.write_text(json.dumps(records, indent=1, sort_keys=True))


def _file_record(path: Path) -> dict:
    datasets: dict[str, str] = {}
    attributes: dict[str, str] = {}

    def visit(name: str, obj: object) -> None:
        for key, value in obj.attrs.items():
            attributes[f"{name}@{key}"] = _text(value)
        if isinstance(obj, h5py.Dataset):
            data = obj[()]
            h = hashlib.sha256(f"{obj.dtype}{obj.shape}".encode())
            h.update(np.ascontiguousarray(data).tobytes() if isinstance(data, np.ndarray) else repr(data).encode())
            datasets[name] = h.hexdigest()

    with h5py.File(path, "r") as f:
        for key, value in f.attrs.items():
            attributes[f"/@{key}"] = _text(value)
        f.visititems(visit)
    return {"datasets": datasets, "attributes": attributes}


def _text(value: object) -> str:
    if isinstance(value, np.ndarray):
        return hashlib.sha256(value.tobytes()).hexdigest() if value.dtype != object else repr(value.tolist())
    if isinstance(value, bytes):
        return value.decode(errors="replace")
    return repr(value)


def _normalised(attributes: dict[str, str]) -> dict[str, str]:
    """Attributes with the checkout's path replaced by ``<tree>`` (two trees run their own copies of the scenario
    files) and the FMU build keys of ``settings`` moved to an attribute of their own (``fmus``: content hashes of
    the FMUs' sources, which change by design when a module moves)."""
    scenario_file = attributes.get("/@scenario_file", "''").strip("'")
    tree = str(Path(scenario_file).parent.parent)
    out = {k: v.replace(tree, "<tree>") for k, v in attributes.items()}
    if "/@settings" in out:
        settings = json.loads(ast.literal_eval(out["/@settings"]))
        out["/@fmus"] = repr(settings.pop("fmus", None))
        out["/@settings"] = repr(json.dumps(settings, sort_keys=True))
    return out


def compare(a_path: Path, b_path: Path) -> int:
    a, b = json.loads(a_path.read_text()), json.loads(b_path.read_text())
    failures = 0
    for name in sorted(set(a) | set(b)):
        ra, rb = a.get(name), b.get(name)
        if ra is None or rb is None:
            print(f"{name}: only in {'first' if rb is None else 'second'} record")
            failures += 1
            continue
        if ra["exit"] != rb["exit"]:
            print(f"{name}: exit {ra['exit']} vs {rb['exit']}")
            failures += 1
            continue
        if ra["exit"] != 0:
            same = ra.get("error", "").splitlines()[-1:] == rb.get("error", "").splitlines()[-1:]
            print(f"{name}: both failed ({'same' if same else 'different'} last line): "
                  f"{ra.get('error', '').splitlines()[-1:]}")
            failures += 0 if same else 1
            continue
        da, db = ra["datasets"], rb["datasets"]
        differ = sorted(k for k in set(da) | set(db) if da.get(k) != db.get(k))
        attr_a, attr_b = _normalised(ra["attributes"]), _normalised(rb["attributes"])
        attr_differ = sorted(k for k in set(attr_a) | set(attr_b) if attr_a.get(k) != attr_b.get(k))
        physics = [k for k in attr_differ if k.split("@")[-1] not in RUN_ATTRIBUTES]
        run_only = [k for k in attr_differ if k.split("@")[-1] in RUN_ATTRIBUTES]
        verdict = "identical" if not differ and not physics else "DIFFERENT"
        failures += verdict != "identical"
        print(f"{name:24s} {verdict}: {len(da)} datasets, {len(differ)} differ; attributes differing: "
              f"{physics or 'none'} (run records: {', '.join(k.split('@')[-1] for k in run_only) or 'none'})")
        for k in differ[:10]:
            print(f"    dataset {k}")
    print(f"{failures} scenario(s) differ" if failures else "every scenario identical")
    return 1 if failures else 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    rec = sub.add_parser("record", help="run every bundled scenario of a tree and record hashes")
    rec.add_argument("--tree", type=Path, default=ROOT)
    rec.add_argument("--out", type=Path, required=True)
    rec.add_argument("--set", action="append", default=[], dest="overrides")
    rec.add_argument("scenarios", nargs="*", type=Path)
    cmp_ = sub.add_parser("compare", help="compare two records")
    cmp_.add_argument("first", type=Path)
    cmp_.add_argument("second", type=Path)
    args = parser.parse_args()
    if args.command == "record":
        scenarios = args.scenarios or sorted((ROOT / "scenarios").glob("*.toml"))
        record(args.tree, args.out, scenarios, args.overrides)
        return 0
    return compare(args.first, args.second)


if __name__ == "__main__":
    raise SystemExit(main())
