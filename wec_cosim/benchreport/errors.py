"""Error measures of the report: each compares a run with an answer that does not come from the run's own code
path (DESIGN: expected values from physics).

* :func:`regular_wave_error` (hinge barge, regular waves): the exact linear frequency-domain answer
  (``orchestrator.reference.frequency_domain``: the database's A(w), B(w), no time stepping) of every body DOF and joint
  coordinate; the error is the largest complex relative error |X - X_exact| / |X_exact| of the steady first
  harmonic (amplitude and phase together) over the last ``simulation.steady_periods`` periods (DOFs the waves
  do not excite: against 1e-3 of the largest amplitude of their unit).
* :func:`decay_error` (F3OF decay test 3, released from 1 deg: the linear regime, where the roots are the answer;
  from the bundled 10 deg the amplitude alone moves the modes by about 1.6 %): the two free modes' period and
  damping ratio fitted to the run (``orchestrator.reference.decay.fit_decay``) against the linear model's roots
  with the impulse response's continuous transform (``orchestrator.reference.decay.natural_modes`` with the kernel
  sampled at ``DECAY_REFERENCE_DT``, where the roots no longer move: the run's own quadrature of the convolution
  at its macro step is part of its error); the error is the largest of the four relative errors.

Estimates (the run's own error estimate, :mod:`orchestrator.cosim.error_estimate`, of the same measure):
:func:`run_estimate` for the regular and irregular cases (the run's summary estimates exactly these measures), and
:func:`decay_estimate` for the decay (Richardson extrapolation of the fitted modes against the run's coarse shadow,
kept in its results file).
* :func:`irregular_error` (two floats in an irregular sea): the exact linear response to the very wave
  components the hydro FMU realises (seeded), sum over components of RAO(w_k) a_k exp(i (w_k t + phi_k)); the
  error is the largest RMS deviation over the bodies' DOFs relative to the largest RMS response, over the
  window after the ramp and the radiation memory (the start-up transient is not in the frequency domain).
"""

from __future__ import annotations

import numpy as np

from orchestrator.scenario import DOFS


def regular_wave_error(scene, data: dict, result) -> float:  # noqa: ANN001 - Scene, RunResult
    """Largest |X - X_exact| / max(|X_exact|, 1e-3 X_unit) over the run's motion comparisons, X_unit the largest
    exact amplitude of the same unit (m or rad): a DOF that the waves do not excite (sway, roll, yaw in head seas)
    counts by its absolute deviation against the scene's motion scale, not by a ratio of two round-off numbers.
    PTO powers are left out (quadratic in the motion; the summary prints them)."""
    motions = [c for c in result.comparisons if c.unit in ("m", "rad")]
    if not motions:
        raise ValueError("no comparison with the exact answer: " + ("; ".join(getattr(result, "notes", []))
                                                                    or "the scene is not in regular waves"))
    scale = {u: max(abs(c.exact) for c in motions if c.unit == u) for u in {c.unit for c in motions}}
    return max(abs(c.measured - c.exact) / max(abs(c.exact), 1e-3 * scale[c.unit]) for c in motions
               if scale[c.unit] > 0)


DECAY_REFERENCE_DT = 0.0125  # s: the roots' kernel sampling (0.025 s moves them by 3e-5 at most)
_ROOTS: dict[tuple, list] = {}


def reference_roots(scene, radiation: str = "impulse_response") -> list:  # noqa: ANN001 - Scene
    """The linear model's roots with the kernel sampled at ``DECAY_REFERENCE_DT`` (independent of the run's step;
    computed once per database and radiation settings); ``radiation = "state_space"``: with the scene's fit."""
    from orchestrator.reference.decay import natural_modes

    h = scene.scenario.hydro
    key = (str(scene.hdb_file), h.irf_duration, h.irf_d_omega, h.damping_tail, h.added_mass_inf,
           tuple(tuple(b.dofs) for b in scene.scenario.bodies), radiation,
           (h.state_space_tolerance, h.state_space_max_order) if radiation == "state_space" else None)
    if key not in _ROOTS:
        _ROOTS[key] = natural_modes(scene, dt=DECAY_REFERENCE_DT, radiation=radiation)
    return _ROOTS[key]


def decay_modes(scene, data: dict, window_start: float) -> list[tuple[float, float]]:  # noqa: ANN001
    """F3OF DT3: (period, damping ratio) relative errors of the two free modes (flaps pitching the same way and
    mirror-wise: half sum and half difference of the pitches) fitted from ``window_start`` to the end, against
    the linear model's roots (:func:`reference_roots`)."""
    from orchestrator.reference.decay import fit_decay

    same, mirror = _paired_roots(scene, reference_roots(scene))
    # Every k-th sample, about 0.2 s apart whatever the step (the modes' periods are ~10-30 s): the pencil's SVD
    # grows as the cube of the samples, and a sum of damped exponentials is fitted exactly at any sampling.
    t = np.asarray(data["time"])
    k = max(1, int(round(0.2 / float(t[1] - t[0]))))
    t = t[::k]
    a, b = (data[f"bodies/{f}/displacement"][::k, 4] for f in ("flap1", "flap2"))
    out = []
    for channel, root in (((a + b) / 2, same), ((a - b) / 2, mirror)):
        m = fit_decay(t, channel, 1, (window_start, float(t[-1]))).modes[0]
        out.append((m.period / root.period - 1, m.damping_ratio / root.damping_ratio - 1))
    return out


