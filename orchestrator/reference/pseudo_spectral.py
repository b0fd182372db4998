"""Pseudo-spectral periodic steady state of a scene in regular waves (seed paper 003).

Method: Fourier collocation. Every generalised coordinate (and, in DAE form, every dynamic
Lagrange multiplier) is a truncated Fourier series in the wave frequency omega,

    x(t) = X_0 + sum_{k=1..N} Re[X_k exp(i k omega t)],

and the equations of motion are enforced at M = 2N + 1 equally spaced instants of one period
(equivalently: the first N harmonics of the residual vanish, trigonometric interpolation being
exact on those points). The linear part is applied harmonic by harmonic in the frequency domain,
so the radiation memory, frequency-dependent added mass and damping, and the excitation are
exact (no impulse response, no time step):

    Z(k omega) X_k + C^T L_k = F_exc,k + N_k(X),      C X_k = 0            (DAE form)
    P^T [Z(k omega) P Y_k - F_exc,k - N_k(P Y)] = 0,  X_k = P Y_k          (ODE form)

with ``Z`` the linear impedance of :mod:`orchestrator.reference.frequency_domain` (the linearised
constrained multibody system: mass, damping, stiffness including geometric terms, hydrostatics,
A(omega), B(omega)), ``C`` the independent rows of the linearised constraint Jacobian, ``P`` its
null space, ``F_exc`` the wave excitation (first harmonic only) and ``N_k`` the k-th harmonic of
the nonlinear forces evaluated at the collocation instants:

* quadratic (Morison-type) drag ``-q |v| v`` on the hydrodynamic DOFs (as the hydro FMU applies it);
* nonlinear PTO laws (:class:`mbd_fmu.force_elements.PtoLaw`: Coulomb, quadratic damping,
  saturation) on the PTO coordinate, linearised kinematics ``q = row . x``;
* nonlinear force elements of the multibody model (catenary mooring lines, ropes, joint
  friction) evaluated with exact kinematics at the displaced pose.

Only the part of each nonlinear force beyond its linearisation at equilibrium enters ``N``
(the linearisation is already in ``Z``), so with no nonlinear term the method reduces to the
linear frequency-domain solution for any N, and with N = 1 it is that solution. Kinematics
and constraints are linearised (small motions about the equilibrium), as in seed 003.

The nonlinear algebraic system (real unknowns: mean, cosine and sine parts) is solved by
scipy's MINPACK hybrid Powell method (``scipy.optimize.root(method="hybr")``) from the linear
solution, with an analytic Jacobian: the Fourier analysis and synthesis matrices around the
pointwise force derivatives (analytic for drag and PTO laws, central differences for the
model's force elements). Convergence in N is spectral for smooth forces and algebraic for
forces with non-smooth derivatives (|v| v: harmonic amplitudes fall like k^-3).

A mean (k = 0) direction with no static stiffness (e.g. an unmoored surge) is held at zero.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from scipy.linalg import null_space
from scipy.optimize import root

from orchestrator.scene import Scene

from .frequency_domain import LinearModel, incident_wave_power, linear_model


@dataclass
class SteadyState:
    """Periodic steady state: harmonics ``k = 0..N`` of the motion on the scene's coordinates.

    Attributes:
        omega: wave frequency (rad/s); amplitude: wave amplitude (m); harmonics: N; form: dae | ode.
        coordinates: (body, dof) of each column of ``motion``.
        motion: complex harmonics (N + 1, n): x(t) = Re sum_k X_k exp(i k omega t); X_0 the mean (m, rad).
        multipliers: harmonics of the dynamic Lagrange multipliers (N + 1, r), N.
        pto_power: mean absorbed power per PTO (W), over a finely resampled period.
        joint_motion: per joint, harmonics of its coordinates (N + 1, k); reactions: per joint,
            harmonics of the force and moment on body 2 from body 1 about the joint point (N + 1, 6).
        residual: largest residual harmonic relative to the excitation force amplitude.
        converged, message, evaluations, wall_time (s): solver report.
        incident_power: incident wave power per metre of crest (W/m).
    """

    omega: float
    amplitude: float
    harmonics: int
    form: str
    coordinates: list[tuple[str, int]]
    motion: np.ndarray
    multipliers: np.ndarray
    pto_power: dict[str, float]
    joint_motion: dict[str, np.ndarray]
    reactions: dict[str, np.ndarray]
    residual: float
    converged: bool
    message: str
    evaluations: int
    wall_time: float
    incident_power: float
    joint_coordinates: dict[str, list[str]] = field(default_factory=dict)

    @property
    def period(self) -> float:
        return 2 * math.pi / self.omega

    def body_motion(self, body: str) -> np.ndarray:
        """Harmonics of ``body``'s six DOFs (N + 1, 6), zero for inactive ones."""
        out = np.zeros((self.harmonics + 1, 6), complex)
        for j, (b, d) in enumerate(self.coordinates):
            if b == body:
                out[:, d] = self.motion[:, j]
        return out

    def time_series(self, t: np.ndarray, harmonics: np.ndarray | None = None) -> np.ndarray:
        """Synthesise ``harmonics`` (default the motion) at times ``t``: (len(t), columns)."""
        h = self.motion if harmonics is None else harmonics
        k = np.arange(self.harmonics + 1)
        phase = np.exp(1j * self.omega * np.outer(np.asarray(t, float), k))
        return np.real(phase @ h)

    def harmonic_amplitudes(self) -> np.ndarray:
        """|X_k| (N + 1, n)."""
        return np.abs(self.motion)

    def capture_width(self, pto: str) -> float:
        """Mean PTO power over the incident power per metre of crest (m)."""
        return self.pto_power[pto] / (self.incident_power * self.amplitude**2)


