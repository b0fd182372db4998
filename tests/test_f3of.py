"""Seed 000's F3OF (base and two flaps on hinges): database, decay tests DT1-DT3 and regular-wave RAOs.

References are physics, never a previous run: the closed bodies' volumes and centres of buoyancy
(divergence theorem on the repaired meshes), static balance (weight against buoyancy), the free
modes of the linear constrained model with the frequency-dependent radiation of the time-domain
model (``orchestrator.reference.decay.natural_modes``: complex roots of det Z), the exact linear free decay
(``orchestrator.reference.decay.linear_decay``) and the exact linear frequency-domain response
(``frequency_domain.solve``). Windows, tolerances and measured numbers: docs/f3of.md.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydro_fmu.meshes import read_mesh
from orchestrator.cosim.simulation import run_scenario
from orchestrator.reference.decay import database_modes, fit_decay, linear_decay, natural_modes
from orchestrator.results import read_results
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

from .conftest import SCENARIOS

F3OF = SCENARIOS / "data" / "f3of"
NAMES = ("f3of_dt1", "f3of_dt2", "f3of_dt3", "f3of_rao")
RAO_PERIODS = tuple(float(T) for T in range(5, 16))


def scenario(name: str, **changes):
    s = load_scenario(SCENARIOS / f"{name}.toml")
    for key, value in changes.items():
        section, field = key.split("__")
        setattr(getattr(s, section), field, value)
    return s


def flap1_from(s, degrees: float):
    """Release flap 1 from ``degrees`` about its hinge (3.5 m below its cg)."""
    th = math.radians(degrees)
    b = next(b for b in s.bodies if b.name == "flap1")
    b.initial_displacement = [3.5 * math.sin(th), 0.0, 3.5 * (math.cos(th) - 1.0), 0.0, th, 0.0]
    return s


def run(s, tmp_path, *, in_process: bool = True) -> dict:
    path = tmp_path / f"{s.name}.h5"
    run_scenario(s, path, in_process=in_process, progress=False, log=None)
    return read_results(path)


# ---------------------------------------------------------------------------------------- database
def test_database_passes_the_checks_and_carries_the_closed_bodies_hydrostatics() -> None:
    """All four scenes load the committed 18 x 18 database (symmetry and positive damping checked on
    each scene's DOFs at the default 5 %). Its volumes and centres of buoyancy are the closed bodies'
    (z-form divergence theorem on the repaired meshes, independent of Capytaine): the flaps' centre of
    buoyancy is on the hinge's vertical, so with Table 1's masses each flap stands upright at
    equilibrium, and the whole device is in static balance (the linearisation's residual force is
    negligible against the weight)."""
    from mbd_fmu.linearize import linearize

    weight = (1089825.0 + 2 * 179250.0) * 9.81
    for name in NAMES:
        scene = load_scene(scenario(name), log=None)
        assert scene.scenario.hydro.check_tolerance == 0.05
        hdb = scene.hdb
        for i, (mesh, pos) in enumerate((("base", (0, 0, -9)), ("flap", (-12.5, 0, -5.5)), ("flap", (12.5, 0, -5.5)))):
            wet = read_mesh(F3OF / f"{mesh}_repaired_x2.obj").translated(pos).immersed_part()
            volume, centre = wet.volume_and_centroid()
            assert hdb.displaced_volume[i] == pytest.approx(volume, rel=1e-9)
            np.testing.assert_allclose(hdb.cb[i], centre, atol=1e-9)
        assert hdb.cb[1][0] == pytest.approx(-12.5, abs=1e-9) and hdb.cb[2][0] == pytest.approx(12.5, abs=1e-9)
        lin = linearize(scene.multibody_simulator().model)
        assert lin.equilibrium_residual < 1e-6 * weight, name


def test_radiation_kernel_reproduces_the_database() -> None:
    """The time-domain model's radiation (A_inf and B's continuation above 1.5 rad/s fitted to A(omega),
    ``added_mass_inf = "kramers_kronig"``) rebuilds every scene's A(omega) and B(omega) at the database's 50
    frequencies within 1 % on the check's scales (measured 0.006-0.009; 0.11-0.20 with Ogilvie's A_inf and the
    power law alone, docs/f3of.md). The fitted continuation reaches the hydro FMU through its spec unchanged."""
    import json

    for name in NAMES:
        scene = load_scene(scenario(name), log=None)
        assert scene.scenario.hydro.added_mass_inf == "kramers_kronig"
        model = scene.hydro_model()
        assert model.report.frequency_error < 0.01, (name, model.report.frequency_error)
        nodes, values = scene.tail_correction()
        sent = json.loads(json.dumps(scene.hydro_spec("database.h5")))["radiation"]["tail_correction"]
        np.testing.assert_array_equal(np.array(sent["nodes"]), nodes)
        np.testing.assert_array_equal(np.array(sent["values"]), values)


# ---------------------------------------------------------------------------------------- decays
DT3_WINDOW = (20.0, 400.0)  # s: from after the first cycle to the end (26 cycles of about 14 s)
# s: the linear-regime window starts after the radiation kernel's 240 s: before it the record carries the
# memory's non-modal start, which moves the mirror-wise mode's fitted damping ratio (1.6e-4, its amplitude
# falls 3 % over 380 s) by +8 % over 20-400 s (docs/f3of.md, decay tests); 85 cycles.
DT3_LINEAR_WINDOW = (300.0, 1500.0)


def mode_channels(data: dict) -> np.ndarray:
    """DT3's two modes: the device is mirror-symmetric fore and aft with the base fixed, so its two free
    modes are the flaps pitching the same way (half sum of the pitches) and mirror-wise, towards and
    away from each other (half difference); each channel then holds one mode."""
    a = data["bodies/flap1/displacement"][:, 4]
    b = data["bodies/flap2/displacement"][:, 4]
    return np.column_stack([(a + b) / 2, (a - b) / 2])


def dt3_modes(scene) -> tuple:
    """DT3's roots as (same way, mirror-wise), by the relative sign of the flap pitches in the mode shape."""
    coords = list(scene.multibody_simulator().model.coordinates)
    p1, p2 = coords.index(("flap1", 4)), coords.index(("flap2", 4))
    modes = natural_modes(scene)
    same = [m for m in modes if np.real(m.shape[p1] / m.shape[p2]) > 0]
    mirror = [m for m in modes if np.real(m.shape[p1] / m.shape[p2]) < 0]
    assert len(same) == len(mirror) == 1, [m.shape for m in modes]
    return same[0], mirror[0], (p1, p2)


