"""The wave-to-wire energy account read from a run's energy series: work in = PTO + radiated + dissipated +
stored, and its residual (J)."""

from __future__ import annotations


def wave_balance(e: dict) -> float:
    """Residual of the wave-to-wire energy balance (J) from one row's (or whole series') energy terms:
    ``W_exc - (E_pto + E_radiated + E_dissipated + E_stored - E_stored,0)`` with ``E_radiated = -W_rad``,
    the dissipation outside the PTOs ``D - E_pto - W_visc`` and the stored energy ``T + V - W_hs`` (kinetic
    energy with A_inf, potential energy of the multibody model, hydrostatic energy); it equals the work the
    hydro FMU's forces did minus the work the multibody FMU received, minus the multibody balance."""
    stored = e["energy/balance"] + e["energy/external_work"] - e["energy/dissipated"]  # T + V - (T0 + V0)
    return (e["energy/excitation_work"] - e["energy/pto"] + e["energy/radiation_work"]
            - (e["energy/dissipated"] - e["energy/pto"] - e["energy/viscous_work"])
            - (stored - e["energy/hydrostatic_work"]))


def energy_terms(e: dict) -> dict:
    """The wave-to-wire energy account's terms (J) from a results file's ``energy/*`` series (arrays, one
    value per row) or one row's values: work in (excitation), PTO, radiated, dissipated outside the PTOs
    (viscous, ropes, bushings...), stored (kinetic, potential and hydrostatic, change since the start) and the
    residual of ``work in = PTO + radiated + dissipated + stored`` (:func:`wave_balance`)."""
    stored = e["energy/balance"] + e["energy/external_work"] - e["energy/dissipated"]
    return {"work_in": e["energy/excitation_work"], "pto": e["energy/pto"],
            "radiated": -e["energy/radiation_work"],
            "dissipated": e["energy/dissipated"] - e["energy/pto"] - e["energy/viscous_work"],
            "stored": stored - e["energy/hydrostatic_work"], "residual": wave_balance(e)}


def energy_account(data: dict) -> dict[str, float] | None:
    """The wave-to-wire energy account at the end of a results file (J), or None without one."""
    if "energy/excitation_work" not in data:
        return None
    return energy_terms({k: float(v[-1]) for k, v in data.items() if k.startswith("energy/")})
