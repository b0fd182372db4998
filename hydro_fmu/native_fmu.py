"""The native hydrodynamics FMU: the compiled runtime behind FMI 2.0 co-simulation, with no Python inside.

:func:`build_native_hydro_fmu` writes an FMU from a prepared :class:`hydro_fmu.model.HydroModel`:

* ``resources/hydro.wecrt``: the runtime's input (:mod:`hydro_fmu.runtime_input`), plus the FMU's own arrays
  ``fmu.token`` (the GUID the binary checks) and ``fmu.constants`` (the values fixed at build time);
* ``binaries/linux64/wec_hydro_native.so``: ``native/src`` (the runtime) and ``native/fmi`` (the FMI glue, after the
  Modelica Reference-FMUs) compiled with the system C compiler (``CC``, default ``cc``); the library depends on the C
  library and libm only;
* ``sources/``: the same C sources with ``<SourceFiles>`` in the model description, so that a tool on another
  platform compiles its own binary (fmpy: ``fmpy.build.build_platform_binary``);
* ``modelDescription.xml``: the variables of :mod:`hydro_fmu.slave` by the same names (``body.x[i]``, ``body.v[i]``
  inputs; ``body.F[i]`` and its parts, ``wave.elevation``, ``energy.*_work``, the linearised interface ``F0``,
  ``F0_rate``, ``dF_dx[k,l]``, ``dF_dv[k,l]`` outputs for every pair; ``A_inf[k,l]`` calculated parameters), with
  output dependencies and ``fmi2GetDirectionalDerivative`` of the total force ``F`` with respect to ``x`` and ``v``.

What is fixed at build time: the scene (bodies, DOFs, methods), the sea (its components, the ramp) and the
radiation step; the sea's parameters are published as constants (``wave.height`` ...). Value references follow
``native/fmi/hydro/config.h``. Communication steps must be whole multiples of the radiation step for the
convolution (any step for the state space); a step the runtime refuses ends the run with ``fmi2Error`` and its reason
in the log.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import tempfile
import uuid
import zipfile
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING
from xml.sax.saxutils import quoteattr

import numpy as np

from fmu_base import runtime_data

from .runtime_input import KIND, runtime_arrays

if TYPE_CHECKING:
    from .model import HydroModel
    from .sea import SeaSpec

ROOT = Path(__file__).resolve().parent.parent
NATIVE = ROOT / "native"
MODEL_IDENTIFIER = "wec_hydro_native"
RESOURCE = "hydro.wecrt"
CFLAGS = ["-std=c11", "-O2", "-Wall", "-Wextra", "-fPIC", "-fvisibility=hidden"]
LDFLAGS = ["-shared", "-Wl,-Bsymbolic", "-lm"]

# value references (native/fmi/hydro/config.h)
VR_ELEVATION, VR_WORK, VR_CONSTANT = 1, 2, 100
VR_X, VR_V, VR_F, VR_F0, VR_F0_RATE = 1000, 2000, 3000, 8000, 9000
VR_ROW = {"F": 3000, "F_exc": 4000, "F_rad": 5000, "F_hs": 6000, "F_visc": 7000}
VR_DF_DX, VR_DF_DV, VR_A_INF = 100000, 200000, 300000
VR3 = {"x": 11, "v": 12, "F": 13, "F_exc": 14, "F_rad": 15, "F_hs": 16, "F_visc": 17, "F0": 18, "F0_rate": 19,
       "dF_dx": 20, "dF_dv": 21, "A_inf": 22, "energy.work": 23}
WORK_NAMES = ("energy.excitation_work", "energy.radiation_work", "energy.hydrostatic_work", "energy.viscous_work")
DOF_UNITS = ("m", "m", "m", "rad", "rad", "rad")
VEL_UNITS = ("m/s", "m/s", "m/s", "rad/s", "rad/s", "rad/s")
FORCE_UNITS = ("N", "N", "N", "N.m", "N.m", "N.m")
UNITS = {  # unit: (kg, m, s, rad) exponents
    "m": (0, 1, 0, 0), "rad": (0, 0, 0, 1), "m/s": (0, 1, -1, 0), "rad/s": (0, 0, -1, 1), "N": (1, 1, -2, 0),
    "N.m": (1, 2, -2, 0), "J": (1, 2, -2, 0), "s": (0, 0, 1, 0), "1": (0, 0, 0, 0),
}
ROW_TEXT = {"F": "total hydrodynamic force", "F_exc": "excitation force", "F_rad": "radiation force (memory only)",
            "F_hs": "hydrostatic force", "F_visc": "viscous force"}


class NativeBuildError(RuntimeError):
    """The native FMU could not be compiled (no compiler, or the compiler failed: its output is in the message)."""


@dataclass(frozen=True)
class FixedValue:
    """A value fixed at build time, published as a constant of the FMU (readable, not settable)."""

    name: str
    value: float
    unit: str = "1"
    description: str = ""


def sea_constants(spec: SeaSpec) -> list[FixedValue]:
    """The sea's parameters of ``spec``, as constants of the native FMU (they are fixed at build time: the sea's
    components and the excitation are computed offline)."""
    kind = spec.kind
    out = [FixedValue("wave.kind", float(("still", "regular", "irregular", "elevation").index(kind)), "1",
                      "sea fixed at build time: 0 still, 1 regular, 2 irregular (spectrum), 3 elevation record")]
    if kind == "regular":
        out += [FixedValue("wave.height", spec.height, "m", "regular wave height, crest to trough"),
                FixedValue("wave.period", spec.period, "s", "regular wave period"),
                FixedValue("wave.phase", spec.phase, "rad", "regular wave phase at the origin")]
    elif kind == "irregular":
        out += [FixedValue("wave.hs", spec.hs, "m", f"significant wave height ({spec.spectrum} spectrum)"),
                FixedValue("wave.tp", spec.tp, "s", "peak period"),
                FixedValue("wave.gamma", spec.gamma, "1", "JONSWAP peak enhancement factor"),
                FixedValue("wave.seed", float(spec.seed), "1", "seed of the random phases")]
    out += [FixedValue("wave.heading", spec.heading, "rad", "main direction of propagation (0 = towards +x)"),
            FixedValue("wave.ramp_time", spec.ramp_time, "s", "half-cosine start-up ramp of the excitation")]
    return out


def compiler() -> str:
    """The C compiler (``CC`` or ``cc``); :class:`NativeBuildError` with what to install if there is none."""
    cc = os.environ.get("CC", "cc")
    if shutil.which(cc.split()[0]) is None:
        raise NativeBuildError(f"native hydro FMU: no C compiler ({cc!r} is not on PATH); install one (Debian/Ubuntu: "
                               "apt-get install gcc) or set CC")
    return cc


def fmi_headers() -> Path:
    """The FMI 2.0 and 3.0 headers (the ones fmpy ships, from the FMI standard's repository)."""
    import fmpy

    return Path(fmpy.__file__).parent / "c-code"


def source_layout() -> dict[str, Path]:
    """The FMU's ``sources/`` (relative name -> file in this repository): headers at the top (the one include
    directory a tool adds), the runtime under ``src/``, the FMI glue under ``fmi/``."""
    files: dict[str, Path] = {}
    for h in sorted((NATIVE / "include").glob("*.h")):
        files[h.name] = h
    files["cosimulation.h"] = NATIVE / "fmi" / "cosimulation.h"
    files["config.h"] = NATIVE / "fmi" / "hydro" / "config.h"
    for name in ("fmi2Functions.h", "fmi2FunctionTypes.h", "fmi2TypesPlatform.h", "fmi3Functions.h",
                 "fmi3FunctionTypes.h", "fmi3PlatformTypes.h"):
        files[name] = fmi_headers() / name
    for sub in ("common", "hydro"):
        for f in sorted((NATIVE / "src" / sub).iterdir()):
            if f.suffix in (".c", ".h"):
                files[f"src/{sub}/{f.name}"] = f
    files["fmi/cosimulation.c"] = NATIVE / "fmi" / "cosimulation.c"
    files["fmi/fmi2Functions.c"] = NATIVE / "fmi" / "fmi2Functions.c"
    files["fmi/fmi3Functions.c"] = NATIVE / "fmi" / "fmi3Functions.c"
    files["fmi/model.c"] = NATIVE / "fmi" / "hydro" / "model.c"
    return files


def c_sources(layout: dict[str, Path]) -> list[str]:
    return [name for name in layout if name.endswith(".c")]


def _cache_dir() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "wec-cosim" / "native-fmu"


def compile_binary(layout: dict[str, Path], target: Path) -> Path:
    """Compiles the sources into ``target`` (a shared library); the result is cached by the sources' and flags'
    hash (the binary is the same for every scene: the model is in the resources)."""
    cc = compiler()
    digest = hashlib.sha256(" ".join([cc, *CFLAGS, *LDFLAGS]).encode())
    for name in sorted(layout):
        digest.update(name.encode() + b"\0" + layout[name].read_bytes())
    cached = _cache_dir() / f"{MODEL_IDENTIFIER}-{digest.hexdigest()[:24]}.so"
    if not cached.exists():
        with tempfile.TemporaryDirectory() as tmp:
            src = Path(tmp) / "sources"
            _copy_layout(layout, src)
            out = Path(tmp) / "out.so"
            command = [*cc.split(), *CFLAGS, f"-I{src}", *[str(src / c) for c in c_sources(layout)], "-o", str(out),
                       *LDFLAGS]
            result = subprocess.run(command, capture_output=True, text=True)
            if result.returncode != 0:
                raise NativeBuildError(f"native hydro FMU: the C compiler failed ({' '.join(command[:3])} ...):\n"
                                       f"{result.stderr[-4000:]}")
            cached.parent.mkdir(parents=True, exist_ok=True)
            partial = cached.with_suffix(f".{os.getpid()}.tmp")
            shutil.copyfile(out, partial)
            os.replace(partial, cached)
    target.parent.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(cached, target)
    return target


def _copy_layout(layout: dict[str, Path], root: Path) -> None:
    for name, path in layout.items():
        dest = root / name
        dest.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(path, dest)


@dataclass
class _Variable:
    name: str
    vr: int
    causality: str
    variability: str
    description: str
    unit: str | None = None
    initial: str | None = None
    start: float | None = None
    dependencies: list[str] | None = None  # names; None: every input


def _labels(model: HydroModel) -> tuple[list[str], list[int], list[int]]:
    """Per selected DOF: body name, DOF (0..5) and scene number 6 b + d + 1."""
    bodies, dofs, numbers = [], [], []
    for b, ds in enumerate(model.dofs):
        for d in ds:
            bodies.append(model.bodies[b])
            dofs.append(d)
            numbers.append(6 * b + d + 1)
    return bodies, dofs, numbers


def _variables(model: HydroModel, arrays: dict, constants: list[FixedValue]) -> list[_Variable]:
    bodies, dofs, numbers = _labels(model)
    n = len(dofs)
    xs = [f"{b}.x[{d + 1}]" for b, d in zip(bodies, dofs, strict=True)]
    vs = [f"{b}.v[{d + 1}]" for b, d in zip(bodies, dofs, strict=True)]
    out = [_Variable("wave.elevation", VR_ELEVATION, "output", "continuous",
                     "incident wave elevation at the origin", "m", dependencies=[])]
    for k, name in enumerate(WORK_NAMES):
        out.append(_Variable(name, VR_WORK + k, "output", "continuous",
                             f"work of the {name[7:-5]} force on the bodies since the start", "J"))
    for k, c in enumerate(constants):
        out.append(_Variable(c.name, VR_CONSTANT + k, "local", "constant", c.description + " (fixed at build time)",
                             c.unit, "exact", c.value))
    for i in range(n):
        out.append(_Variable(xs[i], VR_X + i, "input", "continuous", "displacement from equilibrium",
                             DOF_UNITS[dofs[i]], start=0.0))
    for i in range(n):
        out.append(_Variable(vs[i], VR_V + i, "input", "continuous", "velocity", VEL_UNITS[dofs[i]], start=0.0))
    nonlinear_fk = bool(arrays["froude_krylov.nonlinear"])
    rows = {"F": None,
            "F_exc": (None if nonlinear_fk else []) if (arrays["excitation.method"] or nonlinear_fk) else False,
            "F_rad": vs if arrays["radiation.method"] else False,
            "F_hs": xs if arrays["hydrostatics.method"] else False,
            "F_visc": vs if "viscous.linear" in arrays else False}
    for row, deps in rows.items():
        if deps is False:
            continue
        for i in range(n):
            out.append(_Variable(f"{bodies[i]}.{row}[{dofs[i] + 1}]", VR_ROW[row] + i, "output", "continuous",
                                 ROW_TEXT[row], FORCE_UNITS[dofs[i]], dependencies=deps))
    for i in range(n):
        out.append(_Variable(f"{bodies[i]}.F0[{dofs[i] + 1}]", VR_F0 + i, "output", "continuous",
                             "linearised force: value at zero displacement and velocity (F - dF_dx x - dF_dv v)",
                             FORCE_UNITS[dofs[i]]))
    for i in range(n):
        out.append(_Variable(f"{bodies[i]}.F0_rate[{dofs[i] + 1}]", VR_F0_RATE + i, "output", "continuous",
                             "linearised force: time rate of F0 over the next step"))
    for prefix, base, text in (("dF_dx", VR_DF_DX, "displacement"), ("dF_dv", VR_DF_DV, "velocity")):
        for k in range(n):
            for m in range(n):
                out.append(_Variable(f"{prefix}[{numbers[k]},{numbers[m]}]", base + k * n + m, "output",
                                     "continuous", f"linearised force: derivative with respect to the {text}"))
    for k in range(n):
        for m in range(n):
            out.append(_Variable(f"A_inf[{numbers[k]},{numbers[m]}]", VR_A_INF + k * n + m, "calculatedParameter",
                                 "fixed", "infinite-frequency added mass (for the multibody mass matrix)",
                                 initial="calculated", dependencies=[]))
    return out


def _units_and_experiment(units: list[str], experiment: tuple[float, float, float] | None) -> list[str]:
    """The unit definitions' entries and their end, and the default experiment (FMI 2.0 and 3.0 alike)."""
    lines = []
    for u in units:
        kg, m, s, rad = UNITS[u]
        attrs = " ".join(f'{k}="{e}"' for k, e in (("kg", kg), ("m", m), ("s", s), ("rad", rad)) if e)
        lines.append(f'    <Unit name="{u}"><BaseUnit {attrs}/></Unit>' if attrs else f'    <Unit name="{u}"/>')
    lines.append('  </UnitDefinitions>')
    if experiment is not None:
        start, stop, step = experiment
        lines.append(f'  <DefaultExperiment startTime="{start!r}" stopTime="{stop!r}" stepSize="{step!r}"/>')
    return lines


def _model_description(model: HydroModel, arrays: dict, constants: list[FixedValue], guid: str, name: str,
                       description: str, experiment: tuple[float, float, float] | None,
                       sources: list[str]) -> str:
    variables = _variables(model, arrays, constants)
    index = {v.name: k + 1 for k, v in enumerate(variables)}
    units = sorted({v.unit for v in variables if v.unit})
    lines = ['<?xml version="1.0" encoding="UTF-8"?>',
             f'<fmiModelDescription fmiVersion="2.0" modelName={quoteattr(name)} guid="{guid}" '
             f'description={quoteattr(description)} generationTool="wec-cosim (native hydro FMU)" '
             'variableNamingConvention="structured" numberOfEventIndicators="0">',
             f'  <CoSimulation modelIdentifier="{MODEL_IDENTIFIER}" canHandleVariableCommunicationStepSize="true" '
             'canGetAndSetFMUstate="true" canSerializeFMUstate="true" providesDirectionalDerivative="true" '
             'canNotUseMemoryManagementFunctions="true">',
             '    <SourceFiles>']
    lines += [f'      <File name="{s}"/>' for s in sources]
    lines += ['    </SourceFiles>', '  </CoSimulation>', '  <UnitDefinitions>']
    lines += _units_and_experiment(units, experiment)
    lines.append('  <ModelVariables>')
    for v in variables:
        attrs = f'name={quoteattr(v.name)} valueReference="{v.vr}" causality="{v.causality}" ' \
                f'variability="{v.variability}"'
        if v.initial:
            attrs += f' initial="{v.initial}"'
        attrs += f' description={quoteattr(v.description)}'
        real = ' unit="' + v.unit + '"' if v.unit else ""
        if v.start is not None:
            real += f' start="{float(v.start)!r}"'
        lines.append(f'    <ScalarVariable {attrs}><Real{real}/></ScalarVariable>')
    lines.append('  </ModelVariables>')
    lines.append('  <ModelStructure>')

    def unknown(v: _Variable) -> str:
        deps = "" if v.dependencies is None else \
            f' dependencies="{" ".join(str(index[d]) for d in v.dependencies)}"'
        return f'      <Unknown index="{index[v.name]}"{deps}/>'

    outputs = [v for v in variables if v.causality == "output"]
    lines += ['    <Outputs>', *[unknown(v) for v in outputs], '    </Outputs>']
    initial = [v for v in variables if v.causality == "output" or v.initial == "calculated"]
    lines += ['    <InitialUnknowns>', *[unknown(v) for v in sorted(initial, key=lambda v: index[v.name])],
              '    </InitialUnknowns>']
    lines += ['  </ModelStructure>', '</fmiModelDescription>', '']
    return "\n".join(lines)


def _common_unit(units: list[str]) -> str | None:
    return units[0] if units and all(u == units[0] for u in units) else None


def _model_description3(model: HydroModel, arrays: dict, constants: list[FixedValue], token: str, name: str,
                        description: str, experiment: tuple[float, float, float] | None) -> str:
    """FMI 3.0 model description: arrays x, v, F, its parts, F0, F0_rate (n), dF_dx, dF_dv, A_inf (n x n)."""
    bodies, dofs, _ = _labels(model)
    n = len(dofs)
    order = ", ".join(f"{b} {('surge', 'sway', 'heave', 'roll', 'pitch', 'yaw')[d]}" for b, d in zip(bodies, dofs,
                                                                                                       strict=True))
    nonlinear_fk = bool(arrays["froude_krylov.nonlinear"])
    force_unit = _common_unit([FORCE_UNITS[d] for d in dofs])
    rows = {"F": None,
            "F_exc": ([] if not nonlinear_fk else None) if (arrays["excitation.method"] or nonlinear_fk) else False,
            "F_rad": [VR3["v"]] if arrays["radiation.method"] else False,
            "F_hs": [VR3["x"]] if arrays["hydrostatics.method"] else False,
            "F_visc": [VR3["v"]] if "viscous.linear" in arrays else False}
    # (name, vr, causality, variability, description, unit, dims, start, dependencies or None = all inputs)
    variables: list[tuple] = [
        ("wave.elevation", VR_ELEVATION, "output", "continuous", "incident wave elevation at the origin", "m", (),
         None, []),
        ("energy.work", VR3["energy.work"], "output", "continuous", "work of the excitation, radiation, hydrostatic "
         "and viscous forces on the bodies since the start", "J", (4,), None, None)]
    for k, c in enumerate(constants):
        variables.append((c.name, VR_CONSTANT + k, "local", "constant", c.description + " (fixed at build time)",
                          c.unit, (), c.value, None))
    variables.append(("x", VR3["x"], "input", "continuous", f"displacements from equilibrium ({order})",
                      _common_unit([DOF_UNITS[d] for d in dofs]), (n,), 0.0, None))
    variables.append(("v", VR3["v"], "input", "continuous", f"velocities ({order})",
                      _common_unit([VEL_UNITS[d] for d in dofs]), (n,), 0.0, None))
    for row, deps in rows.items():
        if deps is not False:
            variables.append((row, VR3[row], "output", "continuous", ROW_TEXT[row], force_unit, (n,), None, deps))
    variables += [
        ("F0", VR3["F0"], "output", "continuous", "linearised force: value at zero displacement and velocity",
         force_unit, (n,), None, None),
        ("F0_rate", VR3["F0_rate"], "output", "continuous", "linearised force: time rate of F0 over the next step",
         None, (n,), None, None),
        ("dF_dx", VR3["dF_dx"], "output", "continuous", "linearised force: derivative with respect to x (row: "
         "force, column: displacement)", None, (n, n), None, None),
        ("dF_dv", VR3["dF_dv"], "output", "continuous", "linearised force: derivative with respect to v", None,
         (n, n), None, None),
        ("A_inf", VR3["A_inf"], "calculatedParameter", "fixed", "infinite-frequency added mass (for the multibody "
         "mass matrix)", None, (n, n), None, [])]
    units = sorted({v[5] for v in variables if v[5]} | {"s"})
    lines = ['<?xml version="1.0" encoding="UTF-8"?>',
             f'<fmiModelDescription fmiVersion="3.0" modelName={quoteattr(name)} instantiationToken="{token}" '
             f'description={quoteattr(description)} generationTool="wec-cosim (native hydro FMU)" '
             'variableNamingConvention="structured">',
             f'  <CoSimulation modelIdentifier="{MODEL_IDENTIFIER}" canHandleVariableCommunicationStepSize="true" '
             'canGetAndSetFMUState="true" canSerializeFMUState="true" providesDirectionalDerivatives="true" '
             'hasEventMode="false" canNotUseMemoryManagementFunctions="true"/>', '  <UnitDefinitions>']
    lines += _units_and_experiment(units, experiment)
    lines += ['  <ModelVariables>', '    <Float64 name="time" valueReference="0" causality="independent" '
              'variability="continuous" description="simulation time" unit="s"/>']
    for vname, vr, causality, variability, text, unit, dims, start, _ in variables:
        attrs = f'name={quoteattr(vname)} valueReference="{vr}" causality="{causality}" ' \
                f'variability="{variability}" description={quoteattr(text)}'
        if unit:
            attrs += f' unit="{unit}"'
        if start is not None:
            count = int(np.prod(dims)) if dims else 1
            attrs += ' start="' + " ".join([repr(float(start))] * count) + '"'
        if dims:
            inner = "".join(f'<Dimension start="{d}"/>' for d in dims)
            lines.append(f'    <Float64 {attrs}>{inner}</Float64>')
        else:
            lines.append(f'    <Float64 {attrs}/>')
    lines += ['  </ModelVariables>', '  <ModelStructure>']

    def unknown(tag: str, vr: int, deps: list[int] | None) -> str:
        if deps is None:
            deps = [VR3["x"], VR3["v"]]
        return f'    <{tag} valueReference="{vr}" dependencies="{" ".join(map(str, deps))}"/>' if deps else \
            f'    <{tag} valueReference="{vr}" dependencies=""/>'

    lines += [unknown("Output", v[1], v[8]) for v in variables if v[2] == "output"]
    lines += [unknown("InitialUnknown", v[1], v[8]) for v in variables if v[2] in ("output", "calculatedParameter")]
    lines += ['  </ModelStructure>', '</fmiModelDescription>', '']
    return "\n".join(lines)


def _build_description(sources: list[str]) -> str:
    files = "\n".join(f'      <SourceFile name="{s}"/>' for s in sources)
    return ('<?xml version="1.0" encoding="UTF-8"?>\n<fmiBuildDescription fmiVersion="3.0">\n'
            f'  <BuildConfiguration modelIdentifier="{MODEL_IDENTIFIER}">\n    <SourceFileSet language="C11">\n'
            f'{files}\n    </SourceFileSet>\n  </BuildConfiguration>\n</fmiBuildDescription>\n')


def runtime_file(model: HydroModel, token: str, constants: list[FixedValue]) -> bytes:
    """The FMU's ``resources/hydro.wecrt``: the runtime input of ``model`` with the build's token and constants."""
    arrays = dict(runtime_arrays(model))
    arrays["fmu.token"] = np.frombuffer(token.encode("ascii"), dtype=np.uint8)
    arrays["fmu.constants"] = np.array([c.value for c in constants], dtype=float)
    return runtime_data.write(KIND, arrays)


def build_native_hydro_fmu(model: HydroModel, path: str | os.PathLike, *, constants: list[FixedValue] = (),
                           name: str = "wec_hydro", description: str = "",
                           experiment: tuple[float, float, float] | None = None, fmi_version: int = 2) -> Path:
    """Writes the native co-simulation hydro FMU of ``model`` to ``path`` (module docstring), FMI ``fmi_version`` 2
    or 3; returns the path. ``constants``: values fixed at build time published as constants (e.g.
    :func:`sea_constants`); ``experiment``: the default experiment (start, stop, step; s). :class:`NativeBuildError`
    if the sources do not compile."""
    if fmi_version not in (2, 3):
        raise ValueError(f"native hydro FMU: FMI version {fmi_version!r} (2 or 3)")
    path = Path(path)
    constants = list(constants)
    arrays = runtime_arrays(model)
    token = "{" + str(uuid.UUID(bytes=hashlib.sha256(
        runtime_data.write(KIND, arrays) + repr([(c.name, c.value) for c in constants]).encode()).digest()[:16])) + "}"
    data = runtime_file(model, token, constants)
    layout = source_layout()
    description = description or ("Hydrodynamic forces (Cummins equation) of " + ", ".join(model.bodies)
                                  + ": the wec-cosim compiled runtime, no Python needed")
    if fmi_version == 2:
        xml = _model_description(model, arrays, constants, token, name, description, experiment, c_sources(layout))
    else:
        xml = _model_description3(model, arrays, constants, token, name, description, experiment)
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        (root / "resources").mkdir()
        (root / "resources" / RESOURCE).write_bytes(data)
        (root / "modelDescription.xml").write_text(xml, encoding="utf-8")
        _copy_layout(layout, root / "sources")
        if fmi_version == 3:
            (root / "sources" / "buildDescription.xml").write_text(_build_description(c_sources(layout)))
        platform = "linux64" if fmi_version == 2 else "x86_64-linux"
        compile_binary(layout, root / "binaries" / platform / f"{MODEL_IDENTIFIER}.so")
        path.parent.mkdir(parents=True, exist_ok=True)
        with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
            for f in sorted(root.rglob("*")):
                if f.is_file():
                    z.write(f, f.relative_to(root).as_posix())
    return path
