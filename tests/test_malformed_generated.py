"""Generated malformed input: hundreds of invalid scenarios, files, options and paths through the CLI.

Every case must end with exit status 2 and one paragraph on stderr naming the file and the key (or
option) at fault: no traceback, no crash, no hang (each in-process case has a 120 s alarm), no exit
0 on invalid input. The generator is seeded (``SEED``), so CI runs the same cases every time.

* schema mutations: every scalar or array key of three bundled scenarios (cylinder, two floats, the
  hinge barge) given a value of the wrong type, NaN, or a value its check forbids (0 or -1 for a
  positive key, -1 for a non-negative one), plus unknown keys; a seeded sample of them;
* hand-written classes the issue lists and more: files that are not UTF-8 TOML, deep nesting, sizes
  that would exhaust memory, seeds, durations, wave periods outside the database, data files that
  are broken, output paths that cannot be written or would destroy a foreign file, names with path
  separators, control endpoints, CLI options, resume and plot on the wrong files.

Most cases run in-process through ``wec_cosim.cli.main`` (the console script's function); a
representative set runs in real subprocesses (FMU failures under fmpy, a write failure mid-run,
SIGINT), where a crash would show as a negative exit status. ``pytest -m slow`` runs every
generated schema mutation instead of the sample.
"""

from __future__ import annotations

import contextlib
import dataclasses
import io
import math
import os
import random
import resource
import signal
import subprocess
import sys
import time
import typing
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest

from orchestrator import scenario as scenario_module
from orchestrator.scenario.schema import non_negative, positive
from wec_cosim.cli import main

from .conftest import ROOT
from .toml_text import bundled, dumps

SEED = 17
SAMPLE = 170  # generated schema mutations in the default suite (all of them with -m slow)
TIMEOUT = 120  # s, a case that takes longer is a hang


@dataclass
class Case:
    """One invalid input: files to write, the command line, the fragments stderr must contain."""

    name: str
    argv: list[str]  # "{dir}" is replaced by the case's folder
    files: dict[str, Any] = field(default_factory=dict)  # name -> dict (TOML), str or bytes, or callable(path)
    expect: list[str] = field(default_factory=list)  # "{dir}" replaced as in argv


def _run_argv(scenario: str = "s.toml", command: str = "run") -> list[str]:
    if command == "run":
        return ["run", f"{{dir}}/{scenario}", "--quiet", "--out", "{dir}/out.h5"]
    if command in ("rao", "steady", "sweep"):
        return [command, f"{{dir}}/{scenario}", "--out", "{dir}/out.h5"]
    return [command, f"{{dir}}/{scenario}"]


# ------------------------------------------------------------------------------------- schema mutations
def _schema_fields() -> dict[str, dataclasses.Field]:
    """Key path pattern (list indices as [i]) -> dataclass field, over the whole scenario schema."""
    out: dict[str, dataclasses.Field] = {}

    def walk(cls: type, prefix: str) -> None:
        hints = typing.get_type_hints(cls)
        for f in dataclasses.fields(cls):
            if not f.init or f.name.startswith("_"):
                continue
            path = f"{prefix}.{f.name}" if prefix else f.name
            tp = hints[f.name]
            inner = [a for a in typing.get_args(tp) if a is not type(None)] or [tp]
            base = inner[0] if typing.get_origin(tp) in (typing.Union, type(int | None)) else tp
            if dataclasses.is_dataclass(base):
                walk(base, path)
            elif typing.get_origin(base) is list and dataclasses.is_dataclass(typing.get_args(base)[0]):
                walk(typing.get_args(base)[0], path + "[i]")
            else:
                out[path] = f
    walk(scenario_module.Scenario, "")
    return out


FIELDS = _schema_fields()


def _leaves(data: Any, path: str = "") -> list[tuple[str, Any]]:
    """(key path, value) of every scalar or plain array in a scenario dict."""
    out = []
    if isinstance(data, dict):
        for k, v in data.items():
            out += _leaves(v, f"{path}.{k}" if path else k)
    elif isinstance(data, list) and data and all(isinstance(x, dict) for x in data):
        for i, v in enumerate(data):
            out += _leaves(v, f"{path}[{i}]")
    else:
        out.append((path, data))
    return out


