"""Decay-record fits (orchestrator.reference.decay): exact recovery of known damped modes."""

from __future__ import annotations

import math

import numpy as np
import pytest

from orchestrator.reference.decay import fit_decay


def test_fit_recovers_two_close_damped_modes_and_an_offset() -> None:
    """Two modes 3 % apart in frequency (two coupled flaps), damping ratios 0.12 and 0.05, different
    amplitudes on two channels, a constant offset: the fit returns them to round-off."""
    t = np.arange(0.0, 60.0, 0.1)
    modes = [(0.60, 0.12), (0.62, 0.05)]
    x = np.zeros((len(t), 2))
    for (wn, zeta), amps in zip(modes, [(1.0, 0.8), (0.7, -0.9)], strict=True):
        sigma, wd = zeta * wn, wn * math.sqrt(1 - zeta**2)
        for j, a in enumerate(amps):
            x[:, j] += a * np.exp(-sigma * t) * np.cos(wd * t + 0.3 * j)
    x += [0.01, -0.02]
    fit = fit_decay(t, x, 2, (5.0, 50.0))
    assert fit.residual < 1e-9
    for mode, (wn, zeta) in zip(fit.modes, modes, strict=True):
        assert mode.damping_ratio == pytest.approx(zeta, rel=1e-8)
        assert mode.period == pytest.approx(2 * math.pi / (wn * math.sqrt(1 - zeta**2)), rel=1e-9)


def test_fit_of_too_few_oscillations_is_an_error() -> None:
    t = np.arange(0.0, 10.0, 0.1)
    with pytest.raises(ValueError, match="fewer than 2 oscillating modes"):
        fit_decay(t, np.exp(-0.1 * t), 2, (0.0, 10.0))


def test_natural_mode_of_a_damped_float_without_memory_is_the_oscillator_root() -> None:
    """With the radiation memory switched off the floating cylinder in heave is a damped oscillator,
    (m + A_inf) x'' + c x' + C33 x = 0: its root is w = sqrt(k/M - (c / 2M)^2) + i c / 2M exactly.
    With the memory on, the kernel's impedance on the real axis equals the frequency-domain solver's
    ``radiation="impulse_response"`` impedance; and for the lightly damped float (PTO off) the database's
    first-order root agrees with the kernel's to 1 % in period and 5 % in damping ratio."""
    from orchestrator.reference.decay import ModalImpedance, database_modes, natural_modes
    from orchestrator.reference.frequency_domain import linear_model
    from orchestrator.scenario import load_scenario
    from orchestrator.scene import load_scene

    from .conftest import SCENARIOS

    s = load_scenario(SCENARIOS / "cylinder_regular.toml")
    s.hydro.radiation = False
    scene = load_scene(s, log=None)
    mass = scene.body_mass(s.bodies[0]) + scene.hdb.added_mass_inf[2, 2]
    k, c = scene.hdb.hydrostatic_stiffness[0, 2, 2], s.ptos[0].damping
    (mode,) = natural_modes(scene)
    assert mode.omega.imag == pytest.approx(c / (2 * mass), rel=1e-9)
    assert mode.omega.real == pytest.approx(math.sqrt(k / mass - (c / (2 * mass)) ** 2), rel=1e-9)

    s.hydro.radiation = True
    scene = load_scene(s, log=None)
    z = ModalImpedance(scene)
    w = np.array([0.5, 1.1, 2.3])
    reference = linear_model(scene, w, radiation="impulse_response").impedance
    np.testing.assert_allclose([z(x) for x in w], reference, rtol=1e-10)
    # The continuation is well conditioned only for a lightly damped mode (module docstring: tail weight
    # exp(sigma T_K) near 1). With the PTO the mode's damping ratio is 0.18 and the tail weight about 5e3,
    # so the two roots are compared on the undamped-PTO float (damping ratio 0.035, radiation only).
    s.ptos[0].damping = 0.0
    scene = load_scene(s, log=None)
    (kernel,), (table,) = natural_modes(scene), database_modes(scene)
    assert kernel.tail_weight < 10.0
    assert kernel.period == pytest.approx(table.period, rel=0.01)
    assert kernel.damping_ratio == pytest.approx(table.damping_ratio, rel=0.05)


def test_fit_recovers_an_almost_undamped_mode_beside_a_close_damped_one_on_two_channels() -> None:
    """F3OF DT3's regime: two modes 3 % apart in frequency, damping ratios 1.75e-4 (the flaps mirror-wise:
    the amplitude falls only 9 % over the window) and 3.9e-3 (the same way), on the two flap pitches with
    a 2 % asymmetry of the same-way mode between them and an offset decaying over 1000 s that the fit's
    constant does not model. Fitted together on both channels (common frequencies) the two damping ratios
    come back within 0.1 % over the 300-1500 s window of the slow DT3 test; the half difference of the
    channels fitted with one mode would be 4 % off (the same-way share that leaks into it beats with the
    mirror-wise mode: asserted, so the signal does discriminate)."""
    t = np.arange(0.0, 1500.0 + 1e-9, 1.0)
    mirror, same = complex(0.44269, 7.753e-5), complex(0.45707, 1.7693e-3)
    m = 5e-3 * np.exp(1j * mirror * t).real
    s = 5e-3 * np.exp(1j * (same * t + 0.3)).real
    offset = 1e-4 * np.exp(-t / 1000.0)
    x = np.column_stack([m + 1.02 * s + offset, -m + 0.98 * s + offset])
    fit = fit_decay(t, x, 2, (300.0, 1500.0))
    for mode, root in zip(fit.modes, (mirror, same), strict=True):
        assert mode.damping_ratio == pytest.approx(root.imag / abs(root), rel=1e-3)
        assert mode.period == pytest.approx(2 * math.pi / root.real, rel=1e-6)
    half_difference = fit_decay(t, (x[:, 0] - x[:, 1]) / 2, 1, (300.0, 1500.0)).modes[0]
    assert abs(half_difference.damping_ratio / (mirror.imag / abs(mirror)) - 1) > 0.01
