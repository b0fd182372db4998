"""Master building blocks: step-averaged extrapolation weights."""

from __future__ import annotations

import numpy as np
import pytest

from orchestrator.cosim.masters import step_average_weights


@pytest.mark.parametrize("p", [0, 1, 2])
def test_weights_average_polynomials_of_their_degree_exactly(p) -> None:
    h, tau = 0.3, [0.0, -0.3, -0.7][: p + 1]  # uneven history steps
    w = step_average_weights(tau, h)
    for degree in range(p + 1):
        samples = np.array(tau) ** degree
        exact = h**degree / (degree + 1)  # (1/h) int_0^h s^degree ds
        assert w @ samples == pytest.approx(exact, rel=1e-12, abs=1e-15)


def test_uniform_weights_match_the_documented_formulas() -> None:
    np.testing.assert_allclose(step_average_weights([0, -1], 1.0), [1.5, -0.5])
    # u_n + (u_n - u_{n-1})/2 + 5/12 (u_n - 2 u_{n-1} + u_{n-2})
    np.testing.assert_allclose(step_average_weights([0, -1, -2], 1.0), [1 + 0.5 + 5 / 12, -0.5 - 10 / 12, 5 / 12])


class _Outputs:
    """A component that only publishes the values a test puts in it (for the master's read check)."""

    feedthrough = False

    def __init__(self, names: list[str]) -> None:
        self.values = np.zeros(len(names))

    def port(self, names: list[str]):  # noqa: ANN201
        from orchestrator.fmi.components import Port

        return Port(list(names), list(range(len(names))))

    def get_reals(self, port) -> np.ndarray:  # noqa: ANN001
        return self.values.copy()


def test_a_read_stops_on_each_value_beyond_its_limit_or_not_finite_and_only_then() -> None:
    """The divergence check's one-dot-product screen (sum of |value| / limit <= 1) never lets a bad value through
    and never stops a run whose values are each within their limits, whatever their sum."""
    from orchestrator.cosim.masters import JacobiMaster, MasterSettings
    from orchestrator.errors import MasterError

    names = ["x", "v", "energy.kinetic"]
    comp = _Outputs(names)
    master = JacobiMaster({"a": comp}, [], observe={"a": names}, settings=MasterSettings(energy_scale=10.0))
    comp.values[:] = [2.0, 0.0, 0.0]  # first read: limits 1e8 * (2, 1, 10)
    master._read("a")
    for ok in ([1.9e8, 0.9e8, 9e8], [-2e8, -1e8, 1e9], [0.0, 0.0, 0.0]):
        comp.values[:] = ok
        np.testing.assert_array_equal(master._read("a"), ok)
    for bad, message in (([2.0000001e8, 0.0, 0.0], "output x exceeds 2e\\+08"),
                         ([0.0, -1.0000001e8, 0.0], "output v exceeds 1e\\+08"),
                         ([0.0, 0.0, 1.0000001e9], "output energy.kinetic exceeds 1e\\+09"),
                         ([0.0, np.nan, 0.0], "output v is not finite"),
                         ([1.0, 1.0, -np.inf], "output energy.kinetic is not finite")):
        comp.values[:] = bad
        with pytest.raises(MasterError, match=message):
            master._read("a")