def _set(data: dict, path: str, value: Any) -> dict:
    import copy
    import re

    data = copy.deepcopy(data)
    parts = re.findall(r"[^.\[\]]+|\[\d+\]", path)
    node = data
    for p in parts[:-1]:
        node = node[int(p[1:-1])] if p.startswith("[") else node[p]
    node[parts[-1]] = value
    return data


def _mutations(path: str, value: Any) -> list[tuple[str, Any, str]]:
    """(label, bad value, expected fragment) for one key."""
    import re

    f = FIELDS.get(re.sub(r"\[\d+\]", "[i]", path))
    if f is None:
        return []
    check = f.metadata.get("check")
    out = []
    if isinstance(value, bool):
        out.append(("string for a boolean", "yes", "expected true or false"))
    elif isinstance(value, (int, float)):
        out.append(("string for a number", "many", "expected a"))
        if isinstance(value, float) or f.type in ("float", "float | None"):
            out.append(("nan", math.nan, "expected a finite number"))
        if check is positive:
            out.append(("zero for a positive key", 0, "must be positive"))
        if check in (positive, non_negative):
            out.append(("negative", -1, "must"))
    elif isinstance(value, str):
        out.append(("number for a string", 42, "expected a string"))
    elif isinstance(value, list):
        out.append(("number for an array", 3.5, "expected an array"))
        if value and isinstance(value[0], (int, float)) and not isinstance(value[0], bool):
            out.append(("string in an array", ["x"] * len(value), "expected a number"))
    elif isinstance(value, dict):
        out.append(("number for a table", 1.0, "expected a table"))
    return out


BASES = ("cylinder_regular", "two_floats", "hinge_barge")


def schema_cases() -> list[Case]:
    cases = []
    for base in BASES:
        data = bundled(base)
        for path, value in _leaves(data):
            if path.startswith("hydro.cache_dir") or path in ("name", "description"):
                continue
            for label, bad, fragment in _mutations(path, value):
                case_path = path.split("[", 1)[0] if isinstance(bad, dict) else path
                cases.append(Case(f"{base}: {path}: {label}", _run_argv(),
                                  {"s.toml": _set(data, path, bad)}, ["{dir}/s.toml", case_path, fragment]))
        for section in ("simulation", "waves", "hydro", "environment"):
            if section in data:
                bad = _set(data, f"{section}.bogus_key", 1.0)
                cases.append(Case(f"{base}: unknown key in [{section}]", _run_argv(), {"s.toml": bad},
                                  ["{dir}/s.toml", f"unknown key '{section}.bogus_key'"]))
    return cases


# ------------------------------------------------------------------------------------- hand-written cases
def _cyl(**sections: dict) -> dict:
    data = bundled("cylinder_regular")
    for section, values in sections.items():
        if values is None:
            data.pop(section, None)
        elif not isinstance(values, dict) or section == "bodies":
            data[section] = values
        else:
            data.setdefault(section, {}).update(values)
    return data


def _elevation(kind: str) -> dict:
    return _cyl(waves={"kind": "elevation", "elevation_file": f"eta.{kind}", "height": 0.0, "period": 0.0})


def _h5_without_datasets(path: Path) -> None:
    with h5py.File(path, "w") as f:
        f["time"] = np.arange(10.0)


def _sweep_file(path: Path) -> None:
    with h5py.File(path, "w") as f:
        f["values"] = np.arange(3.0)
        f["periods"] = np.arange(1.0, 4.0)
        f.attrs["parameter"] = "ptos.pto.damping"
        f.attrs["method"] = "frequency_domain"


def _foreign_h5(path: Path) -> None:
    with h5py.File(path, "w") as f:
        f["x"] = 1.0


def _nested(depth: int) -> str:
    return "x = " + "[" * depth + "]" * depth + "\n"


