"""How well the truncated radiation impulse response reproduces the database, and what that means for a run.

The radiation force of the convolution model is F_r = -A_inf x'' - int_0^T K(tau) x'(t - tau) dtau, with K the
impulse response of B(omega) (:mod:`hydro_fmu.radiation`) on [0, T] (``hydro.irf_duration``), sampled at the
step dt. In the frequency domain its memory part is the impedance

    K^(omega) = dt-trapezoid of int_0^T K(t) exp(-i omega t) dt,   Re K^ = B(omega),  Im K^ = omega (A(omega) - A_inf)

for an exact, untruncated kernel. Two numbers compare K^ with the database's B(omega) and A(omega) - A_inf:

* the **impedance error** (what the hydro FMU reports as ``radiation.frequency_error``): for each pair of degrees of
  freedom the 2-norm over the database's frequencies of the difference of [B; omega (A - A_inf)], divided by the
  same norm of the diagonal entries sqrt(s_i s_j); dimensionless, the largest over the pairs. It says how well the
  memory force is reproduced *relative to the memory force itself*. It is large where that force is itself small
  (a deep heave plate radiates almost nothing; surge of a long barge at high frequency), so alone it does not say
  whether a run is at risk.
* the **share of the inertia**: on each diagonal entry, max over the database's frequencies of
  |K^_ii(omega) - K^_db,ii(omega)| / (omega (M_ii + A_inf,ii)), with M_ii + A_inf,ii the inertia a force on that
  degree of freedom meets (its structural mass or moment of inertia with A_inf, and, for a body tied to others by
  joints, theirs too: 1 / [P (P^T M P)^-1 P^T]_ii with P the null space of the constraints; ``Scene.radiation_check``):
  the error of the radiation force as a fraction of the inertia force of the same motion.
  An error that acts like an added mass of this share changes a response by about the share away from resonance,
  and by up to share / (2 zeta) at a resonance of damping ratio zeta (the natural frequency moves by half the
  share; the response at the old peak drops by the square of that shift over 2 zeta). A run is at risk when the
  share is above 1 % (:data:`INERTIA_SHARE_AT_RISK`; measured effect in ``benchmarks/results/irf_check.txt``).

What to change when it is: a longer ``hydro.irf_duration`` (memory cut too early; keep it below pi / d_omega of
the database), ``hydro.damping_tail`` (B cut at the database's last frequency leaves out part of A(omega) - A_inf),
``hydro.added_mass_inf = "kramers_kronig"`` (the BEM's A_inf not consistent with its A(omega)), or a database
over a wider frequency range.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .radiation import impulse_response, kernel_table

INERTIA_SHARE_AT_RISK = 0.01


@dataclass
class ImpedanceCheck:
    """Per diagonal entry (one per degree of freedom): ``impedance_error`` (dimensionless, module docstring), the
    part it is mostly in (``"A - A_inf"`` or ``"B"``) and ``inertia_share`` (dimensionless); ``labels`` name them."""

    labels: list[str]
    impedance_error: np.ndarray
    part: list[str]
    inertia_share: np.ndarray
    at_omega: np.ndarray  # frequency of each entry's largest share (rad/s)
    band: tuple[float, float]  # the frequencies the share was taken over (rad/s)

    @property
    def worst(self) -> int:
        """Index of the entry with the largest share of the inertia."""
        return int(np.argmax(self.inertia_share))

    def text(self, reported: float) -> str:
        """One paragraph for the run's summary; ``reported`` is the hydro FMU's impedance error over all pairs."""
        k = self.worst
        e = int(np.argmax(self.impedance_error))
        share = self.inertia_share[k]
        verdict = ("a result is at risk" if share > INERTIA_SHARE_AT_RISK else "below the 1 % at which a result is "
                   "at risk")
        advice = (": lengthen hydro.irf_duration, set hydro.damping_tail, or hydro.added_mass_inf = "
                  "\"kramers_kronig\" (docs/hydrodynamics.md, \"Checking the impulse response\")"
                  if share > INERTIA_SHARE_AT_RISK else "")
        return (f"  the impulse response's memory impedance B + i omega (A - A_inf) against the database: relative "
                f"error {reported:.3g} (2-norm over the database's frequencies, no unit; largest on "
                f"{self.labels[e]}, in {self.part[e]}); as a force over {self.band[0]:.3g}..{self.band[1]:.3g} rad/s, "
                f"at most {100 * share:.2g} % of the inertia (M + A_inf) of {self.labels[k]} (at "
                f"{self.at_omega[k]:.3g} rad/s): {verdict}{advice}")


def impedance_check(omega: np.ndarray, added_mass: np.ndarray, damping: np.ndarray, added_mass_inf: np.ndarray,
                    inertia: np.ndarray, labels: list[str], dt: float, duration: float, *, d_omega: float = 0.0,
                    tail_exponent: float = 0.0, tail_correction: tuple[np.ndarray, np.ndarray] | None = None,
                    band: tuple[float, float] | None = None) -> ImpedanceCheck:
    """The check of the diagonal entries for the convolution kernel the hydro model builds from these settings
    (``dt``, ``duration`` s; ``d_omega``, ``tail_exponent``, ``tail_correction`` as in
    :func:`hydro_fmu.radiation.kernel_table`); the tables are those of the scene's degrees of freedom: A, B (Nw, n, n),
    A_inf (n, n); ``inertia`` (n,) the inertia of each without its A_inf (kg, kg m^2; module docstring). The share
    of the inertia is taken over the database's frequencies in ``band`` (rad/s; the sea's frequencies: the last
    frequencies of a database, where B is cut, carry no waves in most runs); default all of them."""
    n = len(labels)
    diag = np.arange(n)
    b_diag = damping[:, diag, diag]
    correction = None
    if tail_correction is not None:
        nodes, values = tail_correction
        correction = (np.asarray(nodes, dtype=float), np.asarray(values)[:, diag, diag])
    table = kernel_table(omega, b_diag, d_omega=d_omega, tail_exponent=tail_exponent, tail_correction=correction)
    t = np.arange(max(2, int(math.ceil(duration / dt)) + 1)) * dt
    kernel = impulse_response(*table, t)  # (Nt, n)
    weights = np.full(len(t), dt)
    weights[0] = weights[-1] = dt / 2
    phase = np.exp(-1j * np.outer(omega, t)) * weights
    got = phase @ kernel  # (Nw, n): B + i omega (A - A_inf) of the kernel (Ogilvie)
    want = b_diag + 1j * omega[:, None] * (added_mass[:, diag, diag] - added_mass_inf[diag, diag])
    diff = got - want
    size = np.sqrt(np.sum(want.real ** 2 + want.imag ** 2, axis=0))
    error = np.sqrt(np.sum(np.abs(diff) ** 2, axis=0)) / np.where(size > 0, size, 1.0)
    in_b, in_a = np.sum(diff.real ** 2, axis=0), np.sum(diff.imag ** 2, axis=0)
    part = ["B" if rb > ra else "A - A_inf" for rb, ra in zip(in_b, in_a, strict=True)]
    total = np.asarray(inertia, dtype=float) + added_mass_inf[diag, diag]
    lo, hi = band if band is not None else (omega[0], omega[-1])
    inside = (omega >= lo * (1 - 1e-9)) & (omega <= hi * (1 + 1e-9))
    if not inside.any():  # a band between two database frequencies: the nearest one
        inside = np.abs(omega - 0.5 * (lo + hi)) == np.min(np.abs(omega - 0.5 * (lo + hi)))
    ratio = np.abs(diff[inside]) / (omega[inside, None] * np.where(total > 0, total, np.inf))
    where = np.argmax(ratio, axis=0)
    return ImpedanceCheck(list(labels), error, part, ratio[where, np.arange(n)], omega[inside][where],
                          (float(omega[inside][0]), float(omega[inside][-1])))
