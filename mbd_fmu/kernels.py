"""Compiled (numba) kernels of the constrained equations of motion: one call per time step.

The same equations as :mod:`mbd_fmu.model`, :mod:`mbd_fmu.constraints` and :mod:`mbd_fmu.formulations`
(see them for the physics), evaluated on a *plan*: a tuple of plain arrays describing the model
(:func:`mbd_fmu.fast.build_plan`), so that a whole generalised-alpha step (predictor, Newton
iterations, iteration matrix, LU factorisation, update) or a whole consistent-acceleration solve
runs without returning to Python. Only the model parts listed in :mod:`mbd_fmu.fast` are compiled;
every other model runs on the Python path.

Conventions: full slot vectors have six entries per body and six for the ground (last, always zero);
``colmap[s]`` is the generalised slot of full slot ``s`` (-1 if inactive); ``rr`` (N+1, 3), ``RR``
(N+1, 3, 3), ``W`` (N+1, 6) are the snapshot with the ground appended (:class:`mbd_fmu.kinematics.Kin`).

Plan layout (index: content):
 0 sel (n,) int; 1 colmap (6(N+1),) int; 2 mass_const (n, n); 3 inertia (N, 3, 3);
 4 rot_idx (k, 5) int (mass-matrix scatter: row, col, body, local row, local col); 5 force_const (N+1, 6);
 6 flags (2,) int (rotating mass, has rotation);
 7 prim_kind (P,) int (0 point, 1 perp, 2 plane, 3 distance); 8 prim_body (P, 2) int; 9 prim_vec (P, 3, 3)
 (v_i, v_j, n_i); 10 prim_c0 (P,); 11 prim_rows (P, 3) int (global rows, -1 none); 12 prim_kept (P, 3) int
 (kept position, -1 none);
 13 moor_body (Q,) int; 14 moor_kd (Q, 2, 6, 6) (K, D); 15 moor_r0 (Q, 3);
 16 coord_kind (S,) int (0 distance, 1 slide, 2 angle, 3 + k component k of a rotation vector); 17 coord_body
 (S, 2) int; 18 coord_vec (S, 6, 3) (s_i, s_j, n or axes_i columns x, y, z, x_j; a rotation component: axes_i rows
 0-2, axes_j rows 3-5); 19 spring_coord (E,) int; 20 angle_ref (S,) (unwrapping references, updated by the caller);
 21 spring_par (E, 9) (k, c, u, neutral, friction, quadratic, force limit, velocity scale, law: 0 spring-damper/PTO,
 1 rope (k, c, length in the neutral's place), 2 Coulomb friction (F_c in the friction's place, v_reg));
 22 m (all rows), 23 n_kept rows; 24 order (n + r,) int of the saddle-point unknowns (reverse Cuthill-McKee of the
 structure); 25 band (4,) int (lower, upper bandwidth in that order of the iteration matrix, then of the
consistent-acceleration matrix ``[[M, C^T], [C, 0]]``, narrower: no tangents couple bodies; n + r - 1 each for a
dense matrix);
 26 prim_joint (P,) int (joint of each primitive, -1 for DOF locks); 27 joint_body2 (J,) int; 28 joint_offset (J, 3)
 (body 2's joint point from its cg, body axes); 29 static (N+1, 6) (static loads); 30 energy (4 N + 3,) (masses,
 gravity vector, equilibrium cgs).
"""

from __future__ import annotations

import math

import numpy as np

from fmu_base._jit import njit

# ---------------------------------------------------------------------------------------------- plan packing
# The plan travels as two flat arrays (ints, floats): numba types a tuple of 24 arrays in Python at every
# call (tens of microseconds), two arrays in C. Header of ``ints``: per entry (kind, offset, d0, d1, d2, d3),
# kind 0 int array, 1 float array, 2 int scalar.
_ENTRIES = 31
_HEAD = 6


def pack(plan: tuple) -> tuple[np.ndarray, np.ndarray]:
    """(ints, floats) holding every entry of ``plan`` (see the module docstring)."""
    head = np.zeros((_ENTRIES, _HEAD), dtype=np.int64)
    ints, floats = [np.zeros(_ENTRIES * _HEAD, dtype=np.int64)], []
    ni, nf = _ENTRIES * _HEAD, 0
    for k, e in enumerate(plan):
        if isinstance(e, (int, np.integer)):
            head[k, :3] = (2, int(e), 0)
            continue
        a = np.asarray(e)
        shape = list(a.shape) + [1] * (4 - a.ndim)
        if a.dtype.kind in "iub":
            head[k] = (0, ni, *shape)
            ints.append(a.astype(np.int64).ravel())
            ni += a.size
        else:
            head[k] = (1, nf, *shape)
            floats.append(a.astype(float).ravel())
            nf += a.size
    ints[0] = head.ravel()
    return np.concatenate(ints), np.concatenate(floats) if floats else np.zeros(0)


@njit
def _i1(ip, k):
    o, d0 = ip[_HEAD * k + 1], ip[_HEAD * k + 2]
    return ip[o:o + d0]


@njit
def _i2(ip, k):
    o, d0, d1 = ip[_HEAD * k + 1], ip[_HEAD * k + 2], ip[_HEAD * k + 3]
    return ip[o:o + d0 * d1].reshape((d0, d1))


@njit
def _f1(ip, fp, k):
    o, d0 = ip[_HEAD * k + 1], ip[_HEAD * k + 2]
    return fp[o:o + d0]


@njit
def _f2(ip, fp, k):
    o, d0, d1 = ip[_HEAD * k + 1], ip[_HEAD * k + 2], ip[_HEAD * k + 3]
    return fp[o:o + d0 * d1].reshape((d0, d1))


@njit
def _f3(ip, fp, k):
    o, d0, d1, d2 = ip[_HEAD * k + 1], ip[_HEAD * k + 2], ip[_HEAD * k + 3], ip[_HEAD * k + 4]
    return fp[o:o + d0 * d1 * d2].reshape((d0, d1, d2))


@njit
def _f4(ip, fp, k):
    o, d0, d1, d2, d3 = ip[_HEAD * k + 1], ip[_HEAD * k + 2], ip[_HEAD * k + 3], ip[_HEAD * k + 4], ip[_HEAD * k + 5]
    return fp[o:o + d0 * d1 * d2 * d3].reshape((d0, d1, d2, d3))


@njit
def unpack(ip, fp):
    """The plan tuple back from (ints, floats) (views, no copies)."""
    return (_i1(ip, 0), _i1(ip, 1), _f2(ip, fp, 2), _f3(ip, fp, 3), _i2(ip, 4), _f2(ip, fp, 5), _i1(ip, 6),
            _i1(ip, 7), _i2(ip, 8), _f3(ip, fp, 9), _f1(ip, fp, 10), _i2(ip, 11), _i2(ip, 12),
            _i1(ip, 13), _f4(ip, fp, 14), _f2(ip, fp, 15),
            _i1(ip, 16), _i2(ip, 17), _f3(ip, fp, 18), _i1(ip, 19), _f1(ip, fp, 20), _f2(ip, fp, 21),
            ip[_HEAD * 22 + 1], ip[_HEAD * 23 + 1], _i1(ip, 24), _i1(ip, 25),
            _i1(ip, 26), _i1(ip, 27), _f2(ip, fp, 28), _f2(ip, fp, 29), _f1(ip, fp, 30))

# ---------------------------------------------------------------------------------------------- small vectors


@njit
def _cross(a, b):
    return np.array((a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]))


@njit
def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit
def _mv(m, v):
    return np.array((m[0, 0] * v[0] + m[0, 1] * v[1] + m[0, 2] * v[2],
                     m[1, 0] * v[0] + m[1, 1] * v[1] + m[1, 2] * v[2],
                     m[2, 0] * v[0] + m[2, 1] * v[1] + m[2, 2] * v[2]))


@njit
def _mv3(m, v):
    """``_mv`` as three scalars (no array): the same expressions."""
    return (m[0, 0] * v[0] + m[0, 1] * v[1] + m[0, 2] * v[2],
            m[1, 0] * v[0] + m[1, 1] * v[1] + m[1, 2] * v[2],
            m[2, 0] * v[0] + m[2, 1] * v[1] + m[2, 2] * v[2])


@njit
def _mm(a, b):
    """a @ b by loops (numba sends ``@`` to BLAS, whose call costs more than a small product)."""
    n, k, m = a.shape[0], a.shape[1], b.shape[1]
    out = np.zeros((n, m))
    for i in range(n):
        for l in range(k):
            ail = a[i, l]
            if ail != 0.0:
                for j in range(m):
                    out[i, j] += ail * b[l, j]
    return out


@njit
def _matvec(a, x):
    """a @ x by loops."""
    out = np.zeros(a.shape[0])
    for i in range(a.shape[0]):
        s = 0.0
        for j in range(a.shape[1]):
            s += a[i, j] * x[j]
        out[i] = s
    return out


@njit
def _tmatvec(a, x):
    """a.T @ x by loops."""
    out = np.zeros(a.shape[1])
    for i in range(a.shape[0]):
        xi = x[i]
        if xi != 0.0:
            for j in range(a.shape[1]):
                out[j] += a[i, j] * xi
    return out


@njit
def _add_tmatvec(out, a, x, sign=1.0):
    """out[:a.shape[1]] += sign * (a.T @ x) with the sums of :func:`_tmatvec` (rows in order, zero x skipped; sign
    +-1, exact), row-wise (contiguous)."""
    m = a.shape[1]
    t = np.zeros(m)
    for i in range(a.shape[0]):
        xi = x[i]
        if xi != 0.0:
            for j in range(m):
                t[j] += a[i, j] * xi
    for j in range(m):
        out[j] += sign * t[j]


@njit
def _vdot(a, b):
    s = 0.0
    for i in range(a.shape[0]):
        s += a[i] * b[i]
    return s


@njit
def _centripetal(w, a):
    """w x (w x a)."""
    return w * _dot(w, a) - a * _dot(w, w)


@njit
def _skew(v):
    s = np.zeros((3, 3))
    s[0, 1], s[0, 2] = -v[2], v[1]
    s[1, 0], s[1, 2] = v[2], -v[0]
    s[2, 0], s[2, 1] = -v[1], v[0]
    return s


@njit
def exp_so3(x, y, z):
    """Rodrigues (mbd_fmu.rotations.exp_so3)."""
    t2 = x * x + y * y + z * z
    t = math.sqrt(t2)
    if t < 1e-6:
        a, b = 1 - t2 / 6, 0.5 - t2 / 24
    else:
        a, b = math.sin(t) / t, (1 - math.cos(t)) / t2
    out = np.empty((3, 3))
    bxy, bxz, byz = b * x * y, b * x * z, b * y * z
    out[0, 0], out[0, 1], out[0, 2] = 1 + b * (x * x - t2), bxy - a * z, bxz + a * y
    out[1, 0], out[1, 1], out[1, 2] = bxy + a * z, 1 + b * (y * y - t2), byz - a * x
    out[2, 0], out[2, 1], out[2, 2] = bxz - a * y, byz + a * x, 1 + b * (z * z - t2)
    return out


