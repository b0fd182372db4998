"""Why a run diverged: the causes a diverging run is checked for, named in its error message instead of the
output that happened to cross its limit first (``pto.power``).

* a statically unstable scene (:func:`orchestrator.reference.stability.static_instability`: a negative restoring
  stiffness, e.g. a database with C33 < 0): every run grows along it, whatever the step or the master;
* an external controller's commands that feed energy in: negative PTO damping or stiffness;
* the infinite-frequency added mass applied as an explicit force (``simulation.added_mass = 'explicit_force'``)
  on a body lighter than its added mass: unstable at any step size.
"""

from __future__ import annotations

import numpy as np

from orchestrator.scenario import DOFS


def divergence_causes(plan) -> str:  # noqa: ANN001 - simulation.RunPlan
    """The causes found, as text to append to the divergence message ("" if none is found)."""
    causes = []
    try:
        from orchestrator.reference.stability import static_instability

        unstable = static_instability(plan.scene)
    except Exception:  # noqa: BLE001 - a scene that cannot be linearised: no cause from it
        unstable = None
    if unstable:
        causes.append(unstable)
    control = plan.control
    if control is not None and control.negative:
        causes.append("the controller commanded " + ", ".join(
            f"{name} = {low:.4g} (from t = {first:g} s)" for name, (low, first) in control.negative.items())
            + ": negative damping or stiffness feeds energy into the bodies; narrow control.damping_limits "
              "and control.stiffness_limits, or correct the control law")
    explicit = _explicit_added_mass(plan)
    if explicit:
        causes.append(explicit)
    if not causes:
        return ""
    return ". The cause: " + "; and ".join(causes)


def _explicit_added_mass(plan) -> str:  # noqa: ANN001
    """Why a run with the added mass on the force side diverges, and what to change."""
    scenario = plan.scene.scenario
    if scenario.simulation.added_mass != "explicit_force":
        return ""
    scene = plan.scene
    idx = scene.hydro_index()
    a_inf = np.diag(scene.hdb.added_mass_inf[np.ix_(idx, idx)])
    system = scene.multibody_system(added_mass=False)
    rows = [system.coordinate_index(b, d) for b, d in scene.hydro_coordinates]
    ratios = a_inf / np.diag(system.structural_mass)[rows]
    j = int(np.argmax(ratios))
    b, d = scene.hydro_coordinates[j]
    return (f"simulation.added_mass = 'explicit_force' applies the infinite-frequency added mass as a force computed "
            f"from the previous step's acceleration; that explicit coupling is unstable at any step size whenever "
            f"A_inf exceeds the structural mass, and here A_inf is {ratios[j]:.3g} times the mass ({b} {DOFS[d]}). "
            f"Use simulation.added_mass = 'mass_matrix' (the default), or 'interface' with master = 'iqn_ils' or "
            f"'aitken' for a multibody FMU that cannot take A_inf")