def decay_error(scene, data: dict, result) -> float:  # noqa: ANN001
    """Largest relative period or damping-ratio error of F3OF DT3's two free modes, fitted after 300 s (after
    the 240 s radiation kernel; docs/f3of.md)."""
    return max(abs(e) for pair in decay_modes(scene, data, DECAY_WINDOW) for e in pair)


DECAY_WINDOW = 300.0  # s: the decay fit's start


def run_estimate(scene, data: dict, result) -> float:  # noqa: ANN001
    """The run's own error estimate (its summary's), NaN if it has none."""
    e = getattr(result, "error_estimate", None)
    return float(e.value) if e is not None and e.available else float("nan")


def decay_estimate(scene, data: dict, result) -> float:  # noqa: ANN001
    """Estimate of :func:`decay_error`: Richardson extrapolation of each fitted period and damping ratio against
    the same fit of the run's coarse shadow (``error_estimate/shadow`` of its results file), (q_2h - q_h) /
    (2^p - 1) relative to the root, plus the radiation model's share: nothing for the convolution (the reference
    is its kernel's continuous transform), the state-space fit's roots against the kernel's for a state space;
    the largest of the four. NaN without a shadow."""
    from orchestrator.cosim.error_estimate import richardson, richardson_order, shadow_data

    shadow = shadow_data(data)
    if shadow is None:
        return float("nan")
    fine = decay_modes(scene, data, DECAY_WINDOW)
    coarse = decay_modes(scene, shadow, DECAY_WINDOW)
    order = richardson_order(scene.scenario)
    model = [(0.0, 0.0)] * len(fine)
    if scene.scenario.hydro.radiation_method == "state_space":
        kernel = _paired_roots(scene, reference_roots(scene))
        fitted = _paired_roots(scene, reference_roots(scene, "state_space"))
        model = [(f.period / k.period - 1, f.damping_ratio / k.damping_ratio - 1)
                 for f, k in zip(fitted, kernel, strict=True)]
    return max(abs(richardson(f, c, order) + m) for pf, pc, pm in zip(fine, coarse, model, strict=True)
               for f, c, m in zip(pf, pc, pm, strict=True))


def _paired_roots(scene, modes: list) -> list:  # noqa: ANN001 - Scene
    """The same-way and the mirror-wise mode of F3OF DT3 among ``modes`` (as :func:`decay_modes` pairs them)."""
    coords = list(scene.multibody_simulator().model.coordinates)
    p1, p2 = coords.index(("flap1", 4)), coords.index(("flap2", 4))
    return [next(m for m in modes if np.real(m.shape[p1] / m.shape[p2]) > 0),
            next(m for m in modes if np.real(m.shape[p1] / m.shape[p2]) < 0)]


def linear_irregular_response(scene, t: np.ndarray) -> tuple[list[tuple[str, int]], np.ndarray]:  # noqa: ANN001
    """The exact linear displacement (len(t), n) of every (body, DOF) of the scene in its own realised sea
    (no ramp: valid once the ramp's transient has decayed)."""
    from orchestrator.reference import frequency_domain

    waves = scene.waves()
    fd = frequency_domain.solve(scene, np.asarray(waves.omega, dtype=float))
    coefficients = fd.rao * waves.complex_amplitude[:, None]  # (K, n)
    return list(fd.coordinates), np.real(np.exp(1j * np.outer(t, waves.omega)) @ coefficients)


def irregular_error(scene, data: dict, result) -> float:  # noqa: ANN001
    """Largest RMS deviation from the exact linear response over the bodies' DOFs, relative to the largest RMS
    response, after the ramp plus the radiation memory."""
    s = scene.scenario
    t = np.asarray(data["time"])
    start = s.ramp_time + s.hydro.irf_duration
    mask = t >= start
    if mask.sum() < 10:
        raise ValueError(f"the run ends before the window starts at {start:g} s (ramp + irf_duration)")
    coordinates, exact = linear_irregular_response(scene, t[mask])
    worst, scale = 0.0, 0.0
    for j, (body, dof) in enumerate(coordinates):
        d = dof if isinstance(dof, int) else DOFS.index(dof)
        x = data[f"bodies/{body}/displacement"][mask, d]
        worst = max(worst, float(np.sqrt(np.mean((x - exact[:, j]) ** 2))))
        scale = max(scale, float(np.sqrt(np.mean(exact[:, j] ** 2))))
    return worst / scale