@njit
def _log3(r):
    """:func:`log_so3` as three scalars (the same expressions; no array away from an angle of pi)."""
    c = min(max((r[0, 0] + r[1, 1] + r[2, 2] - 1) / 2, -1.0), 1.0)
    t = math.acos(c)
    if t <= math.pi - 1e-4:
        factor = 0.5 + t * t / 12 if t < 1e-4 else t / (2 * math.sin(t))
        return factor * (r[2, 1] - r[1, 2]), factor * (r[0, 2] - r[2, 0]), factor * (r[1, 0] - r[0, 1])
    phi = log_so3(r)
    return phi[0], phi[1], phi[2]


@njit
def log_so3(r):
    """Rotation vector of a rotation matrix (mbd_fmu.rotations.log_so3), angle in [0, pi]."""
    c = min(max((r[0, 0] + r[1, 1] + r[2, 2] - 1) / 2, -1.0), 1.0)
    t = math.acos(c)
    w = np.array((r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]))
    if t <= math.pi - 1e-4:
        factor = 0.5 + t * t / 12 if t < 1e-4 else t / (2 * math.sin(t))
        return factor * w
    sym = 0.5 * (r + r.T) - c * np.eye(3)
    k = 0
    for i in range(1, 3):
        if sym[i, i] > sym[k, k]:
            k = i
    n = sym[k] / math.sqrt(max(sym[k, k], 1e-300))
    if _dot(n, w) < 0:
        n = -n
    return n * t


@njit
def _ljinv_t(x, y, z, g0, g1, g2):
    """``_tmatvec(left_jacobian_inverse((x, y, z)), (g0, g1, g2))`` as three scalars (the same entries and sums, zero
    components of g skipped as there)."""
    t2 = x * x + y * y + z * z
    t = math.sqrt(t2)
    c = 1 / 12 + t2 / 720 if t < 1e-4 else (1 - t * math.sin(t) / (2 * (1 - math.cos(t)))) / t2
    cxy, cxz, cyz = c * x * y, c * x * z, c * y * z
    o0, o1, o2 = 0.0, 0.0, 0.0
    if g0 != 0.0:
        o0 += (1 + c * (x * x - t2)) * g0
        o1 += (cxy + 0.5 * z) * g0
        o2 += (cxz - 0.5 * y) * g0
    if g1 != 0.0:
        o0 += (cxy - 0.5 * z) * g1
        o1 += (1 + c * (y * y - t2)) * g1
        o2 += (cyz + 0.5 * x) * g1
    if g2 != 0.0:
        o0 += (cxz + 0.5 * y) * g2
        o1 += (cyz - 0.5 * x) * g2
        o2 += (1 + c * (z * z - t2)) * g2
    return o0, o1, o2


@njit
def left_jacobian_inverse(phi):
    x, y, z = phi[0], phi[1], phi[2]
    t2 = x * x + y * y + z * z
    t = math.sqrt(t2)
    c = 1 / 12 + t2 / 720 if t < 1e-4 else (1 - t * math.sin(t) / (2 * (1 - math.cos(t)))) / t2
    out = np.empty((3, 3))
    cxy, cxz, cyz = c * x * y, c * x * z, c * y * z
    out[0, 0], out[0, 1], out[0, 2] = 1 + c * (x * x - t2), cxy + 0.5 * z, cxz - 0.5 * y
    out[1, 0], out[1, 1], out[1, 2] = cxy - 0.5 * z, 1 + c * (y * y - t2), cyz + 0.5 * x
    out[2, 0], out[2, 1], out[2, 2] = cxz + 0.5 * y, cyz - 0.5 * x, 1 + c * (z * z - t2)
    return out


# ---------------------------------------------------------------------------------------------- dense LU


@njit
def lu_factor(a, piv, kl, ku):
    """In-place LU with partial pivoting of a matrix of lower and upper bandwidths ``kl``, ``ku`` (LINPACK's
    dgbfa scheme on full storage: multipliers kept unswapped, fill-in up to ``kl + ku`` above the diagonal;
    ``kl = ku = n - 1`` is the dense LU); False if singular. Cost O(n kl (kl + ku))."""
    n = a.shape[0]
    for k in range(n):
        lo = min(n - 1, k + kl)
        hi = min(n - 1, k + kl + ku)
        p = k
        big = abs(a[k, k])
        for i in range(k + 1, lo + 1):
            if abs(a[i, k]) > big:
                big, p = abs(a[i, k]), i
        piv[k] = p
        if big == 0.0:
            return False
        if p != k:
            for j in range(k, hi + 1):
                a[k, j], a[p, j] = a[p, j], a[k, j]
        inv = 1.0 / a[k, k]
        for i in range(k + 1, lo + 1):
            f = a[i, k] * inv
            a[i, k] = f
            if f != 0.0:
                for j in range(k + 1, hi + 1):
                    a[i, j] -= f * a[k, j]
    return True


@njit
def lu_solve(a, piv, kl, ku, b):
    """Solve with the factors of :func:`lu_factor`."""
    x = b.copy()
    lu_solve_inplace(a, piv, kl, ku, x)
    return x


@njit
def lu_solve_inplace(a, piv, kl, ku, x):
    """:func:`lu_solve` overwriting the right-hand side ``x`` with the solution."""
    n = a.shape[0]
    for k in range(n):
        p = piv[k]
        if p != k:
            x[k], x[p] = x[p], x[k]
        xk = x[k]
        if xk != 0.0:
            for i in range(k + 1, min(n - 1, k + kl) + 1):
                x[i] -= a[i, k] * xk
    for i in range(n - 1, -1, -1):
        s = x[i]
        for j in range(i + 1, min(n - 1, i + kl + ku) + 1):
            s -= a[i, j] * x[j]
        x[i] = s / a[i, i]


@njit
def factor_into(plan, mat, lu, piv):
    """LU factors of the iteration matrix ``mat`` in the plan's band-reducing order into given arrays (n + r,
    n + r) and (n + r,); False if singular. Only the band (and its
    fill-in) of ``lu`` is written and read."""
    order, band = plan[24], plan[25]
    nn = mat.shape[0]
    kl, ku = band[0], band[1]
    for i in range(nn):
        oi = order[i]
        for j in range(max(0, i - kl), min(nn, i + kl + ku + 1)):
            lu[i, j] = mat[oi, order[j]]
    return lu_factor(lu, piv, kl, ku)


@njit
def solve(plan, lu, piv, b):
    """Solution with the factors of :func:`factor_into` (the iteration matrix's band)."""
    return _solve_ordered(plan[24], lu, piv, plan[25][0], plan[25][1], b)


@njit
def solve_negated_into(plan, lu, piv, b, work, x):
    """``x`` = :func:`solve` (-``b``) with no new array (``work``, ``x``: (n + r,)); the same operations."""
    order = plan[24]
    for i in range(order.shape[0]):
        work[i] = -b[order[i]]
    lu_solve_inplace(lu, piv, plan[25][0], plan[25][1], work)
    for i in range(order.shape[0]):
        x[order[i]] = work[i]


@njit
def _solve_ordered(order, lu, piv, kl, ku, b):
    x = lu_solve(lu, piv, kl, ku, b[order])
    out = np.empty_like(x)
    out[order] = x
    return out


@njit
def factor_saddle(plan, s, c):
    """LU factors of ``[[s, c^T], [c, 0]]`` (s: M or any matrix of M's structure) in the plan's order with the
    consistent-acceleration matrix's band, gathered from ``s`` and ``c`` (the saddle-point matrix is never
    formed): (factors, pivots, ok). Banded LU with partial pivoting, O((n + r) kl (kl + ku))."""
    nn = s.shape[0] + c.shape[0]
    lu = np.empty((nn, nn))
    piv = np.zeros(nn, dtype=np.int64)
    return lu, piv, factor_saddle_into(plan, s, c, lu, piv, 2)


@njit
def factor_saddle_into(plan, s, c, lu, piv, which):
    """:func:`factor_saddle` into given arrays with the band ``plan[25][which:which + 2]`` (0: the iteration
    matrix's, as :func:`factor_into` of :func:`saddle` (s, c) without forming it; 2: the consistent acceleration's);
    False if singular."""
    order, band = plan[24], plan[25]
    n = s.shape[0]
    nn = n + c.shape[0]
    kl, ku = band[which], band[which + 1]
    for i in range(nn):
        oi = order[i]
        for j in range(max(0, i - kl), min(nn, i + kl + ku + 1)):
            oj = order[j]
            if oi < n:
                lu[i, j] = s[oi, oj] if oj < n else c[oj - n, oi]
            else:
                lu[i, j] = c[oi - n, oj] if oj < n else 0.0
    return lu_factor(lu, piv, kl, ku)


@njit
def solve_saddle(plan, lu, piv, b):
    """Solution with the factors of :func:`factor_saddle`."""
    return _solve_ordered(plan[24], lu, piv, plan[25][2], plan[25][3], b)


# ---------------------------------------------------------------------------------------------- model pieces


@njit
def snapshot(pr, pR, v, sel):
    """(rr, RR, W) of a pose and generalised velocities, ground appended."""
    nb = pr.shape[0]
    rr = np.zeros((nb + 1, 3))
    RR = np.empty((nb + 1, 3, 3))
    rr[:nb] = pr
    RR[:nb] = pR
    return rr, RR, _ground_and_velocities(RR, v, sel)


@njit
def _ground_and_velocities(RR, v, sel):
    """The ground's orientation written as the last row of ``RR`` (N + 1, 3, 3); the slot velocities W (N + 1, 6)
    with the generalised velocities ``v`` in their slots ``sel``."""
    nb = RR.shape[0] - 1
    RR[nb] = np.eye(3)
    W = np.zeros((nb + 1, 6))
    wf = W.reshape(-1)
    for i in range(sel.shape[0]):
        wf[sel[i]] = v[i]
    return W


@njit
def retract(pr, pR, delta, sel):
    """pose (+) delta for generalised slots ``delta``."""
    nb = pr.shape[0]
    d = np.zeros(6 * (nb + 1))
    for i in range(sel.shape[0]):
        d[sel[i]] = delta[i]
    r1 = pr.copy()
    R1 = np.empty_like(pR)
    for b in range(nb):
        r1[b, 0] += d[6 * b]
        r1[b, 1] += d[6 * b + 1]
        r1[b, 2] += d[6 * b + 2]
        e = exp_so3(d[6 * b + 3], d[6 * b + 4], d[6 * b + 5])
        R1[b] = _mm(e, pR[b])
    return r1, R1