def dt3_errors(data: dict, roots) -> list[tuple[float, float]]:
    """Per mode (same way, mirror-wise): relative errors of the period and damping ratio fitted to the
    time-domain channel over DT3_WINDOW against the linear model's root."""
    t, channels = data["time"], mode_channels(data)
    out = []
    for k, root in enumerate(roots):
        m = fit_decay(t, channels[:, k], 1, DT3_WINDOW).modes[0]
        out.append((m.period / root.period - 1, m.damping_ratio / root.damping_ratio - 1))
    return out


def dt3_linear_errors(data: dict, roots, window: tuple[float, float] = DT3_LINEAR_WINDOW,
                      sample: float = 0.5) -> list[tuple[float, float]]:
    """As :func:`dt3_errors`, with both modes fitted together to the two flap pitches (common complex
    frequencies, ``fit_decay`` on both channels, samples ``sample`` s apart): no assumption that the
    channels' half sum and half difference separate the modes (they do here: the roots' pitch amplitudes
    are equal to 2e-5). Fitted modes are matched to the roots by frequency."""
    t = data["time"]
    every = max(1, round(sample / (t[1] - t[0])))
    pitches = np.column_stack([data[f"bodies/{b}/displacement"][:, 4] for b in ("flap1", "flap2")])
    fit = fit_decay(t[::every], pitches[::every], 2, window)
    out = []
    for root in roots:
        m = min(fit.modes, key=lambda m: abs(m.omega - root.omega.real))
        out.append((m.period / root.period - 1, m.damping_ratio / root.damping_ratio - 1))
    return out


