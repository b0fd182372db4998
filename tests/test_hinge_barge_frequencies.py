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
the diagnosis and the database changes are in docs/hinge_barge_frequencies.md; ``python -m pytest -s
-m "slow or not slow" tests/test_hinge_barge_frequencies.py`` prints every number, about 2-4 minutes):

    omega rad/s   2.61   3.14   4.0    5.0    5.8    6.28   7.0    7.85
    amplitude %   0.08   0.07   0.34   0.08   0.14   0.18   0.34   1.27 (barge 2 pitch, hinge rotation)
    phase deg     0.02   0.04   0.33   0.12   0.10   0.08   0.28   0.58

with the scenario's database (0.1 rad/s grid to 11 rad/s, 0.02 rad/s across the gap resonance at 8.9 rad/s),
the Ogilvie-consistent A_inf, the damping tail and a 30 s impulse response. 7.85 rad/s fails the criterion in
two quantities (strict xfail): there the exact answer itself is defined by the database only to about 4 %
(reading its slightly asymmetric A and B transposed moves the hinge rotation by 4.5 %, asserted in
test_the_database_defines_the_answer_to_its_own_asymmetry): both pitch responses nearly cancel there, and
barge 2's moves 1 % per 0.1 kg m of the barge 2 surge-pitch added mass, whose two BEM entries differ by 0.18
kg m.
The runs match the exact answer of their own radiation model (impulse-response A and B) within 0.16 % /
0.16 deg (7.0) and 0.72 % / 0.36 deg (7.85), asserted separately.
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np
import pytest

from orchestrator import frequency_domain, study
from orchestrator.analysis import harmonic_fit
from orchestrator.scenario import load_scenario
from orchestrator.scene import Scene, load_scene

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
    "at 7.85 rad/s the database does not define the exact answer to 1 %: reading its A and B transposed (equally "
    "valid, the true coefficients are symmetric) moves the answer by more than 2 % "
    "(test_the_database_defines_the_answer_to_its_own_asymmetry); the run matches its own radiation model's exact "
    "answer (test_..._matches_the_exact_answer_of_its_own_radiation_model)"))


def test_the_database_defines_the_answer_to_its_own_asymmetry() -> None:
    """The exact answer is only as precise as the database. Radiation coefficients are symmetric (reciprocity);
    a BEM's are not quite, and A_ij or A_ji is an equally valid reading. The exact answer with A and B transposed
    differs from the one with A and B as given by less than 1 % and 1 deg up to 7.0 rad/s, where the time-domain
    criterion is met, and by more than 2 % at 7.85 rad/s, where both pitch responses nearly cancel: there the
    1 % criterion is below the data's own precision, which is why that case is an xfail."""
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
    assert np.all(amplitude[:-1] < 0.01) and np.all(phase[:-1] < 1.0)
    assert amplitude[-1] > 0.02


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
