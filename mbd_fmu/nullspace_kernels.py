"""Compiled (numba) steps of the null-space formulation (:class:`mbd_fmu.formulations.NullSpace`).

The reduced ODE ``P^T M P v_s' = P^T (f - M rho)`` has the same solution as the saddle-point system
``[[M, C^T], [C, 0]] [v'; lambda] = [f; gamma]`` restricted to the independent slots (``v' = P v_s' +
rho`` satisfies both; ``P^T C^T = 0``), so a stage evaluates

1. the dependent velocities from ``C_d v_d = -C_s v_s`` (the velocity constraint holds exactly at every
   stage, as on the Python path; the compiled path has no drivers, so ``Phi_t = 0``),
2. the consistent acceleration from the banded saddle-point solve of :mod:`mbd_fmu.kernels`, and returns
   its independent part.

``C_d`` (kept rows x dependent slots) is factorised by banded LU with partial pivoting in an order of
rows and columns chosen once per partition (:func:`mbd_fmu.fast.CompiledModel.dependent_order`: rows
and dependent slots sorted along a breadth-first order of the bodies), so a chain or an array costs
O(r b^2), not O(r^3). The same factors give the Newton corrections of the dependent positions after
the step and the partition's quality (smallest pivot over the largest Jacobian entry), which decides
when to re-choose it. The method and its order are those of the Python path (explicit RKMK, order of
the tableau); results agree to round-off.

These entry points are compiled only when a model runs the null-space formulation on the compiled path
(a separate module: the index-3 and index-1 steps do not pay for their compilation).
"""

from __future__ import annotations

import numpy as np

from fmu_base._jit import njit

from .kernels import (
    _local_rate,
    acceleration,
    angle_references,
    constraints,
    lu_factor,
    lu_solve,
    retract,
    retract_full,
    rkmk_sums,
    snapshot,
    unpack,
)


@njit
def _factor_cd(jac, dep, rows, cols, kl, ku):
    """Banded LU of C_d = jac[:, dep] in the order ``rows`` x ``cols`` (factors, pivots, ok, smallest |pivot|)."""
    r = dep.shape[0]
    lu = np.empty((r, r))
    for i in range(r):
        ri = rows[i]
        for j in range(max(0, i - kl), min(r, i + kl + ku + 1)):
            lu[i, j] = jac[ri, dep[cols[j]]] if j <= i + ku else 0.0
    piv = np.zeros(r, dtype=np.int64)
    ok = lu_factor(lu, piv, kl, ku)
    small = np.inf
    for i in range(r):
        small = min(small, abs(lu[i, i]))
    return lu, piv, ok, small if r else 1.0


@njit
def _solve_cd(lu, piv, kl, ku, rows, cols, b):
    """x (r,) on the dependent slots (in ``dep``'s order) with C_d x = b."""
    y = lu_solve(lu, piv, kl, ku, b[rows])
    x = np.empty_like(y)
    x[cols] = y
    return x


@njit
def _rates(plan, pr, pR, vs, inputs, refs, t, dep, ind, rows, cols, kl, ku):
    """Full velocity, consistent acceleration, multipliers at ``(pose, v_s, t)`` and the partition's quality."""
    sel = plan[0]
    n = sel.shape[0]
    rr, RR, W = snapshot(pr, pR, np.zeros(n), sel)
    _, jac, _ = constraints(plan, rr, RR, W, True, False)
    v = np.zeros(n)
    for k in range(ind.shape[0]):
        v[ind[k]] = vs[k]
    quality = 1.0
    if dep.shape[0]:
        lu, piv, ok, small = _factor_cd(jac, dep, rows, cols, kl, ku)
        rhs = np.zeros(jac.shape[0])
        for i in range(jac.shape[0]):
            s = 0.0
            for k in range(ind.shape[0]):
                s += jac[i, ind[k]] * vs[k]
            rhs[i] -= s
        vd = _solve_cd(lu, piv, kl, ku, rows, cols, rhs)
        for k in range(dep.shape[0]):
            v[dep[k]] = vd[k]
        quality = small / max(np.abs(jac).max(), 1e-300) if ok else 0.0
    acc, lam = acceleration(plan, pr, pR, v, inputs, refs)
    return v, acc, lam, quality


@njit
def partition_quality(ip, fp, pr, pR, refs, t, dep, rows, cols, kl, ku):
    """Smallest pivot of C_d over the largest entry of C at a pose (NullSpace._pivot_ratio)."""
    plan = unpack(ip, fp)
    sel = plan[0]
    rr, RR, W = snapshot(pr, pR, np.zeros(sel.shape[0]), sel)
    _, jac, _ = constraints(plan, rr, RR, W, True, False)
    if not dep.shape[0]:
        return 1.0
    _, _, ok, small = _factor_cd(jac, dep, rows, cols, kl, ku)
    return small / max(np.abs(jac).max(), 1e-300) if ok else 0.0


@njit
def nullspace_step(ip, fp, pr, pR, v, vdot, inputs, refs, t, h, ta, tb, dep, ind, rows, cols, kl, ku, tol,
                   max_iterations):
    """One explicit RKMK step of the reduced ODE in the independent velocities, Newton on the dependent positions
    with the independent ones held, and the new velocity, acceleration and multipliers (NullSpace.step).

    Returns (ok, r, R, v, v', lambda, angle references at the new pose, partition quality at the new pose)."""
    plan = unpack(ip, fp)
    sel = plan[0]
    n = sel.shape[0]
    nf = 6 * (pr.shape[0] + 1)
    s = tb.shape[0]
    ni = ind.shape[0]
    vs = np.empty(ni)
    for k in range(ni):
        vs[k] = v[ind[k]]
    kq = np.zeros((s, nf))
    ky = np.zeros((s, ni))
    for j in range(s):
        theta, yj = rkmk_sums(kq, ky, vs, ta[j], j, h)
        cj = 0.0
        for l in range(j):
            cj += ta[j, l]
        if j == 0:  # the current state: its velocity and consistent acceleration are known
            w = v
            acc = vdot
        else:
            sr, sR = retract_full(pr, pR, theta)
            w, acc, _, _ = _rates(plan, sr, sR, yj, inputs, refs, t + cj * h, dep, ind, rows, cols, kl, ku)
        wf = np.zeros(nf)
        for i in range(n):
            wf[sel[i]] = w[i]
        kq[j] = _local_rate(theta, wf)
        for k in range(ni):
            ky[j, k] = acc[ind[k]]
    theta, vs1 = rkmk_sums(kq, ky, vs, tb, s, h)
    r1, R1 = retract_full(pr, pR, theta)
    ok = dep.shape[0] == 0
    for _ in range(max_iterations if dep.shape[0] else 0):
        rr, RR, W = snapshot(r1, R1, np.zeros(n), sel)
        phi, jac, _ = constraints(plan, rr, RR, W, True, False)
        if np.abs(phi).max() <= tol:
            ok = True
            break
        lu, piv, good, _ = _factor_cd(jac, dep, rows, cols, kl, ku)
        if not good:
            break
        step = _solve_cd(lu, piv, kl, ku, rows, cols, -phi)
        delta = np.zeros(n)
        for k in range(dep.shape[0]):
            delta[dep[k]] = step[k]
        r1, R1 = retract(r1, R1, delta, sel)
    v1, acc1, lam1, quality = _rates(plan, r1, R1, vs1, inputs, refs, t + h, dep, ind, rows, cols, kl, ku)
    rr, RR, W = snapshot(r1, R1, v1, sel)
    return ok, r1, R1, v1, acc1, lam1, angle_references(plan, rr, RR, W, refs), quality