def test_dt3_modes_are_the_flaps_moving_the_same_way_and_mirror_wise() -> None:
    """The two free modes of DT3's linear model (roots of det Z with the time-domain model's radiation):
    equal flap pitch amplitudes; same sign (faster, radiating: the flaps' far fields add) and opposite
    sign (slower, almost undamped: the flaps push the water between them, more added inertia, and their
    far fields nearly cancel). Well conditioned (tail weight < 2), and equal to the database's own roots
    (first-order continuation of the tabulated A, B) within 1 % in period."""
    scene = load_scene(scenario("f3of_dt3"), log=None)
    same, mirror, (p1, p2) = dt3_modes(scene)
    for m in (same, mirror):
        assert abs(m.shape[p1]) == pytest.approx(abs(m.shape[p2]), rel=0.02)
        assert m.tail_weight < 2.0
    assert same.period < mirror.period and same.damping_ratio > 10 * mirror.damping_ratio
    table = sorted(database_modes(scene), key=lambda m: m.period)
    for kernel, tabulated in zip(sorted((same, mirror), key=lambda m: m.period), table, strict=True):
        assert kernel.period == pytest.approx(tabulated.period, rel=0.01)


def test_dt3_from_10_degrees_through_fmpy(tmp_path) -> None:
    """The scenario as bundled (FMUs through fmpy): both modes' periods within 1 % of the linear model's
    roots; damping ratios reported (from 10 deg the decay is measurably nonlinear, docs/f3of.md). The aft
    flap, moved only through the water, first swings against the fore flap's displacement and, the two
    modes being 4 % apart, takes over the motion at the beat (about 180 s): half the pitch amplitude or
    more. The hinge reactions are recorded; at rest the aft hinge holds the flap's net buoyancy down."""
    s = scenario("f3of_dt3", simulation__duration=DT3_WINDOW[1])
    data = run(s, tmp_path, in_process=False)
    scene = load_scene(s, log=None)
    same, mirror, _ = dt3_modes(scene)
    errors = dt3_errors(data, (same, mirror))
    print("DT3 10 deg, fmpy: roots (period, damping ratio)", [(m.period, m.damping_ratio) for m in (same, mirror)],
          "(period, damping) errors", errors)
    for period_error, damping_error in errors:
        assert abs(period_error) < 0.01, (period_error, damping_error)
    t = data["time"]
    fore, aft = data["bodies/flap1/displacement"][:, 4], data["bodies/flap2/displacement"][:, 4]
    # Against the fore flap's initial +10 deg on the modal time scale (theta_2 ~ -(w_s^2 - w_m^2) theta_0 t^2 / 4,
    # docs/f3of.md). The first second is set by the flaps' infinite-frequency cross-coupling, which the database
    # does not pin down (A_inf between the flap pitches: BEM -957, Ogilvie's fit -4.7e5, the Kramers-Kronig fit
    # +1.9e5 kg m^2, both fits absorbing shares of the damping above 1.5 rad/s; with the last the aft flap first
    # moves +0.03 deg for 1.2 s), so it is not asserted.
    early = (t >= 1.5) & (t <= 4.0)
    assert np.all(aft[early] < 0)
    beat = (t > 150) & (t < 250)
    assert np.abs(aft[beat]).max() > 0.5 * math.radians(10)
    assert np.abs(fore[beat]).max() < 0.5 * np.abs(aft[beat]).max() + 0.02
    hdb = scene.hdb
    net_buoyancy = hdb.rho * hdb.g * hdb.displaced_volume[2] - 179250.0 * hdb.g
    force = data["joints/hinge2/force"]
    assert force.shape == (len(t), 3)
    assert force[0, 2] == pytest.approx(-net_buoyancy, rel=0.02)  # aft flap at rest at t = 0


