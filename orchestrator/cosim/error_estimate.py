"""How wrong a run is: the error estimate every run's summary and results file carry.

A run's error against the exact solution of linear potential flow on its database has two parts, and the
estimate adds an estimate of each (signed, per quantity, so that parts of opposite sign are not counted twice):

* **Time discretisation** (coupling, input extrapolation, the multibody integrator's substeps, the radiation
  convolution's quadrature): Richardson extrapolation against a *coarse shadow*, the same scenario run again on
  every other point of the same macro grid (step 2h, the multibody substep ``multibody.max_step`` and the
  radiation grid doubled with it, the FMU slaves in process). With the run's order p (2 for every master with
  ``extrapolation`` >= 1, the linearised interface or the monolithic mode; 1 for a held input),

      e_h = y_h - y = (y_2h - y_h) / (2^p - 1)      (y the exact solution; y_2h - y = 2^p e_h)

  estimates the error of the run itself at each point of the coarse grid (exact for an error C h^p; within a
  factor of about 2 while the coarse step is still in the asymptotic range). The shadow costs about half the
  run. An adaptive run's shadow starts from a grid twice as coarse with the tolerance 2^p times looser.
* **The radiation model** (the impulse response truncated at ``hydro.irf_duration``, or the state-space fit): the
  linear frequency-domain response with the model's own A(w), B(w) (the kernel's transform at a quarter of the
  step, or the fit's transfer function) minus the response with the database's, at the frequencies the sea excites
  (regular and irregular seas, at the sea's main heading; a still-water run has no steady response and this part
  is not in it).

Measures (what the estimate is an estimate of; the same as the true errors of the bench report):

* regular waves: each steady first harmonic (body DOFs and joint coordinates, the summary's comparison
  quantities), complex relative error |dX| / max(|X|, 1e-3 X_unit), X_unit the largest amplitude of that unit;
  the largest over them;
* any other run: each body DOF's RMS deviation over the window after the ramp and the radiation memory (the whole
  run in still water) relative to the largest RMS motion of the same unit; the largest over them.

The shadow's motions are kept in the results file (``error_estimate/shadow/...``) so that any other quantity
can be estimated the same way (:func:`richardson`).
"""

from __future__ import annotations

import copy
import math
import tempfile
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from orchestrator.errors import WecCosimError
from orchestrator.results.analysis import harmonic_fit, steady_window
from orchestrator.scenario import DOFS, Scenario
from orchestrator.scene import Scene

SHADOW = "error_estimate/shadow"  # results-file group of the shadow's series
QUADRATURE_REFINEMENT = 4  # the radiation model's share: its kernel transformed at this fraction of the step
ASYMPTOTIC = 0.3  # a shadow farther than this (relative) from the run: Richardson's premise does not hold
METHOD = ("Richardson extrapolation against a coarse shadow on every other point of the macro grid (step 2h, "
          "order {order}) plus the radiation model's share from the frequency domain")


@dataclass
class ErrorEstimate:
    """A run's error estimate (module docstring).

    Attributes:
        value: the headline estimate (relative), the measure's largest quantity; NaN if unavailable.
        measure: what it measures.
        method: how (or why there is none: ``available`` False).
        order: the order p used in the Richardson step.
        step, shadow_step: the run's macro step and the shadow's (s).
        time_discretisation, radiation_model: the two parts of the headline quantity alone (relative).
        quantities: label -> estimated relative error of every quantity of the measure.
        shadow_wall_time: wall-clock seconds of the shadow run (initialisation included).
        shadow_distance: the largest difference between the shadow and the run over the measure's quantities,
            relative as the errors are; above ``ASYMPTOTIC`` the coarse step is outside the range where the error
            scales as h^p (the run is near a stability limit or far from convergence) and the estimate says so.
    """

    available: bool
    value: float = math.nan
    measure: str = ""
    method: str = ""
    order: int = 2
    step: float = math.nan
    shadow_step: float = math.nan
    time_discretisation: float = math.nan
    radiation_model: float = math.nan
    quantities: dict[str, float] = field(default_factory=dict)
    shadow_wall_time: float = 0.0
    shadow_distance: float = math.nan

    def to_json(self) -> dict:
        return {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in asdict(self).items()}

    def text(self) -> str:
        """The summary line."""
        if not self.available:
            return f"error estimate: none ({self.method})"
        parts = f"time stepping {_pct(self.time_discretisation)}, radiation model {_pct(self.radiation_model)}"
        caveat = ""
        if self.shadow_distance > ASYMPTOTIC:
            caveat = (f"; NOT RELIABLE: the coarse shadow is {_pct(self.shadow_distance)} away from the run, outside "
                      "the range where the error scales with the step (this step is near a stability limit or far "
                      "from convergence: take a smaller one)")
        return (f"error estimate: {_pct(self.value)} ({self.measure}; {parts}); {self.method}, shadow "
                f"{self.shadow_wall_time:.2f} s{caveat}")


