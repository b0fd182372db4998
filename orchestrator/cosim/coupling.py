"""How a scene's FMUs are wired for each added-mass mode (``docs/masters.md``).

* ``mass_matrix`` (mode a, default): our multibody FMU carries A_inf in its mass matrix (copied
  from the hydro FMU's calculated parameters at initialisation); only the radiation memory,
  excitation and hydrostatic force is exchanged.
* ``explicit_force`` (mode b): the same multibody FMU with its A_inf parameters set to zero; the
  master adds -A_inf a_prev to the force input, a_prev the previous step's mean acceleration.
  Unstable whenever A_inf exceeds the structural mass; kept to show why.
* ``interface`` (mode c): a third-party-style multibody FMU that cannot take A_inf
  (:mod:`plain_mbd_fmu`); the master adds -A_inf (v_{n+1} - v_n)/h with the current step's
  acceleration and solves it within each step by interface Newton iterations (iterative masters).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from orchestrator.fmi.fmu_builder import PLAIN_MBD, build_scene_fmus
from orchestrator.scene import HYDRO, MBD, Connection, Scene

from .masters import AddedMassForce
from .step_control import Bond

ADDED_MASS_MODES = ("mass_matrix", "explicit_force", "interface")


@dataclass
class Coupling:
    """FMUs, connections, initialisation links, added-mass force and bonds of a scene."""

    fmus: dict[str, Path]
    connections: list[Connection]
    parameter_links: list[Connection]
    added_mass: AddedMassForce | None
    bonds: list[Bond]
    parameters: dict[str, dict[str, float]] = field(default_factory=dict)


def bonds(scene: Scene) -> list[Bond]:
    """One force/velocity bond per hydrodynamic coordinate."""
    out = []
    for b, d in scene.hydro_coordinates:
        i = d + 1
        out.append(Bond((HYDRO, f"{b}.F[{i}]"), (MBD, f"{b}.F[{i}]"), (MBD, f"{b}.v[{i}]")))
    return out


def scene_coupling(scene: Scene, mode: str = "mass_matrix", out_dir: Path | None = None,
                   interface: str = "force") -> Coupling:
    """Build the FMUs of ``scene`` for added-mass ``mode`` and say how to connect them (``interface``: the
    force, or the linearised force model, :meth:`orchestrator.scene.Scene.linearised_connections`)."""
    if mode not in ADDED_MASS_MODES:
        raise ValueError(f"added-mass mode must be one of {ADDED_MASS_MODES}")
    fmus = build_scene_fmus(scene, out_dir, multibody=PLAIN_MBD if mode == "interface" else MBD)
    links = scene.parameter_links() if mode == "mass_matrix" else []
    added = None
    if mode != "mass_matrix":
        idx = scene.hydro_index()
        matrix = scene.hdb.added_mass_inf[idx][:, idx]
        coords = scene.hydro_coordinates
        added = AddedMassForce(
            matrix=matrix,
            force_inputs=[(MBD, f"{b}.F[{d + 1}]") for b, d in coords],
            velocity_outputs=[(MBD, f"{b}.v[{d + 1}]") for b, d in coords],
            mode="explicit" if mode == "explicit_force" else "interface",
        )
    connections = scene.linearised_connections() if interface == "linearised" else scene.connections()
    # Mode b: the multibody FMU's A_inf start values are the scene's (right on its own): set them to zero.
    labels = [k + 1 for k in scene.hydro_index()]
    parameters = {MBD: {f"A_inf[{k},{l}]": 0.0 for k in labels for l in labels}} if mode == "explicit_force" else {}
    return Coupling(fmus, connections, links, added, bonds(scene), parameters)