@pytest.mark.slow
@pytest.mark.parametrize("step", [pytest.param(0.05, marks=pytest.mark.acceptance), 0.025])
def test_dt3_linear_regime_periods_and_damping_and_step_convergence(tmp_path, step) -> None:
    """From 1 deg (linear regime: from 0.1 deg the damping ratios move by 0.01 %): periods and damping
    ratios of both modes against each step's own roots (the kernel is sampled at the step) within the
    issue's 1 %, fitted over DT3_LINEAR_WINDOW, after the radiation memory's non-modal start. The mirror-wise
    mode's damping ratio (1.6e-4: the flaps' far fields nearly cancel) is the smallest quantity of the F3OF
    decays; at the bundled 0.1 s step the run under-damps it by 2.8 % (same window), at 0.05 s by 0.4 %, so
    the test runs 0.05 s and 0.025 s (the step convergence, docs/f3of.md), as the RAO at 9 s runs the step
    that resolves the base's heave resonance."""
    s = flap1_from(scenario("f3of_dt3", simulation__duration=DT3_LINEAR_WINDOW[1], simulation__step=step), 1.0)
    data = run(s, tmp_path)
    errors = dt3_linear_errors(data, dt3_modes(load_scene(s, log=None))[:2])
    print(f"DT3 1 deg, step {step}: (period, damping) errors (same way, mirror-wise)", errors)
    for period_error, damping_error in errors:
        assert abs(period_error) < 0.01
        assert abs(damping_error) < 0.01


DT1_WINDOW = (400.0, 2000.0)  # s: after the kernel's 240 s, 34 cycles (docs/f3of.md: why so long)


@pytest.mark.slow
@pytest.mark.acceptance
def test_dt1_surge_decay(tmp_path) -> None:
    """DT1: the period and the damping ratio within the issue's 1 % of the linear model's root. The
    damping ratio, about 5e-4 (mostly the impulse response's low-frequency error: the database's own
    surge damping at 47 s gives 6e-6), changes the amplitude by only 3 % over the bundled 400 s; the fit
    then also sees the radiation memory's non-modal start (1.5 % off in damping over 20-400 s), so the
    record is 2000 s long and the fit starts after the kernel's length."""
    s = scenario("f3of_dt1", simulation__duration=DT1_WINDOW[1])
    data = run(s, tmp_path)
    (root,) = natural_modes(load_scene(s, log=None))
    m = fit_decay(data["time"], data["bodies/base/displacement"][:, 0], 1, DT1_WINDOW).modes[0]
    print("DT1", m.period, m.damping_ratio, root.period, root.damping_ratio)
    assert m.period == pytest.approx(root.period, rel=0.01)
    assert m.damping_ratio == pytest.approx(root.damping_ratio, rel=0.01)


@pytest.mark.slow
@pytest.mark.acceptance
def test_dt2_pitch_decay(tmp_path) -> None:
    """DT2 (damping ratio about 0.05: the kernel's continuation is ill-conditioned, tail weight > 100):
    against the exact linear free decay of the database's model, fitted the same way over the same
    cycles (4-60 s, about 7 periods), within 1 % in period and damping ratio."""
    s = scenario("f3of_dt2")
    data = run(s, tmp_path)
    t = data["time"]
    coords, exact = linear_decay(load_scene(s, log=None), t, omega_max=20.0)
    window = (4.0, 60.0)
    fd = fit_decay(t, exact[:, coords.index(("base", 4))], 1, window).modes[0]
    td = fit_decay(t, data["bodies/base/displacement"][:, 4], 1, window).modes[0]
    print("DT2", td.period, td.damping_ratio, fd.period, fd.damping_ratio)
    assert td.period == pytest.approx(fd.period, rel=0.01)
    assert td.damping_ratio == pytest.approx(fd.damping_ratio, rel=0.01)


# ---------------------------------------------------------------------------------------- RAO
RAO_COORDINATES = [("base", 0), ("base", 2), ("base", 4), ("flap1", 0), ("flap1", 2), ("flap1", 4),
                   ("flap2", 0), ("flap2", 2), ("flap2", 4)]