def hand_cases() -> list[Case]:  # noqa: PLR0915 - one line per case
    c: list[Case] = []
    s, run = "{dir}/s.toml", _run_argv()

    def add(name: str, files: dict, expect: list[str], argv: list[str] | None = None) -> None:
        c.append(Case(name, argv or run, files, expect))

    # files that are not UTF-8 TOML scenarios
    add("binary garbage", {"s.toml": bytes(range(256)) * 4}, [s, "not UTF-8"])
    add("Latin-1 text", {"s.toml": b'description = "\xe9t\xe9"\n' + dumps(_cyl()).encode()}, [s, "not UTF-8"])
    add("UTF-16 text", {"s.toml": dumps(_cyl()).encode("utf-16")}, [s, "UTF-16"])
    add("an HDF5 file as the scenario", {"s.toml": _foreign_h5}, [s, "HDF5"])
    add("an empty file", {"s.toml": ""}, [s, "simulation"])
    add("a NUL byte", {"s.toml": dumps(_cyl()) + "\x00"}, [s, "NUL"])
    add("20000 nested arrays", {"s.toml": _nested(20000)}, [s, "nested"])
    add("65 nested inline tables", {"s.toml": "x = " + "{a = " * 65 + "1" + "}" * 65 + "\n"}, [s, "nested"])
    add("a 5 MB file", {"s.toml": "# " + "x" * (5 * 1024 * 1024) + "\n"}, [s, "not a scenario"])
    add("a folder as the scenario", {"s.toml/x": ""}, [s, "directory"])
    add("a missing scenario", {}, [s, "does not exist"])
    add("not TOML", {"s.toml": "[simulation\nduration = 1"}, [s, "not valid TOML"])
    add("no bodies", {"s.toml": _cyl(bodies=None) | {"bodies": []}}, [s, "[[bodies]] is empty"])
    # sizes that would exhaust memory or time
    add("step 1e-12", {"s.toml": _cyl(simulation={"step": 1e-12, "duration": 200.0})}, [s, "simulation.step"])
    add("irf_duration 1e9", {"s.toml": _cyl(hydro={"irf_duration": 1e9})}, [s, "hydro.irf_duration"])
    add("irf_d_omega 1e-9", {"s.toml": _cyl(hydro={"irf_d_omega": 1e-9})}, [s, "hydro.irf_d_omega"])
    add("excitation irf 1e9", {"s.toml": _cyl(hydro={"excitation_irf_duration": 1e9})},
        [s, "hydro.excitation_irf_duration"])
    add("rao frequency step 1e-9", {"s.toml": _cyl(rao={"omega": {"start": 0.1, "stop": 4.0, "step": 1e-9}})},
        [s, "rao.omega"], ["rao", s, "--out", "{dir}/out.h5"])
    add("BEM frequency step 1e-6", {"s.toml": _cyl(hydro={"omega": {"start": 0.1, "stop": 4.0, "step": 1e-6}})},
        [s, "hydro.omega"])
    add("a million harmonics", {"s.toml": _cyl(steady={"harmonics": 1_000_000})}, [s, "steady.harmonics"],
        ["steady", s, "--out", "{dir}/out.h5"])
    add("1e9 wave components", {"s.toml": _cyl(waves={"kind": "irregular", "hs": 2.0, "tp": 7.0,
                                                      "discretisation": "equal_energy", "n_components": 10**9})},
        [s, "waves.n_components"])
    add("repeat period 1e9 s", {"s.toml": _cyl(waves={"kind": "irregular", "hs": 2.0, "tp": 7.0,
                                                      "repeat_period": 1e9})}, [s, "waves.repeat_period"])
    add("panel size 1e-4", {"s.toml": _set(_cyl(), "bodies[0].geometry.panel_size", 1e-4)}, [s, "panel_size"])
    add("radius 1e6 m", {"s.toml": _set(_cyl(), "bodies[0].geometry.radius", 1e6)}, [s, "panel_size"])
    million = {"waves": {"height": [1.0 + i for i in range(1000)]},
               "ptos": {"pto": {"damping": [1e3 * (i + 1) for i in range(1000)]}}}
    add("a million sweep points", {"s.toml": _cyl(sweep={"grid": million})},
        [s, "sweep.grid", "1000000 cases"], ["sweep", s, "--out", "{dir}/out.h5"])
    add("sweep with the keys of an earlier version", {"s.toml": _cyl(sweep={"parameter": "waves.height",
                                                                           "values": [1.0] * 200_001})},
        [s, "[sweep.grid]", "waves.height = [1.0, 1.0"], ["sweep", s, "--out", "{dir}/out.h5"])
    # seeds, durations, steps
    for seed in (2**31, 2**40, 2**63 - 1):
        add(f"seed {seed}", {"s.toml": _cyl(waves={"kind": "irregular", "hs": 2.0, "tp": 7.0, "seed": seed})},
            [s, "waves.seed"])
    add("seed -1", {"s.toml": _cyl(waves={"seed": -1})}, [s, "waves.seed"])
    for value, fragment in ((-1.0, "must be positive"), (0.0, "must be positive"), (math.nan, "finite"),
                            (math.inf, "finite"), (0.05, "longer than")):
        add(f"duration {value}", {"s.toml": _cyl(simulation={"duration": value})}, [s, "simulation.", fragment])
    for value, fragment in (("nan", "--duration"), ("inf", "--duration"), ("-1", "--duration"), ("0", "--duration"),
                            ("abc", "--duration"), ("1e12", "--duration")):
        add(f"--duration {value}", {"s.toml": _cyl()}, [fragment] if value in ("nan", "inf", "-1", "0", "abc")
            else [s, fragment], ["run", s, "--quiet", "--duration", value, "--out", "{dir}/out.h5"])
    for value in ("-3", "0", "x"):
        add(f"steady --harmonics {value}", {"s.toml": _cyl()}, ["--harmonics"],
            ["steady", s, "--harmonics", value, "--out", "{dir}/out.h5"])
    add("output_every 0", {"s.toml": _cyl(simulation={"output_every": 0})}, [s, "simulation.output_every"])
    add("checkpoint_every -1", {"s.toml": _cyl(simulation={"checkpoint_every": -1.0})},
        [s, "simulation.checkpoint_every"])
    add("extrapolation 3", {"s.toml": _cyl(simulation={"extrapolation": 3})}, [s, "simulation.extrapolation"])
    add("master 'best'", {"s.toml": _cyl(simulation={"master": "best"})}, [s, "simulation.master"])
    add("monolithic with adaptive", {"s.toml": _cyl(simulation={"master": "monolithic",
                                                                "adaptive": {"enabled": True}})},
        [s, "monolithic"])
    # wave periods outside the database's frequency range (0.04..4 rad/s)
    for period in (1000.0, 0.5):
        add(f"wave period {period} s", {"s.toml": _cyl(waves={"period": period})}, [s, "waves.period"])
    add("steady period 1000 s", {"s.toml": _cyl(steady={"periods": [1000.0]})}, [s, "steady.periods[0]"],
        ["steady", s, "--out", "{dir}/out.h5"])
    add("peak period 1000 s", {"s.toml": _cyl(waves={"kind": "irregular", "hs": 2.0, "tp": 1000.0})},
        [s, "waves.tp"])
    # data files the scenario names
    for name, text, fragment in (
            ("non-numeric", "t,eta\na,b\n", "not a number"), ("empty", "", "empty"),
            ("NaN", "t,eta\n0,0\n1,nan\n2,0\n3,0\n", "non-finite"), ("header only", "t,eta\n", "no data rows"),
            ("backwards", "t,eta\n3,0\n2,0\n1,0\n0,0\n", "increase"),
            ("wrong header", "a,b,c\n0,0,0\n", "does not name the time column"),
            ("ragged", "t,eta\n0,0\n1\n", "values, expected"),
            ("non-uniform", "t,eta\n0,0\n1,0\n3,0\n4,0\n", "uniform")):
        add(f"elevation file: {name}", {"s.toml": _elevation("csv"), "eta.csv": text},
            ["waves.elevation_file", "{dir}/eta.csv", fragment])
    add("elevation file: HDF5 without datasets", {"s.toml": _elevation("h5"), "eta.h5": _h5_without_datasets},
        ["waves.elevation_file", "{dir}/eta.h5", "missing dataset"])
    add("elevation file: text named .h5", {"s.toml": _elevation("h5"), "eta.h5": "t,eta\n0,0\n"},
        ["waves.elevation_file", "eta.h5"])
    add("elevation file: missing", {"s.toml": _elevation("csv")}, ["waves.elevation_file", "does not exist"])
    add("elevation file: binary", {"s.toml": _elevation("csv"), "eta.csv": bytes(range(256))},
        ["waves.elevation_file", "eta.csv"])
    spectrum = _cyl(waves={"kind": "irregular", "spectrum": "file", "spectrum_file": "S.csv"})
    for name, text in (("negative", "omega,S\n0.5,1\n1.0,-1\n"), ("decreasing", "omega,S\n1.0,1\n0.5,1\n"),
                       ("bad header", "w,S\n0.5,1\n1.0,1\n")):
        add(f"spectrum file: {name}", {"s.toml": spectrum, "S.csv": text}, ["waves.spectrum_file", "S.csv"])
    add("mesh file: garbage", {"s.toml": _set(_set(_cyl(hydro={"cache_dir": "{dir}/cache"}),
                                                   "bodies[0].geometry.shape", "mesh"),
                                              "bodies[0].geometry.mesh_file", "hull.stl"), "hull.stl": b"\x00\x01"},
        ["hull.stl"])
    add("database: a text file", {"s.toml": _cyl(hydro={"database": "db.h5"}), "db.h5": "not hdf5"}, ["db.h5"])
    add("database: HDF5 without coefficients", {"s.toml": _cyl(hydro={"database": "db.h5"}), "db.h5": _foreign_h5},
        ["db.h5"])
    add("cache_dir names a file", {"s.toml": _cyl(hydro={"cache_dir": "cache"}), "cache": "x"},
        [s, "hydro.cache_dir"])
    add("cache_dir under a file", {"s.toml": _cyl(hydro={"cache_dir": "cache/sub"}), "cache": "x"},
        [s, "hydro.cache_dir"])
    # names and output paths
    for name in ("../../x", "/tmp/abs", "a\u0000b", ".hidden", "a/b", "x" * 101, "-rf", "a b"):
        add(f"name {name[:12]!r}", {"s.toml": _cyl(name=name)}, [s, "name"])
    for out, fragment in (("{dir}", "is a folder"), ("{dir}/f.txt/out.h5", "is a file"), ("/dev/full", "not a regular"),
                          ("{dir}/" + "x" * 300 + ".h5", "too long"), ("{dir}/f.txt", "not an HDF5 file"),
                          ("", "empty path")):
        add(f"--out {out[-20:]!r}", {"s.toml": _cyl(), "f.txt": "precious data"}, ["--out", fragment],
            ["run", s, "--quiet", "--out", out])
    add("simulation.output is a text file", {"s.toml": _cyl(simulation={"output": "f.txt"}), "f.txt": "keep me"},
        ["simulation.output", "not an HDF5 file"], ["run", s, "--quiet"])
    add("simulation.output NUL", {"s.toml": _cyl(simulation={"output": "a\u0000b.h5"})}, ["simulation.output"],
        ["run", s, "--quiet"])
    add("rao --out a folder", {"s.toml": _cyl()}, ["--out", "is a folder"], ["rao", s, "--out", "{dir}"])
    add("steady --out under a file", {"s.toml": _cyl(), "f.txt": "x"}, ["--out", "is a file"],
        ["steady", s, "--out", "{dir}/f.txt/o.h5"])
    add("sweep --out a text file", {"s.toml": _cyl(), "f.txt": "x"}, ["--out", "not an HDF5"],
        ["sweep", s, "--out", "{dir}/f.txt"])
    add("export-ssp into a folder", {"s.toml": _cyl()}, ["--out", "is a folder"], ["export-ssp", s, "{dir}"])
    add("build-fmus --out a file", {"s.toml": _cyl(), "f.txt": "x"}, ["--out", "is a file"],
        ["build-fmus", s, "--out", "{dir}/f.txt"])
    # control
    ctl = {"mode": "lockstep"}
    add("control.endpoints = []", {"s.toml": _cyl(control=ctl | {"endpoints": []})}, [s, "control.endpoints"])
    for endpoint in ("nonsense", "tcp/127.0.0.1:99999", "tcp/:7447", "tcp/127.0.0.1"):
        add(f"control endpoint {endpoint!r}", {"s.toml": _cyl(control=ctl | {"endpoints": [endpoint]})},
            [s, "control.endpoints[0]"])
    add("zenoh_config missing", {"s.toml": _cyl(control=ctl | {"zenoh_config": "z.json5"})}, [s, "zenoh_config"])
    add("zenoh_config garbage", {"s.toml": _cyl(control=ctl | {"zenoh_config": "z.json5"}), "z.json5": "{{{"},
        [s, "zenoh_config"])
    add("control.run_id with a slash", {"s.toml": _cyl(control=ctl | {"run_id": "a/b"})}, [s, "control.run_id"])
    add("control period not a multiple", {"s.toml": _cyl(control=ctl | {"period": 0.15})}, [s, "control.period"])
    add("control limits reversed", {"s.toml": _cyl(control=ctl | {"damping_limits": [2.0, 1.0]})},
        [s, "control.damping_limits"])
    # resume and plot on the wrong files
    add("resume a missing file", {}, ["{dir}/r.h5", "does not exist"], ["resume", "{dir}/r.h5"])
    add("resume a scenario", {"s.toml": _cyl()}, [s, "not a wec-cosim results file"], ["resume", s])
    add("resume a foreign HDF5", {"r.h5": _foreign_h5}, ["{dir}/r.h5", "not a wec-cosim results file"],
        ["resume", "{dir}/r.h5"])
    add("resume a folder", {"r.h5/x": ""}, ["{dir}/r.h5"], ["resume", "{dir}/r.h5"])
    add("plot a sweep file", {"w.h5": _sweep_file}, ["{dir}/w.h5", "sweep file"], ["plot", "{dir}/w.h5"])
    add("plot a scenario", {"s.toml": _cyl()}, [s, "HDF5"], ["plot", s])
    add("plot a foreign HDF5", {"r.h5": _foreign_h5}, ["{dir}/r.h5"], ["plot", "{dir}/r.h5"])
    add("plot a missing file", {}, ["{dir}/r.h5", "does not exist"], ["plot", "{dir}/r.h5"])
    # multi-key checks
    add("PTO on an unknown body", {"s.toml": _set(_cyl(), "ptos[0].body", "buoy")}, [s, "ptos[0]", "buoy"])
    add("PTO on an inactive dof", {"s.toml": _set(_cyl(), "ptos[0].dof", "surge")}, [s, "ptos[0]", "surge"])
    add("two bodies of one name", {"s.toml": _cyl() | {"bodies": _cyl()["bodies"] * 2}}, [s, "used twice"])
    add("regular wave without height", {"s.toml": _cyl(waves={"height": 0.0})}, [s, "[waves]"])
    add("omega stop below start", {"s.toml": _cyl(hydro={"omega": {"start": 4.0, "stop": 1.0, "step": 0.1}})},
        [s, "hydro.omega"])
    add("rotations without inertia", {"s.toml": _set(_cyl(), "bodies[0].dofs", ["heave", "pitch"])},
        [s, "inertia"])
    add("steady with mass 1e308", {"s.toml": _set(_cyl(), "bodies[0].mass", 1e308)}, [s, "not finite"],
        ["steady", s, "--out", "{dir}/out.h5"])
    return c