def _pct(x: float) -> str:
    return "n/a" if not math.isfinite(x) else f"{100 * x:.3g} %"


def richardson_order(scenario: Scenario) -> int:
    """Order p of the run's global error in the macro step: 1 for a held force input (``extrapolation = 0`` with
    the force interface, outside the monolithic mode), else 2 (docs/masters.md)."""
    sim = scenario.simulation
    if sim.master != "monolithic" and sim.interface == "force" and sim.extrapolation == 0:
        return 1
    return 2


def richardson(fine: np.ndarray | complex, coarse: np.ndarray | complex, order: int) -> np.ndarray | complex:
    """Estimated error ``fine`` - exact of a quantity at step h from the same quantity at step 2h, for an error
    C h^p: (coarse - fine) / (2^p - 1)."""
    return (coarse - fine) / (2.0**order - 1.0)


def unavailable_reason(scenario: Scenario) -> str | None:
    """Why a run gets no estimate (None: it gets one)."""
    sim = scenario.simulation
    if sim.error_estimate == "none":
        return "simulation.error_estimate = 'none'"
    if scenario.control.mode != "off":
        return "an external controller drives the run: a shadow run cannot replay its commands"
    if sim.duration < 4 * sim.step - 1e-9 * sim.step:
        return "the run is shorter than two steps of the coarse shadow"
    return None


def shadow_scenario(scenario: Scenario) -> Scenario:
    """The coarse shadow's scenario: step, radiation grid and multibody substep doubled, the duration cut to a whole
    number of coarse steps, no estimate, checkpoint or output thinning of its own."""
    s = copy.deepcopy(scenario)
    sim = s.simulation
    coarse = 2 * sim.step
    sim.duration = math.floor(sim.duration / coarse + 1e-9) * coarse
    sim.step = coarse
    sim.error_estimate = "none"
    sim.error_tolerance = 0.0
    sim.output_every = 1
    sim.checkpoint_every = 0.0
    sim.output = ""
    if sim.adaptive.enabled:
        sim.adaptive.tolerance *= 2.0 ** richardson_order(scenario)
        sim.adaptive.max_step = max(sim.adaptive.max_step, coarse)
    mb = s.multibody
    if mb.max_step > 0:
        mb.max_step *= 2
    return s


Runner = Callable[[Scenario, Path, Scene], Any]  # runs a scenario into a results file, quietly, in process


def run_shadow(scene: Scene, run: Runner) -> tuple[dict[str, Any] | None, float, str]:
    """Run the coarse shadow of ``scene``'s scenario with ``run`` (``run(scenario, results path, scene)``: in
    process, no output): (its results, wall time, '') or (None, wall time, why it did not finish)."""
    from orchestrator.errors import MasterError
    from orchestrator.results import read_results

    start = time.perf_counter()
    shadow = shadow_scenario(scene.scenario)
    with tempfile.TemporaryDirectory(prefix="wec_shadow_") as tmp:
        out = Path(tmp) / "shadow.h5"
        try:
            run(shadow, out, scene)
        except (MasterError, WecCosimError, ValueError, FloatingPointError, OSError) as exc:
            text = " ".join(str(exc).split())
            if " (results up to" in text:
                text = text[:text.index(" (results up to")]
            return None, time.perf_counter() - start, text
        data = read_results(out)
    return data, time.perf_counter() - start, ""


def estimate_run(scene: Scene, data: dict[str, Any], shadow: dict[str, Any], *, wall_time: float = 0.0
                 ) -> ErrorEstimate:
    """The estimate of a finished run (``data``: its results) from its shadow's results (module docstring)."""
    s = scene.scenario
    order = richardson_order(s)
    out = ErrorEstimate(True, order=order, step=s.simulation.step, shadow_step=2 * s.simulation.step,
                        method=METHOD.format(order=order), shadow_wall_time=wall_time)
    if s.waves.kind == "regular" and s.simulation.duration >= s.ramp_time + s.simulation.steady_periods * \
            s.waves.period:
        _harmonic_estimate(scene, data, shadow, out)
    else:
        _trajectory_estimate(scene, data, shadow, out)
    return out