# (macro step s, run length s, free modes fitted) of the RAO runs where the bundled 0.1 s, 300 s and one
# free mode are not enough (docs/f3of.md, RAO). At 9 s the waves drive the base's heave resonance (0.70 rad/s,
# damping ratio 0.005, amplification about 100): the step's second-order period error shifts the resonance,
# and the fore flap's surge, a near-cancellation of the 20.8 m/m heave, moves by 21 % at 0.1 s, 5.2 % at
# 0.05 s, 1.4 % at 0.025 s and 0.5 % at 0.0125 s (T/720). At 6 and 7 s the forcing lies near the 6.64 s mode
# (damping ratio 0.027) besides the base heave (8.99 s) and the 48 s surge modes the ramp starts: the fit
# needs the three and a 600 s record to separate them, and base surge (the smallest coordinate at 6 s)
# carries a step error of 1.45 % at 0.1 s, 0.29 % at 0.05 s.
# The acceptance run (`pytest -m acceptance`) checks the periods that need their own step and run length.
ACCEPTANCE_PERIODS = (6.0, 9.0)
RAO_RUNS = {6.0: (0.025, 600.0, 3), 7.0: (0.025, 600.0, 3), 9.0: (0.0125, 300.0, 1)}


def rao_errors(tmp_path, period: float) -> tuple[np.ndarray, np.ndarray]:
    """(amplitude error, phase error deg) per coordinate of the time-domain steady state at ``period``
    against the exact linear answer with the database's A and B (the acceptance) and, for diagnosis,
    with the A and B of the truncated impulse response the time-domain model convolves. The lightly
    damped free modes started by the ramp (the base's heave near 9 s rings for minutes) are fitted out
    with the steady harmonic (``decay.fit_forced``)."""
    from orchestrator.reference import frequency_domain
    from orchestrator.reference.decay import fit_forced

    step, duration, modes = RAO_RUNS.get(period, (0.1, 300.0, 1))
    s = scenario("f3of_rao", simulation__duration=duration, simulation__step=step, simulation__error_tolerance=0.0,
                 simulation__error_estimate="none")  # the step this test pins (RAO_RUNS), no estimate
    s.waves.period = period
    data = run(s, tmp_path)
    omega = 2 * math.pi / period
    every = max(1, round(0.1 / step))  # the fit on samples 0.1 s apart (30 or more per period)
    x = np.column_stack([data[f"bodies/{b}/displacement"][::every, j] for b, j in RAO_COORDINATES])
    measured, free = fit_forced(data["time"][::every], x, omega, modes, (3 * period + 60.0, duration))
    scene = load_scene(s, log=None)
    out = []
    for radiation in ("database", "impulse_response"):
        fd = frequency_domain.solve(scene, np.array([omega]), radiation=radiation)
        exact = np.array([fd.body_rao(b)[0][j] for b, j in RAO_COORDINATES]) * s.waves.height / 2
        ratio = measured / exact
        out.append(np.column_stack([np.abs(ratio) - 1, np.degrees(np.angle(ratio))]))
    database, kernel = out
    print(f"T = {period:g} s: largest amplitude error {100 * np.abs(database[:, 0]).max():.2f} %, "
          f"phase {np.abs(database[:, 1]).max():.2f} deg (against the kernel's own A, B: "
          f"{100 * np.abs(kernel[:, 0]).max():.2f} %, {np.abs(kernel[:, 1]).max():.2f} deg); worst: "
          f"{RAO_COORDINATES[int(np.argmax(np.abs(database[:, 0])))]}, free mode fitted "
          f"{[(round(m.period, 2), round(m.damping_ratio, 4)) for m in free.modes]}")
    return database, kernel


def test_rao_at_10_s(tmp_path) -> None:
    """Surge, heave and pitch of the three bodies at T = 10 s within 1 % and 2 deg of the exact answer."""
    errors, _ = rao_errors(tmp_path, 10.0)
    assert np.all(np.abs(errors[:, 0]) < 0.01) and np.all(np.abs(errors[:, 1]) < 2.0), errors


@pytest.mark.slow
@pytest.mark.parametrize("period", [pytest.param(T, marks=pytest.mark.acceptance) if T in ACCEPTANCE_PERIODS else T
                                    for T in RAO_PERIODS if T != 10.0])
def test_rao_at_every_period(tmp_path, period) -> None:
    errors, _ = rao_errors(tmp_path, period)
    assert np.all(np.abs(errors[:, 0]) < 0.01) and np.all(np.abs(errors[:, 1]) < 2.0), errors