def all_cases(sample: int | None) -> list[Case]:
    generated = schema_cases()
    if sample is not None and sample < len(generated):
        generated = random.Random(SEED).sample(generated, sample)
    return hand_cases() + generated


# ------------------------------------------------------------------------------------- running a case
def _materialise(case: Case, folder: Path) -> list[str]:
    for name, content in case.files.items():
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(content, dict):
            path.write_text(dumps(_fill(content, folder)))
        elif isinstance(content, bytes):
            path.write_bytes(content)
        elif isinstance(content, str):
            path.write_text(content)
        else:
            content(path)
    return [a.replace("{dir}", str(folder)) for a in case.argv]


def _fill(data: Any, folder: Path) -> Any:
    if isinstance(data, dict):
        return {k: _fill(v, folder) for k, v in data.items()}
    if isinstance(data, list):
        return [_fill(v, folder) for v in data]
    return data.replace("{dir}", str(folder)) if isinstance(data, str) else data


class _Hang(Exception):
    pass


def run_in_process(argv: list[str]) -> tuple[int, str]:
    """Exit status and stderr of ``wec-cosim ARGV`` run by the console script's function."""
    err, out = io.StringIO(), io.StringIO()

    def alarm(signum, frame):  # noqa: ANN001, ANN202
        raise _Hang(f"no answer within {TIMEOUT} s")

    old = signal.signal(signal.SIGALRM, alarm)
    signal.alarm(TIMEOUT)
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
            try:
                code = main(argv)
            except SystemExit as exc:  # argparse
                code = exc.code if isinstance(exc.code, int) else 2
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
    return code, err.getvalue()


