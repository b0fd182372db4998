"""Master building blocks: step-averaged extrapolation weights."""

from __future__ import annotations

import numpy as np
import pytest

from orchestrator.masters import step_average_weights


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
