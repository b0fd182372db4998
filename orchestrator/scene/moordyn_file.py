"""A MoorDyn input file in the multibody FMU's specification (``[mooring_lines] moordyn_file``).

With ``mooring_lines.model = "moordyn"`` the file runs in MoorDyn inside the multibody FMU
(:func:`dynamic_spec`): each ``Coupled`` point of the file is a ``moordyn_point`` force element on the scenario
body named for it in ``mooring_lines.coupled_bodies``, and one ``moordyn_tensions`` element outputs the tension at
both ends of every line. With ``model = "quasi_static"`` (and for the frequency-domain and steady-state solvers,
and the static equilibrium) the lines are their linearised quasi-static stiffness on each coupled body about its
cg, from central differences of MoorDyn's own static solves of the file, plus the lines' mean wrench as a constant
load (:func:`linearised_spec`; :func:`mbd_fmu.moordyn_files.body_stiffness`).
"""

from __future__ import annotations

import numpy as np

from mbd_fmu.moordyn_files import MoorDynFile, body_stiffness, read_moordyn_file, run_text
from orchestrator.scenario import DOFS, Scenario

POINT = "moordyn_point{}"  # force element (FMU variable prefix) of coupled point ID
TENSIONS = "moordyn_lines"  # the end-tension output element


def moordyn_file(scenario: Scenario) -> MoorDynFile:
    return read_moordyn_file(scenario.resolve(scenario.mooring_lines.moordyn_file))


def results_series(scenario: Scenario) -> dict[str, list[str]]:
    """Results path -> multibody FMU outputs: each coupled point's force on its body (world frame, N) and each line's
    tension at end A and end B (N)."""
    m = scenario.mooring_lines
    if not m.moordyn_file or m.model != "moordyn":
        return {}
    f = moordyn_file(scenario)
    out = {f"mooring/point{pid}/force": [f"{POINT.format(pid)}.force[{i + 1}]" for i in range(3)]
           for pid, _ in f.coupled}
    for k, lid in enumerate(f.line_ids):
        out[f"mooring/line{lid}/tension"] = [f"{TENSIONS}.force[{2 * k + 1}]", f"{TENSIONS}.force[{2 * k + 2}]"]
    return out


def dynamic_spec(scenario: Scenario, spec: dict) -> None:
    """Add the file (its text with MoorDyn's own output off), the coupled points and the tension output."""
    f = moordyn_file(scenario)
    env = scenario.environment
    spec["moordyn_file"] = {"text": run_text(f, env.rho, env.g), "path": f.path}
    spec["moordyn"] = {"time_step": f.time_step, "rho": env.rho, "g": env.g}
    for (pid, position), body in zip(f.coupled, scenario.mooring_lines.coupled_bodies, strict=True):
        spec["forces"].append({"name": POINT.format(pid), "kind": "moordyn_point", "body": body,
                               "position": position.tolist()})
    spec["forces"].append({"name": TENSIONS, "kind": "moordyn_tensions", "lines": len(f.line_ids)})


def linearised(scenario: Scenario) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Body name -> (6 x 6 quasi-static stiffness about its cg, mean wrench (6,)) of the file's lines."""
    f = moordyn_file(scenario)
    names = list(dict.fromkeys(scenario.mooring_lines.coupled_bodies))
    bodies = {b.name: b for b in scenario.bodies}
    index = np.array([names.index(n) for n in scenario.mooring_lines.coupled_bodies], dtype=int)
    centres = np.array([bodies[n].cg for n in names], float)
    dofs = [[DOFS.index(d) for d in bodies[n].dofs] for n in names]
    env = scenario.environment
    positions = np.array([p for _, p in f.coupled])
    text = run_text(f, env.rho, env.g)
    mask = np.zeros((len(names), 6), dtype=np.int8)
    for i, d in enumerate(dofs):
        mask[i, d] = 1

    def compute() -> dict:
        stiffness, wrench = body_stiffness(text, positions, index, centres, len(names), dofs)
        return {"stiffness": stiffness, "wrench": wrench}

    import mbd_fmu.moordyn_files

    from .fit_cache import cached_fit

    # A few seconds per MoorDyn static solve, 2 per degree of freedom: kept on disk like the A_inf fits.
    stored = cached_fit("moordyn_statics", {"text": np.frombuffer(text.encode(), dtype=np.uint8),
                                            "positions": positions, "index": index, "centres": centres,
                                            "dofs": mask}, mbd_fmu.moordyn_files.__file__, compute)
    return {n: (stored["stiffness"][i], stored["wrench"][i]) for i, n in enumerate(names)}


def linearised_spec(spec: dict, lines: dict[str, tuple[np.ndarray, np.ndarray]]) -> None:
    """The lines as a linear mooring per coupled body and their mean wrench added to its constant load."""
    for b in spec["bodies"]:
        if b["name"] in lines:
            stiffness, wrench = lines[b["name"]]
            spec["forces"].append({"name": f"moordyn_{b['name']}", "kind": "mooring", "body": b["name"],
                                   "stiffness": stiffness.ravel().tolist(), "damping": None})
            load = np.asarray(b.get("static_load", [0.0] * 6), float) + wrench
            b["static_load"] = load.tolist()