def check(case: Case, code: int, stderr: str, folder: Path) -> None:
    assert code == 2, f"{case.name}: exit status {code}\n{stderr}"
    assert "Traceback" not in stderr, f"{case.name}: traceback\n{stderr}"
    lines = [line for line in stderr.splitlines() if line.strip()]
    assert len(lines) == 1, f"{case.name}: not one paragraph\n{stderr}"
    for fragment in case.expect:
        fragment = fragment.replace("{dir}", str(folder))
        assert fragment in stderr, f"{case.name}: {fragment!r} not in\n{stderr}"
    out = folder / "out.h5"
    if out.is_file():
        with h5py.File(out, "r", swmr=True) as f:
            status = f.attrs.get("status")
        assert status is None or str(status).startswith(("failed", "interrupted")), f"{case.name}: status {status}"


DEFAULT_CASES = all_cases(SAMPLE)


def test_the_generated_set_is_large_and_covers_every_class() -> None:
    assert len(DEFAULT_CASES) >= 200
    assert len(all_cases(None)) > len(DEFAULT_CASES)
    names = " ".join(c.name for c in DEFAULT_CASES)
    for word in ("UTF", "nested", "1e-12", "seed", "duration", "elevation file", "--out", "name", "control",
                 "resume", "plot", "cache_dir", "wave period", "nan", "negative", "unknown key", "mass 1e308"):
        assert word in names, word


