"""Macro steps that alias a fast mode of the scene onto the waves: detected before the run, said in its first lines.

The master hands the multibody FMU a force held (or ramped) over each macro step h. Seen at the communication
points, a mode of natural frequency w_n above the Nyquist frequency pi / h appears at its alias

    w_a = |w_n - 2 pi m / h|,   m the nearest whole number to w_n h / (2 pi),

and where the alias falls among the frequencies the sea drives, the step-by-step forcing feeds the mode at
resonance: a stiff PTO spring whose period is a whole number of macro steps drives the steady heave wrong by ~99 %
for every master (the bench report's stiff-PTO map: 14.5 % at h / T_n = 0.95 and 1.05, within 0.1 % at 1.5 and
2.5). The check: the undamped modes of the linearised scene with the infinite-frequency added mass (the mode
frequencies a fast spring sees), and a warning for every mode above pi / h whose alias is below ``ALIAS_BAND``
times the highest frequency the sea carries (the regular wave's, or the irregular spectrum's components').
"""

from __future__ import annotations

import math

import numpy as np
from scipy.linalg import eigh

from orchestrator.scene import Scene

ALIAS_BAND = 3.0  # an alias below this times the highest wave frequency is driven by the waves


def undamped_modes(scene: Scene) -> np.ndarray:
    """Natural frequencies (rad/s) of the linearised scene with A_inf and the hydrostatic stiffness, no damping."""
    from orchestrator.reference.frequency_domain import mechanical_matrices

    m = mechanical_matrices(scene)
    mass, stiffness = m.mass.copy(), m.stiffness.copy()
    idx = scene.hydro_index()
    rows = np.asarray(m.rows, dtype=int)
    h = scene.scenario.hydro
    mass[np.ix_(rows, rows)] += scene.hdb.added_mass_inf[np.ix_(idx, idx)]
    if h.hydrostatics:
        from scipy.linalg import block_diag

        stiffness[np.ix_(rows, rows)] += block_diag(*scene.hdb.hydrostatic_stiffness)[np.ix_(idx, idx)]
    if m.basis is not None:
        mass, stiffness = m.basis.T @ mass @ m.basis, m.basis.T @ stiffness @ m.basis
    stiffness = 0.5 * (stiffness + stiffness.T)
    values = eigh(stiffness, 0.5 * (mass + mass.T), eigvals_only=True)
    return np.sqrt(np.clip(values, 0.0, None))


def aliasing_warnings(scene: Scene) -> list[str]:
    """One warning per mode of ``scene`` that its macro step aliases onto the sea's frequencies (module docstring);
    none in still water or for an adaptive step."""
    s = scene.scenario
    if s.waves.kind not in ("regular", "irregular") or s.simulation.adaptive.enabled:
        return []
    omega = np.asarray(scene.waves().omega, dtype=float)
    if not len(omega):
        return []
    top = float(omega.max())
    h = s.simulation.step
    out = []
    for w in undamped_modes(scene):
        if w * h <= math.pi:
            continue
        m = round(w * h / (2 * math.pi))
        alias = abs(w - 2 * math.pi * m / h)
        if alias < ALIAS_BAND * top:
            period = 2 * math.pi / w
            out.append(
                f"the macro step {h:g} s is {h / period:.2f} periods of the scene's mode at {w:.4g} rad/s (period "
                f"{period:.4g} s, e.g. a stiff PTO spring): at this step the mode appears at {alias:.3g} rad/s, among "
                f"the wave frequencies (up to {top:.3g} rad/s), and the force held over each step drives it at "
                f"resonance (the steady response can be wrong by tens of per cent, whatever the master); use a step "
                f"below half its period ({period / 2:.3g} s) or away from whole multiples of it")
    return out
