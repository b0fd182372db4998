"""Heave added mass and damping of a floating hemisphere by Hulme's (1982) multipole method.

Reference solution for the BEM acceptance test, independent of any panel method: the potential
of a hemisphere of radius a heaving with unit velocity in deep water (time factor exp(-i w t),
z up, fluid z < 0, K = w^2 / g) is expanded as in Havelock (1955) and Hulme (1982),

    phi = c_0 phi_0 + sum_{n=1}^{N} c_n phi_2n,

with phi_0 the wave source at the origin and phi_2n the wave-free multipoles

    phi_0  = 1/r + K F(z, R) + i pi K exp(K z) J0(K R),
    F      = PV int_0^inf exp(k z) J0(k R) / (k - K) dk,
    phi_2n = P_2n(mu) / r^(2n+1) + K / (2n) P_(2n-1)(mu) / r^(2n),       mu = -z / r,

each satisfying Laplace's equation and the free-surface condition phi_z = K phi. F is evaluated
without any oscillatory integral: it solves dF/dz - K F = 1/r with F(0, R) = -(pi/2)(H0(KR) +
Y0(KR)) (Struve and Bessel functions), so F = exp(Kz) [F(0, R) - int_z^0 exp(-K s) / sqrt(R^2
+ s^2) ds], and dF/dR likewise from dF/dR(0, R) = -(pi/2) K (2/pi - H1(KR) - Y1(KR)). The body
condition d phi / dr = -mu on r = a is imposed in the least-squares sense at Gauss-Legendre
points in mu (weights of the surface measure). Then

    A = 2 pi rho a^2 Re int_0^1 phi mu dmu,   B = 2 pi rho a^2 w Im int_0^1 phi mu dmu,

reported as mu_33 = A / (rho 2/3 pi a^3) and lambda_33 = B / (rho 2/3 pi a^3 w), the
normalisation of Hulme's tables. Independent check: the radiated power of the source term gives
B = 2 rho w pi^2 K |c_0|^2 (energy conservation), which must agree with the pressure integral.
"""

from __future__ import annotations

import numpy as np
from numpy.polynomial.legendre import leggauss
from scipy import integrate, special


def _source(K: float, R: float, z: float) -> tuple[complex, complex, complex]:
    """phi_0 and its derivatives d/dR, d/dz at (R, z), z < 0."""
    r = np.hypot(R, z)
    f0 = -0.5 * np.pi * (special.struve(0, K * R) + special.y0(K * R))
    g0 = -0.5 * np.pi * K * (2 / np.pi - special.struve(1, K * R) - special.y1(K * R))
    i_f = integrate.quad(lambda s: np.exp(-K * s) / np.hypot(R, s), z, 0.0, epsabs=1e-13, epsrel=1e-12,
                         limit=200)[0]
    i_g = integrate.quad(lambda s: np.exp(-K * s) * R / np.hypot(R, s) ** 3, z, 0.0, epsabs=1e-13,
                         epsrel=1e-12, limit=200)[0]
    F = np.exp(K * z) * (f0 - i_f)
    dF_dR = np.exp(K * z) * (g0 + i_g)
    dF_dz = K * F + 1.0 / r
    wave = 1j * np.pi * K * np.exp(K * z)
    phi = 1.0 / r + K * F + wave * special.j0(K * R)
    d_dR = -R / r**3 + K * dF_dR - wave * K * special.j1(K * R)
    d_dz = -z / r**3 + K * dF_dz + wave * K * special.j0(K * R)
    return phi, d_dR, d_dz


def _legendre(n: int, mu: np.ndarray) -> np.ndarray:
    return special.eval_legendre(n, mu)


def hemisphere_heave(ka: float, n_multipoles: int = 12, n_points: int = 48) -> tuple[float, float, float]:
    """(mu_33, lambda_33, lambda_33 from the radiated energy) at K a = ``ka`` (a = 1)."""
    K = float(ka)
    x, w = leggauss(n_points)
    mu = 0.5 * (x + 1.0)  # (0, 1)
    weight = 0.5 * w
    sin_t = np.sqrt(1 - mu**2)
    R, z = sin_t, -mu  # points on r = 1
    columns_dr = np.empty((n_points, n_multipoles + 1), complex)
    columns_phi = np.empty((n_points, n_multipoles + 1), complex)
    for j in range(n_points):
        phi, d_dR, d_dz = _source(K, R[j], z[j])
        columns_phi[j, 0] = phi
        columns_dr[j, 0] = d_dR * sin_t[j] + d_dz * (-mu[j])  # e_r = (sin, -mu) in (R, z)
    for n in range(1, n_multipoles + 1):
        p_even, p_odd = _legendre(2 * n, mu), _legendre(2 * n - 1, mu)
        columns_phi[:, n] = p_even + K / (2 * n) * p_odd
        columns_dr[:, n] = -(2 * n + 1) * p_even - K / (2 * n) * (2 * n) * p_odd
    rhs = -mu
    sqrt_w = np.sqrt(weight)
    coefficients, *_ = np.linalg.lstsq(columns_dr * sqrt_w[:, None], rhs * sqrt_w, rcond=None)
    phi_body = columns_phi @ coefficients
    integral = np.sum(weight * phi_body * mu)
    volume = 2.0 / 3.0 * np.pi
    added_mass = 2 * np.pi * integral.real / volume
    damping = 2 * np.pi * integral.imag / volume
    energy = 2 * np.pi**2 * K * abs(coefficients[0]) ** 2 / volume
    return float(added_mass), float(damping), float(energy)


if __name__ == "__main__":
    for ka in (0.05, 0.2, 0.5, 1.0, 2.0, 20.0):
        print(ka, hemisphere_heave(ka), hemisphere_heave(ka, 16, 64))