@pytest.mark.parametrize("case", DEFAULT_CASES, ids=[c.name for c in DEFAULT_CASES])
def test_malformed_input_is_one_clean_error(tmp_path, case, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    argv = _materialise(case, tmp_path)
    start = time.monotonic()
    code, stderr = run_in_process(argv)
    assert time.monotonic() - start < TIMEOUT
    check(case, code, stderr, tmp_path)


@pytest.mark.slow
@pytest.mark.parametrize("case", [c for c in all_cases(None) if c not in DEFAULT_CASES],
                         ids=lambda c: c.name)
def test_every_generated_mutation_is_one_clean_error(tmp_path, case, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    code, stderr = run_in_process(_materialise(case, tmp_path))
    check(case, code, stderr, tmp_path)


# ------------------------------------------------------------------------------------- real processes
def cli(argv: list[str], *, limit_bytes: int | None = None, timeout: float = 600) -> subprocess.CompletedProcess:
    def limits() -> None:
        if limit_bytes is not None:
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # writes past the limit fail with EFBIG, as on a full disk
            resource.setrlimit(resource.RLIMIT_FSIZE, (limit_bytes, limit_bytes))

    return subprocess.run([sys.executable, "-m", "wec_cosim.cli", *argv], capture_output=True, text=True,
                          cwd=ROOT, timeout=timeout, preexec_fn=limits, env=os.environ.copy())


def test_a_failed_state_space_fit_is_the_fmus_own_message_under_fmpy_and_in_process(tmp_path) -> None:
    """The hinge barge's radiation cannot be fitted by a state space of order 1 at this tolerance: the
    hydro FMU raises in its initialisation. Through fmpy (a real process: a crash would be a negative
    status) and in-process the user reads the same message, exit 2, and the results file says failed."""
    data = bundled("two_floats")
    data["hydro"].update(radiation_method="state_space", state_space_tolerance=1e-4, state_space_max_order=1)
    data["simulation"]["duration"] = 1.0
    path = tmp_path / "s.toml"
    path.write_text(dumps(data))
    messages = []
    for extra in ([], ["--in-process"]):
        out = tmp_path / f"out{len(extra)}.h5"
        proc = cli(["run", str(path), "--quiet", "--out", str(out), *extra])
        assert proc.returncode == 2, proc.stderr
        assert "Traceback" not in proc.stderr and proc.stderr.count("\n") == 1, proc.stderr
        with h5py.File(out, "r", swmr=True) as f:
            assert f.attrs["status"].startswith("failed")
        messages.append(proc.stderr.split("exitInitializationMode failed: ", 1)[-1])
    assert "state-space realisation" in messages[0] and messages[0] == messages[1]


def test_a_write_failure_mid_run_keeps_the_rows_and_records_failed(tmp_path) -> None:
    """A file-size limit (RLIMIT_FSIZE, SIGXFSZ ignored: writes fail with EFBIG as on a full disk) stops the
    results file growing mid-run: one clean message, exit 2, the rows written before kept, status failed."""
    data = bundled("cylinder_regular")
    data["simulation"].update(duration=600.0, flush_seconds=0.05)
    path = tmp_path / "s.toml"
    path.write_text(dumps(data))
    assert cli(["build-fmus", str(path), "--out", str(tmp_path / "fmus")]).returncode == 0  # FMUs (~1 MB) cached
    out = tmp_path / "out.h5"
    # above the FMU's unpacked database (~140 kB), below the 6000 rows' ~1 MB
    proc = cli(["run", str(path), "--quiet", "--out", str(out)], limit_bytes=400_000)
    assert proc.returncode == 2, proc.stderr
    assert "Traceback" not in proc.stderr and proc.stderr.count("\n") == 1, proc.stderr
    assert str(out) in proc.stderr and "rows written before are kept" in proc.stderr
    with h5py.File(out, "r", swmr=True) as f:
        assert f.attrs["status"].startswith("failed: writing the results")
        n = len(f["time"])
        t = f["time"][()]
    assert 0 < n < 6001 and np.all(np.diff(t) > 0)


def test_sigint_leaves_an_interrupted_file_and_no_traceback(tmp_path) -> None:
    data = bundled("cylinder_regular")
    # long enough that the run cannot end before the signal, even when the file's first rows are seen late under
    # load (with 2000 s it once ended, status 0, before the SIGINT); it is interrupted after ~10 rows
    data["simulation"].update(duration=200_000.0, flush_seconds=0.05)
    path = tmp_path / "s.toml"
    path.write_text(dumps(data))
    out = tmp_path / "out.h5"
    proc = subprocess.Popen([sys.executable, "-m", "wec_cosim.cli", "run", str(path), "--quiet", "--out", str(out)],
                            cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline and proc.poll() is None:
        if out.is_file():
            try:
                with h5py.File(out, "r", swmr=True) as f:
                    if len(f["time"]) > 10:
                        break
            except (OSError, KeyError):
                pass
        time.sleep(0.1)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "Traceback" not in err and "interrupted" in err
    with h5py.File(out, "r", swmr=True) as f:
        assert f.attrs["status"] == "interrupted" and len(f["time"]) > 10
