"""The summary of one case: mean and largest PTO power, significant and largest motions, largest joint
reactions, incident wave power.

A summary is a flat mapping from a path (``ptos/<p>/mean_power``, ``bodies/<b>/significant``...)
to a number or an array, the layout of a case's group in the sweep file and of the matrices.

Time domain (over the analysis window: the last ``simulation.steady_periods`` periods of a regular
wave, else every sample after the transient):

* ``ptos/<p>/mean_power`` (W): time average of the absorbed power (trapezoidal rule);
  ``ptos/<p>/max_power`` (W): its largest sample;
* ``bodies/<b>/significant`` (6, m or rad): 4 standard deviations of each displacement (the
  significant height of a Gaussian response, 4 sqrt(m0)); ``bodies/<b>/maximum`` (6): the largest
  absolute displacement from equilibrium;
* ``joints/<j>/max_force`` (N), ``joints/<j>/max_moment`` (N m): largest magnitude of the reaction
  force and moment on body 2 (static part included);
* ``incident_power`` (W/m): sum of rho g a^2 c_g / 2 over the sea's components.

Frequency domain (exact, linear; quadratic drag and nonlinear laws are left out): the same
quantities from the RAOs. Regular wave of amplitude a: mean power (1/2) omega^2 c |Q|^2; a linear
PTO's power c qdot^2 + k q qdot peaks at P_mean (1 + sqrt(1 + (k / (c omega))^2)); significant =
2 sqrt(2) |X| a (4 sigma of a sinusoid), maximum = |X| a. Irregular sea: the spectral statistics of
``frequency_domain.irregular_response`` (mean power, 4 sqrt(m0)); maxima of a random sea and joint
reactions (dynamic part only in the linear model) are not given: NaN.
"""

from __future__ import annotations

import math

import numpy as np

from hydro_fmu.spectra import component_power
from orchestrator.reference import frequency_domain
from orchestrator.results.analysis import steady_window, window_mean
from orchestrator.scene import Scene

Summary = dict[str, float | np.ndarray]

UNITS = {"mean_power": "W", "max_power": "W", "significant": "m, rad (4 standard deviations)",
         "maximum": "m, rad", "max_force": "N", "max_moment": "N m", "incident_power": "W/m"}


def analysis_window(scene: Scene, t: np.ndarray, transient: float | None) -> np.ndarray:
    """Mask of the samples the statistics use (module docstring)."""
    s = scene.scenario
    if s.waves.kind == "regular" and transient is None:
        return steady_window(t, s.waves.period, s.simulation.steady_periods)
    start = default_transient(scene) if transient is None else transient
    mask = t >= start - 1e-9
    if np.count_nonzero(mask) < 2:
        raise ValueError(f"the transient ({start:g} s) leaves no samples to analyse in a run of {t[-1]:g} s; "
                         "lengthen simulation.duration or shorten sweep.transient")
    return mask


def default_transient(scene: Scene) -> float:
    """Time discarded by default: the ramp plus the length of the radiation impulse response."""
    s = scene.scenario
    return s.ramp_time + s.hydro.irf_duration


def time_domain_summary(scene: Scene, data: dict, mask: np.ndarray) -> Summary:
    """Statistics of a results file's series (``orchestrator.results.results_file.read_results``) over ``mask``."""
    s = scene.scenario
    t = data["time"]
    out: Summary = {}
    for p in s.ptos:
        power = data[f"ptos/{p.name}/power"]
        out[f"ptos/{p.name}/mean_power"] = window_mean(t, power, mask)
        out[f"ptos/{p.name}/max_power"] = float(np.max(power[mask]))
    for b in s.bodies:
        x = data[f"bodies/{b.name}/displacement"][mask]
        out[f"bodies/{b.name}/significant"] = 4 * np.std(x, axis=0)
        out[f"bodies/{b.name}/maximum"] = np.max(np.abs(x), axis=0)
    for j in s.joints:
        for key, name in (("force", "max_force"), ("moment", "max_moment")):
            series = data.get(f"joints/{j.name}/{key}")
            if series is not None:
                out[f"joints/{j.name}/{name}"] = float(np.max(np.linalg.norm(series[mask], axis=1)))
    env = s.environment
    out["incident_power"] = component_power(scene.waves(), env.rho, env.g, env.water_depth)
    return out


def frequency_domain_summary(scene: Scene) -> Summary:
    """Exact linear statistics of the scene's sea (module docstring)."""
    s = scene.scenario
    w = s.waves
    out: Summary = {}
    if w.kind == "regular":
        omega = 2 * math.pi / w.period
        a = w.height / 2
        fd = frequency_domain.solve(scene, np.array([omega]))
        for p in s.ptos:
            mean = float(fd.pto_power[p.name][0] * a**2)
            out[f"ptos/{p.name}/mean_power"] = mean
            out[f"ptos/{p.name}/max_power"] = (mean * (1 + math.sqrt(1 + (p.stiffness / (p.damping * omega)) ** 2))
                                               if p.damping > 0 and not p.nonlinear else math.nan)
        for b in s.bodies:
            amplitude = np.abs(fd.body_rao(b.name)[0]) * a
            out[f"bodies/{b.name}/significant"] = 2 * math.sqrt(2) * amplitude
            out[f"bodies/{b.name}/maximum"] = amplitude
        out["incident_power"] = float(frequency_domain.incident_wave_power(scene, np.array([omega]))[0] * a**2)
    else:
        from hydro_fmu.sea import sea_spectrum
        from orchestrator.reference.response_files import rao_grid

        fd = frequency_domain.solve(scene, rao_grid(scene))
        stats = frequency_domain.irregular_response(fd, sea_spectrum(scene.sea_spec()))
        for p in s.ptos:
            out[f"ptos/{p.name}/mean_power"] = stats.mean_power[p.name]
            out[f"ptos/{p.name}/max_power"] = math.nan
        for b in s.bodies:
            sig = np.zeros(6)
            for k, (name, dof) in enumerate(fd.coordinates):
                if name == b.name:
                    sig[dof] = stats.significant_response[k]
            out[f"bodies/{b.name}/significant"] = sig
            out[f"bodies/{b.name}/maximum"] = np.full(6, math.nan)
        out["incident_power"] = stats.incident_power
        out["spectrum_fraction_on_grid"] = stats.fraction_on_grid
    for j in s.joints:
        out[f"joints/{j.name}/max_force"] = math.nan
        out[f"joints/{j.name}/max_moment"] = math.nan
    return out
