"""Seed 003's hinge-barge across the tank tests' frequency range (2.61 to 7.85 rad/s): the
time-domain co-simulation's steady state against the exact linear frequency-domain answer.

Criterion (issue 7): within 1 % in amplitude and 2 degrees in phase for surge, heave and pitch of
both barges and the hinge's relative rotation (pitch of barge 2 minus pitch of barge 1: exact for
planar motion). The exact answer is ``orchestrator.reference.frequency_domain.solve`` (the constrained system
on the null space of the linearised hinge, database A(omega) and B(omega)); the pseudo-spectral
solver with N = 1 reproduces it to 1e-8, so this also checks that solution.

Set-up per frequency: wave amplitude 1 cm (linear regime: barge 1 pitches at most 0.03 rad),
macro step T/200 (T/100 for the fmpy run at 5.8 rad/s; the macro step is also the radiation grid), one
generalised-alpha step per macro step, half-cosine
ramp RAMP s (a long ramp puts little energy into the free modes: the lightest, barge 1's surge on
its mooring at 9.3 rad/s, has a damping ratio of about 0.003, time constant about 36 s), then
SETTLE s for the remaining transient, then the fit over the last FIT periods (``harmonic_fit``).
Free modes of the linearised system (natural frequency / damping ratio, from Z(omega) at the
mode): 4.8 / 0.13, 5.8 / 0.20, 8.5 / 0.05, 9.3 / 0.003 (surge).

Which run is which: the default-suite frequency runs the two FMUs through fmpy; the slow ones call
the same FMUs' slave classes in-process (``in_process=True``: the FMUs are built and unpacked and
their slave objects stepped by the same Jacobi master without the FMI C layer: same physics,
same variables).

Measured (largest amplitude error over the seven quantities, largest phase error; the full table,
the diagnosis and the database history are in docs/hinge_barge_frequencies.md; ``python -m pytest -s
-m "slow or not slow" tests/test_hinge_barge_frequencies.py`` prints every number, about 5 minutes):

    omega rad/s   2.61   3.14   4.0    5.0    5.8    6.28   7.0    7.85
    amplitude %   see docs/hinge_barge_frequencies.md (largest 0.81 at 7.85 rad/s, barge 2 pitch)

with the scenario's database (0.03 m panels, 0.1 rad/s grid to 14 rad/s, 0.04 rad/s across the gap resonance at
8.9 rad/s), the Ogilvie-consistent A_inf, the damping tail and a 30 s impulse response. 7.85 rad/s is the hard
case: both pitch responses nearly cancel there, so the answer is sensitive to the coefficients (barge 2's pitch
moves 1 % per 0.1 kg m of its surge-pitch added mass) and relative time-stepping errors are large (0.70 % at
T/100, 0.20 % at T/200: second order, asserted). With the earlier 0.05 m database the two BEM entries of that
coefficient differed by 0.18 kg m and the exact answer itself was defined only to 4.5 % there; at 0.03 m they
differ by 0.05 kg m and reading the database transposed moves the answer by at most 0.4 % (asserted).
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np
import pytest

from orchestrator.cosim import study
from orchestrator.reference import frequency_domain
from orchestrator.results.analysis import harmonic_fit
from orchestrator.scenario import load_scenario
from orchestrator.scene import Scene, load_scene

from .conftest import SCENARIOS

SCENARIO = SCENARIOS / "hinge_barge.toml"
AMPLITUDE = 0.01  # m
# The slow sweep's step. At T/100 the time-stepping error at 7.85 rad/s is 0.70 % of barge 2's (tiny) pitch and the
# run misses the 1 % criterion there (1.34 %); at T/200 it is 0.20 % (docs/hinge_barge_frequencies.md).
STEPS_PER_PERIOD = 200
FMU_STEPS_PER_PERIOD = 100  # the default-suite fmpy run at 5.8 rad/s (within 0.11 % at T/100)
RAMP = 8.0  # s
SETTLE = 6.0  # s after the ramp
# At 7.85 rad/s the forced heave and pitch are small (0.2 mm, 0.2 mrad per cm of wave) and the lightly damped surge
# mode at 9.3 rad/s rings for long: a 6 s settle leaves it at 1.5 % of barge 1's pitch, 40 s at 0.3 % (measured).
SETTLE_BY_OMEGA = {7.85: 40.0}
FIT = 10  # periods
LABELS = ("barge1 surge", "barge1 heave", "barge1 pitch", "barge2 surge", "barge2 heave", "barge2 pitch",
          "hinge rotation")


@functools.cache
def steady_state(omega: float, *, in_process: bool, steps_per_period: int = STEPS_PER_PERIOD,
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(measured, exact, exact of the time-domain model) complex amplitudes in LABELS order
    (exp(+i omega t), m and rad). The last is the frequency-domain answer with the radiation
    coefficients of the truncated, sampled impulse response the time-domain model uses
    (``radiation="impulse_response"``): it separates the time-stepping error from the database's."""
    period = 2 * math.pi / omega
    s = load_scenario(SCENARIO)
    s.waves.height = 2 * AMPLITUDE
    s.waves.period = period
    s.waves.ramp_time = RAMP
    s.simulation.step = period / steps_per_period
    s.multibody.max_step = s.simulation.step
    periods = math.ceil((RAMP + SETTLE_BY_OMEGA.get(omega, SETTLE)) / period) + FIT
    s.simulation.duration = periods * period
    scene = load_scene(s, log=None)
    series = study.run_series(study.variant(s, "jacobi", s.simulation.step), scene=scene, in_process=in_process)
    t, x = series.time, series.displacement  # columns: barge1 surge, heave, pitch, barge2 surge, heave, pitch
    x = np.column_stack([x, x[:, 5] - x[:, 2]])
    mask = t >= t[-1] - FIT * period - 1e-9 * period
    measured = np.array([harmonic_fit(t[mask], x[mask, j], omega)[0] for j in range(len(LABELS))])

    def amplitudes(**kwargs) -> np.ndarray:
        rao = frequency_domain.solve(scene, np.array([omega]), **kwargs).rao[0]
        return AMPLITUDE * np.concatenate([rao, [rao[5] - rao[2]]])

    return measured, amplitudes(), amplitudes(radiation="impulse_response", dt=s.simulation.step)


