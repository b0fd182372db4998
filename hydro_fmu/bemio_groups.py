"""The optional groups of a BEMIO HDF5 file: impulse responses and the radiation state-space realisation.

WEC-Sim's body class reads them from each ``/body<i>/hydro_coeffs`` group when a run asks for the
radiation convolution (``K``, ``t``), the state-space radiation (``state_space``) or the excitation
convolution (``excitation/impulse_response_fun``). Layout as h5py sees it (row-major; the MATLAB
``writeBEMIOH5`` and the Python ``bemio`` ``write_hdf5`` give the same index order), normalised as
WEC-Sim's BEMIO normalises them:

``radiation_damping/impulse_response_fun/K`` (6, 6N, Nt)
    K(t) / rho, K(t) = (2/pi) int_0^inf B(omega) cos(omega t) domega (N s^-1 m^-1 ... per unit velocity).
``radiation_damping/impulse_response_fun/t`` (Nt,), s; ``.../w`` the frequencies integrated over, rad/s.
``radiation_damping/state_space/{A,B,C,D}/all`` (6, 6N, r, r), (6, 6N, r, 1), (6, 6N, 1, r), (6, 6N)
    one single-input single-output realisation per entry (k, l): K_kl(t) ~ rho C_kl exp(A_kl t) B_kl
    (C and D normalised by rho); ``.../it`` (6, 6N) the order of each entry (zero-padded to r = max it).
``excitation/impulse_response_fun/f`` (6, Nh, Nt) K_ex(t) / (rho g), ``.../t`` (Nt,) s, from -T to T.

These groups are derived data: the scene never takes them from a file (it computes its own impulse
response from B(omega), whose settings the scenario states), so a file without them, or with NaN in
them, reads as well as any other; :func:`read_radiation_groups` returns what is there, for tests and
for users who compare.
"""

from __future__ import annotations

from dataclasses import dataclass

import h5py
import numpy as np

from .excitation import excitation_impulse_response
from .hdb import HydroDatabase
from .radiation import impulse_response
from .state_space import StateSpaceFitError, fit_state_space, scaled_error

# Kernel written by default: 40 s at 0.05 s (801 samples; the bundled scenarios' hydro.irf_duration is 30-40 s).
IRF_DURATION = 40.0
IRF_STEP = 0.05
# Each entry's realisation within 1 % of its entry's scale on the fit's own samples: measured on the cylinder's heave,
# 0.02 gave order 3 and 2.8 % (max) / 5.0 % (rms) off the written kernel, 0.01 order 4 and 0.6 % / 1.1 %.
SS_TOLERANCE = 0.01
SS_MAX_ORDER = 12


@dataclass
class RadiationGroups:
    """What a file's optional groups hold, in SI units (normalisations undone).

    Attributes:
        t: kernel times (Nt,), s; ``kernel`` K(t) (Nt, 6N, 6N).
        ss_order: (6N, 6N) order of each entry's realisation (None if the file has none);
        ss_a, ss_b, ss_c, ss_d: (6N, 6N, r, r), (6N, 6N, r, 1), (6N, 6N, 1, r), (6N, 6N).
        ex_t, ex_kernel: excitation kernel times (Nt,) s and K_ex (Nh, Nt, 6N), N/m/s (None if absent).
    """

    t: np.ndarray | None = None
    kernel: np.ndarray | None = None
    ss_order: np.ndarray | None = None
    ss_a: np.ndarray | None = None
    ss_b: np.ndarray | None = None
    ss_c: np.ndarray | None = None
    ss_d: np.ndarray | None = None
    ex_t: np.ndarray | None = None
    ex_kernel: np.ndarray | None = None

    def state_space_response(self, t: np.ndarray) -> np.ndarray:
        """sum of the entries' realisations C exp(A t) B at times ``t``: (len(t), 6N, 6N)."""
        n = self.ss_order.shape[0]
        out = np.zeros((len(t), n, n))
        for k in range(n):
            for m in range(n):
                r = int(self.ss_order[k, m])
                if r == 0:
                    continue
                a, b, c = self.ss_a[k, m, :r, :r], self.ss_b[k, m, :r, 0], self.ss_c[k, m, 0, :r]
                lam, vec = np.linalg.eig(a)
                out[:, k, m] = np.real(np.exp(np.outer(t, lam)) @ ((c @ vec) * np.linalg.solve(vec, b)))
        return out


@dataclass
class RadiationRealisation:
    """Impulse responses and per-entry state-space fits of a whole database (SI units)."""

    t: np.ndarray
    kernel: np.ndarray
    ex_t: np.ndarray
    ex_kernel: np.ndarray
    order: np.ndarray
    a: np.ndarray
    b: np.ndarray
    c: np.ndarray
    worst_error: float


