"""`wec-cosim rao` and `wec-cosim steady`: frequency-domain and pseudo-spectral results as HDF5.

RAO file (per metre of wave amplitude, ``exp(+i omega t)`` convention; see docs/frequency_domain.md):
``omega``, ``incident_power`` (W/m per m^2), ``bodies/<b>/rao`` (Nw, 6), ``ptos/<p>/mean_power``
(W per m^2) and ``capture_width`` (m), ``joints/<j>/rao`` (Nw, k; attribute ``coordinates``) and
``joints/<j>/reaction`` (Nw, 6: force and moment on body 2 about the joint point), for the first
heading; ``heading_sweep/`` the body RAOs, PTO powers and joint RAOs with a leading heading axis when
``[rao] headings_deg`` lists several; ``irregular/`` the response spectra, significant responses and mean powers in the
scenario's irregular sea.

Steady-state file: per wave period group ``periods/<i>/``: ``omega``, ``harmonics`` attributes,
``bodies/<b>/harmonics`` (N + 1, 6) complex, ``bodies/<b>/one_period`` (samples, 6) with ``time``,
``ptos/<p>/mean_power`` (W), ``joints/<j>/harmonics``, ``joints/<j>/reaction_harmonics``, the
solver report (residual, converged, message, evaluations, wall time).
"""

from __future__ import annotations

import math
from pathlib import Path

import h5py
import numpy as np

from orchestrator.errors import WecCosimError
from orchestrator.scene import Scene

from . import frequency_domain
from .pseudo_spectral import SteadyState, solve_steady

RAO_UNIT = "m/m (translations), rad/m (rotations); exp(+i omega t) convention"


def rao_grid(scene: Scene) -> np.ndarray:
    grid = scene.scenario.rao.omega
    return np.arange(grid.start, grid.stop + grid.step / 2, grid.step) if grid else scene.hdb.omega


def refuse_unstable(scene: Scene) -> None:
    """A statically unstable scene has no motion that settles to a frequency-domain answer: refuse it."""
    from .stability import static_instability

    problem = static_instability(scene)
    if problem:
        raise WecCosimError(f"{scene.scenario.file}: {problem}")


def write_rao_file(scene: Scene, out: Path) -> list[frequency_domain.FrequencyResponse]:
    """Solve the scene's RAOs over ``[rao]`` (each heading) and write them; returns the responses."""
    s = scene.scenario
    refuse_unstable(scene)
    omega = rao_grid(scene)
    headings = list(s.rao.headings_deg) or [s.waves.heading_deg]
    responses = [_solve(scene, omega, h) for h in headings]
    out.parent.mkdir(parents=True, exist_ok=True)
    with h5py.File(out, "w") as f:
        f.create_dataset("omega", data=omega).attrs["unit"] = "rad/s"
        _write_response(f, s, responses[0])
        if len(responses) > 1:
            g = f.create_group("heading_sweep")
            g.create_dataset("headings_deg", data=np.array(headings))
            for b in s.bodies:
                g.create_dataset(f"bodies/{b.name}/rao", data=np.array([r.body_rao(b.name) for r in responses]))
            for name in responses[0].pto_power:
                g.create_dataset(f"ptos/{name}/mean_power", data=np.array([r.pto_power[name] for r in responses]))
            for name in responses[0].joint_rao:
                ds = g.create_dataset(f"joints/{name}/rao", data=np.array([r.joint_rao[name] for r in responses]))
                ds.attrs["coordinates"] = responses[0].joint_coordinates[name]
        if s.waves.kind == "irregular":
            _write_irregular(f, scene, responses[0])
        f.attrs["form"] = responses[0].form
        f.attrs["scenario"] = s.text
        f.attrs["scenario_file"] = str(s.file)
        f.attrs["overrides"] = "; ".join(s._overrides)  # `--set` items, as `wec-cosim rao/steady --set` gave them
    return responses


def _solve(scene: Scene, omega: np.ndarray, heading: float) -> frequency_domain.FrequencyResponse:
    try:
        return frequency_domain.solve(scene, omega, form=scene.scenario.rao.form, heading_deg=heading)
    except (KeyError, ValueError) as exc:
        raise WecCosimError(f"{scene.scenario.file}: rao: {exc}") from None


def _write_response(f: h5py.File, s, fd: frequency_domain.FrequencyResponse) -> None:
    f.attrs["heading_deg"] = fd.heading_deg
    f.create_dataset("incident_power", data=fd.incident_power).attrs["unit"] = "W/m per m^2 of wave amplitude"
    for b in s.bodies:
        f.create_dataset(f"bodies/{b.name}/rao", data=fd.body_rao(b.name)).attrs["unit"] = RAO_UNIT
    for name, p in fd.pto_power.items():
        f.create_dataset(f"ptos/{name}/mean_power", data=p).attrs["unit"] = "W/m^2"
        f.create_dataset(f"ptos/{name}/capture_width", data=fd.capture_width(name)).attrs["unit"] = "m"
    for name, rao in fd.joint_rao.items():
        ds = f.create_dataset(f"joints/{name}/rao", data=rao)
        ds.attrs["coordinates"] = fd.joint_coordinates[name]
        ds.attrs["unit"] = "rad/m (angles), m/m (displacements)"
        ds = f.create_dataset(f"joints/{name}/reaction", data=fd.reaction_rao[name])
        ds.attrs["unit"] = "N/m (force), N m/m (moment about the joint point); on body 2 from body 1, world frame"


