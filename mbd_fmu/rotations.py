"""Rotations: skew matrices, the exponential and logarithm of SO(3), and its tangent maps.

Conventions used throughout :mod:`mbd_fmu`: a body's orientation is the rotation matrix ``R``
from its equilibrium orientation to the current one (body axes = world axes at equilibrium);
angular velocities ``w`` are in the world frame, ``dR/dt = S(w) R``. A *rotation vector* ``phi``
(axis times angle, rad) describes ``R = exp(S(phi))``. For the left (world-frame) convention
``dR/dt = S(w) R`` with ``R = exp(S(phi))`` the rotation vector obeys ``phi' = J_l(phi)^-1 w``,
``J_l`` the left Jacobian of SO(3). All functions are vectorised over leading axes.
"""

from __future__ import annotations

import math

import numpy as np

_SMALL = 1e-6


# S(v) = v @ _SKEW reshaped: entry (a, b) of S is -eps_abc v_c (exact: one non-zero term per entry)
_SKEW = np.array([[0, 0, 0, 0, 0, -1, 0, 1, 0], [0, 0, 1, 0, 0, 0, -1, 0, 0], [0, -1, 0, 1, 0, 0, 0, 0, 0]], float)
_EYE = np.eye(3)


def skew(v: np.ndarray) -> np.ndarray:
    """S(v) with S(v) u = v x u; ``v`` (..., 3) -> (..., 3, 3)."""
    v = np.asarray(v, dtype=float)
    return (v @ _SKEW).reshape(v.shape[:-1] + (3, 3))


def _norm(v: np.ndarray) -> np.ndarray:
    """Euclidean norm over the last axis (what ``np.linalg.norm(v, axis=-1)`` computes, without its overhead)."""
    return np.sqrt(np.add.reduce(v * v, axis=-1))