def realise(hdb: HydroDatabase, duration: float = IRF_DURATION, step: float = IRF_STEP,
            tolerance: float = SS_TOLERANCE, max_order: int = SS_MAX_ORDER) -> RadiationRealisation:
    """K(t) on [0, duration], K_ex(t) on [-duration/2, duration/2] for every heading, and one single-input
    single-output realisation per entry of K (ERA, :func:`hydro_fmu.state_space.fit_state_space`), each within
    ``tolerance`` of its entry measured on the pair's diagonal scale sqrt(s_k s_l) (so an entry that is only
    numerical noise gets order 0). The order of an entry is the lowest that meets the tolerance, at most
    ``max_order``; an entry that no order up to it meets gets the lowest order within twice, four times ... the
    tolerance (``worst_error`` says how far off the worst entry is)."""
    t = np.arange(0.0, duration + step / 2, step)
    kernel = impulse_response(hdb.omega, hdb.radiation_damping, t)
    n = hdb.n_dofs
    diag = np.sqrt(np.sum(np.einsum("tii->ti", kernel) ** 2, axis=0))
    half = np.arange(-np.ceil(duration / 2 / step), np.ceil(duration / 2 / step) + 1) * step
    ex = np.stack([excitation_impulse_response(hdb, h, np.arange(n), half) for h in hdb.headings])
    fits, worst = {}, 0.0
    for k in range(n):
        for m in range(n):
            entry = kernel[:, k:k + 1, m:m + 1]
            floor = np.array([np.sqrt(diag[k] * diag[m])])
            if not floor[0] > 0 or scaled_error(entry, np.zeros_like(entry), floor) <= tolerance:
                continue
            fit, tol = None, tolerance
            while fit is None and tol < 1.0:  # the lowest order meeting the tolerance, else a looser one
                try:
                    fit = fit_state_space(t, entry, hdb.omega[-1], tol, max_order, floors=floor)
                except StateSpaceFitError:
                    tol *= 2
            if fit is None:
                continue
            fits[k, m] = fit
            worst = max(worst, fit.kernel_error)
    r = max((f.order for f in fits.values()), default=1)
    order = np.zeros((n, n), dtype=int)
    a, b, c = np.zeros((n, n, r, r)), np.zeros((n, n, r, 1)), np.zeros((n, n, 1, r))
    for (k, m), fit in fits.items():
        o = fit.order
        order[k, m] = o
        a[k, m, :o, :o], b[k, m, :o, 0], c[k, m, 0, :o] = fit.a, fit.b[:, 0], fit.c[0]
    return RadiationRealisation(t, kernel, half, ex, order, a, b, c, worst)


def write_radiation_groups(hc: h5py.Group, hdb: HydroDatabase, rows: slice, real: RadiationRealisation,
                           dataset) -> None:
    """The optional groups of one body (rows of the 6N system) under its ``hydro_coeffs`` group ``hc``;
    ``dataset(group, name, data, description, unit)`` writes one dataset with its attributes."""
    rho, g = hdb.rho, hdb.g
    irf = hc.require_group("radiation_damping").create_group("impulse_response_fun")
    dataset(irf, "K", np.transpose(real.kernel[:, rows, :], (1, 2, 0)) / rho, "Impulse response function", "")
    dataset(irf, "t", real.t, "Time", "s")
    dataset(irf, "w", hdb.omega, "Frequency", "rad/s")
    ss = hc["radiation_damping"].create_group("state_space")
    dataset(ss, "it", real.order[rows], "Order of state space realization", "")
    dataset(ss.create_group("A"), "all", real.a[rows], "State Space A Coefficient", "")
    dataset(ss.create_group("B"), "all", real.b[rows], "State Space B Coefficient", "")
    dataset(ss.create_group("C"), "all", real.c[rows] / rho, "State Space C Coefficient", "")
    dataset(ss.create_group("D"), "all", np.zeros((6, hdb.n_dofs)), "State Space D Coefficient", "")
    ex = hc.require_group("excitation").create_group("impulse_response_fun")
    dataset(ex, "f", np.transpose(real.ex_kernel[:, :, rows], (2, 0, 1)) / (rho * g), "Impulse response function",
            "")
    dataset(ex, "t", real.ex_t, "Time", "s")
    dataset(ex, "w", hdb.omega, "Frequency", "rad/s")


def read_radiation_groups(f: h5py.File, bodies: list[str], n: int, nh: int, rho: float, g: float,
                          shaped) -> RadiationGroups:
    """The optional groups of every body, where all bodies have them and they are finite (else left None);
    ``shaped(value, shape, what)`` checks a shape (accepting MATLAB's reversed order)."""
    out = RadiationGroups()

    def gather(path: str, tail: tuple[int, ...]) -> np.ndarray | None:
        parts = []
        for key in bodies:
            full = f"{key}/hydro_coeffs/{path}"
            if full not in f or not isinstance(f[full], h5py.Dataset):
                return None
            value = np.asarray(f[full][()], dtype=float)
            try:
                value = shaped(value, (6,) + tail, full)
            except ValueError:
                return None
            if not np.all(np.isfinite(value)):
                return None
            parts.append(value)
        return np.concatenate(parts, axis=0)

    def times(path: str) -> np.ndarray | None:
        full = f"{bodies[0]}/hydro_coeffs/{path}"
        if full not in f:
            return None
        value = np.asarray(f[full][()], dtype=float).ravel()
        return value if np.all(np.isfinite(value)) else None

    t = times("radiation_damping/impulse_response_fun/t")
    if t is not None:
        k = gather("radiation_damping/impulse_response_fun/K", (n, len(t)))
        if k is not None:
            out.t, out.kernel = t, np.transpose(k, (2, 0, 1)) * rho
    order = gather("radiation_damping/state_space/it", (n,))
    if order is not None:
        base = f"{bodies[0]}/hydro_coeffs/radiation_damping/state_space/A/all"
        r = int(np.asarray(f[base]).shape[-1]) if base in f else 0
        a = gather("radiation_damping/state_space/A/all", (n, r, r))
        b = gather("radiation_damping/state_space/B/all", (n, r, 1))
        c = gather("radiation_damping/state_space/C/all", (n, 1, r))
        d = gather("radiation_damping/state_space/D/all", (n,))
        if all(v is not None for v in (a, b, c, d)):
            out.ss_order, out.ss_a, out.ss_b = order.astype(int), a, b
            out.ss_c, out.ss_d = c * rho, d * rho
    te = times("excitation/impulse_response_fun/t")
    if te is not None:
        fx = gather("excitation/impulse_response_fun/f", (nh, len(te)))
        if fx is not None:
            out.ex_t, out.ex_kernel = te, np.transpose(fx, (1, 2, 0)) * rho * g
    return out