@njit
def world_inertia(plan, RR):
    inertia = plan[3]
    nb = inertia.shape[0]
    iw = np.empty((nb, 3, 3))
    for b in range(nb):
        r, i0 = RR[b], inertia[b]
        for i in range(3):
            for j in range(i, 3):
                acc = 0.0
                for k in range(3):
                    rik = r[i, k]
                    if rik != 0.0:
                        acc += rik * (i0[k, 0] * r[j, 0] + i0[k, 1] * r[j, 1] + i0[k, 2] * r[j, 2])
                iw[b, i, j] = acc
                iw[b, j, i] = acc
    return iw


@njit
def mass_matrix(plan, iw):
    m = plan[2].copy()
    if plan[6][0]:
        idx = plan[4]
        for k in range(idx.shape[0]):
            m[idx[k, 0], idx[k, 1]] += iw[idx[k, 2], idx[k, 3], idx[k, 4]]
    return m


@njit
def _two_points(rr, RR, W, bi, bj, si, sj):
    ai = _mv(RR[bi], si)
    aj = _mv(RR[bj], sj)
    d = rr[bj] + aj - rr[bi] - ai
    wi, wj = W[bi, 3:].copy(), W[bj, 3:].copy()
    dd = W[bj, :3] + _cross(wj, aj) - W[bi, :3] - _cross(wi, ai)
    return ai, aj, d, wi, wj, dd


@njit
def _rotation_component(RR, bi, bj, vec, k):
    """Component ``k`` of log(F_i^T F_j) (F = R A, marker axes A in ``vec[0:3]``, ``vec[3:6]``) and its Jacobian row
    on body j's rotation slots (mbd_fmu.coordinates.RotationComponent.evaluate_jacobian_only)."""
    fi = _mm(RR[bi], vec[0:3])
    fj = _mm(RR[bj], vec[3:6])
    phi = log_so3(_mm(fi.T.copy(), fj))
    jinv = left_jacobian_inverse(phi)
    row = np.zeros(3)
    for c in range(3):
        row[c] = jinv[k, 0] * fi[c, 0] + jinv[k, 1] * fi[c, 1] + jinv[k, 2] * fi[c, 2]
    return phi[k], row


@njit
def coordinate(plan, s, rr, RR, W, ref):
    """Value, rate and 12-slot Jacobian of compiled coordinate ``s`` (kind 0 distance, 1 slide, 2 angle, 3 + k
    component k of a rotation vector): :func:`coordinate_into` with a new Jacobian array."""
    jac = np.empty(12)
    value, rate = coordinate_into(plan, s, rr, RR, W, ref, jac)
    return value, rate, jac


@njit
def coordinate_into(plan, s, rr, RR, W, ref, jac):
    """Value and rate of compiled coordinate ``s``, its 12-slot Jacobian written into ``jac`` (12,) (every entry
    set); scalar arithmetic, no temporary arrays except for a rotation component."""
    kind = plan[16][s]
    bi, bj = plan[17][s, 0], plan[17][s, 1]
    vec = plan[18][s]
    jac[:] = 0.0
    if kind >= 3:  # component kind - 3 of a relative rotation vector (mbd_fmu.coordinates.RotationComponent)
        value, row = _rotation_component(RR, bi, bj, vec, kind - 3)
        jac[3:6] = -row
        jac[9:12] = row
    elif kind == 2:  # angle of x_j about z_i from x_i (mbd_fmu.coordinates.Angle)
        fx0, fx1, fx2 = _mv3(RR[bi], vec[2])
        fy0, fy1, fy2 = _mv3(RR[bi], vec[3])
        x0, x1, x2 = _mv3(RR[bj], vec[5])
        c = x0 * fx0 + x1 * fx1 + x2 * fx2
        sn = x0 * fy0 + x1 * fy1 + x2 * fy2
        raw = math.atan2(sn, c)
        value = raw + 2 * math.pi * np.rint((ref - raw) / (2 * math.pi))
        cy0, cy1, cy2 = _cross3(x0, x1, x2, fy0, fy1, fy2)
        cx0, cx1, cx2 = _cross3(x0, x1, x2, fx0, fx1, fx2)
        den = c * c + sn * sn
        g0, g1, g2 = (c * cy0 - sn * cx0) / den, (c * cy1 - sn * cx1) / den, (c * cy2 - sn * cx2) / den
        jac[3], jac[4], jac[5] = -g0, -g1, -g2
        jac[9], jac[10], jac[11] = g0, g1, g2
    else:  # the two points' separation d = r_j + a_j - r_i - a_i (:func:`_two_points`)
        a0, a1, a2 = _mv3(RR[bi], vec[0])
        b0, b1, b2 = _mv3(RR[bj], vec[1])
        d0 = rr[bj, 0] + b0 - rr[bi, 0] - a0
        d1 = rr[bj, 1] + b1 - rr[bi, 1] - a1
        d2 = rr[bj, 2] + b2 - rr[bi, 2] - a2
        if kind == 0:
            length = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
            e0, e1, e2 = d0 / length, d1 / length, d2 / length
            value = length
            jac[0], jac[1], jac[2] = -e0, -e1, -e2
            u0, u1, u2 = _cross3(a0, a1, a2, e0, e1, e2)
            jac[3], jac[4], jac[5] = -u0, -u1, -u2
            jac[6], jac[7], jac[8] = e0, e1, e2
            jac[9], jac[10], jac[11] = _cross3(b0, b1, b2, e0, e1, e2)
        else:
            n0, n1, n2 = _mv3(RR[bi], vec[2])
            value = n0 * d0 + n1 * d1 + n2 * d2 - vec[3, 0]
            jac[0], jac[1], jac[2] = -n0, -n1, -n2
            jac[3], jac[4], jac[5] = _cross3(n0, n1, n2, d0 + a0, d1 + a1, d2 + a2)
            jac[6], jac[7], jac[8] = n0, n1, n2
            jac[9], jac[10], jac[11] = _cross3(b0, b1, b2, n0, n1, n2)
    rate = 0.0
    for k in range(6):
        rate += jac[k] * W[bi, k] + jac[6 + k] * W[bj, k]
    return value, rate


@njit
def angle_references(plan, rr, RR, W, refs):
    """Unwrapped angle values at a committed state (mbd_fmu.coordinates.Angle.commit); others unchanged."""
    out = refs.copy()
    jac = np.empty(12)
    for s in range(plan[16].shape[0]):
        if plan[16][s] == 2:
            out[s] = coordinate_into(plan, s, rr, RR, W, refs[s], jac)[0]
    return out


@njit
def _law(par, x, v):
    """Force and (dF/dx, dF/dv) of a PTO law (mbd_fmu.force_elements.PtoLaw)."""
    k, c, u, fric, quad, flim, vs = par[0], par[1], par[2], par[4], par[5], par[6], par[7]
    linear = -k * x - c * v + u
    if fric == 0.0 and quad == 0.0 and flim == 0.0:
        return linear, -k, -c
    g = linear - fric * math.tanh(v / vs) - quad * abs(v) * v
    dg_dv = -c - fric / vs / math.cosh(v / vs) ** 2 - 2 * quad * abs(v)
    if flim > 0:
        slope = 1.0 / math.cosh(g / flim) ** 2
        return flim * math.tanh(g / flim), slope * -k, slope * dg_dv
    return g, -k, dg_dv


@njit
def _element_law(par, x, v):
    """Generalised force on the coordinate and (dF/dx, dF/dv) of a coordinate element at ``x`` from its neutral
    value (rope: from its length) and rate ``v``; the law is ``par[8]``: 0 spring-damper/PTO law (:func:`_law`),
    1 tension-only rope (mbd_fmu.force_elements.Rope: -max(0, k x + c v) when x > 0, tangent k, c while taut),
    2 regularised Coulomb friction (mbd_fmu.force_elements.CoulombFriction: -F_c tanh(v / v_reg))."""
    law = par[8]
    if law == 0.0:
        return _law(par, x, v)
    if law == 1.0:
        t = max(0.0, par[0] * x + par[1] * v) if x > 0 else 0.0
        if t > 0:
            return -t, -par[0], -par[1]
        return 0.0, 0.0, 0.0
    r = v / par[7]
    return -par[4] * math.tanh(r), 0.0, -par[4] / par[7] / math.cosh(min(abs(r), 50.0)) ** 2


@njit
def _element_energy(par, x, v):
    """(potential energy, dissipated power, power supplied by the command, FMU output) of a coordinate element
    (the Python elements' ``potential``, ``dissipation`` and ``output``; the PTO's supply is its force command times
    the rate; a rope reports its tension, the others their force on the coordinate)."""
    law = par[8]
    f = _element_law(par, x, v)[0]
    if law == 0.0:
        if par[4] == 0.0 and par[5] == 0.0 and par[6] == 0.0:
            diss = par[1] * v * v
        else:
            diss = -(f + par[0] * x - par[2]) * v
        return 0.5 * par[0] * x * x, diss, par[2] * v, f
    if law == 1.0:
        stretch = max(x, 0.0)
        diss = (-f - par[0] * stretch) * v if f < 0 else 0.0
        return 0.5 * par[0] * stretch * stretch, diss, 0.0, -f
    return 0.0, -f * v, 0.0, f


@njit
def _add_full(out, colmap, si, sj, val):
    gi, gj = colmap[si], colmap[sj]
    if gi >= 0 and gj >= 0:
        out[gi, gj] += val


@njit
def element_forces(plan, rr, RR, W, refs, f):
    """Add the compiled force elements' generalised forces into the full slot vector ``f`` (scalar arithmetic: a
    mooring's -K x - D w with x = (r - r0, log R), its moment through J_l(log R)^-T; a coordinate element's force
    along the coordinate's Jacobian)."""
    for q in range(plan[13].shape[0]):
        b = plan[13][q]
        k, d = plan[14][q, 0], plan[14][q, 1]
        r0 = plan[15][q]
        p0, p1, p2 = _log3(RR[b])
        x = (rr[b, 0] - r0[0], rr[b, 1] - r0[1], rr[b, 2] - r0[2], p0, p1, p2)
        g = np.empty(6)
        for i in range(6):
            sk = 0.0
            sd = 0.0
            for j in range(6):
                sk += k[i, j] * x[j]
            for j in range(6):
                sd += d[i, j] * W[b, j]
            g[i] = -sk - sd
        f[6 * b] += g[0]
        f[6 * b + 1] += g[1]
        f[6 * b + 2] += g[2]
        m0, m1, m2 = _ljinv_t(p0, p1, p2, g[3], g[4], g[5])
        f[6 * b + 3] += m0
        f[6 * b + 4] += m1
        f[6 * b + 5] += m2
    jac = np.empty(12)
    for e in range(plan[19].shape[0]):
        s = plan[19][e]
        par = plan[21][e]
        value, rate = coordinate_into(plan, s, rr, RR, W, refs[s], jac)
        force = _element_law(par, value - par[3], rate)[0]
        bi, bj = plan[17][s, 0], plan[17][s, 1]
        for k in range(6):
            f[6 * bi + k] += jac[k] * force
            f[6 * bj + k] += jac[6 + k] * force