def _coefficients(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """a = sin t / t, b = (1 - cos t) / t^2 with Taylor series near 0."""
    small = t < _SMALL
    if not small.any():
        return np.sin(t) / t, (1 - np.cos(t)) / t**2
    ts = np.where(small, 1.0, t)
    a = np.where(small, 1 - t**2 / 6, np.sin(ts) / ts)
    b = np.where(small, 0.5 - t**2 / 24, (1 - np.cos(ts)) / ts**2)
    return a, b


def exp_so3(phi: np.ndarray) -> np.ndarray:
    """Rodrigues: exp(S(phi)) for rotation vectors ``phi`` (..., 3)."""
    phi = np.asarray(phi, dtype=float)
    if phi.ndim <= 2 and phi.size <= 3 * _FEW:  # a few vectors: plain floats (numpy's per-call cost dominates)
        out = np.array([_exp_one(p) for p in phi.tolist()] if phi.ndim == 2 else _exp_one(phi.tolist()))
        return out.reshape(phi.shape[:-1] + (3, 3))
    a, b = _coefficients(_norm(phi))
    s = skew(phi)
    return _EYE + a[..., None, None] * s + b[..., None, None] * (s @ s)


_FEW = 4


def _exp_one(phi: list[float]) -> list[list[float]]:
    """exp(S(phi)) of one rotation vector in plain floats: I + a S + b S^2, S^2 = phi phi^T - t^2 I."""
    x, y, z = phi
    t2 = x * x + y * y + z * z
    t = math.sqrt(t2)
    if t < _SMALL:
        a, b = 1 - t2 / 6, 0.5 - t2 / 24
    else:
        a, b = math.sin(t) / t, (1 - math.cos(t)) / t2
    bxy, bxz, byz = b * x * y, b * x * z, b * y * z
    return [[1 + b * (x * x - t2), bxy - a * z, bxz + a * y],
            [bxy + a * z, 1 + b * (y * y - t2), byz - a * x],
            [bxz - a * y, byz + a * x, 1 + b * (z * z - t2)]]


_AXIAL_I, _AXIAL_J = np.array([2, 0, 1]), np.array([1, 2, 0])  # w = (R_21 - R_12, R_02 - R_20, R_10 - R_01)


def log_so3(r: np.ndarray) -> np.ndarray:
    """Rotation vector of rotation matrices ``r`` (..., 3, 3), angle in [0, pi]."""
    r = np.asarray(r, dtype=float)
    if r.ndim == 3 and 0 < len(r) <= _FEW:  # a few matrices: one by one in plain floats
        return np.array([log_so3(m) for m in r])
    if r.ndim == 2:  # one matrix: plain floats (cheaper than numpy), except near pi
        (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = r.tolist()
        t = math.acos(min(max((r00 + r11 + r22 - 1) / 2, -1.0), 1.0))
        if t <= np.pi - 1e-4:
            factor = 0.5 + t * t / 12 if t < 1e-4 else t / (2 * math.sin(t))
            return np.array((factor * (r21 - r12), factor * (r02 - r20), factor * (r10 - r01)))
    cos_t = np.clip((r[..., 0, 0] + r[..., 1, 1] + r[..., 2, 2] - 1) / 2, -1.0, 1.0)
    t = np.arccos(cos_t)
    w = r[..., _AXIAL_I, _AXIAL_J] - r[..., _AXIAL_J, _AXIAL_I]
    small = t < 1e-4
    if small.any():
        sin_t = np.sin(np.where(small, 1.0, t))
        factor = np.where(small, 0.5 + t**2 / 12, t / (2 * sin_t))
    else:
        factor = t / (2 * np.sin(t))
    phi = factor[..., None] * w
    near_pi = t > np.pi - 1e-4
    if near_pi.any():  # axis from the symmetric part: R = I + 2 n n^T - ... at t = pi
        for idx in zip(*np.nonzero(np.atleast_1d(near_pi)), strict=False):
            m = r[idx] if r.ndim > 2 else r
            sym = (m + m.T) / 2 - np.cos(t[idx] if t.ndim else t) * np.eye(3)
            k = int(np.argmax(np.diag(sym)))
            n = sym[k] / np.sqrt(max(sym[k, k], 1e-300))
            if np.dot(n, w[idx] if w.ndim > 1 else w) < 0:
                n = -n
            value = n * (t[idx] if t.ndim else t)
            if phi.ndim > 1:
                phi[idx] = value
            else:
                phi = value
    return phi


def left_jacobian_inverse(phi: np.ndarray) -> np.ndarray:
    """J_l(phi)^-1: phi' = J_l^-1 w for R = exp(S(phi)), dR/dt = S(w) R."""
    phi = np.asarray(phi, dtype=float)
    if phi.ndim == 1:  # one vector: plain floats, S^2 = phi phi^T - t^2 I
        x, y, z = phi.tolist()
        t2 = x * x + y * y + z * z
        t = math.sqrt(t2)
        c = 1 / 12 + t2 / 720 if t < 1e-4 else (1 - t * math.sin(t) / (2 * (1 - math.cos(t)))) / t2
        cxy, cxz, cyz = c * x * y, c * x * z, c * y * z
        return np.array([[1 + c * (x * x - t2), cxy + 0.5 * z, cxz - 0.5 * y],
                         [cxy - 0.5 * z, 1 + c * (y * y - t2), cyz + 0.5 * x],
                         [cxz + 0.5 * y, cyz - 0.5 * x, 1 + c * (z * z - t2)]])
    else:
        t = _norm(phi)
        small = t < 1e-4
        if small.any():
            ts = np.where(small, 1.0, t)
            c = np.where(small, 1 / 12 + t**2 / 720, (1 - ts * np.sin(ts) / (2 * (1 - np.cos(ts)))) / ts**2)
        else:
            c = (1 - t * np.sin(t) / (2 * (1 - np.cos(t)))) / t**2
    s = skew(phi)
    return _EYE - 0.5 * s + c[..., None, None] * (s @ s)


def left_jacobian(phi: np.ndarray) -> np.ndarray:
    """J_l(phi) = I + (1 - cos t)/t^2 S + (t - sin t)/t^3 S^2."""
    phi = np.asarray(phi, dtype=float)
    t = _norm(phi)
    small = t < 1e-4
    ts = np.where(small, 1.0, t)
    _, b = _coefficients(t)
    c = np.where(small, 1 / 6 - t**2 / 120, (ts - np.sin(ts)) / ts**3)
    s = skew(phi)
    return np.eye(3) + b[..., None, None] * s + c[..., None, None] * (s @ s)


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a x b over the last axis (faster than ``np.cross`` for small arrays)."""
    if a.ndim == 1 and b.ndim == 1:
        a0, a1, a2 = a.tolist()
        b0, b1, b2 = b.tolist()
        return np.array((a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0))
    if a.shape != b.shape:
        a, b = np.broadcast_arrays(a, b)
    return a[..., _NEXT] * b[..., _PREV] - a[..., _PREV] * b[..., _NEXT]


_NEXT, _PREV = np.array([1, 2, 0]), np.array([2, 0, 1])  # (a x b)_i = a_{i+1} b_{i+2} - a_{i+2} b_{i+1}