# ---------------------------------------------------------------------------------------- Fourier
@dataclass(frozen=True)
class FourierBasis:
    """Real Fourier basis of N harmonics on M = 2N + 1 collocation instants of one period.

    Real coefficient vector per scalar: ``[X_0, Re X_1, Im X_1, ..., Re X_N, Im X_N]`` (H = 2N + 1).
    ``synthesis`` (M, H) gives values, ``derivative`` (M, H) time derivatives and ``analysis``
    (H, M) the coefficients of sampled values (its inverse for M = 2N + 1: exact trigonometric
    interpolation; discrete orthogonality holds for any M > 2N).
    """

    omega: float
    harmonics: int
    points: int = 0  # sampling instants; default (0) the M = 2N + 1 collocation points

    @property
    def size(self) -> int:
        return 2 * self.harmonics + 1

    @property
    def count(self) -> int:
        return self.points or self.size

    @property
    def times(self) -> np.ndarray:
        return np.arange(self.count) * (2 * math.pi / self.omega) / self.count

    def _theta(self) -> tuple[np.ndarray, np.ndarray]:
        k = np.arange(1, self.harmonics + 1)
        return k, np.outer(self.omega * self.times, k)

    @property
    def synthesis(self) -> np.ndarray:
        _, th = self._theta()
        out = np.empty((self.count, self.size))
        out[:, 0] = 1.0
        out[:, 1::2], out[:, 2::2] = np.cos(th), -np.sin(th)
        return out

    @property
    def derivative(self) -> np.ndarray:
        k, th = self._theta()
        out = np.zeros((self.count, self.size))
        out[:, 1::2], out[:, 2::2] = -k * self.omega * np.sin(th), -k * self.omega * np.cos(th)
        return out

    @property
    def analysis(self) -> np.ndarray:
        _, th = self._theta()
        m = self.count
        out = np.empty((self.size, m))
        out[0] = 1.0 / m
        out[1::2], out[2::2] = 2.0 / m * np.cos(th).T, -2.0 / m * np.sin(th).T
        return out