@njit
def forces(plan, rr, RR, W, iw, inputs, refs):
    """Generalised force (gyroscopic, gravity, static loads, elements) plus the input, (n,)."""
    fc = plan[5]
    nb = fc.shape[0] - 1
    f = fc.copy().reshape(-1)
    for b in range(nb):
        w0, w1, w2 = W[b, 3], W[b, 4], W[b, 5]
        if w0 != 0.0 or w1 != 0.0 or w2 != 0.0:
            i = iw[b]
            h0 = i[0, 0] * w0 + i[0, 1] * w1 + i[0, 2] * w2
            h1 = i[1, 0] * w0 + i[1, 1] * w1 + i[1, 2] * w2
            h2 = i[2, 0] * w0 + i[2, 1] * w1 + i[2, 2] * w2
            f[6 * b + 3] -= w1 * h2 - w2 * h1
            f[6 * b + 4] -= w2 * h0 - w0 * h2
            f[6 * b + 5] -= w0 * h1 - w1 * h0
    element_forces(plan, rr, RR, W, refs, f)
    sel = plan[0]
    out = np.empty(sel.shape[0])
    for i in range(sel.shape[0]):
        out[i] = f[sel[i]] + inputs[i]
    return out


@njit
def tangents(plan, rr, RR, W, iw, acc, lam_kept, refs):
    """Stiffness and damping (n, n) of the Newton matrix: force elements, inertial and geometric stiffness,
    gyroscopic damping (mbd_fmu.model.MultibodyModel.tangents and the three following methods)."""
    sel, colmap = plan[0], plan[1]
    n = sel.shape[0]
    kt = np.zeros((n, n))
    dt = np.zeros((n, n))
    for q in range(plan[13].shape[0]):
        b = plan[13][q]
        kd = plan[14][q]
        for i in range(6):
            for j in range(6):
                _add_full(kt, colmap, 6 * b + i, 6 * b + j, kd[0, i, j])
                _add_full(dt, colmap, 6 * b + i, 6 * b + j, kd[1, i, j])
    for e in range(plan[19].shape[0]):
        s = plan[19][e]
        par = plan[21][e]
        value, rate, jac = coordinate(plan, s, rr, RR, W, refs[s])
        _, dfdx, dfdv = _element_law(par, value - par[3], rate)
        bi, bj = plan[17][s, 0], plan[17][s, 1]
        for i in range(12):
            si = 6 * bi + i if i < 6 else 6 * bj + i - 6
            for j in range(12):
                sj = 6 * bi + j if j < 6 else 6 * bj + j - 6
                _add_full(kt, colmap, si, sj, -dfdx * jac[i] * jac[j])
                _add_full(dt, colmap, si, sj, -dfdv * jac[i] * jac[j])
    if not plan[6][1]:
        return kt, dt
    nb = iw.shape[0]
    af = np.zeros(6 * (nb + 1))
    for i in range(n):
        af[sel[i]] = acc[i]
    for b in range(nb):
        a = af[6 * b + 3:6 * b + 6]
        w = W[b, 3:]
        ks = -_skew(_mv(iw[b], a)) + _mm(iw[b], _skew(a))
        ds = _mm(_skew(w), iw[b]) - _skew(_mv(iw[b], w))
        for i in range(3):
            for j in range(3):
                _add_full(kt, colmap, 6 * b + 3 + i, 6 * b + 3 + j, ks[i, j])
                _add_full(dt, colmap, 6 * b + 3 + i, 6 * b + 3 + j, ds[i, j])
    # geometric stiffness of the point and perp primitives (mbd_fmu.constraints.ConstraintSet.geometric_stiffness)
    kinds, bodies, vecs, kept = plan[7], plan[8], plan[9], plan[12]
    for p in range(kinds.shape[0]):
        bi, bj = bodies[p, 0], bodies[p, 1]
        if kinds[p] == 0:
            lk = np.zeros(3)
            for c in range(3):
                if kept[p, c] >= 0:
                    lk[c] = lam_kept[kept[p, c]]
            for side in range(2):
                b = bi if side == 0 else bj
                sign = 1.0 if side == 0 else -1.0
                a = _mv(RR[b], vecs[p, side])
                al = _dot(a, lk)
                for i in range(3):
                    for j in range(3):
                        val = a[i] * lk[j] - (al if i == j else 0.0)
                        _add_full(kt, colmap, 6 * b + 3 + i, 6 * b + 3 + j, sign * val)
        elif kinds[p] == 1 and kept[p, 0] >= 0:
            lk = lam_kept[kept[p, 0]]
            u = _mv(RR[bi], vecs[p, 0])
            w = _mv(RR[bj], vecs[p, 1])
            uw = _dot(u, w)
            for i in range(3):
                for j in range(3):
                    d = uw if i == j else 0.0
                    ii = lk * (u[i] * w[j] - d)
                    ij = lk * (d - w[i] * u[j])
                    _add_full(kt, colmap, 6 * bi + 3 + i, 6 * bi + 3 + j, ii)
                    _add_full(kt, colmap, 6 * bi + 3 + i, 6 * bj + 3 + j, ij)
                    _add_full(kt, colmap, 6 * bj + 3 + i, 6 * bi + 3 + j, -ii)
                    _add_full(kt, colmap, 6 * bj + 3 + i, 6 * bj + 3 + j, -ij)
    return kt, dt


@njit
def _put(jac, row, colmap, slot, value):
    g = colmap[slot]
    if g >= 0:
        jac[row, g] = value


@njit
def _cross3(a0, a1, a2, b0, b1, b2):
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


@njit
def _point_perp_gamma(W, bi, bj, kind, a0, a1, a2, b0, b1, b2):
    """gamma of a point primitive's three rows (w_j x (w_j x a_j) - w_i x (w_i x a_i), kind 0) or of a perp row
    (-((w_i x u) x w + u x (w_j x w)) . (w_i - w_j), u = a, w = b, kind 1) in scalars (:func:`constraints`' general
    branch's expressions)."""
    i0, i1, i2 = W[bi, 3], W[bi, 4], W[bi, 5]
    j0, j1, j2 = W[bj, 3], W[bj, 4], W[bj, 5]
    if kind == 0:
        si, sj = i0 * a0 + i1 * a1 + i2 * a2, j0 * b0 + j1 * b1 + j2 * b2
        ni, nj = i0 * i0 + i1 * i1 + i2 * i2, j0 * j0 + j1 * j1 + j2 * j2
        return ((j0 * sj - b0 * nj) - (i0 * si - a0 * ni), (j1 * sj - b1 * nj) - (i1 * si - a1 * ni),
                (j2 * sj - b2 * nj) - (i2 * si - a2 * ni))
    p0, p1, p2 = _cross3(i0, i1, i2, a0, a1, a2)
    q0, q1, q2 = _cross3(p0, p1, p2, b0, b1, b2)
    r0, r1, r2 = _cross3(j0, j1, j2, b0, b1, b2)
    s0, s1, s2 = _cross3(a0, a1, a2, r0, r1, r2)
    return -((q0 + s0) * (i0 - j0) + (q1 + s1) * (i1 - j1) + (q2 + s2) * (i2 - j2)), 0.0, 0.0


@njit
def _point_perp(rr, RR, W, bi, bj, vec, c0, kind, kept, colmap, phi, jac, want_jac, gam, want_gamma):
    """Value, Jacobian rows and (``want_gamma``) gamma of a point (kind 0) or perp (kind 1) primitive in scalar
    arithmetic, no temporary arrays (the same expressions as :func:`constraints`' general branch)."""
    ri, rj = RR[bi], RR[bj]
    a0 = ri[0, 0] * vec[0, 0] + ri[0, 1] * vec[0, 1] + ri[0, 2] * vec[0, 2]
    a1 = ri[1, 0] * vec[0, 0] + ri[1, 1] * vec[0, 1] + ri[1, 2] * vec[0, 2]
    a2 = ri[2, 0] * vec[0, 0] + ri[2, 1] * vec[0, 1] + ri[2, 2] * vec[0, 2]
    b0 = rj[0, 0] * vec[1, 0] + rj[0, 1] * vec[1, 1] + rj[0, 2] * vec[1, 2]
    b1 = rj[1, 0] * vec[1, 0] + rj[1, 1] * vec[1, 1] + rj[1, 2] * vec[1, 2]
    b2 = rj[2, 0] * vec[1, 0] + rj[2, 1] * vec[1, 1] + rj[2, 2] * vec[1, 2]
    si, sj = 6 * bi, 6 * bj
    if kind == 1:  # u . w = c0, u = a, w = b
        row = kept[0]
        if row < 0:
            return
        phi[row] = a0 * b0 + a1 * b1 + a2 * b2 - c0
        if want_gamma:
            gam[row] = _point_perp_gamma(W, bi, bj, 1, a0, a1, a2, b0, b1, b2)[0]
        if want_jac:
            x0, x1, x2 = a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0
            _put(jac, row, colmap, si + 3, x0)
            _put(jac, row, colmap, si + 4, x1)
            _put(jac, row, colmap, si + 5, x2)
            _put(jac, row, colmap, sj + 3, -x0)
            _put(jac, row, colmap, sj + 4, -x1)
            _put(jac, row, colmap, sj + 5, -x2)
        return
    a = (a0, a1, a2)
    b = (b0, b1, b2)
    g = _point_perp_gamma(W, bi, bj, 0, a0, a1, a2, b0, b1, b2) if want_gamma else (0.0, 0.0, 0.0)
    for c in range(3):
        row = kept[c]
        if row < 0:
            continue
        phi[row] = rr[bi, c] + a[c] - rr[bj, c] - b[c]
        if want_gamma:
            gam[row] = g[c]
        if not want_jac:
            continue
        _put(jac, row, colmap, si + c, 1.0)
        _put(jac, row, colmap, sj + c, -1.0)
        # -S(a_i) row c on body i's rotations, S(a_j) row c on body j's: S(v) rows (0,-v2,v1), (v2,0,-v0), (-v1,v0,0)
        if c == 0:
            _put(jac, row, colmap, si + 4, a2)
            _put(jac, row, colmap, si + 5, -a1)
            _put(jac, row, colmap, sj + 4, -b2)
            _put(jac, row, colmap, sj + 5, b1)
        elif c == 1:
            _put(jac, row, colmap, si + 3, -a2)
            _put(jac, row, colmap, si + 5, a0)
            _put(jac, row, colmap, sj + 3, b2)
            _put(jac, row, colmap, sj + 5, -b0)
        else:
            _put(jac, row, colmap, si + 3, a1)
            _put(jac, row, colmap, si + 4, -a0)
            _put(jac, row, colmap, sj + 3, -b1)
            _put(jac, row, colmap, sj + 4, b0)


