"""SSP export: the scene's FMUs, connections and parameters as an SSP 1.0 archive.

``wec-cosim export-ssp SCENARIO OUT.ssp`` writes

* ``SystemStructure.ssd``: components ``hydro`` and ``mbd`` (sources ``resources/*.fmu``), a
  connector for every connected variable and bound parameter (with its ``ssc:Real`` type), the
  connections (motion mbd -> hydro; the linearised force interface hydro -> mbd: ``F0``,
  ``F0_rate``, ``dF_dx``, ``dF_dv``, see ``hydro_fmu.linearisation``), and the parameter bindings inline
  (``ssd:ParameterValues``): the infinite-frequency added mass ``A_inf[k,l]`` the multibody FMU
  must carry in its mass matrix (what our master copies from the hydro FMU's calculated parameters).
  ``ssd:DefaultExperiment`` holds the start and stop time and, as an OSP annotation
  (``osp:FixedStepAlgorithm baseStepSize``), the macro step: libcosim's SSP loader takes its
  algorithm from there (without it ``from_ssp_file`` without a step size crashed here). The system
  carries OMSimulator's fixed-step master annotation (``oms:FixedStepMaster stepSize`` under an
  ``org.openmodelica`` annotation): OMSimulator's command line aborts on an SSD without it;
* ``resources/parameters.ssv``: the same parameters with component-qualified names
  (``mbd.A_inf[3,3]``) for hosts that take a parameter set, such as fmpy's ``simulate_ssp``
  (``parameter_set=read_ssv(...)``);
* ``OspSystemStructure.xml``: the same system for libcosim's own configuration format
  (``CosimExecution.from_osp_config_file``), algorithm ``fixedStep``.

With ``native=True`` (``wec-cosim export-ssp --native``) the ``hydro`` component is the native hydro FMU
(:mod:`hydro_fmu.native_fmu`, FMI 2.0, compiled C, no Python in the host; the sea is fixed at build time) with the
same variable names; the multibody component stays the PythonFMU one.

The exported system is the added-mass mode (a) coupling; modes (b) and (c) need a master that
changes the force input and are not exportable. Generic hosts run a plain fixed-step Jacobi with
zero-order hold (see :class:`orchestrator.cosim.masters.SimpleJacobiMaster`): with the linearised
interface that is second order and stable (docs/masters.md, "Plain fixed-step hosts"); the
parameter set is optional (the FMUs' start values are the same).
"""

from __future__ import annotations

import shutil
import tempfile
import zipfile
from pathlib import Path
from xml.etree.ElementTree import Element, SubElement, indent, tostring

from orchestrator.errors import WecCosimError
from orchestrator.scene import HYDRO, MBD, Scene

from .fmu_builder import build_fmu, build_scene_fmus, cache_dir

NS = {
    "ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription",
    "ssc": "http://ssp-standard.org/SSP1/SystemStructureCommon",
    "ssv": "http://ssp-standard.org/SSP1/SystemStructureParameterValues",
    "osp": "http://opensimulationplatform.com/SSP/OSPAnnotations",
    "oms": "https://raw.githubusercontent.com/OpenModelica/OMSimulator/master/schema/oms.xsd",
}


def _q(tag: str) -> str:
    prefix, name = tag.split(":")
    return f"{{{NS[prefix]}}}{name}"


def parameters(scene: Scene) -> dict[str, dict[str, float]]:
    """Parameter values per component that a host must set (the multibody FMU's A_inf)."""
    idx = scene.hydro_index()
    a_inf = scene.hdb.added_mass_inf[idx][:, idx]
    labels = [k + 1 for k in idx]
    values = {f"A_inf[{k},{l}]": float(a_inf[i, j]) for i, k in enumerate(labels) for j, l in enumerate(labels)}
    return {MBD: values}