# ---------------------------------------------------------------------------------------------- measures
def motion_channels(scene: Scene, data: dict[str, Any]) -> list[tuple[str, str, np.ndarray]]:
    """(label, unit, series) of every body DOF and joint coordinate of a results file."""
    from mbd_fmu.joints import JOINT_COORDINATE_NAMES, JOINT_COORDINATE_UNITS

    s = scene.scenario
    t = np.asarray(data["time"])
    out = []
    for b in s.bodies:
        series = np.asarray(data[f"bodies/{b.name}/displacement"])
        for d in b.dofs:
            j = DOFS.index(d)
            out.append((f"{b.name} {d}", "m" if j < 3 else "rad", series[:, j]))
    for jt in s.joints:
        key = f"joints/{jt.name}/coordinate"
        if key not in data:
            continue
        series = np.asarray(data[key]).reshape(len(t), -1)
        for i, (name, (unit, _)) in enumerate(zip(JOINT_COORDINATE_NAMES[jt.kind], JOINT_COORDINATE_UNITS[jt.kind],
                                                  strict=True)):
            out.append((f"{jt.name} {name}", unit, series[:, i]))
    return out


def common_points(t_fine: np.ndarray, t_coarse: np.ndarray, step: float) -> tuple[np.ndarray, np.ndarray]:
    """Indices into both series of the times they share (grid indices of the fine step)."""
    a = np.rint(np.asarray(t_fine) / step).astype(np.int64)
    b = np.rint(np.asarray(t_coarse) / step).astype(np.int64)
    shared, ia, ib = np.intersect1d(a, b, return_indices=True)
    return ia, ib


def _harmonic_estimate(scene: Scene, data: dict[str, Any], shadow: dict[str, Any], out: ErrorEstimate) -> None:
    """Steady first harmonics: Richardson on each harmonic (each series' own last periods) plus the radiation
    model's share at the wave frequency."""
    s = scene.scenario
    w = s.waves
    omega = 2 * math.pi / w.period
    periods = s.simulation.steady_periods
    fine, coarse = motion_channels(scene, data), motion_channels(scene, shadow)
    tf, tc = np.asarray(data["time"]), np.asarray(shadow["time"])
    mf, mc = steady_window(tf, w.period, periods), steady_window(tc, w.period, periods)
    model = radiation_model_response(scene, np.array([omega]))
    labels, units, time_part, model_part, scale = [], [], [], [], []
    for (label, unit, yf), (_, _, yc) in zip(fine, coarse, strict=True):
        xf, _ = harmonic_fit(tf[mf], yf[mf], omega)
        xc, _ = harmonic_fit(tc[mc], yc[mc], omega)
        labels.append(label)
        units.append(unit)
        time_part.append(richardson(xf, xc, out.order))
        model_part.append(model.get(label, np.zeros(1, complex))[0] * (w.height / 2) * np.exp(1j * math.radians(
            w.phase_deg)))
        scale.append(abs(xf))
    _fill(out, labels, units, np.array(time_part), np.array(model_part), np.array(scale),
          "steady first harmonic of every body DOF and joint coordinate, complex relative error, the largest")



