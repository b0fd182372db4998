"""A small native one-body heave FMU (native/fmi/heave_body: an example of a user's own multibody model, no Python
inside) and an SSP of it with the native hydro FMU, for the third-party host tests (tests/test_native_hydro_fmu.py).
"""

from __future__ import annotations

import tempfile
import zipfile
from pathlib import Path

from hydro_fmu.native_fmu import NATIVE, compile_binary, fmi_headers

MODEL_IDENTIFIER = "wec_heave_body"
TOKEN = "{5e1b7c3a-0d2f-4c61-9a0e-7d1f3b2a9c01}"  # native/fmi/heave_body/config.h


def _layout() -> dict[str, Path]:
    files = {"cosimulation.h": NATIVE / "fmi" / "cosimulation.h",
             "config.h": NATIVE / "fmi" / "heave_body" / "config.h"}
    for name in ("fmi2Functions.h", "fmi2FunctionTypes.h", "fmi2TypesPlatform.h"):
        files[name] = fmi_headers() / name
    files["fmi/cosimulation.c"] = NATIVE / "fmi" / "cosimulation.c"
    files["fmi/fmi2Functions.c"] = NATIVE / "fmi" / "fmi2Functions.c"
    files["fmi/model.c"] = NATIVE / "fmi" / "heave_body" / "model.c"
    return files


def model_description(mass: float, added_mass: float, damping: float, step: float, stop: float) -> str:
    def par(name, vr, value, unit, text):
        return (f'    <ScalarVariable name="{name}" valueReference="{vr}" causality="parameter" variability="fixed" '
                f'initial="exact" description="{text}"><Real unit="{unit}" start="{value!r}"/></ScalarVariable>')

    def inp(name, vr, text):
        return (f'    <ScalarVariable name="{name}" valueReference="{vr}" causality="input" variability="continuous" '
                f'description="{text}"><Real start="0.0"/></ScalarVariable>')

    def out(name, vr, unit, text):
        return (f'    <ScalarVariable name="{name}" valueReference="{vr}" causality="output" '
                f'variability="continuous" description="{text}"><Real unit="{unit}"/></ScalarVariable>')

    mass, added_mass, damping = float(mass), float(added_mass), float(damping)
    variables = [par("mass", 1, mass, "kg", "body mass"),
                 par("A_inf", 2, added_mass, "kg", "infinite-frequency added mass"),
                 par("pto_damping", 3, damping, "N.s/m", "linear PTO damping"),
                 inp("F0", 10, "linearised hydro force at zero motion"), inp("F0_rate", 11, "its rate"),
                 inp("dF_dx", 12, "its derivative in x"), inp("dF_dv", 13, "its derivative in v"),
                 out("x", 20, "m", "heave displacement"), out("v", 21, "m/s", "heave velocity"),
                 out("pto_power", 22, "W", "power absorbed by the PTO")]
    units = {"kg": 'kg="1"', "N.s/m": 'kg="1" s="-1"', "m": 'm="1"', "m/s": 'm="1" s="-1"',
             "W": 'kg="1" m="2" s="-3"'}
    return "\n".join([
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<fmiModelDescription fmiVersion="2.0" modelName="heave_body" guid="{TOKEN}" '
        'description="one-body heave integrator (trapezoidal rule on the linearised hydro force)" '
        'generationTool="wec-cosim tests" variableNamingConvention="flat" numberOfEventIndicators="0">',
        f'  <CoSimulation modelIdentifier="{MODEL_IDENTIFIER}" canHandleVariableCommunicationStepSize="true" '
        'canGetAndSetFMUstate="true" canSerializeFMUstate="true"/>',
        '  <UnitDefinitions>', *[f'    <Unit name="{u}"><BaseUnit {b}/></Unit>' for u, b in units.items()],
        '  </UnitDefinitions>',
        f'  <DefaultExperiment startTime="0.0" stopTime="{stop!r}" stepSize="{step!r}"/>',
        '  <ModelVariables>', *variables, '  </ModelVariables>',
        '  <ModelStructure>', '    <Outputs>', *[f'      <Unknown index="{i}" dependencies=""/>' for i in (8, 9, 10)],
        '    </Outputs>', '    <InitialUnknowns>',
        *[f'      <Unknown index="{i}" dependencies=""/>' for i in (8, 9, 10)],
        '    </InitialUnknowns>', '  </ModelStructure>', '</fmiModelDescription>', ''])