def _connectors(scene: Scene) -> dict[str, list[tuple[str, str]]]:
    out: dict[str, list[tuple[str, str]]] = {HYDRO: [], MBD: []}
    for link in scene.linearised_connections():
        out[link.source].append((link.source_variable, "output"))
        out[link.target].append((link.target_variable, "input"))
    for comp, values in parameters(scene).items():
        out[comp] += [(name, "parameter") for name in values]
    return {c: list(dict.fromkeys(v)) for c, v in out.items()}


def _parameter_set(parent: Element, values: dict[str, float], prefix: str = "") -> None:
    pset = SubElement(parent, _q("ssv:ParameterSet"), {"version": "1.0", "name": "parameters"})
    params = SubElement(pset, _q("ssv:Parameters"))
    for name, value in values.items():
        p = SubElement(params, _q("ssv:Parameter"), {"name": prefix + name})
        SubElement(p, _q("ssv:Real"), {"value": repr(value)})


def system_structure(scene: Scene) -> str:
    """The SSD document (SSP 1.0) of the scene."""
    s = scene.scenario
    root = Element(_q("ssd:SystemStructureDescription"), {"version": "1.0", "name": s.name})
    system = SubElement(root, _q("ssd:System"), {"name": s.name})
    elements = SubElement(system, _q("ssd:Elements"))
    params = parameters(scene)
    for comp, connectors in _connectors(scene).items():
        c = SubElement(elements, _q("ssd:Component"), {"name": comp, "source": f"resources/{comp}.fmu",
                                                      "type": "application/x-fmu-sharedlibrary"})
        conns = SubElement(c, _q("ssd:Connectors"))
        for name, kind in connectors:
            SubElement(SubElement(conns, _q("ssd:Connector"), {"name": name, "kind": kind}), _q("ssc:Real"))
        if comp in params:
            binding = SubElement(SubElement(c, _q("ssd:ParameterBindings")), _q("ssd:ParameterBinding"))
            _parameter_set(SubElement(binding, _q("ssd:ParameterValues")), params[comp])
    links = SubElement(system, _q("ssd:Connections"))
    for link in scene.linearised_connections():
        SubElement(links, _q("ssd:Connection"), {"startElement": link.source, "startConnector": link.source_variable,
                                                 "endElement": link.target, "endConnector": link.target_variable})
    sim = s.simulation
    # OMSimulator's fixed-step master (its command line aborts with "[NewSystem] internal error" without it)
    oms = SubElement(SubElement(SubElement(system, _q("ssd:Annotations")), _q("ssc:Annotation"),
                                {"type": "org.openmodelica"}), _q("oms:Annotations"))
    SubElement(SubElement(oms, _q("oms:SimulationInformation")), _q("oms:FixedStepMaster"),
               {"description": "oms-ma", "stepSize": repr(sim.step)})
    experiment = SubElement(root, _q("ssd:DefaultExperiment"), {"startTime": "0.0", "stopTime": repr(sim.duration)})
    note = SubElement(SubElement(experiment, _q("ssd:Annotations")), _q("ssc:Annotation"),
                      {"type": "com.opensimulationplatform"})
    SubElement(SubElement(note, _q("osp:Algorithm")), _q("osp:FixedStepAlgorithm"),
               {"baseStepSize": repr(sim.step)})
    return _xml(root)


def parameter_values(scene: Scene) -> str:
    """``parameters.ssv``: component-qualified parameter names (``mbd.A_inf[3,3]``)."""
    root = Element(_q("ssv:ParameterSet"), {"version": "1.0", "name": "parameters"})
    params = SubElement(root, _q("ssv:Parameters"))
    for comp, values in parameters(scene).items():
        for name, value in values.items():
            p = SubElement(params, _q("ssv:Parameter"), {"name": f"{comp}.{name}"})
            SubElement(p, _q("ssv:Real"), {"value": repr(value)})
    return _xml(root)