def _trajectory_estimate(scene: Scene, data: dict[str, Any], shadow: dict[str, Any], out: ErrorEstimate) -> None:
    """RMS deviation of each body DOF over the window after the ramp and the radiation memory (the whole run in
    still water), Richardson at the shared points plus the radiation model's steady response share."""
    s = scene.scenario
    tf, tc = np.asarray(data["time"]), np.asarray(shadow["time"])
    ia, ib = common_points(tf, tc, s.simulation.step)
    t = tf[ia]
    start = 0.0 if s.waves.kind == "still" else s.ramp_time + s.hydro.irf_duration
    window = t >= start - 1e-9
    where = "the whole run"
    if s.waves.kind != "still":
        where = f"after the ramp and the radiation memory (t >= {start:g} s)"
        if window.sum() < 10:
            start = s.ramp_time
            window = t >= start - 1e-9
            where = f"after the ramp (t >= {start:g} s)"
    if window.sum() < 2:
        window = np.ones_like(t, dtype=bool)
        where = "the whole run"
    t = t[window]
    bodies = {f"{b.name} {d}" for b in s.bodies for d in b.dofs}
    fine = [c for c in motion_channels(scene, data) if c[0] in bodies]
    coarse = [c for c in motion_channels(scene, shadow) if c[0] in bodies]
    model = radiation_model_series(scene, t) if s.waves.kind in ("regular", "irregular") else {}
    labels, units, time_rms, model_rms, total_rms, scale = [], [], [], [], [], []
    for (label, unit, yf), (_, _, yc) in zip(fine, coarse, strict=True):
        e_t = richardson(yf[ia][window], yc[ib][window], out.order)
        e_m = model.get(label, np.zeros_like(t))
        labels.append(label)
        units.append(unit)
        time_rms.append(_rms(e_t))
        model_rms.append(_rms(e_m))
        total_rms.append(_rms(e_t + e_m))
        scale.append(_rms(yf[ia][window] - np.mean(yf[ia][window]) if s.waves.kind == "still" else yf[ia][window]))
    units_ = np.array(units)
    unit_scale = np.array([max(s_ for s_, u_ in zip(scale, units, strict=True) if u_ == u) for u in units])
    denominator = np.where(unit_scale > 0, unit_scale, 1.0)
    quantities = np.array(total_rms) / denominator
    out.measure = (f"RMS deviation of every body DOF over {where}, relative to the largest RMS motion of its unit, "
                   "the largest")
    out.quantities = {lab: float(q) for lab, q in zip(labels, quantities, strict=True)}
    if len(quantities):
        k = int(np.argmax(quantities))
        out.value = float(quantities[k])
        out.time_discretisation = float(time_rms[k] / denominator[k])
        out.radiation_model = float(model_rms[k] / denominator[k])
        out.shadow_distance = (2.0**out.order - 1.0) * float(np.max(np.array(time_rms) / denominator))
    del units_


def _fill(out: ErrorEstimate, labels: list[str], units: list[str], time_part: np.ndarray, model_part: np.ndarray,
          scale: np.ndarray, measure: str) -> None:
    """Relative errors |dX| / max(|X|, 1e-3 X_unit) of complex quantities; the largest is the headline."""
    unit_scale = np.array([max(float(s_) for s_, u_ in zip(scale, units, strict=True) if u_ == u) for u in units])
    denominator = np.maximum(scale, 1e-3 * unit_scale)
    denominator = np.where(denominator > 0, denominator, 1.0)
    quantities = np.abs(time_part + model_part) / denominator
    out.measure = measure
    out.quantities = {lab: float(q) for lab, q in zip(labels, quantities, strict=True)}
    if len(quantities):
        k = int(np.argmax(quantities))
        out.value = float(quantities[k])
        out.time_discretisation = float(abs(time_part[k]) / denominator[k])
        out.radiation_model = float(abs(model_part[k]) / denominator[k])
        out.shadow_distance = (2.0**out.order - 1.0) * float(np.max(np.abs(time_part) / denominator))


def _rms(x: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.square(x)))) if len(x) else 0.0


# ---------------------------------------------------------------------------------------------- radiation model
def radiation_model_response(scene: Scene, omega: np.ndarray) -> dict[str, np.ndarray]:
    """Label -> (len(omega),) complex: the linear response per unit wave amplitude with the run's own radiation
    model minus that with the database's A(w), B(w) (body DOFs and joint coordinates), or {} when the radiation
    force is off."""
    from orchestrator.reference import frequency_domain

    s = scene.scenario
    if not s.hydro.radiation:
        return {}
    exact = frequency_domain.solve(scene, omega)
    model = model_solve(scene, omega)
    out: dict[str, np.ndarray] = {}
    for b in s.bodies:
        for d in b.dofs:
            j = DOFS.index(d)
            out[f"{b.name} {d}"] = model.body_rao(b.name)[:, j] - exact.body_rao(b.name)[:, j]
    for jt in s.joints:
        if jt.name not in exact.joint_rao:
            continue
        for i, name in enumerate(exact.joint_coordinates[jt.name]):
            out[f"{jt.name} {name}"] = model.joint_rao[jt.name][:, i] - exact.joint_rao[jt.name][:, i]
    return out