def errors(measured: np.ndarray, exact: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return np.abs(measured) / np.abs(exact) - 1, np.degrees(np.angle(measured / exact))


def check(omega: float, *, in_process: bool, reference: str = "database",
          steps_per_period: int = STEPS_PER_PERIOD) -> None:
    measured, exact, own = steady_state(omega, in_process=in_process, steps_per_period=steps_per_period)
    target = exact if reference == "database" else own
    amplitude, phase = errors(measured, target)
    print(f"\nomega = {omega} rad/s against the {reference} answer: " + ", ".join(
        f"{label} {100 * a:+.2f} % {p:+.2f} deg" for label, a, p in zip(LABELS, amplitude, phase, strict=True)))
    bad = [f"{label}: {100 * a:+.2f} %, {p:+.2f} deg (exact {abs(e):.3g})"
           for label, a, p, e in zip(LABELS, amplitude, phase, target, strict=True) if abs(a) > 0.01 or abs(p) > 2.0]
    assert not bad, f"omega = {omega} rad/s: " + "; ".join(bad)


def test_cosimulated_hinge_barge_matches_the_exact_answer_mid_range() -> None:
    """FMUs through fmpy at 5.8 rad/s (the top of the range where seed 003's model matched the tank)."""
    check(5.8, in_process=False, steps_per_period=FMU_STEPS_PER_PERIOD)


def test_the_database_defines_the_answer_better_than_the_criterion() -> None:
    """The exact answer is only as precise as the database. Radiation coefficients are symmetric (reciprocity);
    a BEM's are not quite, and A_ij or A_ji is an equally valid reading. For the 1 % / 2 deg comparison to be
    decidable the two readings must give answers much closer than that: the exact answer with A and B transposed
    differs from the one with A and B as given by less than half the criterion (0.5 %, 1 deg) at every tested
    frequency. The 0.05 m database failed this at 7.85 rad/s (4.5 %): there both pitch responses nearly cancel,
    and the two entries of barge 2's surge-pitch added mass differed by 0.18 kg m (0.05 at 0.03 m)."""
    scene = load_scene(load_scenario(SCENARIO), log=None)
    omega = np.array([2.61, 3.14, 4.0, 5.8, 6.28, 7.0, 7.85])
    hdb = scene.hdb
    swapped = dataclasses.replace(hdb, added_mass=np.swapaxes(hdb.added_mass, 1, 2),
                                  radiation_damping=np.swapaxes(hdb.radiation_damping, 1, 2))
    given = frequency_domain.solve(scene, omega).rao
    other = frequency_domain.solve(Scene(scene.scenario, swapped, scene.hdb_file), omega).rao
    given, other = (np.column_stack([x, x[:, 5] - x[:, 2]]) for x in (given, other))
    amplitude = np.max(np.abs(np.abs(other) / np.abs(given) - 1), axis=1)
    phase = np.max(np.abs(np.degrees(np.angle(other / given))), axis=1)
    print("\n" + "\n".join(f"omega {w}: transposed database moves the answer by {100 * a:.2f} %, {p:.2f} deg"
                             for w, a, p in zip(omega, amplitude, phase, strict=True)))
    assert np.all(amplitude < 0.005) and np.all(phase < 1.0)


@pytest.mark.slow
@pytest.mark.parametrize("omega", [2.61, 3.14, 4.0, 5.0, 6.28, 7.0, 7.85])
def test_hinge_barge_steady_state_across_the_tested_range(omega: float) -> None:
    """The rest of the tank tests' range, same criterion (in-process slaves)."""
    check(omega, in_process=True)


@pytest.mark.slow
@pytest.mark.parametrize("omega", [2.61, 7.0, 7.85])
def test_hinge_barge_matches_the_exact_answer_of_its_own_radiation_model(omega: float) -> None:
    """Against the frequency-domain answer with the impulse response's own A and B: the time stepping
    (coupling, generalised-alpha, convolution) is right across the range, including where the
    database limits the comparison above."""
    check(omega, in_process=True, reference="impulse response")


@pytest.mark.slow
def test_time_stepping_error_at_7_85_converges_at_second_order() -> None:
    """At 7.85 rad/s, where the responses are smallest and the comparison hardest, the run's error against its own
    radiation model's exact answer is time-stepping error: halving the macro step (T/50 -> T/100; the radiation
    grid and the generalised-alpha step follow) must divide it by about 4 (second order: generalised-alpha, the
    trapezoidal convolution and quadratic extrapolation are all second order). Measured on barge 2's pitch:
    2.72 % (T/50), 0.70 % (T/100), 0.20 % (T/200). T/50 and T/100 keep the fit's error floor (about 0.05 %) small
    against the errors compared."""
    worst = []
    for steps in (50, 100):
        measured, _, own = steady_state(7.85, in_process=True, steps_per_period=steps)
        worst.append(np.max(np.abs(measured / own - 1)))
    order = math.log2(worst[0] / worst[1])
    print(f"\n7.85 rad/s, largest complex error against the own-model answer: T/50 {100 * worst[0]:.2f} %, "
          f"T/100 {100 * worst[1]:.2f} %, observed order {order:.2f}")
    assert order > 1.7
