"""Seed 003's hinge-barge across the tank tests' frequency range (2.61 to 7.85 rad/s): the
time-domain co-simulation's steady state against the exact linear frequency-domain answer.

Criterion (issue 7): within 1 % in amplitude and 2 degrees in phase for surge, heave and pitch of
both barges and the hinge's relative rotation (pitch of barge 2 minus pitch of barge 1: exact for
planar motion). The exact answer is ``orchestrator.frequency_domain.solve`` (the constrained system
on the null space of the linearised hinge, database A(omega) and B(omega)); the pseudo-spectral
solver with N = 1 reproduces it to 1e-8, so this also checks that solution.

Set-up per frequency: wave amplitude 1 cm (linear regime: barge 1 pitches at most 0.03 rad),
macro step T/100 (also the radiation grid), one generalised-alpha step per macro step, half-cosine
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
the diagnosis and the database change are in docs/hinge_barge_frequencies.md; ``python -m pytest -s
-m "slow or not slow" tests/test_hinge_barge_frequencies.py`` prints every number, about 4 minutes):

    omega rad/s   2.61   3.14   4.0    5.0    5.8    6.28   7.0    7.85
    amplitude %   0.07   0.08   0.37   0.45   0.17   0.26   0.40   1.83 (barge 2 pitch)
    phase deg     0.03   0.03   0.29   0.13   0.12   0.04   0.31   1.16

with the scenario's ``hydro.added_mass_inf = "ogilvie"`` (A_inf consistent with the database's A and
B; with Capytaine's own A_inf, 7.0 rad/s was 1.25 % off in surge and 7.85 rad/s 7 %). 7.85 rad/s
still fails the criterion in one quantity (strict xfail): the database's A(omega) and B(omega) are
not Kramers-Kronig consistent to 1 % next to the 0.46 m gap's resonance (8.9 rad/s), so no causal
time-domain model reproduces the database answer there; the runs match the exact answer of their
own radiation model (impulse-response A and B) within 0.16 % / 0.12 deg (7.0) and 0.68 % / 0.35 deg
(7.85), asserted separately.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

from orchestrator import frequency_domain, study
from orchestrator.analysis import harmonic_fit
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

from .conftest import SCENARIOS

SCENARIO = SCENARIOS / "hinge_barge.toml"
AMPLITUDE = 0.01  # m
STEPS_PER_PERIOD = 100
RAMP = 8.0  # s
SETTLE = 6.0  # s after the ramp
# At 7.85 rad/s the forced heave and pitch are small (0.2 mm, 0.2 mrad per cm of wave) and the lightly damped surge
# mode at 9.3 rad/s rings for long: a 6 s settle leaves it at 1.5 % of barge 1's pitch, 40 s at 0.3 % (measured).
SETTLE_BY_OMEGA = {7.85: 40.0}
FIT = 10  # periods
LABELS = ("barge1 surge", "barge1 heave", "barge1 pitch", "barge2 surge", "barge2 heave", "barge2 pitch",
          "hinge rotation")


@functools.cache
def steady_state(omega: float, *, in_process: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(measured, exact, exact of the time-domain model) complex amplitudes in LABELS order
    (exp(+i omega t), m and rad). The last is the frequency-domain answer with the radiation
    coefficients of the truncated, sampled impulse response the time-domain model uses
    (``radiation="impulse_response"``): it separates the time-stepping error from the database's."""
    period = 2 * math.pi / omega
    s = load_scenario(SCENARIO)
    s.waves.height = 2 * AMPLITUDE
    s.waves.period = period
    s.waves.ramp_time = RAMP
    s.simulation.step = period / STEPS_PER_PERIOD
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


def check(omega: float, *, in_process: bool, reference: str = "database") -> None:
    measured, exact, own = steady_state(omega, in_process=in_process)
    target = exact if reference == "database" else own
    amplitude, phase = errors(measured, target)
    print(f"\nomega = {omega} rad/s against the {reference} answer: " + ", ".join(
        f"{label} {100 * a:+.2f} % {p:+.2f} deg" for label, a, p in zip(LABELS, amplitude, phase, strict=True)))
    bad = [f"{label}: {100 * a:+.2f} %, {p:+.2f} deg (exact {abs(e):.3g})"
           for label, a, p, e in zip(LABELS, amplitude, phase, target, strict=True) if abs(a) > 0.01 or abs(p) > 2.0]
    assert not bad, f"omega = {omega} rad/s: " + "; ".join(bad)


def test_cosimulated_hinge_barge_matches_the_exact_answer_mid_range() -> None:
    """FMUs through fmpy at 5.8 rad/s (the top of the range where seed 003's model matched the tank)."""
    check(5.8, in_process=False)


DATABASE_LIMIT = pytest.mark.xfail(strict=True, reason=(
    "barge 2's pitch is 1.8 % off at 7.85 rad/s (all else within 1 % and 2 deg): the database's A(omega) and "
    "B(omega) are not consistent (Kramers-Kronig) to 1 % next to the gap resonance at 8.9 rad/s, even with "
    "the Ogilvie-consistent A_inf, so the causal time-domain model cannot reproduce A there; the run itself "
    "matches its own exact answer (test_..._matches_the_exact_answer_of_its_own_radiation_model)"))


@pytest.mark.slow
@pytest.mark.parametrize("omega", [2.61, 3.14, 4.0, 5.0, 6.28, 7.0, pytest.param(7.85, marks=DATABASE_LIMIT)])
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
