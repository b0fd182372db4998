"""Hydrodynamic database (HDB): linear potential-flow coefficients of N rigid bodies.

Conventions (the coupling contract of ``docs/design.md``):

* SI units; rotations in radians; world frame right-handed, z up, still water level z = 0.
* Degrees of freedom are ordered per body (surge, sway, heave, roll, pitch, yaw) and bodies
  one after another, so DOF ``k = 6*b + d``. Forces and motions are about each body's centre of
  gravity ``cg`` (the BEMIO convention), in the world frame.
* Complex amplitudes use the ``exp(+i omega t)`` time convention of WEC-Sim: a quantity is
  ``q(t) = Re[Q exp(i omega t)]`` for an incident wave whose elevation at the world origin is
  ``eta(t) = Re[a exp(i omega t)]``. Excitation is per metre of wave amplitude.
* ``hydrostatic_stiffness`` is the BEM matrix (WAMIT, Capytaine, BEMIO) about ``cg``. The BEM
  formula adds the moment of the weight, ``-m g (z_g - z_ref)``, to roll and pitch; with the
  reference point at the centre of gravity that term is zero, so about ``cg`` the matrix is the
  restoring of the pressure (buoyancy) forces alone, ``rho g (I_wp + V (z_b - z_g))`` in pitch.
  Gravity belongs to the multibody side, which applies the weight at the centre of gravity.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

DOF_NAMES = ("surge", "sway", "heave", "roll", "pitch", "yaw")


class HydroDatabaseError(ValueError):
    """A hydrodynamic database is inconsistent; the message names the source and quantity."""


@dataclass
class HydroDatabase:
    """Frequency-domain coefficients of ``N`` bodies (``n = 6 N`` degrees of freedom).

    Attributes:
        body_names: body names, length N.
        omega: wave frequencies (Nw,), rad/s, strictly increasing and positive.
        added_mass: A(omega), (Nw, n, n), kg / kg m / kg m^2.
        radiation_damping: B(omega), (Nw, n, n), N s/m / N m s/rad.
        added_mass_inf: A at infinite frequency, (n, n).
        headings: wave headings (Nh,), rad; 0 means waves travelling towards +x.
        excitation: complex excitation per metre of amplitude, (Nh, Nw, n), N/m or N m/m.
        froude_krylov, diffraction: the two parts of ``excitation`` when known, same shape.
        hydrostatic_stiffness: (N, 6, 6), BEM convention (see the module docstring).
        cg, cb: centre of gravity and of buoyancy of each body at equilibrium (N, 3), m.
        displaced_volume: (N,), m^3.
        rho, g, water_depth: kg/m^3, m/s^2, m (``inf`` for deep water).
        source: where the data came from (file name, solver and version).
    """

    body_names: list[str]
    omega: np.ndarray
    added_mass: np.ndarray
    radiation_damping: np.ndarray
    added_mass_inf: np.ndarray
    headings: np.ndarray
    excitation: np.ndarray
    hydrostatic_stiffness: np.ndarray
    cg: np.ndarray
    cb: np.ndarray
    displaced_volume: np.ndarray
    rho: float = 1025.0
    g: float = 9.81
    water_depth: float = float("inf")
    froude_krylov: np.ndarray | None = None
    diffraction: np.ndarray | None = None
    source: str = ""
    extra: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.omega = np.asarray(self.omega, dtype=float)
        self.headings = np.atleast_1d(np.asarray(self.headings, dtype=float))
        self.cg = np.asarray(self.cg, dtype=float).reshape(-1, 3)
        self.cb = np.asarray(self.cb, dtype=float).reshape(-1, 3)
        self.displaced_volume = np.atleast_1d(np.asarray(self.displaced_volume, dtype=float))
        self.validate()

    # ------------------------------------------------------------------ shape and checks
    @property
    def n_bodies(self) -> int:
        return len(self.body_names)

    @property
    def n_dofs(self) -> int:
        return 6 * self.n_bodies

    def body_index(self, name: str) -> int:
        try:
            return self.body_names.index(name)
        except ValueError:
            raise HydroDatabaseError(
                f"{self.source or 'hydrodynamic database'}: no body named {name!r} "
                f"(bodies: {', '.join(self.body_names)})"
            ) from None

    def validate(self) -> None:
        """Check shapes, finiteness and the frequency grid; raise :class:`HydroDatabaseError`."""
        where = self.source or "hydrodynamic database"
        nw, n, nh = len(self.omega), self.n_dofs, len(self.headings)
        expected = {
            "added_mass": (nw, n, n),
            "radiation_damping": (nw, n, n),
            "added_mass_inf": (n, n),
            "excitation": (nh, nw, n),
            "hydrostatic_stiffness": (self.n_bodies, 6, 6),
            "cg": (self.n_bodies, 3),
            "cb": (self.n_bodies, 3),
            "displaced_volume": (self.n_bodies,),
        }
        if self.froude_krylov is not None:
            expected["froude_krylov"] = (nh, nw, n)
        if self.diffraction is not None:
            expected["diffraction"] = (nh, nw, n)
        for name, shape in expected.items():
            value = np.asarray(getattr(self, name))
            if value.shape != shape:
                raise HydroDatabaseError(f"{where}: {name} has shape {value.shape}, expected {shape}")
            bad = ~np.isfinite(value)
            if bad.any():
                idx = np.argwhere(bad)[0]
                raise HydroDatabaseError(
                    f"{where}: {name} has {int(bad.sum())} non-finite values"
                    f"{self._locate(name, tuple(idx))}"
                )
        if nw < 2 or np.any(self.omega <= 0) or np.any(np.diff(self.omega) <= 0):
            raise HydroDatabaseError(
                f"{where}: frequencies must be positive and strictly increasing with at least two "
                f"values (got {nw} values from {self.omega.min(initial=np.nan):g} rad/s)"
            )
        for name in ("rho", "g"):
            if not (np.isfinite(getattr(self, name)) and getattr(self, name) > 0):
                raise HydroDatabaseError(f"{where}: {name} must be positive and finite")
        if not self.water_depth > 0:
            raise HydroDatabaseError(f"{where}: water_depth must be positive (inf for deep water)")

    def _locate(self, name: str, idx: tuple[int, ...]) -> str:
        """Human-readable location (body, dof, frequency) of an array element."""
        parts = []
        if name in ("added_mass", "radiation_damping"):
            parts.append(f"omega = {self.omega[idx[0]]:g} rad/s")
            idx = idx[1:2]
        elif name in ("excitation", "froude_krylov", "diffraction"):
            parts.append(f"omega = {self.omega[idx[1]]:g} rad/s")
            idx = idx[2:3]
        elif name == "added_mass_inf":
            idx = idx[0:1]
        elif name == "hydrostatic_stiffness":
            idx = (6 * idx[0] + idx[1],)
        else:
            idx = (6 * idx[0],)
        k = idx[0]
        parts.insert(0, f"body {self.body_names[k // 6]!r} {DOF_NAMES[k % 6]}")
        return " (first at " + ", ".join(parts) + ")"

    def check_physics(self, dofs: np.ndarray | None = None, tolerance: float = 0.05) -> list[str]:
        """Problems of the radiation coefficients on the degrees of freedom ``dofs`` (6N numbering).

        Checked at every frequency (and at infinity for A): symmetry of A and B, and positive
        semi-definiteness of B (no energy created by radiation). Entries are compared on the
        scale of their DOFs, s_ij = sqrt(s_i s_j) with s_i = max over frequency of |X_ii|, so
        translations and rotations mix fairly: |X_ij - X_ji| > tolerance s_ij, or an eigenvalue
        of the symmetric part of S^-1/2 B S^-1/2 below -tolerance, is a problem. Returns one
        message per quantity (worst place first); empty if all is well.
        """
        index = np.arange(self.n_dofs) if dofs is None else np.asarray(dofs, dtype=int)
        where = self.source or "hydrodynamic database"
        problems = []
        for name in ("added_mass", "radiation_damping", "added_mass_inf"):
            table = np.asarray(getattr(self, name))
            table = table[None] if table.ndim == 2 else table
            sub = table[:, index][:, :, index]
            scale = np.sqrt(np.abs(np.einsum("wii->wi", sub)).max(axis=0))
            scale[scale == 0] = 1.0
            pair = np.outer(scale, scale)
            rel = np.abs(sub - np.transpose(sub, (0, 2, 1))) / pair
            if rel.max() > tolerance:
                w, i, j = np.unravel_index(int(np.argmax(rel)), rel.shape)
                at = f", omega = {self.omega[w]:g} rad/s" if name != "added_mass_inf" else ""
                problems.append(
                    f"{where}: {name} is not symmetric: between {self._dof_label(index[i])} and "
                    f"{self._dof_label(index[j])}{at} the two entries differ by {rel.max():.1%} of their scale "
                    f"({sub[w, i, j]:.4g} and {sub[w, j, i]:.4g})")
            if name == "radiation_damping":
                scaled = sub / pair
                eig = np.linalg.eigvalsh(0.5 * (scaled + np.transpose(scaled, (0, 2, 1))))
                w = int(np.argmin(eig[:, 0]))
                if eig[w, 0] < -tolerance:
                    vec = np.linalg.eigh(0.5 * (scaled[w] + scaled[w].T))[1][:, 0]
                    k = int(np.argmax(np.abs(vec)))
                    problems.append(
                        f"{where}: radiation_damping is not positive semi-definite at omega = {self.omega[w]:g} rad/s "
                        f"(scaled eigenvalue {eig[w, 0]:.3g}, mostly {self._dof_label(index[k])}): radiation would "
                        "create energy")
        return problems

    def _dof_label(self, k: int) -> str:
        return f"body {self.body_names[k // 6]!r} {DOF_NAMES[k % 6]}"

    # ------------------------------------------------------------------ derived quantities
    def heading_index(self, heading: float) -> int:
        """Index of the tabulated heading (rad) equal to ``heading`` within 1e-6 rad."""
        diff = np.abs(np.angle(np.exp(1j * (self.headings - heading))))
        i = int(np.argmin(diff))
        if diff[i] > 1e-6:
            raise HydroDatabaseError(
                f"{self.source or 'hydrodynamic database'}: wave heading {np.degrees(heading):g} deg is "
                f"not tabulated (headings: {', '.join(f'{np.degrees(h):g}' for h in self.headings)} deg)"
            )
        return i

    def interpolate(self, omega: np.ndarray | float, heading: float = 0.0) -> tuple[np.ndarray, ...]:
        """A(omega), B(omega) and the excitation at ``heading``, linearly interpolated.

        Outside the tabulated range B and the excitation are taken as zero above the last
        frequency and A as A_inf; below the first frequency the first values are held.
        Returns ``(A (k, n, n), B (k, n, n), X (k, n))`` for ``k`` frequencies.
        """
        w = np.atleast_1d(np.asarray(omega, dtype=float))
        X = self.excitation[self.heading_index(heading)]

        def interp(table: np.ndarray, above: np.ndarray | float) -> np.ndarray:
            flat = table.reshape(len(self.omega), -1)
            out = np.empty((len(w), flat.shape[1]), dtype=flat.dtype)
            for j in range(flat.shape[1]):
                if np.iscomplexobj(flat):
                    out[:, j] = np.interp(w, self.omega, flat[:, j].real) + 1j * np.interp(
                        w, self.omega, flat[:, j].imag
                    )
                else:
                    out[:, j] = np.interp(w, self.omega, flat[:, j])
            high = w > self.omega[-1]
            out[high] = np.broadcast_to(np.asarray(above).reshape(-1), out[high].shape)
            return out.reshape((len(w),) + table.shape[1:])

        A = interp(self.added_mass, self.added_mass_inf)
        B = interp(self.radiation_damping, 0.0)
        Xw = interp(X, 0.0)
        return A, B, Xw

    def excitation_at(self, omega: np.ndarray, heading: np.ndarray | float,
                      table: np.ndarray | None = None) -> np.ndarray:
        """Excitation per metre of amplitude (K, n) for components at (omega_k, heading_k).

        Linear in frequency (zero above the last frequency, held below the first) and linear in
        heading between the tabulated headings; if the headings cover the circle (the largest
        gap, across 360 deg included, is no larger than the others) the table wraps round.
        ``table`` replaces the excitation (e.g. the Froude-Krylov or diffraction part).
        """
        w = np.atleast_1d(np.asarray(omega, dtype=float))
        h = np.broadcast_to(np.asarray(heading, dtype=float), w.shape)
        data = self.excitation if table is None else table
        out = np.zeros((len(w), self.n_dofs), complex)
        for value in np.unique(h):
            rows = np.flatnonzero(h == value)
            for index, weight in self._heading_weights(float(value)):
                out[rows] += weight * self._interp_frequency(data[index], w[rows])
        return out

    def _interp_frequency(self, table: np.ndarray, w: np.ndarray) -> np.ndarray:
        """table (Nw, n) complex, linearly interpolated at w; zero above the last frequency."""
        out = np.empty((len(w), table.shape[1]), complex)
        for j in range(table.shape[1]):
            out[:, j] = np.interp(w, self.omega, table[:, j].real) + 1j * np.interp(w, self.omega, table[:, j].imag)
        out[w > self.omega[-1]] = 0.0
        return out

    def _heading_weights(self, heading: float) -> list[tuple[int, float]]:
        """Tabulated heading indices and weights that interpolate linearly to ``heading`` (rad)."""
        hs = self.headings
        diff = np.abs(np.angle(np.exp(1j * (hs - heading))))
        exact = int(np.argmin(diff))
        if diff[exact] <= 1e-6:
            return [(exact, 1.0)]
        order = np.argsort(np.mod(hs - hs.min(), 2 * np.pi))
        base = hs[order[0]]
        rel = np.mod(hs[order] - base, 2 * np.pi)
        x = np.mod(heading - base, 2 * np.pi)
        gaps = np.diff(np.append(rel, 2 * np.pi))
        wraps = len(hs) > 1 and gaps[-1] <= gaps[:-1].max() + 1e-9
        if x <= rel[-1]:
            k = int(np.searchsorted(rel, x)) - 1
            f = (x - rel[k]) / (rel[k + 1] - rel[k])
            return [(int(order[k]), 1 - f), (int(order[k + 1]), f)]
        if wraps:
            f = (x - rel[-1]) / (2 * np.pi - rel[-1])
            return [(int(order[-1]), 1 - f), (int(order[0]), f)]
        raise HydroDatabaseError(
            f"{self.source or 'hydrodynamic database'}: wave heading {np.degrees(heading):g} deg is outside the "
            f"tabulated headings ({', '.join(f'{np.degrees(v):g}' for v in hs)} deg); compute the database "
            "with more headings (hydro.headings_deg)")

    def select_bodies(self, names: list[str]) -> HydroDatabase:
        """A database restricted to ``names`` (in that order), interaction blocks kept."""
        idx = [self.body_index(nm) for nm in names]
        dofs = np.concatenate([np.arange(6 * i, 6 * i + 6) for i in idx])

        def sub3(a: np.ndarray | None) -> np.ndarray | None:
            return None if a is None else a[:, :, dofs]

        return HydroDatabase(
            body_names=list(names),
            omega=self.omega,
            added_mass=self.added_mass[:, dofs][:, :, dofs],
            radiation_damping=self.radiation_damping[:, dofs][:, :, dofs],
            added_mass_inf=self.added_mass_inf[dofs][:, dofs],
            headings=self.headings,
            excitation=self.excitation[:, :, dofs],
            froude_krylov=sub3(self.froude_krylov),
            diffraction=sub3(self.diffraction),
            hydrostatic_stiffness=self.hydrostatic_stiffness[idx],
            cg=self.cg[idx],
            cb=self.cb[idx],
            displaced_volume=self.displaced_volume[idx],
            rho=self.rho,
            g=self.g,
            water_depth=self.water_depth,
            source=self.source,
            extra={k: v for k, v in self.extra.items() if isinstance(v, str)},  # notes; arrays by DOF do not carry
        )