@njit
def constraints(plan, rr, RR, W, want_jac, want_gamma):
    """Kept rows: Phi (r,), Jacobian (r, n) on generalised slots, gamma (r,) (mbd_fmu.constraints)."""
    colmap = plan[1]
    n = plan[0].shape[0]
    nk = plan[23]
    phi = np.zeros(nk)
    jac = np.zeros((nk, n)) if want_jac else np.zeros((0, 0))
    gam = np.zeros(nk) if want_gamma else np.zeros(0)
    kinds, bodies, vecs, c0, kept = plan[7], plan[8], plan[9], plan[10], plan[12]
    blk = np.zeros((3, 12))
    for p in range(kinds.shape[0]):
        kind = kinds[p]
        if kept[p, 0] < 0 and kept[p, 1] < 0 and kept[p, 2] < 0:
            continue
        if kind <= 1:  # scalars only, no temporary arrays (the general branch below has the same expressions)
            _point_perp(rr, RR, W, bodies[p, 0], bodies[p, 1], vecs[p], c0[p], kind, kept[p], colmap, phi, jac,
                        want_jac, gam, want_gamma)
            continue
        bi, bj = bodies[p, 0], bodies[p, 1]
        val = np.zeros(3)
        gm = np.zeros(3)
        blk[:] = 0.0
        if kind == 0:
            ai = _mv(RR[bi], vecs[p, 0])
            aj = _mv(RR[bj], vecs[p, 1])
            val = rr[bi] + ai - rr[bj] - aj
            si, sj = _skew(ai), _skew(aj)
            for c in range(3):
                blk[c, c] = 1.0
                blk[c, 6 + c] = -1.0
                for k in range(3):
                    blk[c, 3 + k] = -si[c, k]
                    blk[c, 9 + k] = sj[c, k]
            if want_gamma:
                gm = _centripetal(W[bj, 3:], aj) - _centripetal(W[bi, 3:], ai)
        elif kind == 1:
            u = _mv(RR[bi], vecs[p, 0])
            w = _mv(RR[bj], vecs[p, 1])
            val[0] = _dot(u, w) - c0[p]
            uxw = _cross(u, w)
            blk[0, 3:6] = uxw
            blk[0, 9:12] = -uxw
            if want_gamma:
                wi, wj = W[bi, 3:].copy(), W[bj, 3:].copy()
                d = _cross(_cross(wi, u), w) + _cross(u, _cross(wj, w))
                gm[0] = -_dot(d, wi - wj)
        else:
            ai, aj, d, wi, wj, dd = _two_points(rr, RR, W, bi, bj, vecs[p, 0], vecs[p, 1])
            cent = _centripetal(wj, aj) - _centripetal(wi, ai)
            if kind == 2:
                nv = _mv(RR[bi], vecs[p, 2])
                val[0] = _dot(nv, d) - c0[p]
                blk[0, 0:3] = -nv
                blk[0, 3:6] = _cross(nv, d + ai)
                blk[0, 6:9] = nv
                blk[0, 9:12] = _cross(aj, nv)
                if want_gamma:
                    win = _cross(wi, nv)
                    gm[0] = -(_dot(_cross(wi, win), d) + 2 * _dot(win, dd) + _dot(nv, cent))
            else:
                length = math.sqrt(_dot(d, d))
                e = d / length
                val[0] = length - c0[p]
                blk[0, 0:3] = -e
                blk[0, 3:6] = -_cross(ai, e)
                blk[0, 6:9] = e
                blk[0, 9:12] = _cross(aj, e)
                if want_gamma:
                    ed = _dot(e, dd)
                    gm[0] = -(_dot(e, cent) + (_dot(dd, dd) - ed * ed) / length)
        for c in range(3):
            row = kept[p, c]
            if row < 0:
                continue
            phi[row] = val[c]
            if want_gamma:
                gam[row] = gm[c]
            if want_jac:
                for k in range(12):
                    g = colmap[6 * bi + k] if k < 6 else colmap[6 * bj + k - 6]
                    if g >= 0:
                        jac[row, g] = blk[c, k]
    return phi, jac, gam


@njit
def saddle(s, c):
    n, r = s.shape[0], c.shape[0]
    out = np.zeros((n + r, n + r))
    out[:n, :n] = s
    out[:n, n:] = c.T
    out[n:, :n] = c
    return out


@njit
def acceleration_packed(ip, fp, pr, pR, v, inputs, refs):
    """:func:`acceleration` on a packed plan (the entry point from Python)."""
    return acceleration(unpack(ip, fp), pr, pR, v, inputs, refs)


@njit
def acceleration(plan, pr, pR, v, inputs, refs):
    """Consistent v' and lambda (kept rows) from the saddle-point system (Formulation.acceleration)."""
    vd, lam, _, _, _ = acceleration_factored(plan, pr, pR, v, inputs, refs)
    return vd, lam


@njit
def _saddle_parts(plan, pr, pR, v, inputs, refs):
    """Mass matrix M, forces f, kept constraint Jacobian C and gamma at (pose, v): the saddle-point system
    ``[[M, C^T], [C, 0]] [v'; lambda] = [f; gamma]``."""
    rr, RR, W = snapshot(pr, pR, v, plan[0])
    iw = world_inertia(plan, RR)
    mass = mass_matrix(plan, iw)
    f = forces(plan, rr, RR, W, iw, inputs, refs)
    _, jac, gam = constraints(plan, rr, RR, W, True, True)
    return mass, f, jac, gam


@njit
def acceleration_factored(plan, pr, pR, v, inputs, refs):
    """:func:`acceleration` and the LU factors of its saddle-point matrix (plan's order): (v', lambda, factors,
    pivots, ok); v' and lambda NaN when the matrix is singular."""
    n = plan[0].shape[0]
    mass, f, jac, gam = _saddle_parts(plan, pr, pR, v, inputs, refs)
    r = jac.shape[0]
    rhs = np.empty(n + r)
    rhs[:n] = f
    rhs[n:] = gam
    lu, piv, ok = factor_saddle(plan, mass, jac)
    if not ok:
        return np.full(n, np.nan), np.full(r, np.nan), lu, piv, False
    x = solve_saddle(plan, lu, piv, rhs)
    return x[:n].copy(), x[n:].copy(), lu, piv, True


@njit
def saddle_residual(plan, pr, pR, v, inputs, refs, vd, lam):
    """``[f - M v' - C^T lambda; gamma - C v']`` of the saddle-point system at (pose, v) for given v', lambda."""
    return _saddle_residual_at(plan, snapshot(pr, pR, v, plan[0]), inputs, refs, vd, lam)


@njit
def _saddle_residual_at(plan, snap, inputs, refs, vd, lam):
    """:func:`saddle_residual` at a snapshot ``snap`` = (rr, RR, W) of the state."""
    rr, RR, W = snap
    iw = world_inertia(plan, RR)
    mass = mass_matrix(plan, iw)
    f = forces(plan, rr, RR, W, iw, inputs, refs)
    _, jac, gam = constraints(plan, rr, RR, W, True, True)
    n, r = vd.shape[0], lam.shape[0]
    out = np.empty(n + r)
    for i in range(n):  # f - M v' - C^T lambda, the sums in _matvec's and _tmatvec's order
        s = 0.0
        for j in range(n):
            s += mass[i, j] * vd[j]
        out[i] = f[i] - s
    _add_tmatvec(out, jac, lam, -1.0)
    for k in range(r):
        s = 0.0
        for j in range(n):
            s += jac[k, j] * vd[j]
        out[n + k] = gam[k] - s
    return out


@njit
def row_quality(ip, fp, pr, pR):
    """Smallest singular value of the row-normalised kept Jacobian (Formulation.reselect_rows)."""
    plan = unpack(ip, fp)
    rr, RR, W = snapshot(pr, pR, np.zeros(plan[0].shape[0]), plan[0])
    return _row_quality(plan, rr, RR, W)


@njit
def _row_quality(plan, rr, RR, W):
    jac = constraints(plan, rr, RR, W, True, False)[1]
    for i in range(jac.shape[0]):
        jac[i] /= max(math.sqrt(np.sum(jac[i] ** 2)), 1e-300)
    gram = np.zeros((jac.shape[0], jac.shape[0]))
    for i in range(jac.shape[0]):
        for j in range(i + 1):
            gram[i, j] = gram[j, i] = _vdot(jac[i], jac[j])
    return math.sqrt(max(np.linalg.eigvalsh(gram).min(), 0.0)) if jac.shape[0] else 1.0


# ---------------------------------------------------------------------------------------------- generalised-alpha


@njit
def _retract_snapshot(pr, pR, d, v, sel):
    """:func:`snapshot` of (:func:`retract` (pr, pR, delta), v) for the full slot increment ``d`` (6 (N + 1),) (the
    same arithmetic, no intermediate pose)."""
    nb = pr.shape[0]
    rr = np.zeros((nb + 1, 3))
    RR = np.empty((nb + 1, 3, 3))
    for b in range(nb):
        rr[b, 0] = pr[b, 0] + d[6 * b]
        rr[b, 1] = pr[b, 1] + d[6 * b + 1]
        rr[b, 2] = pr[b, 2] + d[6 * b + 2]
        e = exp_so3(d[6 * b + 3], d[6 * b + 4], d[6 * b + 5])
        p = pR[b]
        for i in range(3):
            for j in range(3):  # _mm(e, pR[b]): zero factors skipped as there
                acc = 0.0
                for k in range(3):
                    eik = e[i, k]
                    if eik != 0.0:
                        acc += eik * p[k, j]
                RR[b, i, j] = acc
    return rr, RR, _ground_and_velocities(RR, v, sel)


@njit
def _ga_residual(plan, pr, pR, vd, lam, vd_n, a_n, v_n, h, coef, inputs, refs):
    """Residual of the index-3 generalised-alpha equations at (v', lambda) (mbd_fmu.formulations.Index3.step):
    [M v' - f + C^T lambda; Phi / (h^2 beta zeta)] at the step's end state, and that state's snapshot, world
    inertia, mass matrix and constraint Jacobian. Elementwise scalar loops, the same expressions as the array form
    ``a1 = (af vd_n - am a_n + (1 - af) vd) / (1 - am)``, ``v1 = v_n + h ((1 - g) a_n + g a1)``, increment
    ``h (v_n + h ((0.5 - b) a_n + b a1))``."""
    am, af, g, b = coef[0], coef[1], coef[2], coef[3]
    zeta = (1 - af) / (1 - am)
    sel = plan[0]
    n = sel.shape[0]
    nb = pr.shape[0]
    v1 = np.empty(n)
    d = np.zeros(6 * (nb + 1))
    for i in range(n):
        a1 = (af * vd_n[i] - am * a_n[i] + (1 - af) * vd[i]) / (1 - am)
        v1[i] = v_n[i] + h * ((1 - g) * a_n[i] + g * a1)
        d[sel[i]] = h * (v_n[i] + h * ((0.5 - b) * a_n[i] + b * a1))
    rr, RR, W = _retract_snapshot(pr, pR, d, v1, sel)
    iw = world_inertia(plan, RR)
    mass = mass_matrix(plan, iw)
    phi, jac, _ = constraints(plan, rr, RR, W, True, False)
    f = forces(plan, rr, RR, W, iw, inputs, refs)
    r = phi.shape[0]
    res = np.empty(n + r)
    for i in range(n):  # M v' - f + C^T lambda, the sums in _matvec's and _tmatvec's order
        s = 0.0
        for j in range(n):
            s += mass[i, j] * vd[j]
        res[i] = s - f[i]
    _add_tmatvec(res, jac, lam)
    scale = h * h * b * zeta
    for k in range(r):
        res[n + k] = phi[k] / scale
    return res, rr, RR, W, iw, mass, jac


