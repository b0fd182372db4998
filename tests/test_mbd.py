"""Linear multibody model and its exact integrator."""

from __future__ import annotations

import numpy as np
import pytest

from mbd_fmu import LinearMultibodySystem, LinearPTO, RigidBody


def oscillator(mass=2.0, k=50.0, c=3.0, added=1.5) -> LinearMultibodySystem:
    body = RigidBody("b", mass, np.eye(3), np.zeros(3), dofs=(2,))
    pto = LinearPTO("p", "b", 2, stiffness=k, damping=c)
    return LinearMultibodySystem([body], [pto], np.array([[added]]), [("b", 2)])


def test_zero_order_hold_step_is_exact_for_a_damped_oscillator() -> None:
    """m x'' + c x' + k x = F (constant): closed-form solution, any step size."""
    m, k, c, f = 3.5, 50.0, 3.0, 7.0  # m includes the added mass
    sys = oscillator()
    sys.set_state(np.array([0.1]), np.array([-0.2]))
    wn, zeta = np.sqrt(k / m), c / (2 * np.sqrt(k * m))
    wd = wn * np.sqrt(1 - zeta**2)
    xs = f / k
    a, b = 0.1 - xs, (-0.2 + zeta * wn * (0.1 - xs)) / wd
    t = 0.0
    for h in (0.5, 1.3, 0.01, 2.0):  # large and uneven steps: still exact
        sys.step(h, np.array([f]))
        t += h
        exact = xs + np.exp(-zeta * wn * t) * (a * np.cos(wd * t) + b * np.sin(wd * t))
        assert sys.q[0] == pytest.approx(exact, rel=1e-12, abs=1e-14)


def test_added_mass_between_bodies_enters_the_mass_matrix() -> None:
    bodies = [RigidBody("a", 1.0, np.eye(3), np.zeros(3), (0, 2)), RigidBody("arm", 2.0, np.eye(3), np.zeros(3), (2,)),
              RigidBody("c", 3.0, np.eye(3), np.zeros(3), (2,))]
    a_inf = np.array([[10.0, 1.0, 2.0], [1.0, 20.0, 3.0], [2.0, 3.0, 30.0]])
    sys = LinearMultibodySystem(bodies, [], a_inf, [("a", 0), ("a", 2), ("c", 2)])
    expected = np.diag([1.0, 1.0, 2.0, 3.0])
    expected[np.ix_([0, 1, 3], [0, 1, 3])] += a_inf  # the link arm has no hydrodynamics
    np.testing.assert_array_equal(sys.mass, expected)


def test_pto_power_is_absorbed_power() -> None:
    pto = LinearPTO("p", "b", 2, stiffness=10.0, damping=4.0)
    assert pto.force(0.5, 2.0) == pytest.approx(-10 * 0.5 - 4 * 2.0)
    assert pto.power(0.5, 2.0) == pytest.approx(10 * 0.5 * 2.0 + 4 * 2.0**2)


@pytest.mark.parametrize("kwargs, message", [
    ({"mass": 0.0}, "mass must be positive"),
    ({"inertia": np.array([[1, 2, 0], [0, 1, 0], [0, 0, 1.0]])}, "not symmetric"),
    ({"dofs": (2, 1)}, "increasing"),
])
def test_invalid_bodies_are_rejected(kwargs, message) -> None:
    args = {"name": "b", "mass": 1.0, "inertia": np.eye(3), "cg": np.zeros(3), "dofs": (1, 2)} | kwargs
    with pytest.raises(ValueError, match=message):
        RigidBody(**args)


def test_pto_commands_change_the_law_between_steps() -> None:
    """A constant commanded force u moves the equilibrium to x = u / k; new gains take effect."""
    sys = oscillator(k=50.0, c=30.0)
    sys.set_pto_commands(np.array([50.0]), np.array([30.0]), np.array([5.0]))
    for _ in range(400):
        sys.step(0.1, np.zeros(1))
    assert sys.q[0] == pytest.approx(5.0 / 50.0, rel=1e-9)
    sys.set_pto_commands(np.array([100.0]), np.array([30.0]), np.array([5.0]))
    for _ in range(400):
        sys.step(0.1, np.zeros(1))
    assert sys.q[0] == pytest.approx(5.0 / 100.0, rel=1e-9)
    assert sys.pto_forces()[0] == pytest.approx(0.0, abs=1e-8)  # at rest the PTO balances its command