def _write_irregular(f: h5py.File, scene: Scene, fd: frequency_domain.FrequencyResponse) -> None:
    from hydro_fmu.sea import sea_spectrum

    stats = frequency_domain.irregular_response(fd, sea_spectrum(scene.sea_spec()))
    g = f.create_group("irregular")
    g.create_dataset("wave_spectrum", data=stats.wave_spectrum).attrs["unit"] = "m^2 s/rad"
    g.attrs["hs"] = stats.hs
    g.attrs["incident_power"] = stats.incident_power
    g.attrs["spectrum_fraction_on_grid"] = stats.fraction_on_grid
    for b in scene.scenario.bodies:
        j = [k for k, (name, _) in enumerate(fd.coordinates) if name == b.name]
        g.create_dataset(f"bodies/{b.name}/response_spectrum", data=stats.response_spectra[:, j])
        g.create_dataset(f"bodies/{b.name}/significant_response",
                         data=stats.significant_response[j]).attrs["unit"] = "m, rad (4 sqrt(m0))"
        g[f"bodies/{b.name}"].attrs["dofs"] = [fd.coordinates[k][1] for k in j]
    for name, p in stats.mean_power.items():
        ds = g.create_dataset(f"ptos/{name}/mean_power", data=p)
        ds.attrs["unit"] = "W"
        ds.attrs["capture_width"] = p / stats.incident_power


def wave_periods(scene: Scene) -> list[float]:
    s = scene.scenario
    if s.steady.periods:
        return list(s.steady.periods)
    if s.waves.kind != "regular":
        raise WecCosimError(f"{s.file}: steady: the pseudo-spectral steady state needs regular waves ([waves] kind = "
                            f"'regular', got {s.waves.kind!r}) or [steady] periods")
    return [s.waves.period]


def write_steady_file(scene: Scene, out: Path, harmonics: int | None = None, form: str | None = None,
                      log=print) -> list[SteadyState]:
    """Solve the steady state at each period of ``[steady]`` and write it (module docstring)."""
    s = scene.scenario
    refuse_unstable(scene)
    n = harmonics or s.steady.harmonics
    form = form or s.steady.form
    periods = wave_periods(scene)
    if not s.waves.height > 0:
        raise WecCosimError(f"{s.file}: steady: waves.height must be positive")
    states = []
    out.parent.mkdir(parents=True, exist_ok=True)
    with h5py.File(out, "w") as f:
        f.attrs["scenario"] = s.text
        f.attrs["scenario_file"] = str(s.file)
        f.attrs["overrides"] = "; ".join(s._overrides)  # `--set` items, as `wec-cosim rao/steady --set` gave them
        f.attrs["form"] = form
        f.attrs["harmonics"] = n
        for i, period in enumerate(periods):
            state = solve_steady(scene, 2 * math.pi / period, s.waves.height / 2, n, form=form,
                                 tolerance=s.steady.tolerance)
            states.append(state)
            _write_state(f.create_group(f"periods/{i}"), s, state)
            if log:
                flag = "" if state.converged else f"  NOT CONVERGED: {state.message}"
                log(f"T = {period:g} s: residual {state.residual:.2g} after {state.evaluations} evaluations, "
                    f"{state.wall_time:.3f} s{flag}")
    return states


def _write_state(g: h5py.Group, s, state: SteadyState) -> None:
    for key in ("omega", "amplitude", "harmonics", "residual", "converged", "message", "evaluations", "wall_time",
                "incident_power"):
        g.attrs[key] = getattr(state, key)
    t = np.linspace(0.0, state.period, 20 * (2 * state.harmonics + 1), endpoint=False)
    g.create_dataset("time", data=t).attrs["unit"] = "s"
    for b in s.bodies:
        h = state.body_motion(b.name)
        g.create_dataset(f"bodies/{b.name}/harmonics", data=h).attrs["unit"] = "m, rad; exp(+i k omega t)"
        g.create_dataset(f"bodies/{b.name}/one_period", data=state.time_series(t, h)).attrs["unit"] = "m, rad"
    for name, p in state.pto_power.items():
        g.create_dataset(f"ptos/{name}/mean_power", data=p).attrs["unit"] = "W"
        g[f"ptos/{name}"].attrs["capture_width"] = state.capture_width(name)
    for name, h in state.joint_motion.items():
        g.create_dataset(f"joints/{name}/harmonics", data=h).attrs["coordinates"] = state.joint_coordinates[name]
        g.create_dataset(f"joints/{name}/reaction_harmonics", data=state.reactions[name]).attrs["unit"] = "N, N m"