def build_heave_body_fmu(path: Path, mass: float, added_mass: float, damping: float, step: float,
                         stop: float) -> Path:
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        compile_binary(_layout(), root / "binaries" / "linux64" / f"{MODEL_IDENTIFIER}.so")
        (root / "modelDescription.xml").write_text(model_description(mass, added_mass, damping, step, stop))
        (root / "resources").mkdir()
        values = f"{float(mass)!r} {float(added_mass)!r} {float(damping)!r}\n"
        (root / "resources" / "parameters.txt").write_text(values)
        with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
            for f in sorted(root.rglob("*")):
                if f.is_file():
                    z.write(f, f.relative_to(root).as_posix())
    return path


def write_ssp(path: Path, hydro_fmu: Path, body_fmu: Path, body: str, dof: int, label: int, step: float,
              stop: float) -> Path:
    """An SSP: the hydro FMU and the heave body, coupled by the linearised force interface, with OMSimulator's
    fixed-step master annotation and OSP's fixed-step algorithm (libcosim)."""
    hydro_in = [("x", f"{body}.x[{dof}]"), ("v", f"{body}.v[{dof}]")]
    hydro_out = [(f"{body}.F0[{dof}]", "F0"), (f"{body}.F0_rate[{dof}]", "F0_rate"),
                 (f"dF_dx[{label},{label}]", "dF_dx"), (f"dF_dv[{label},{label}]", "dF_dv")]

    def connectors(items):
        return "\n".join(f'          <ssd:Connector name="{n}" kind="{k}"><ssc:Real/></ssd:Connector>'
                         for n, k in items)

    hydro_conn = connectors([(h, "input") for _, h in hydro_in] + [(h, "output") for h, _ in hydro_out])
    body_conn = connectors([(b, "input") for _, b in hydro_out] + [(b, "output") for b, _ in hydro_in])
    links = [("body", b, "hydro", h) for b, h in hydro_in] + [("hydro", h, "body", b) for h, b in hydro_out]
    connections = "\n".join(f'      <ssd:Connection startElement="{a}" startConnector="{b}" endElement="{c}" '
                            f'endConnector="{d}"/>' for a, b, c, d in links)
    ssd = f'''<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon"
  xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription"
  xmlns:oms="https://raw.githubusercontent.com/OpenModelica/OMSimulator/master/schema/oms.xsd"
  xmlns:osp="http://opensimulationplatform.com/SSP/OSPAnnotations"
  name="native_cylinder" version="1.0">
  <ssd:System name="root">
    <ssd:Elements>
      <ssd:Component name="hydro" type="application/x-fmu-sharedlibrary" source="resources/hydro.fmu">
        <ssd:Connectors>
{hydro_conn}
        </ssd:Connectors>
      </ssd:Component>
      <ssd:Component name="body" type="application/x-fmu-sharedlibrary" source="resources/body.fmu">
        <ssd:Connectors>
{body_conn}
        </ssd:Connectors>
      </ssd:Component>
    </ssd:Elements>
    <ssd:Connections>
{connections}
    </ssd:Connections>
    <ssd:Annotations>
      <ssc:Annotation type="org.openmodelica">
        <oms:Annotations>
          <oms:SimulationInformation>
            <oms:FixedStepMaster description="oms-ma" stepSize="{step!r}"/>
          </oms:SimulationInformation>
        </oms:Annotations>
      </ssc:Annotation>
    </ssd:Annotations>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0.0" stopTime="{stop!r}">
    <ssd:Annotations>
      <ssc:Annotation type="com.opensimulationplatform">
        <osp:Algorithm><osp:FixedStepAlgorithm baseStepSize="{step!r}"/></osp:Algorithm>
      </ssc:Annotation>
    </ssd:Annotations>
  </ssd:DefaultExperiment>
</ssd:SystemStructureDescription>
'''
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("SystemStructure.ssd", ssd)
        z.write(hydro_fmu, "resources/hydro.fmu")
        z.write(body_fmu, "resources/body.fmu")
    return path