def osp_system_structure(scene: Scene) -> str:
    """libcosim's ``OspSystemStructure.xml`` for the same system."""
    s = scene.scenario
    root = Element("OspSystemStructure", {"xmlns": "http://opensimulationplatform.com/MSMI/OSPSystemStructure",
                                          "version": "0.1"})
    SubElement(root, "StartTime").text = "0.0"
    SubElement(root, "BaseStepSize").text = repr(s.simulation.step)
    SubElement(root, "Algorithm").text = "fixedStep"
    sims = SubElement(root, "Simulators")
    params = parameters(scene)
    for comp in (HYDRO, MBD):
        node = SubElement(sims, "Simulator", {"name": comp, "source": f"resources/{comp}.fmu"})
        if comp in params:
            init = SubElement(node, "InitialValues")
            for name, value in params[comp].items():
                SubElement(SubElement(init, "InitialValue", {"variable": name}), "Real", {"value": repr(value)})
    conns = SubElement(root, "Connections")
    for link in scene.linearised_connections():
        c = SubElement(conns, "VariableConnection")
        SubElement(c, "Variable", {"simulator": link.source, "name": link.source_variable})
        SubElement(c, "Variable", {"simulator": link.target, "name": link.target_variable})
    return _xml(root, namespaced=False)


def _xml(root: Element, namespaced: bool = True) -> str:
    if namespaced:
        for prefix, uri in NS.items():
            from xml.etree.ElementTree import register_namespace

            register_namespace(prefix, uri)
    indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + tostring(root, encoding="unicode") + "\n"


def _native_fmus(scene: Scene, folder: Path) -> dict[str, Path]:
    """The native hydro FMU (FMI 2.0, built into ``folder``) and the PythonFMU multibody FMU of ``scene``."""
    from hydro_fmu.native_fmu import NativeBuildError, build_native_hydro_fmu, sea_constants

    s = scene.scenario
    hydro = folder / f"{HYDRO}.fmu"
    try:
        build_native_hydro_fmu(scene.hydro_model(), hydro, constants=sea_constants(scene.sea_spec()),
                               name=f"{s.name}_hydro", fmi_version=2,
                               experiment=(0.0, s.simulation.duration, s.simulation.step))
    except NativeBuildError as exc:
        raise WecCosimError(f"export-ssp --native: {exc}") from None
    return {HYDRO: hydro, MBD: build_fmu(MBD, scene.mbd_spec(), {}, cache_dir())}


def export_ssp(scene: Scene, out: str | Path, native: bool = False) -> Path:
    """Write the SSP archive of ``scene`` to ``out`` (a ``.ssp`` zip file); returns its path. ``native``: the hydro
    component is the native hydro FMU (FMI 2.0, no Python in the host, the sea fixed at build time) instead of the
    PythonFMU one."""
    s = scene.scenario
    if s.simulation.added_mass != "mass_matrix" or s.simulation.master == "monolithic":
        raise WecCosimError(
            f"{s.file}: export-ssp writes the standard coupling (A_inf in the multibody mass matrix); "
            f"simulation.added_mass = {s.simulation.added_mass!r} needs our master's added-mass force and cannot "
            "be expressed in SSP; remove the key to export")
    out = Path(out)
    if out.suffix != ".ssp":
        raise WecCosimError(f"export-ssp: the output file must end in .ssp (got {out})")
    out.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="wec_ssp_") as tmp:
        fmus = _native_fmus(scene, Path(tmp)) if native else build_scene_fmus(scene)
        partial = Path(tmp) / out.name
        with zipfile.ZipFile(partial, "w", zipfile.ZIP_DEFLATED) as z:
            z.writestr("SystemStructure.ssd", system_structure(scene))
            z.writestr("OspSystemStructure.xml", osp_system_structure(scene))
            z.writestr("resources/parameters.ssv", parameter_values(scene))
            for comp, path in fmus.items():
                z.write(path, f"resources/{comp}.fmu")
        shutil.move(partial, out)
    return out
