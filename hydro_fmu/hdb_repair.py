"""Repairs of a hydrodynamic database that physics justifies, each reported in numbers.

* :func:`truncated` keeps the frequencies up to a limit (above it the BEM is known to be wrong, e.g.
  a thin plate meshed coarser than its thickness; the impulse response continues the damping
  above the database with ``hydro.damping_tail``).
* :func:`reciprocal_passive` makes ``A(omega)``, ``A_inf`` and ``B(omega)`` symmetric (reciprocity:
  Newman 1977, 6.18) and ``B(omega)`` positive semi-definite (a radiating body cannot take energy
  from the waves it makes) by replacing B's negative eigenvalues with zero. It returns the largest
  change of any entry relative to the largest entry of that matrix over the frequency grid (the
  BEM's numerical noise where a coefficient is itself near zero, e.g. a deep heave plate's heave
  damping), so a user can judge whether the database was close to physical to begin with.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .hdb import HydroDatabase


def truncated(hdb: HydroDatabase, omega_max: float) -> HydroDatabase:
    """The database restricted to ``omega <= omega_max`` (rad/s)."""
    keep = hdb.omega <= omega_max * (1 + 1e-12)

    def cut(a, axis):
        return None if a is None else np.compress(keep, a, axis=axis)

    return dataclasses.replace(
        hdb, omega=hdb.omega[keep], added_mass=cut(hdb.added_mass, 0), radiation_damping=cut(hdb.radiation_damping, 0),
        excitation=cut(hdb.excitation, 1), froude_krylov=cut(hdb.froude_krylov, 1),
        diffraction=cut(hdb.diffraction, 1), source=f"{hdb.source}; frequencies <= {omega_max:g} rad/s")


def reciprocal_passive(hdb: HydroDatabase, dofs: np.ndarray) -> tuple[HydroDatabase, dict[str, float]]:
    """Symmetric A, A_inf and B; B positive semi-definite on the degrees of freedom ``dofs`` (indices in the
    database's 6N numbering: those a scene uses; a sub-block of a passive B is passive, the others are
    left as they are); and the largest relative changes on ``dofs``."""

    def sym(a):
        return 0.5 * (a + np.swapaxes(a, -1, -2))

    a, a_inf, b = sym(hdb.added_mass), sym(hdb.added_mass_inf), sym(hdb.radiation_damping)
    block = np.ix_(np.arange(len(hdb.omega)), dofs, dofs)
    values, vectors = np.linalg.eigh(b[block])
    b_psd = b.copy()
    b_psd[block] = np.einsum("wij,wj,wkj->wik", vectors, np.clip(values, 0.0, None), vectors)
    sub = np.ix_(dofs, dofs)
    hdb_b, hdb_a = hdb.radiation_damping[block], hdb.added_mass[block]
    def scaled(change, matrix):
        """Largest |change_ij| over sqrt(max_w |M_ii| max_w |M_jj|) (per entry, consistent units)."""
        d = np.abs(np.diagonal(matrix.reshape(-1, *matrix.shape[-2:]), axis1=1, axis2=2)).max(axis=0)
        scale = np.sqrt(np.outer(d, d))
        ok = scale > 0
        return float((np.abs(change).reshape(-1, *matrix.shape[-2:]).max(axis=0)[ok] / scale[ok]).max())

    report = {
        "added_mass_asymmetry": scaled(hdb_a - a[block], hdb_a),
        "added_mass_inf_asymmetry": scaled(hdb.added_mass_inf[sub] - a_inf[sub], hdb.added_mass_inf[sub]),
        "damping_asymmetry": scaled(hdb_b - b[block], hdb_b),
        "damping_negative_part": scaled(b_psd[block] - b[block], hdb_b),
    }
    out = dataclasses.replace(hdb, added_mass=a, added_mass_inf=a_inf, radiation_damping=b_psd,
                              source=f"{hdb.source}; A, B symmetrised, B made positive semi-definite")
    return out, report