def to_complex(u: np.ndarray) -> np.ndarray:
    """Real coefficients (H, c) -> complex harmonics (N + 1, c)."""
    out = np.empty(((u.shape[0] + 1) // 2, u.shape[1]), complex)
    out[0] = u[0]
    out[1:] = u[1::2] + 1j * u[2::2]
    return out


def to_real(x: np.ndarray) -> np.ndarray:
    """Complex harmonics (N + 1, c) -> real coefficients (H, c) (the mean's imaginary part is dropped)."""
    out = np.empty((2 * x.shape[0] - 1, x.shape[1]))
    out[0] = x[0].real
    out[1::2], out[2::2] = x[1:].real, x[1:].imag
    return out


# ---------------------------------------------------------------------------------------- nonlinear forces
class NonlinearForce:
    """A force beyond its linearisation: ``evaluate(x, v)`` on (M, n) samples returns the force (M, n)
    and its derivatives with respect to x and v (M, n, n)."""

    def evaluate(self, x: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        raise NotImplementedError  # pragma: no cover - abstract


@dataclass
class QuadraticDrag(NonlinearForce):
    """``-q |v| v`` on the coordinates ``rows`` (q = rho Cd A / 2); its linearisation at rest is zero."""

    rows: np.ndarray
    q: np.ndarray

    def evaluate(self, x, v):
        m, n = x.shape
        f, jx, jv = np.zeros((m, n)), np.zeros((m, n, n)), np.zeros((m, n, n))
        vr = v[:, self.rows]
        f[:, self.rows] = -self.q * np.abs(vr) * vr
        jv[:, self.rows, self.rows] = -2 * self.q * np.abs(vr)
        return f, jx, jv


@dataclass
class PtoLawForce(NonlinearForce):
    """A PTO with a nonlinear law on its linearised coordinate ``q = row . x``, minus the law's tangent at rest."""

    row: np.ndarray
    element: object  # mbd_fmu.force_elements.CoordinateSpringDamper

    def evaluate(self, x, v):
        q, qd = x @ self.row, v @ self.row
        e = self.element
        f0 = e.law_force(0.0, 0.0)
        dx0, dv0 = e.law_derivatives(0.0, 0.0)
        force = e.law_force(q, qd) - f0 - dx0 * q - dv0 * qd
        dx, dv = e.law_derivatives(q, qd)
        outer = np.outer(self.row, self.row)
        return (np.outer(force, self.row), (np.asarray(dx) - dx0)[:, None, None] * outer,
                (np.asarray(dv) - dv0)[:, None, None] * outer)


@dataclass
class ElementForce(NonlinearForce):
    """A nonlinear force element of the multibody model with exact kinematics at the displaced pose,
    minus its force and tangent at equilibrium (central differences, step ``eps``)."""

    model: object  # mbd_fmu.model.MultibodyModel
    element: object
    eps: float = 1e-6

    def __post_init__(self) -> None:
        n = self.model.n
        self._f0 = self._force(np.zeros(n), np.zeros(n))
        self._kx, self._kv = self._tangent(np.zeros(n), np.zeros(n))

    def _force(self, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        m = self.model
        k = m.kin(m.reference.retract(m.full(x)), v)
        f = np.zeros(6 * (m.N + 1))
        self.element.apply(k, f)
        return f[m.sel]

    def _tangent(self, x: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        n = len(x)
        kx, kv = np.empty((n, n)), np.empty((n, n))
        for i in range(n):
            e = np.zeros(n)
            e[i] = self.eps
            kx[:, i] = (self._force(x + e, v) - self._force(x - e, v)) / (2 * self.eps)
            kv[:, i] = (self._force(x, v + e) - self._force(x, v - e)) / (2 * self.eps)
        return kx, kv

    def evaluate(self, x, v):
        f = np.array([self._force(a, b) for a, b in zip(x, v, strict=True)])
        f -= self._f0 + x @ self._kx.T + v @ self._kv.T
        tangents = [self._tangent(a, b) for a, b in zip(x, v, strict=True)]
        jx = np.array([t[0] for t in tangents]) - self._kx
        jv = np.array([t[1] for t in tangents]) - self._kv
        return f, jx, jv


def nonlinear_forces(scene: Scene, model: LinearModel) -> list[NonlinearForce]:
    """The scene's nonlinear forces (module docstring) on the linear model's coordinates."""
    out: list[NonlinearForce] = []
    viscous = scene.viscous() if scene.scenario.hydro.viscous else None
    if viscous is not None and np.any(viscous.quadratic):
        system = model.system
        if model.basis is None:
            rows = [system.coordinate_index(b, d) for b, d in scene.hydro_coordinates]
        else:
            rows = [system.slot_of(b, d) for b, d in scene.hydro_coordinates]
        out.append(QuadraticDrag(np.asarray(rows), np.asarray(viscous.quadratic)))
    for row, _, element in (model.pto_rows or {}).values():
        if element is not None and element.nonlinear:
            out.append(PtoLawForce(row, element))
    if model.basis is not None:
        ptos = {id(e) for _, _, e in model.pto_rows.values()}
        out += [ElementForce(model.system, e) for e in model.system.elements
                if getattr(e, "nonlinear", False) and id(e) not in ptos]
    return out


# ---------------------------------------------------------------------------------------- problem
class PeriodicProblem:
    """The collocation equations of one scene at one wave frequency (module docstring)."""

    def __init__(self, scene: Scene, omega: float, amplitude: float, harmonics: int, form: str = "dae",
                 heading_deg: float | None = None) -> None:
        if harmonics < 1:
            raise ValueError(f"harmonics must be at least 1, got {harmonics}")
        if form not in ("dae", "ode"):
            raise ValueError(f"form must be 'dae' or 'ode', not {form!r}")
        self.scene, self.omega, self.amplitude, self.form = scene, float(omega), float(amplitude), form
        self.basis = FourierBasis(self.omega, harmonics)
        k = np.arange(harmonics + 1)
        self.model = linear_model(scene, k * self.omega, heading_deg=heading_deg)
        z, c = self.model.full_impedance, self.model.constraint
        self.n, self.r = z.shape[1], c.shape[0]
        self.null = self.model.basis if self.model.basis is not None else np.eye(self.n)
        self.H = self.basis.size
        self.linear = self._linear_operator(z)
        self.excitation = np.zeros((self.H, self.n))
        first = self.amplitude * self.model.full_excitation[1]
        self.excitation[1], self.excitation[2] = first.real, first.imag
        self.forces = nonlinear_forces(scene, self.model)
        self._syn, self._der, self._ana = self.basis.synthesis, self.basis.derivative, self.basis.analysis

    def _linear_operator(self, z: np.ndarray) -> np.ndarray:
        """Real (H n, H n) operator of the impedance, harmonic by harmonic; unstiff mean directions pinned."""
        n, H = self.n, self.H
        op = np.zeros((H, n, H, n))
        k0 = z[0].real.copy()
        p = self.null
        soft = null_space(p.T @ k0 @ p, rcond=1e-10)
        if soft.size:
            scale = max(float(np.max(np.abs(k0))), 1.0)
            k0 += scale * (p @ soft) @ (p @ soft).T
        op[0, :, 0, :] = k0
        for k in range(1, self.basis.harmonics + 1):
            zr, zi = z[k].real, z[k].imag
            a, b = 2 * k - 1, 2 * k
            op[a, :, a, :], op[a, :, b, :] = zr, -zi
            op[b, :, a, :], op[b, :, b, :] = zi, zr
        return op.reshape(H * n, H * n)

    @property
    def nonlinear(self) -> bool:
        return bool(self.forces)

    def unknowns(self) -> int:
        return self.H * (self.n + self.r) if self.form == "dae" else self.H * self.null.shape[1]

    def motion_of(self, u: np.ndarray) -> np.ndarray:
        """Real motion coefficients (H, n) of the unknown vector."""
        if self.form == "dae":
            return u[: self.H * self.n].reshape(self.H, self.n)
        return u.reshape(self.H, -1) @ self.null.T

    def multipliers_of(self, u: np.ndarray) -> np.ndarray:
        """Real multiplier coefficients (H, r): solved (DAE) or recovered from C^T L = F - Z X (ODE)."""
        if self.form == "dae":
            return u[self.H * self.n:].reshape(self.H, self.r)
        x = self.motion_of(u)
        force = self.excitation + self.nonlinear_harmonics(x)[0] - (self.linear @ x.ravel()).reshape(self.H, self.n)
        if not self.r:
            return np.zeros((self.H, 0))
        return np.linalg.lstsq(self.model.constraint.T, force.T, rcond=None)[0].T

    def nonlinear_harmonics(self, x: np.ndarray, jacobian: bool = False,
                            include: bool = True) -> tuple[np.ndarray, np.ndarray | None]:
        """Harmonics (H, n) of the nonlinear forces for motion coefficients ``x`` (H, n), and d/dx (H n, H n);
        zero if ``include`` is False."""
        H, n = self.H, self.n
        if not (self.forces and include):
            return np.zeros((H, n)), (np.zeros((H * n, H * n)) if jacobian else None)
        xs, vs = self._syn @ x, self._der @ x
        f, jx, jv = np.zeros((H, n)), np.zeros((H, n, n)), np.zeros((H, n, n))
        for force in self.forces:
            a, b, c = force.evaluate(xs, vs)
            f, jx, jv = f + a, jx + b, jv + c
        harmonics = self._ana @ f
        if not jacobian:
            return harmonics, None
        jac = (np.einsum("hj,jil,jg->higl", self._ana, jx, self._syn)
               + np.einsum("hj,jil,jg->higl", self._ana, jv, self._der))
        return harmonics, jac.reshape(H * n, H * n)

    def residual(self, u: np.ndarray, jacobian: bool = True, nonlinear: bool = True):
        """Collocation residual (and its Jacobian) of the unknown vector ``u``; ``nonlinear=False`` leaves
        the nonlinear forces out."""
        H, n, r = self.H, self.n, self.r
        x = self.motion_of(u)
        nl, dnl = self.nonlinear_harmonics(x, jacobian, nonlinear)
        force = (self.linear @ x.ravel()).reshape(H, n) - self.excitation - nl
        if self.form == "dae":
            lam = u[H * n:].reshape(H, r)
            c = self.model.constraint
            res = np.concatenate([(force + lam @ c).ravel(), (x @ c.T).ravel()])
            if not jacobian:
                return res
            ec = np.kron(np.eye(H), c)
            jac = np.block([[self.linear - dnl, ec.T], [ec, np.zeros((H * r, H * r))]])
            return res, jac
        p = self.null
        res = (force @ p).ravel()
        if not jacobian:
            return res
        ep = np.kron(np.eye(H), p)
        return res, ep.T @ (self.linear - dnl) @ ep

    def linear_solution(self) -> np.ndarray:
        """The unknowns of the linear problem (nonlinear forces left out): one direct solve."""
        res, jac = self.residual(np.zeros(self.unknowns()), nonlinear=False)
        return np.linalg.solve(jac, -res)


def solve_steady(scene: Scene, omega: float, amplitude: float, harmonics: int = 5, *, form: str = "dae",
                 heading_deg: float | None = None, tolerance: float = 1e-12,
                 guess: SteadyState | None = None) -> SteadyState:
    """Periodic steady state of ``scene`` in regular waves of frequency ``omega`` (rad/s) and amplitude
    ``amplitude`` (m), with ``harmonics`` harmonics, in ``form`` ``dae`` or ``ode`` (module docstring).

    ``tolerance`` is MINPACK's relative step tolerance; ``guess`` (e.g. the solution at fewer harmonics)
    starts the solver, default the linear solution. The report's ``residual`` is the largest residual
    harmonic relative to the excitation force amplitude; ``converged`` is False if MINPACK says so.
    """
    start = time.perf_counter()
    problem = PeriodicProblem(scene, omega, amplitude, harmonics, form, heading_deg)
    u = problem.linear_solution()
    if guess is not None and guess.form == form:
        u = _resize_guess(problem, guess, u)
    converged, message, evaluations = True, "linear: one direct solve", 1
    if problem.nonlinear:
        sol = root(problem.residual, u, jac=True, method="hybr", options={"xtol": tolerance})
        u, converged, message, evaluations = sol.x, bool(sol.success), str(sol.message), int(sol.nfev)
    scale = max(float(np.max(np.abs(problem.excitation))), 1e-300)
    residual = float(np.max(np.abs(problem.residual(u, jacobian=False)))) / scale
    return _steady_state(problem, u, residual, converged, message, evaluations, time.perf_counter() - start)


def _resize_guess(problem: PeriodicProblem, guess: SteadyState, default: np.ndarray) -> np.ndarray:
    """The unknowns of ``guess`` padded or truncated to ``problem``'s harmonics."""
    x = np.zeros((problem.basis.harmonics + 1, problem.n), complex)
    k = min(len(x), len(guess.motion))
    x[:k] = guess.motion[:k]
    if problem.form == "ode":
        return (to_real(x) @ problem.null).ravel()
    lam = np.zeros((len(x), problem.r), complex)
    lam[:k] = guess.multipliers[:k]
    return np.concatenate([to_real(x).ravel(), to_real(lam).ravel()]) if problem.r else to_real(x).ravel()


def _steady_state(problem: PeriodicProblem, u: np.ndarray, residual: float, converged: bool, message: str,
                  evaluations: int, wall: float) -> SteadyState:
    model = problem.model
    x_real = problem.motion_of(u)
    motion = to_complex(x_real)
    lam = to_complex(problem.multipliers_of(u)) if problem.r else np.zeros((len(motion), 0), complex)
    power = {name: _mean_pto_power(problem, x_real, row, damping, element)
             for name, (row, damping, element) in (model.pto_rows or {}).items()}
    joints = {name: motion @ rows.T for name, (_, rows, _) in model.joints.items()}
    reactions = {name: lam @ reaction.T for name, (_, _, reaction) in model.joints.items()}
    incident = float(incident_wave_power(problem.scene, np.array([problem.omega]))[0])
    return SteadyState(problem.omega, problem.amplitude, problem.basis.harmonics, problem.form, model.coordinates,
                       motion, lam, power, joints, reactions, residual, converged, message, evaluations, wall,
                       incident, {name: names for name, (names, _, _) in model.joints.items()})


def _mean_pto_power(problem: PeriodicProblem, x: np.ndarray, row: np.ndarray, damping: float, element) -> float:
    """Mean of -F q' over one period, sampled finely enough (16 (2N + 1) points) to be exact for the
    linear law and accurate for the nonlinear ones."""
    fine = FourierBasis(problem.omega, problem.basis.harmonics, 16 * problem.basis.size)
    syn, der = fine.synthesis, fine.derivative
    q, qd = syn @ x @ row, der @ x @ row
    force = element.law_force(q, qd) if element is not None else -damping * qd
    return float(np.mean(-force * qd))