@njit
def _ga_substep(plan, pr, pR, v_n, vd_n, a_n, lam_n, inputs, refs, h, coef, newton_tolerance, length,
                max_iterations, lu, piv, have_lu):
    """One step of :func:`ga_step` and, if converged, its update, the angle references, (with redundant
    constraints) the kept rows' quality and the powers at the new state: (status, iterations, keep, quality, v',
    lambda, r, R, v, a, refs, dissipated power, supplied power, springs' dissipated powers); the state entries are
    the old ones when not converged."""
    tol = newton_tolerance * max(length, np.abs(v_n).max() if v_n.shape[0] else 0.0)
    status, iterations, keep, vd, lam = ga_step(plan, pr, pR, v_n, vd_n, a_n, lam_n, inputs, refs, h, coef,
                                                tol, max_iterations, lu, piv, have_lu)
    if status != 0:
        return (status, iterations, keep, 1.0, vd_n, lam_n, pr, pR, v_n, a_n, refs, 0.0, 0.0,
                np.zeros(plan[19].shape[0]))
    rr, RR, W, v1, a1 = _ga_update_snapshot(plan, pr, pR, v_n, vd_n, a_n, vd, h, coef)
    nb = pr.shape[0]
    r1, R1 = rr[:nb], RR[:nb]  # the new pose: views of the snapshot (ground last)
    refs1 = angle_references(plan, rr, RR, W, refs)
    quality = _row_quality(plan, rr, RR, W) if plan[23] < plan[22] else 1.0
    diss, supply, spring = _powers_at(plan, rr, RR, W, v1, inputs, refs1)
    return status, iterations, keep, quality, vd, lam, r1, R1, v1, a1, refs1, diss, supply, spring


@njit
def ga_step(plan, pr, pR, v_n, vd_n, a_n, lam_n, inputs, refs, h, coef, tol, max_iterations, lu, piv, have_lu):
    """One Lie group generalised-alpha step of the index-3 DAE (mbd_fmu.formulations.Index3.step, same
    iteration: modified Newton with the matrix kept across steps, damped when the residual grows, a
    finite-difference Jacobian when the contraction stagnates). ``lu``, ``piv`` (n + r): the factors, used if
    ``have_lu`` and overwritten when refreshed.

    Returns (status, iterations, keep matrix, vd, lam): status 0 converged, 1 not converged, 2 singular matrix.
    """
    am, af, g, b = coef[0], coef[1], coef[2], coef[3]
    zeta = (1 - af) / (1 - am)
    n = v_n.shape[0]
    vd, lam = vd_n.copy(), lam_n.copy()
    nn = n + lam.shape[0]
    exact = False
    size = np.inf
    r_norm_prev = np.inf
    dx = np.zeros(nn)
    work = np.empty(nn)
    has_dx = False
    previous = -1.0
    lu_ok = have_lu
    status = 1
    iterations = 0
    it = 0
    for it in range(max_iterations):
        res, rr, RR, W, iw, mass, jac = _ga_residual(plan, pr, pR, vd, lam, vd_n, a_n, v_n, h, coef, inputs, refs)
        r_norm = np.abs(res).max() if nn else 0.0
        backtracks = 0
        while has_dx and it >= 2 and r_norm > r_norm_prev and backtracks < 6:
            dx = 0.5 * dx
            vd = vd - dx[:n]
            lam = lam - dx[n:]
            res, rr, RR, W, iw, mass, jac = _ga_residual(plan, pr, pR, vd, lam, vd_n, a_n, v_n, h, coef, inputs,
                                                         refs)
            r_norm = np.abs(res).max()
            backtracks += 1
        r_norm_prev = r_norm
        if not lu_ok:
            if exact:
                mat = np.zeros((nn, nn))
                for i in range(n):
                    e = 1e-7 * max(1.0, abs(vd[i]))
                    vde = vd.copy()
                    vde[i] += e
                    mat[:, i] = (_ga_residual(plan, pr, pR, vde, lam, vd_n, a_n, v_n, h, coef, inputs, refs)[0]
                                 - res) / e
                mat[:n, n:] = jac.T
                if not factor_into(plan, mat, lu, piv):
                    return 2, iterations, False, vd, lam
            else:
                kt, dt = tangents(plan, rr, RR, W, iw, vd, lam, refs)
                cd, ck = h * g * zeta, h * h * b * zeta
                for i in range(n):  # S = M + h g zeta D + h^2 b zeta K in place of K (elementwise, the same sums)
                    for j in range(n):
                        kt[i, j] = mass[i, j] + cd * dt[i, j] + ck * kt[i, j]
                if not factor_saddle_into(plan, kt, jac, lu, piv, 0):
                    return 2, iterations, False, vd, lam
            lu_ok = True
        solve_negated_into(plan, lu, piv, res, work, dx)
        has_dx = True
        for i in range(n):
            vd[i] += dx[i]
        for k in range(nn - n):
            lam[k] += dx[n + k]
        iterations += 1
        size = max(h * h * b, h * g) * zeta * np.abs(dx[:n]).max() if n else 0.0
        if size <= 1e-2 * tol:
            status = 0
            break
        if previous > 0:
            theta = size / previous
            if (theta < 1 and size * theta / (1 - theta) <= tol) or (theta > 0.5 and size <= 100 * tol):
                status = 0
                break
            if theta > 0.3:
                exact = exact or it >= 4
                lu_ok = False
        previous = size
    keep = status == 0 and (not exact) and it < 3 and lu_ok
    return status, iterations, keep, vd, lam


@njit
def _ga_update_snapshot(plan, pr, pR, v_n, vd_n, a_n, vd, h, coef):
    """Positions, velocities and algorithmic acceleration at the end of a converged generalised-alpha step, as the
    new state's snapshot (rr, RR, W) (the pose: its first N rows), v, a (:func:`_ga_residual`'s loops):
    a1 = (af v'_n - am a_n + (1 - af) v') / (1 - am), v1 = v_n + h ((1 - g) a_n + g a1),
    q1 = q_n (+) h (v_n + h ((1/2 - b) a_n + b a1))."""
    am, af, g, b = coef[0], coef[1], coef[2], coef[3]
    sel = plan[0]
    n = sel.shape[0]
    v1 = np.empty(n)
    a1 = np.empty(n)
    d = np.zeros(6 * (pr.shape[0] + 1))
    for i in range(n):
        a1[i] = (af * vd_n[i] - am * a_n[i] + (1 - af) * vd[i]) / (1 - am)
        v1[i] = v_n[i] + h * ((1 - g) * a_n[i] + g * a1[i])
        d[sel[i]] = h * (v_n[i] + h * ((0.5 - b) * a_n[i] + b * a1[i]))
    rr, RR, W = _retract_snapshot(pr, pR, d, v1, sel)
    return rr, RR, W, v1, a1


@njit
def start_acceleration(ip, fp, pr, pR, v, vdot, inputs, refs, h, delta):
    """a = v' + Delta h v'' with v'' = d/dt of the consistent acceleration along the motion
    (Index3._start_acceleration); returns (a, stiff) with ``stiff`` when the shift is meaningless and a = v' was
    used. One factorisation (the centre's): :func:`taylor_shift`."""
    plan = unpack(ip, fp)
    vd0, lam0, lu, piv, ok = acceleration_factored(plan, pr, pR, v, inputs, refs)
    if not ok:
        return vdot.copy(), True
    return taylor_shift(plan, pr, pR, v, vdot, vd0, lam0, lu, piv, inputs, refs, h, delta)


@njit
def taylor_shift(plan, pr, pR, v, vdot, vd0, lam0, lu, piv, inputs, refs, h, delta):
    """Generalised-alpha's starting value a = v' + Delta h v'' (Arnold & Bruls 2007) from the centre's consistent
    solution x0 = (v'0, lambda0) of ``S(q, v) x = b(q, v)`` and the LU factors of S0 (:func:`acceleration_factored`).

    Method: x(s) along the motion (q retracted by s v, v + s v') has x' = S0^-1 (b' - S' x0); b' - S' x0 is the
    central difference of the residuals r(+-eps) = b(+-eps) - S(+-eps) x0 (eps = 1e-5 h), so v'' costs two model
    evaluations and one solve with the centre's factors, no new factorisation. It equals the central difference
    of the two shifted solutions, each corrected once from x0 (x+- = x0 + S0^-1 r(+-eps), exact to O(eps^2) with
    the same eps^2 term on both sides), hence truncation error O(eps^2) (second order in eps) plus round-off
    O(u |x| / eps) with u the machine precision; the shift's error Delta h * that is far below the step's
    own O(h^3) error. Returns (a, stiff): when |Delta h v''| > 0.5 |v'| (stiff components, h |lambda| >> 1) the
    Taylor shift is meaningless and a = v' is returned with ``stiff`` True."""
    eps = 1e-5 * h
    sel = plan[0]
    n = sel.shape[0]
    d = np.zeros(6 * (pr.shape[0] + 1))
    for i in range(n):
        d[sel[i]] = eps * v[i]
    rp = _saddle_residual_at(plan, _retract_snapshot(pr, pR, d, v + eps * vdot, sel), inputs, refs, vd0, lam0)
    for i in range(n):
        d[sel[i]] = -eps * v[i]
    rm = _saddle_residual_at(plan, _retract_snapshot(pr, pR, d, v - eps * vdot, sel), inputs, refs, vd0, lam0)
    correction = delta * h * solve_saddle(plan, lu, piv, (rp - rm) / (2 * eps))[:n]
    if np.abs(correction).max() > 0.5 * np.abs(vdot).max() + 1e-12:
        return vdot.copy(), True
    return vdot + correction, False


@njit
def committed(ip, fp, pr, pR, v, refs):
    """Angle references after an accepted step."""
    plan = unpack(ip, fp)
    rr, RR, W = snapshot(pr, pR, v, plan[0])
    return angle_references(plan, rr, RR, W, refs)


# ---------------------------------------------------------------------------------------------- energy account