def model_solve(scene: Scene, omega: np.ndarray):  # noqa: ANN201 - FrequencyResponse
    """The frequency-domain response with the run's radiation model: the truncated kernel (convolution) or the
    state-space fit's transfer function (the convolution when a block fell back). The kernel's transform is taken at
    a quarter of the macro step (its quadrature at the macro step is the run's own time discretisation, which the
    shadow measures)."""
    from orchestrator.reference import frequency_domain

    s = scene.scenario
    dt = s.simulation.step / QUADRATURE_REFINEMENT
    method = "state_space" if s.hydro.radiation_method == "state_space" else "impulse_response"
    return frequency_domain.solve(scene, omega, radiation=method, dt=dt)


def radiation_model_series(scene: Scene, t: np.ndarray) -> dict[str, np.ndarray]:
    """Label -> the radiation model's share of each body DOF's steady response to the scene's own sea at ``t``
    (superposition of the components; no ramp)."""
    waves = scene.waves()
    omega = np.asarray(waves.omega, dtype=float)
    if not len(omega):
        return {}
    diff = radiation_model_response(scene, omega)
    bodies = {f"{b.name} {d}" for b in scene.scenario.bodies for d in b.dofs}
    labels = [label for label in diff if label in bodies]
    if not labels:
        return {}
    coefficients = np.column_stack([diff[label] * waves.complex_amplitude for label in labels])  # (K, labels)
    out = np.empty((len(t), len(labels)))
    for start in range(0, len(t), 4096):  # (times x components) in blocks: a 3-hour sea has 10^5 points
        chunk = t[start:start + 4096]
        out[start:start + len(chunk)] = np.real(np.exp(1j * np.outer(chunk, omega)) @ coefficients)
    return {label: out[:, j] for j, label in enumerate(labels)}


# ---------------------------------------------------------------------------------------------- the run's end
def for_run(scene: Scene, path: Path, run: Runner, data: dict[str, Any] | None = None) -> ErrorEstimate:
    """Run the shadow (with ``run``, :func:`run_shadow`), estimate, write the estimate and the shadow's motions into
    the results file ``path``."""
    reason = unavailable_reason(scene.scenario)
    if reason is not None:
        estimate = ErrorEstimate(False, method=reason)
        _write(path, estimate, None)
        return estimate
    shadow, wall, failure = run_shadow(scene, run)
    if shadow is None:
        estimate = ErrorEstimate(False, method=f"the coarse shadow at {2 * scene.scenario.simulation.step:g} s did "
                                        f"not finish ({failure}): this step is near the limit of these settings",
                                 shadow_wall_time=wall)
        _write(path, estimate, None)
        return estimate
    if data is None:
        from orchestrator.results import read_results

        data = read_results(path)
    try:
        estimate = estimate_run(scene, data, shadow, wall_time=wall)
    except (ValueError, ArithmeticError, np.linalg.LinAlgError, KeyError, WecCosimError) as exc:  # the run is kept
        estimate = ErrorEstimate(False, method=f"the estimate could not be formed ({' '.join(str(exc).split())[:200]})",
                                 shadow_wall_time=wall)
    _write(path, estimate, shadow)
    return estimate


def _write(path: Path, estimate: ErrorEstimate, shadow: dict[str, Any] | None) -> None:
    """The estimate (root attribute ``error_estimate``, JSON) and the shadow's motions (fixed-size datasets)."""
    import json

    with h5py.File(path, "a") as f:
        f.attrs["error_estimate"] = json.dumps(estimate.to_json())
        if SHADOW in f:
            del f[SHADOW]
        if shadow is None:
            return
        group = f.require_group(SHADOW)
        group.create_dataset("time", data=np.asarray(shadow["time"]))
        for key, value in shadow.items():
            if key.startswith(("bodies/", "joints/")) and key.endswith(("/displacement", "/coordinate")):
                group.create_dataset(key, data=np.asarray(value))


def shadow_data(data: dict[str, Any]) -> dict[str, Any] | None:
    """The shadow's series from a results file read by :func:`orchestrator.results.read_results` (keys as the
    run's own: ``time``, ``bodies/<b>/displacement``, ``joints/<j>/coordinate``), or None."""
    prefix = SHADOW + "/"
    out = {k[len(prefix):]: v for k, v in data.items() if isinstance(k, str) and k.startswith(prefix)}
    return out or None