@njit
def powers(ip, fp, pr, pR, v, inputs, refs):
    """(dissipated power, power supplied from outside, each spring's dissipated power (E,)) of the compiled
    elements and the input (MultibodySimulator.powers; the compiled path has no drivers)."""
    return _powers(unpack(ip, fp), pr, pR, v, inputs, refs)


@njit
def _powers(plan, pr, pR, v, inputs, refs):
    rr, RR, W = snapshot(pr, pR, v, plan[0])
    return _powers_at(plan, rr, RR, W, v, inputs, refs)


@njit
def _skew_part_nonzero(k):
    """Whether 0.5 (k - k^T) has a non-zero entry (a 6 x 6 mooring stiffness that supplies power)."""
    for i in range(6):
        for j in range(6):
            if 0.5 * (k[i, j] - k[j, i]) != 0.0:
                return True
    return False


@njit
def _powers_at(plan, rr, RR, W, v, inputs, refs):
    """:func:`powers` at a snapshot ``rr``, ``RR``, ``W`` of the state (pose, ``v``)."""
    diss = 0.0
    supply = 0.0
    spring = np.zeros(plan[19].shape[0])
    for q in range(plan[13].shape[0]):
        b = plan[13][q]
        kd = plan[14][q]
        w = W[b]
        dw = 0.0  # w . (D w)
        for i in range(6):
            si = 0.0
            for j in range(6):
                si += kd[1, i, j] * w[j]
            dw += w[i] * si
        diss += dw
        if _skew_part_nonzero(kd[0]):
            sk = 0.5 * (kd[0] - kd[0].T)
            phi = log_so3(RR[b])
            x = np.empty(6)
            x[:3] = rr[b] - plan[15][q]
            x[3:] = phi
            g = -_matvec(sk, x)
            g[3:] = _tmatvec(left_jacobian_inverse(phi), g[3:])
            supply += _vdot(g, w)
    jac = np.empty(12)
    for e in range(plan[19].shape[0]):
        s = plan[19][e]
        par = plan[21][e]
        value, rate = coordinate_into(plan, s, rr, RR, W, refs[s], jac)
        _, spring[e], supplied, _ = _element_energy(par, value - par[3], rate)
        diss += spring[e]
        supply += supplied
    return diss, supply + _vdot(inputs, v), spring


# ---------------------------------------------------------------------------------------------- index-1 RKMK


@njit
def retract_full(pr, pR, d):
    nb = pr.shape[0]
    r1 = pr.copy()
    R1 = np.empty_like(pR)
    for b in range(nb):
        r1[b] += d[6 * b:6 * b + 3]
        R1[b] = _mm(exp_so3(d[6 * b + 3], d[6 * b + 4], d[6 * b + 5]), pR[b])
    return r1, R1


@njit
def _local_rate(theta, wf):
    """Translations as they are, rotations J_l(theta)^-1 w (mbd_fmu.integrators._local_rate)."""
    out = wf.copy()
    for b in range(theta.shape[0] // 6):
        out[6 * b + 3:6 * b + 6] = _matvec(left_jacobian_inverse(theta[6 * b + 3:6 * b + 6]), wf[6 * b + 3:6 * b + 6])
    return out


@njit
def project_positions(plan, pr, pR, tol, max_iterations):
    """Nearest consistent position in the mass metric (Index1.project): simplified Newton on Phi(q) = 0,
    q += W^-1 C0^T mu with ``[[W, C0^T], [C0, 0]]`` of the first iterate factorised once (W = M there). The
    step's drift is tiny, so the contraction rate O(|correction|) makes one iteration usual; the converged pose
    satisfies Phi = 0 to ``tol`` whatever the matrix. (ok, r, R); no factorisation when already consistent."""
    sel = plan[0]
    n = sel.shape[0]
    zero = np.zeros(n)
    lu = np.empty((0, 0))
    piv = np.zeros(0, dtype=np.int64)
    for _ in range(max_iterations):
        rr, RR, W = snapshot(pr, pR, zero, sel)
        phi, jac, _ = constraints(plan, rr, RR, W, lu.shape[0] == 0, False)
        r = phi.shape[0]
        if r == 0 or np.abs(phi).max() <= tol:
            return True, pr, pR
        if lu.shape[0] == 0:
            lu, piv, ok = factor_saddle(plan, mass_matrix(plan, world_inertia(plan, RR)), jac)
            if not ok:
                return False, pr, pR
        rhs = np.zeros(n + r)
        rhs[n:] = -phi
        pr, pR = retract(pr, pR, solve_saddle(plan, lu, piv, rhs)[:n], sel)
    return False, pr, pR


@njit
def consistent_state(plan, pr, pR, v, inputs, refs):
    """At a consistent pose: the velocity projected onto C v = 0 in the mass metric (v += M^-1 C^T mu) and the
    consistent acceleration and multipliers there, both from one factorisation of ``[[M, C^T], [C, 0]]``
    (the same matrix). (v, v', lambda, ok)."""
    sel = plan[0]
    n = sel.shape[0]
    rr, RR, W = snapshot(pr, pR, v, sel)
    mass = mass_matrix(plan, world_inertia(plan, RR))
    jac = constraints(plan, rr, RR, W, True, False)[1]
    r = jac.shape[0]
    lu, piv, ok = factor_saddle(plan, mass, jac)
    if not ok:
        return v, np.full(n, np.nan), np.full(r, np.nan), False
    if r:
        rhs = np.zeros(n + r)
        rhs[n:] = -_matvec(jac, v)
        v = v + solve_saddle(plan, lu, piv, rhs)[:n]
    rr, RR, W = snapshot(pr, pR, v, sel)
    iw = world_inertia(plan, RR)
    rhs = np.empty(n + r)
    rhs[:n] = forces(plan, rr, RR, W, iw, inputs, refs)
    rhs[n:] = constraints(plan, rr, RR, W, False, True)[2]
    x = solve_saddle(plan, lu, piv, rhs)
    return v, x[:n].copy(), x[n:].copy(), True


@njit
def rkmk_sums(kq, ky, y0, coef, count, h):
    """An RKMK stage's (``coef`` = a row of the Butcher matrix, ``count`` = the stage's index) or the step's
    (``coef`` = b, ``count`` = stages) increments: theta = h sum_l coef_l kq_l (the Lie algebra's, all bodies' 6
    slots) and y = y0 + h sum_l coef_l ky_l (the integrated velocities), over l < count, zero weights skipped."""
    theta = np.zeros(kq.shape[1])
    y = y0.copy()
    for l in range(count):
        if coef[l] != 0.0:
            theta += h * coef[l] * kq[l]
            y += h * coef[l] * ky[l]
    return theta, y


@njit
def rkmk_index1(ip, fp, pr, pR, v, vdot, inputs, refs, h, ta, tb, tol, max_iterations):
    """One explicit RKMK step of the index-1 DAE, projection and the new consistent acceleration
    (Index1.step): (ok, r, R, v, v', lambda, angle references). Factorisations of the banded saddle-point
    matrix: one per stage after the first (the stage's consistent acceleration), one for the position projection
    when the step drifted (:func:`project_positions`), one shared by the velocity projection and the new
    acceleration (:func:`consistent_state`)."""
    plan = unpack(ip, fp)
    sel = plan[0]
    n = sel.shape[0]
    nf = 6 * (pr.shape[0] + 1)
    s = tb.shape[0]
    kq = np.zeros((s, nf))
    ky = np.zeros((s, n))
    for j in range(s):
        theta, yj = rkmk_sums(kq, ky, v, ta[j], j, h)
        if j == 0:
            yd = vdot
        else:
            sr, sR = retract_full(pr, pR, theta)
            yd = acceleration(plan, sr, sR, yj, inputs, refs)[0]
        wf = np.zeros(nf)
        for i in range(n):
            wf[sel[i]] = yj[i]
        kq[j] = _local_rate(theta, wf)
        ky[j] = yd
    theta, y = rkmk_sums(kq, ky, v, tb, s, h)
    r1, R1 = retract_full(pr, pR, theta)
    ok, r1, R1 = project_positions(plan, r1, R1, tol, max_iterations)
    if not ok:
        return False, r1, R1, y, np.full(n, np.nan), np.full(plan[23], np.nan), refs.copy()
    v1, vd1, lam1, _ = consistent_state(plan, r1, R1, y, inputs, refs)
    rr, RR, W = snapshot(r1, R1, v1, sel)
    return ok, r1, R1, v1, vd1, lam1, angle_references(plan, rr, RR, W, refs)


# ---------------------------------------------------------------------------------------------- outputs


@njit
def outputs(ip, fp, pr, pR, v, lam_kept, refs):
    """:func:`_outputs` on a packed plan (the entry point from Python)."""
    return _outputs(unpack(ip, fp), pr, pR, v, lam_kept, refs)


@njit
def _outputs(plan, pr, pR, v, lam_kept, refs):
    """Everything the FMU reports, in one call (MultibodySimulator's output methods): flat array of
    displacements (N, 6) (cg translation from ``cg``, rotation vector), kinetic and potential energy, the largest
    constraint residual over all rows, each joint's reaction force and moment about its point on body 2 (J, 6),
    each compiled coordinate's value and rate (S, 2) and each spring's force (E,)."""
    sel = plan[0]
    nb = pr.shape[0]
    rr, RR, W = snapshot(pr, pR, v, sel)
    iw = world_inertia(plan, RR)
    mass = mass_matrix(plan, iw)
    energy = plan[30]
    cg = energy[nb + 3:].reshape((nb, 3))
    gravity = energy[nb:nb + 3]
    static = plan[29]
    n_joint = plan[27].shape[0]
    n_coord = plan[16].shape[0]
    n_spring = plan[19].shape[0]
    out = np.zeros(6 * nb + 3 + 6 * n_joint + 2 * n_coord + n_spring)
    potential = 0.0
    for b in range(nb):
        phi = log_so3(RR[b])
        for k in range(3):
            out[6 * b + k] = rr[b, k] - cg[b, k]
            out[6 * b + 3 + k] = phi[k]
            potential -= energy[b] * gravity[k] * rr[b, k] + static[b, k] * (rr[b, k] - cg[b, k])
            potential -= static[b, 3 + k] * phi[k]
    out[6 * nb] = 0.5 * _vdot(v, _matvec(mass, v))
    for q in range(plan[13].shape[0]):
        b = plan[13][q]
        x = np.empty(6)
        x[:3] = rr[b] - plan[15][q]
        x[3:] = log_so3(RR[b])
        ks = 0.5 * (plan[14][q, 0] + plan[14][q, 0].T)
        potential += 0.5 * _vdot(x, _matvec(ks, x))
    base = 6 * nb + 3 + 6 * n_joint
    jac = np.empty(12)
    for c in range(n_coord):
        value, rate = coordinate_into(plan, c, rr, RR, W, refs[c], jac)
        out[base + 2 * c] = value
        out[base + 2 * c + 1] = rate
    for e in range(n_spring):
        c = plan[19][e]
        par = plan[21][e]
        energy_e, _, _, out[base + 2 * n_coord + e] = _element_energy(par, out[base + 2 * c] - par[3],
                                                                      out[base + 2 * c + 1])
        potential += energy_e
    out[6 * nb + 1] = potential
    # residuals of all rows and the joints' reactions from the kept rows' multipliers
    kinds, bodies, vecs, c0, kept = plan[7], plan[8], plan[9], plan[10], plan[12]
    worst = 0.0
    for p in range(kinds.shape[0]):
        bi, bj = bodies[p, 0], bodies[p, 1]
        kind = kinds[p]
        val = np.zeros(3)
        blk = np.zeros((3, 12))
        if kind == 0:
            ai = _mv(RR[bi], vecs[p, 0])
            aj = _mv(RR[bj], vecs[p, 1])
            val = rr[bi] + ai - rr[bj] - aj
            sj = _skew(aj)
            for c in range(3):
                blk[c, 6 + c] = -1.0
                for k in range(3):
                    blk[c, 9 + k] = sj[c, k]
        elif kind == 1:
            u = _mv(RR[bi], vecs[p, 0])
            w = _mv(RR[bj], vecs[p, 1])
            val[0] = _dot(u, w) - c0[p]
            blk[0, 9:12] = -_cross(u, w)
        else:
            ai, aj, d, wi, wj, dd = _two_points(rr, RR, W, bi, bj, vecs[p, 0], vecs[p, 1])
            if kind == 2:
                nv = _mv(RR[bi], vecs[p, 2])
                val[0] = _dot(nv, d) - c0[p]
                blk[0, 6:9] = nv
                blk[0, 9:12] = _cross(aj, nv)
            else:
                length = math.sqrt(_dot(d, d))
                e = d / length
                val[0] = length - c0[p]
                blk[0, 6:9] = e
                blk[0, 9:12] = _cross(aj, e)
        rows = plan[11][p]
        joint = plan[26][p]
        for c in range(3):
            if rows[c] < 0:
                continue
            worst = max(worst, abs(val[c]))
            if joint >= 0 and kept[p, c] >= 0:
                lk = lam_kept[kept[p, c]]
                for k in range(6):
                    out[6 * nb + 3 + 6 * joint + k] -= blk[c, 6 + k] * lk
    out[6 * nb + 2] = worst
    for j in range(n_joint):
        b2 = plan[27][j]
        o = 6 * nb + 3 + 6 * j
        arm = -_mv(RR[b2], plan[28][j])  # cg minus the joint point
        f = out[o:o + 3].copy()
        out[o + 3:o + 6] += _cross(arm, f)
    return out


# ---------------------------------------------------------------------------------------------- fused macro step


@njit
def macro_layout(n, r, nb, s, e, o, p):
    """Offsets in :func:`ga_macro_step`'s ``out`` (n slots, r kept rows, nb bodies, s coordinates, e springs, o
    outputs, p PTOs): v', lambda, r (nb, 3), R (nb, 3, 3), v, a, angle references, [dissipated, external work, PTO
    energy], [dissipated, supplied, PTO power], springs' dissipated powers, row quality, :func:`outputs`, [energy
    balance, each PTO's (coordinate from neutral, rate, force, absorbed power)]; the last entry is the total size."""
    sizes = np.array([n, r, 3 * nb, 9 * nb, n, n, s, 3, 3, e, 1, o, 1 + 4 * p])
    offsets = np.zeros(sizes.shape[0] + 1, dtype=np.int64)
    for k in range(sizes.shape[0]):
        offsets[k + 1] = offsets[k] + sizes[k]
    return offsets


@njit
def ga_macro_step(ip, fp, pr, pR, v, vdot, a, lam, inputs, refs, h, substeps, coef, newton_tolerance, length,
                  max_iterations, lu, piv, have_lu, consistent, shift, delta, pto_springs, energy, out):
    """A whole multibody macro step of the index-3 formulation in one call (MultibodySimulator.advance with
    Index3's compiled steps, the same operations in the same order):

    1. the restart: with ``consistent`` the consistent v' and lambda of the held ``inputs`` (:func:`acceleration`);
       ``shift`` 1: the algorithmic acceleration restarted as a = v' + Delta h v'' (:func:`start_acceleration`,
       ``delta`` = alpha_m - alpha_f, 0 for a = v'), 2: a += the jump of v' (the ``increment`` restart), 0: a kept;
    2. the powers at the start (:func:`_powers`), then ``substeps`` equal generalised-alpha steps of h / substeps
       (:func:`ga_step`: LU factors ``lu``, ``piv`` reused while ``have_lu`` and the contraction stay good, a
       stale matrix retried once with a fresh one), each followed by the angle references' commit, the row quality
       and the powers at its end, and the trapezoidal energy sums ``energy`` = (dissipated, external work, PTO
       energy) += 0.5 h / substeps (P_start + P_end) (O(h^2)); ``pto_springs``: the PTOs' spring positions;
       ``energy[4:7]``, if given: the powers at the start (dissipated, supplied, PTO), used when the call makes no
       restart (the end powers of the step that led here: the same state and inputs);
    3. the outputs at the end (:func:`_outputs`), the energy balance (``energy[3]``: the initial mechanical energy)
       and the PTOs' outputs, if ``out`` has room for them.

    With ``substeps`` 0 it evaluates the state given: the restart's accelerations, the powers, the kept rows'
    quality (redundant constraints) and the outputs (each formulation's compiled evaluation of an index-3 run goes
    through this one entry point: numba compiles one call tree).

    It stops early after a substep that did not converge (status 1 or 2: the caller takes the remaining substeps on
    its own path) or, with redundant constraints, after a substep whose kept rows' quality fell below 0.5 (the
    caller re-selects the rows). Writes the state reached into ``out`` (:func:`macro_layout`) and returns
    (status, substeps done, Newton iterations, stale-matrix retries, keep the factors, stiff restart); status 3:
    singular consistent acceleration (nothing done)."""
    plan = unpack(ip, fp)
    nb = pr.shape[0]
    vd_n, lam_n, a_n = vdot, lam, a
    stiff = False
    lu0, piv0 = np.empty((0, 0)), np.zeros(0, dtype=np.int64)  # the consistent acceleration's factors
    if consistent:
        vd_n, lam_n, lu0, piv0, ok = acceleration_factored(plan, pr, pR, v, inputs, refs)
        if not (ok and np.all(np.isfinite(vd_n))):
            return 3, 0, 0, 0, False, False
        if shift == 2:
            a_n = a + (vd_n - vdot)
    hs = h / substeps if substeps > 0 else h
    if shift == 1:
        if delta == 0.0:
            a_n = vd_n.copy()
        elif consistent:  # start_acceleration at this state, on the factors just made: one factorisation
            a_n, stiff = taylor_shift(plan, pr, pR, v, vd_n, vd_n, lam_n, lu0, piv0, inputs, refs, hs, delta)
        else:
            a_n, stiff = start_acceleration(ip, fp, pr, pR, v, vd_n, inputs, refs, hs, delta)
    if substeps > 0 and not consistent and shift == 0 and energy.shape[0] >= 7:
        # the powers at the start, carried from the step that led here (same state, same inputs): the caller's
        diss, supply, pto = energy[4], energy[5], energy[6]
        spring = np.zeros(plan[21].shape[0])  # (each substep sets them)
    else:
        diss, supply, spring = _powers(plan, pr, pR, v, inputs, refs)
        pto = 0.0
        for i in pto_springs:
            pto += spring[i]
    r_n, R_n, v_n, refs_n = pr, pR, v, refs
    dissipated, work, pto_energy = energy[0], energy[1], energy[2]
    status, done, iterations, retries, keep, quality = 0, 0, 0, 0, have_lu, 1.0
    redundant = plan[23] < plan[22]
    if substeps == 0 and redundant:  # the kept rows' quality at the given pose (Formulation.reselect_rows)
        rr, RR, W = snapshot(pr, pR, v, plan[0])
        quality = _row_quality(plan, rr, RR, W)
    for _ in range(substeps):
        res = _ga_substep(plan, r_n, R_n, v_n, vd_n, a_n, lam_n, inputs, refs_n, hs, coef, newton_tolerance, length,
                          max_iterations, lu, piv, keep)
        iterations += res[1]
        if res[0] != 0 and keep:  # a stale matrix from earlier steps: retry with a fresh one
            retries += 1
            res = _ga_substep(plan, r_n, R_n, v_n, vd_n, a_n, lam_n, inputs, refs_n, hs, coef, newton_tolerance,
                              length, max_iterations, lu, piv, False)
            iterations += res[1]
        status, keep = res[0], res[2]
        if status != 0:
            keep = False
            break
        quality, vd_n, lam_n, r_n, R_n, v_n, a_n, refs_n, d1, s1, spring = res[3:]
        p1 = 0.0
        for i in pto_springs:
            p1 += spring[i]
        c = 0.5 * h / substeps
        dissipated += c * (diss + d1)
        work += c * (supply + s1)
        pto_energy += c * (pto + p1)
        diss, supply, pto = d1, s1, p1
        done += 1
        if redundant and quality < 0.5:
            break
    at = macro_layout(v.shape[0], lam.shape[0], nb, refs.shape[0], spring.shape[0], 0, 0)
    out[at[0]:at[1]] = vd_n
    out[at[1]:at[2]] = lam_n
    out[at[2]:at[3]] = r_n.ravel()
    out[at[3]:at[4]] = R_n.ravel()
    out[at[4]:at[5]] = v_n
    out[at[5]:at[6]] = a_n
    out[at[6]:at[7]] = refs_n
    out[at[7]], out[at[7] + 1], out[at[7] + 2] = dissipated, work, pto_energy
    out[at[8]], out[at[8] + 1], out[at[8] + 2] = diss, supply, pto
    out[at[9]:at[10]] = spring
    out[at[10]] = quality
    if at[11] < out.shape[0]:  # room for the outputs
        flat = _outputs(plan, r_n, R_n, v_n, lam_n, refs_n)
        k = at[11] + flat.shape[0]
        out[at[11]:k] = flat
        # the energy balance T + V + D - W - E0 (E0 = energy[3]) and the PTOs' outputs (MultibodySimulator)
        out[k] = flat[6 * nb] + flat[6 * nb + 1] + dissipated - work - energy[3]
        coords = 6 * nb + 3 + 6 * plan[27].shape[0]
        forces = coords + 2 * plan[16].shape[0]
        for p in range(pto_springs.shape[0]):
            i = pto_springs[p]
            c = plan[19][i]
            rate, force = flat[coords + 2 * c + 1], flat[forces + i]
            out[k + 1 + 4 * p] = flat[coords + 2 * c] - plan[21][i, 3]
            out[k + 2 + 4 * p] = rate
            out[k + 3 + 4 * p] = force
            out[k + 4 + 4 * p] = -force * rate
    return status, done, iterations, retries, keep, stiff
