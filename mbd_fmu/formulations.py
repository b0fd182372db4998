"""Formulations of the constrained equations of motion and their time stepping.

All three share :class:`Formulation`'s interface (``initialize``, ``set_inputs``, ``step``) and
state (pose ``q``, slot velocities ``v``, accelerations ``v'`` and multipliers ``lambda`` of the
kept constraint rows, time ``t``); the external input force is held constant during a step.

* :class:`Index3` - the index-3 DAE ``M v' + C^T lambda = f``, ``Phi(q, t) = 0`` by the Lie
  group generalised-alpha method (:mod:`mbd_fmu.integrators`): Newton iterations on
  ``(v'_{n+1}, lambda_{n+1})`` with the constraint equations scaled by ``1/(h^2 beta zeta)``
  (Bottasso, Bauchau & Cardona 2007), iteration matrix ``[[M + h gamma zeta D + h^2 beta zeta K,
  C^T], [C, 0]]`` (``K``, ``D`` the force elements' tangents; modified Newton, refreshed when
  the contraction rate exceeds 0.5, and kept across steps of the same size), convergence judged
  on the largest correction of positions and velocities (tolerance ``newton_tolerance`` times
  max(1, largest cg coordinate, largest velocity)) with the contraction-rate estimate of Hairer &
  Wanner. Positions satisfy the constraints to the Newton
  tolerance at every step (no drift). Order 2 in q and v.
* :class:`Index1` - the acceleration-level (index-1) DAE solved for ``(v', lambda)`` from the
  saddle-point system ``[[M, C^T], [C, 0]] [v'; lambda] = [f; gamma]``, integrated by an explicit
  RKMK method, followed by a projection of the positions (Newton, mass metric) and velocities
  onto the constraint manifold after every step. Order of the RK method.
* :class:`NullSpace` - the reduced ODE (Maggi / generalised coordinate partitioning,
  Wehage & Haug 1982): the velocities split into ``n - r`` independent and ``r`` dependent
  slots chosen by QR with column pivoting of ``C``; ``v = P v_s + sigma`` with
  ``P = [-C_d^-1 C_s; I]``; the ODE ``P^T M P v_s' = P^T (f - M rho)`` (``rho``: the particular
  solution of ``C v' = gamma`` with ``v_s' = 0``) is integrated by RKMK, the dependent positions
  are recovered by Newton iterations on ``Phi = 0`` with the independent ones held. The
  partition is re-chosen between steps when ``C_d`` degrades. Order of the RK method.

Restart at macro-step boundaries (:meth:`Formulation.set_inputs`): a new held input makes the
acceleration jump. The explicit one-step methods need nothing. Generalised-alpha carries the
algorithmic acceleration ``a``, which approximates ``v'(t + Delta h)`` (``Delta = alpha_m -
alpha_f``); on a jump it is reset from the new consistent acceleration and its derivative,
``a = v' + Delta h v''`` (Arnold & Bruls 2007's starting value), ``v''`` the derivative of the
consistent acceleration along the motion, ``S0^-1 (b' - S' x0)`` with ``b' - S' x0`` by a central
difference of the saddle-point residuals of the centre's solution ``x0`` (one factorisation, three model
evaluations: :func:`mbd_fmu.kernels.taylor_shift`). This keeps second order when the input
changes every step (``restart="consistent"``). ``"increment"`` adds the jump of the consistent
acceleration to ``a`` (``a += v'_new - v'_old``: one consistent-acceleration solve instead of two); its
error in ``a`` is ``Delta h`` times the jump of ``v''``, O(h) times the input's change, so it keeps second
order for inputs that change by O(h) per step (the master's extrapolated forces) and loses nothing at an
isolated jump. ``"acceleration"`` (``a = v'``) and ``"none"``
(keep ``a``) are available for comparison. When the shift is larger than half the acceleration
(stiff components, ``h |lambda| >> 1``, e.g. regularised friction) the Taylor shift is meaningless
and ``a = v'`` is used for that restart.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import lu_factor, lu_solve, qr
from scipy.sparse import csc_matrix
from scipy.sparse.linalg import splu

from . import kernels
from .assembly import independent_rows
from .fast import CompiledModel, compiled_model
from .integrators import TABLEAUS, GeneralizedAlphaCoefficients, rkmk_step
from .kinematics import Pose
from .model import MultibodyModel

FORMULATIONS = ("index3", "index1", "nullspace")
_NO_LU, _NO_PIV = np.zeros((0, 0)), np.zeros(0, dtype=np.int64)
_NO_PTOS, _NO_ENERGY = np.zeros(0, dtype=np.int64), np.zeros(4)
# offsets of the fused call's output, computed in Python (the kernel's own function, not compiled for this)
_macro_layout = getattr(kernels.macro_layout, "py_func", kernels.macro_layout)
RESTARTS = ("consistent", "increment", "acceleration", "none")


class Factorized:
    """A square matrix ready for repeated solves: explicit inverse when small (cheapest per solve in
    numpy), sparse LU (SuperLU) when large and sparse (chains, arrays of bodies), dense LU otherwise."""

    SMALL = 48

    def __init__(self, a: np.ndarray) -> None:
        n = a.shape[0]
        self.kind = "inv" if n <= self.SMALL else ("sparse" if np.count_nonzero(a) < 0.1 * n * n else "lu")
        if self.kind == "inv":
            self.data = np.linalg.inv(a)
        elif self.kind == "sparse":
            self.matrix = csc_matrix(a)
            self.data = splu(self.matrix)
        else:
            self.data = lu_factor(a, check_finite=False)

    def __getstate__(self) -> dict:
        """Picklable (FMU state): SuperLU factors are rebuilt from the kept matrix, identically."""
        state = self.__dict__.copy()
        if self.kind == "sparse":
            state["data"] = None
        return state

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)
        if self.kind == "sparse":
            self.data = splu(self.matrix)

    def solve(self, b: np.ndarray) -> np.ndarray:
        if self.kind == "inv":
            return self.data @ b
        if self.kind == "sparse":
            return self.data.solve(b)
        return lu_solve(self.data, b, check_finite=False)


class ConvergenceError(RuntimeError):
    """A Newton iteration did not converge (the message says where and how far)."""


@dataclass
class Settings:
    """Formulation and integrator settings (see the module docstring)."""

    formulation: str = "index3"
    integrator: str = ""
    spectral_radius: float = 0.8
    newton_tolerance: float = 1e-10
    max_iterations: int = 30
    restart: str = "consistent"

    def __post_init__(self) -> None:
        if self.formulation not in FORMULATIONS:
            raise ValueError(f"unknown formulation {self.formulation!r}; expected one of {', '.join(FORMULATIONS)}")
        if not self.integrator:
            self.integrator = "generalized_alpha" if self.formulation == "index3" else "rk4"
        if self.formulation == "index3" and self.integrator != "generalized_alpha":
            raise ValueError("the index-3 formulation is integrated by 'generalized_alpha'")
        if self.formulation != "index3" and self.integrator not in TABLEAUS:
            raise ValueError(f"integrator {self.integrator!r} is not one of {', '.join(TABLEAUS)} "
                             f"(the explicit Runge-Kutta methods of the {self.formulation} formulation)")
        if self.restart not in RESTARTS:
            raise ValueError(f"restart must be one of {', '.join(RESTARTS)}")
        GeneralizedAlphaCoefficients(self.spectral_radius)


class Formulation:
    """Shared state and the consistent (index-1) acceleration."""

    length = 1.0  # the model's length scale of the Newton tolerance (m), set by initialize

    def __init__(self, model: MultibodyModel, settings: Settings) -> None:
        self.model = model
        self.settings = settings
        self.inputs = np.zeros(model.n)
        self.newton_iterations = 0
        self.newton_retries = 0
        self.steps = 0
        self.row_changes = 0
        self._row_search: tuple[int, float] | None = None  # (step, best row quality) of the last search
        self._quality: tuple[int, float] | None = None  # (step, kept rows' quality) after a compiled step
        self._compiled: CompiledModel | None | bool = False  # False: not looked at yet
        # (steps, dissipated power, supplied power, springs' dissipated powers) at the end of the last compiled
        # index-3 step (its kernel computes them); None after a restart (new inputs or PTO commands)
        self.end_powers: tuple | None = None
        self.python_path = False  # True: never use the compiled path (comparisons, benchmarks)

    def __getstate__(self) -> dict:
        """The compiled plan is derived from the model: not saved, rebuilt after a restore."""
        state = self.__dict__.copy()
        state["_compiled"] = False
        return state

    @property
    def compiled(self) -> CompiledModel | None:
        """The model's compiled view (:mod:`mbd_fmu.fast`), None when it runs on the Python path. Derived once and
        kept: :meth:`check_model` looks at the model again where a step or a restart begins."""
        if self.python_path:
            return None
        if self._compiled is False:
            # after a restore the plan is rebuilt from the same model: the saved factors stay valid (a restored
            # run repeats the original bit for bit)
            if not hasattr(self, "_signature"):
                self._signature = self._model_signature()
            self._compiled = compiled_model(self.model)
        return self._compiled

    def _model_signature(self) -> tuple:
        m = self.model
        last = m.elements[-1] if m.elements else None  # an FMU appends its input-force element last
        return len(m.elements), type(last).__name__, getattr(last, "active", None), len(m.drivers)

    def check_model(self) -> None:
        """Drop the compiled view (and the factors derived from it) if elements or drivers were added to the model
        (e.g. an FMU's input-force element after the start) or that element was switched on (a host sets the
        linearised force interface). Called by :meth:`initialize`, :meth:`set_inputs`, :meth:`on_restart` and
        each formulation's ``step``: a model changed between steps is looked at before the next one."""
        signature = self._model_signature()
        if signature != getattr(self, "_signature", None):
            self._signature = signature
            self._compiled = False
            self._lu_key = None

    def initialize(self, pose: Pose, v: np.ndarray, t: float, inputs: np.ndarray | None = None) -> None:
        self.check_model()
        self.end_powers = None
        self.pose, self.v, self.t = pose.copy(), np.array(v, float), float(t)
        if inputs is not None:
            self.inputs = np.array(inputs, float)
        self.vdot, self.lam = self.acceleration(self.pose, self.v, self.t)
        scale = np.max(np.abs(self.model.cg)) if self.model.N else 1.0
        self.length = max(1.0, float(scale))

    def set_inputs(self, inputs: np.ndarray) -> bool:
        """Hold ``inputs`` from now on; returns True if they changed (a restart was made)."""
        self.check_model()
        inputs = np.asarray(inputs, float)
        if np.array_equal(inputs, self.inputs):
            return False
        self.inputs = inputs.copy()
        self.on_restart()
        return True

    def on_restart(self) -> None:
        self.check_model()
        self.end_powers = None
        self.vdot, self.lam = self.acceleration(self.pose, self.v, self.t)

    def acceleration(self, pose: Pose, v: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray]:
        """Consistent ``v'`` and ``lambda`` (kept rows) from the saddle-point system."""
        cm = self.compiled
        if cm is not None:
            vd, lam = kernels.acceleration_packed(*cm.plan(), pose.r, pose.R, np.asarray(v, float), self.inputs,
                                                  cm.refs)
            if not np.all(np.isfinite(vd)):
                raise np.linalg.LinAlgError("singular mass or constraint matrix (consistent acceleration)")
            return vd, lam
        m = self.model
        k = m.kin(pose, v, t)
        mass = m.mass_matrix(pose, k)
        f = m.forces(k, self.inputs)
        ev = m.constraint(k)
        r = ev.phi.size
        if r == 0:
            return np.linalg.solve(mass, f), np.zeros(0)
        x = np.linalg.solve(_saddle_point(mass, ev.jac), np.concatenate([f, ev.gamma]))
        return x[: m.n], x[m.n:]

    def step(self, h: float) -> None:  # pragma: no cover - abstract
        raise NotImplementedError

    def reselect_rows(self) -> None:
        """With redundant constraints, re-choose the independent rows at the current pose when the kept
        set has become less than half as well conditioned as the best one (the best set changes along
        the motion, e.g. in Bricard's linkage); multipliers are carried over.

        The search for the best set (QR with column pivoting of all rows) is made when the kept set's quality
        is below 0.5 (no set can be twice as good otherwise: quality <= 1) and has fallen below 0.6 times the
        best set's quality at the last search, or 1000 steps after it: between searches the best set would have
        to improve by a fifth for a switch to be missed (impossible when it was above 0.84, as the quality is at
        most 1), and then only until the next search; a missed switch costs conditioning, not accuracy."""
        m = self.model
        if len(m.kept) == m.m:
            return
        cm = self.compiled
        if cm is not None and self._quality is not None and self._quality[0] == self.steps:
            quality = self._quality[1]  # computed by the compiled step at its end pose
        elif cm is not None:
            quality = self._kept_quality()
        else:
            quality = _row_quality(m.constraint(m.kin(self.pose, self.v, self.t), gamma=False).jac)
        if self.rows_hold(quality):
            return
        _, jf, _, _ = m.constraint_full(m.kin(self.pose, self.v, self.t), gamma=False)
        c = jf[:, m.sel]
        kept, _, _ = independent_rows(c, rank=len(m.kept))
        best = _row_quality(c[kept])
        self._row_search = (self.steps, best)
        if not np.array_equal(kept, m.kept) and _row_quality(c[m.kept]) < 0.5 * best:
            force = c[m.kept].T @ self.lam
            m.kept = kept
            self.lam = np.linalg.lstsq(c[kept].T, force, rcond=None)[0]
            self.row_changes += 1

    def rows_hold(self, quality: float) -> bool:
        """True if :meth:`reselect_rows` keeps the rows without a search at the kept rows' ``quality`` now."""
        last = self._row_search
        return quality >= 0.5 or (last is not None and quality >= 0.6 * last[1] and self.steps - last[0] < 1000)

    def _kept_quality(self) -> float:
        """The kept rows' quality at the current pose on the compiled path (:meth:`reselect_rows`)."""
        cm = self.compiled
        return kernels.row_quality(*cm.plan(), self.pose.r, self.pose.R)

    def _finish(self, h: float) -> None:
        self.t += h
        self.steps += 1
        cm = self.compiled
        if cm is not None:  # compiled models' only non-trivial commit: angle unwrapping
            cm.commit(kernels.committed(*cm.plan(), self.pose.r, self.pose.R, self.v, cm.refs))
            return
        self.model.commit(self.model.kin(self.pose, self.v, self.t))


class Index3(Formulation):
    """Index-3 DAE, Lie group generalised-alpha (module docstring)."""

    _delta: float | None = None  # alpha_m - alpha_f (states saved by earlier versions: computed when first needed)

    def __init__(self, model: MultibodyModel, settings: Settings) -> None:
        super().__init__(model, settings)
        self.coef = GeneralizedAlphaCoefficients(settings.spectral_radius)
        c = self.coef
        self._coef = np.array([c.alpha_m, c.alpha_f, c.gamma, c.beta])
        self._delta = float(c.alpha_m - c.alpha_f)  # the restart's Taylor shift factor
        self.a: np.ndarray | None = None
        self.stiff_restarts = 0
        self._iteration = None  # (step size and kept rows, factorised iteration matrix)
        # compiled path: LU factors of the kept iteration matrix (plain arrays), its step size and kept rows
        self._lu: np.ndarray | None = None
        self._piv: np.ndarray | None = None
        self._lu_key: tuple | None = None

    def initialize(self, pose: Pose, v: np.ndarray, t: float, inputs: np.ndarray | None = None) -> None:
        super().initialize(pose, v, t, inputs)
        self.a = None

    def on_restart(self) -> None:
        if self.settings.restart == "none":
            self.check_model()
            self.end_powers = None
            return
        if self.settings.restart == "increment" and self.a is not None:
            before = self.vdot
            super().on_restart()
            self.a = self.a + (self.vdot - before)  # the acceleration's jump, carried by the algorithmic one
            return
        super().on_restart()
        self.a = None

    def _start_acceleration(self, h: float) -> np.ndarray:
        delta = self.coef.alpha_m - self.coef.alpha_f
        if self.settings.restart == "acceleration" or delta == 0.0:
            return self.vdot.copy()
        if self.compiled is not None:
            _, _, _, _, _, stiff, out, at = self.fused(h, 0, shift=1)
            self.stiff_restarts += int(stiff)
            return out[at[5]:at[6]]
        # the method of kernels.taylor_shift: v'' = S0^-1 (b' - S' x0), b' - S' x0 by the central difference of the
        # residuals of the centre's solution x0 at the poses +-eps along the motion; one factorisation (S0's)
        eps = 1e-5 * h
        m = self.model
        mass, f, jac, gamma = _saddle_parts(m, self.inputs, self.pose, self.v, self.t)
        lu = lu_factor(_saddle_point(mass, jac), check_finite=False)
        x0 = lu_solve(lu, np.concatenate([f, gamma]), check_finite=False)
        fwd = self.pose.retract(m.full(eps * self.v))
        bwd = self.pose.retract(m.full(-eps * self.v))
        rp = _saddle_residual(m, self.inputs, fwd, self.v + eps * self.vdot, self.t + eps, x0)
        rm = _saddle_residual(m, self.inputs, bwd, self.v - eps * self.vdot, self.t - eps, x0)
        correction = delta * h * lu_solve(lu, (rp - rm) / (2 * eps), check_finite=False)[: m.n]
        if np.abs(correction).max() > 0.5 * np.abs(self.vdot).max() + 1e-12:
            # stiff components (h |lambda| >> 1): the Taylor shift is meaningless there; a = v'
            self.stiff_restarts += 1
            return self.vdot.copy()
        return self.vdot + correction

    def step(self, h: float) -> None:
        self.check_model()
        if self.compiled is not None and self._compiled_step(h):
            return
        self.reselect_rows()
        m, c = self.model, self.coef
        if self.a is None:
            self.a = self._start_acceleration(h)
        am, af, g, b = c.alpha_m, c.alpha_f, c.gamma, c.beta
        zeta = (1 - af) / (1 - am)
        vd_n, a_n, v_n = self.vdot, self.a, self.v
        t1 = self.t + h
        vd, lam = vd_n.copy(), self.lam.copy()
        tol = self.settings.newton_tolerance * max(self.length, float(np.abs(v_n).max(initial=0.0)))
        n = m.n
        scale_c = 1.0 / (h * h * b * zeta)

        def residual(vd: np.ndarray, lam: np.ndarray):
            a1 = (af * vd_n - am * a_n + (1 - af) * vd) / (1 - am)
            v1 = v_n + h * ((1 - g) * a_n + g * a1)
            pose1 = self.pose.retract(m.full(h * (v_n + h * ((0.5 - b) * a_n + b * a1))))
            k = m.kin(pose1, v1, t1)
            mass = m.mass_matrix(pose1, k)
            ev = m.constraint(k, gamma=False)
            r1 = mass @ vd - m.forces(k, self.inputs) + ev.jac.T @ lam
            return np.concatenate([r1, ev.phi * scale_c]), k, mass, ev

        previous = None
        # modified Newton: the iteration matrix is kept across steps while the contraction stays fast
        key = (h, tuple(m.kept))
        lu = self._iteration[1] if self._iteration is not None and self._iteration[0] == key else None
        exact = False
        size = np.inf
        r_norm_prev = np.inf
        dx = None
        for it in range(self.settings.max_iterations):
            r, k, mass, ev = residual(vd, lam)
            r_norm = float(np.abs(r).max())
            backtracks = 0
            while dx is not None and it >= 2 and r_norm > r_norm_prev and backtracks < 6:
                dx = 0.5 * dx  # damped Newton: the full step increased the residual
                vd, lam = vd - dx[:n], lam - dx[n:]
                r, k, mass, ev = residual(vd, lam)
                r_norm = float(np.abs(r).max())
                backtracks += 1
            r_norm_prev = r_norm
            if lu is None:
                r_ = len(lam)
                if exact:  # finite-difference Jacobian of the full residual (stagnating modified Newton)
                    jac = np.zeros((n + r_, n + r_))
                    x0 = np.concatenate([vd, lam])
                    for i in range(n):
                        e = np.zeros(n)
                        e[i] = 1e-7 * max(1.0, abs(vd[i]))
                        jac[:, i] = (residual(vd + e, lam)[0] - r) / e[i]
                    jac[:n, n:] = ev.jac.T
                    jac[n:, n:] = 0.0
                    lu = Factorized(jac)
                    del x0
                else:
                    kt, dt = m.tangents(k)
                    kt = kt + m.inertial_stiffness(k, vd) + m.geometric_stiffness(k, lam)
                    dt = dt + m.gyroscopic_damping(k)
                    s = mass + h * g * zeta * dt + h * h * b * zeta * kt
                    lu = Factorized(_saddle_point(s, ev.jac))
            dx = lu.solve(-r)
            vd = vd + dx[:n]
            lam = lam + dx[n:]
            self.newton_iterations += 1
            # largest correction of the step's positions or velocities (velocities dominate for h < 1 s;
            # an acceleration error would otherwise accumulate in v over many small steps)
            size = max(h * h * b, h * g) * zeta * float(np.abs(dx[:n]).max()) if n else 0.0
            if size <= 1e-2 * tol:
                break
            if previous is not None and previous > 0:
                theta = size / previous
                if (theta < 1 and size * theta / (1 - theta) <= tol) or (theta > 0.5 and size <= 100 * tol):
                    break  # converged, or stagnating at the round-off floor
                if theta > 0.3:
                    exact = exact or it >= 4
                    lu = None
            previous = size
        else:
            if self._iteration is not None:  # a stale matrix from earlier steps: retry with a fresh one
                self._iteration = None
                self.newton_retries += 1
                return self.step(h)
            raise ConvergenceError(
                f"generalised-alpha Newton iteration did not converge at t = {t1:g} s (last position correction "
                f"{size:.3g} m or rad); reduce the step (multibody max_step) or check the model")
        # keep the matrix for the next step only if it converged quickly here
        self._iteration = (key, lu) if (not exact and it < 3) else None
        a1 = (af * vd_n - am * a_n + (1 - af) * vd) / (1 - am)
        self.v = v_n + h * ((1 - g) * a_n + g * a1)
        self.pose = self.pose.retract(m.full(h * (v_n + h * ((0.5 - b) * a_n + b * a1))))
        self.vdot, self.a, self.lam = vd, a1, lam
        self._finish(h)


    def _compiled_step(self, h: float) -> bool:
        """The step in one compiled call (:func:`mbd_fmu.kernels.ga_macro_step` with one substep: the same iteration
        as :meth:`step`); False if it did not converge (the Python path then takes the step, with its own retries
        and errors)."""
        self.reselect_rows()
        start = self.a is None
        status, _, iterations, retries, _, stiff, out, at = self.fused(h, 1, shift=int(start))
        self.newton_iterations += iterations
        self.newton_retries += retries
        self.stiff_restarts += int(stiff)
        if status != 0:
            if start:
                self.a = out[at[5]:at[6]]  # the start acceleration the failed attempt began with
            return False
        self.t += h
        self.steps += 1
        self.take_fused(out, at)
        return True

    # ------------------------------------------------------------------ the compiled call
    def fused(self, h: float, substeps: int, consistent: bool = False, shift: int = 0, pose: Pose | None = None,
              v: np.ndarray | None = None, inputs: np.ndarray | None = None, energy: np.ndarray | None = None,
              ptos: np.ndarray | None = None, outputs: bool = False, out: np.ndarray | None = None) -> tuple:
        """One call of :func:`mbd_fmu.kernels.ga_macro_step` (compiled path only) from the current state, or from
        ``pose``, ``v`` (``consistent``: the consistent acceleration there; ``substeps`` 0 then), with ``inputs``
        (default: the held ones): ``substeps`` equal steps over ``h`` after the restart (``consistent``, ``shift``),
        the energy sums ``energy`` (dissipated, external work, PTO energy; the initial mechanical energy for the
        balance; optionally the powers at the start) with the PTOs' springs ``ptos``, the outputs (with the balance
        and the PTOs' outputs) at the end if ``outputs``, written into ``out`` (default: a new array; the per-step
        path's :class:`~mbd_fmu.simulator.FusedBuffers` passes its own, sized for these ``ptos`` and ``outputs``,
        with the LU buffers allocated). Every compiled evaluation of an index-3 run goes through this one entry
        point (numba compiles it once), and every call's arguments are assembled here.
        Returns (status, substeps done, iterations, retries, keep the factors, stiff restart, out, offsets of out
        (None with ``out`` given: the caller's));
        the formulation's state is not changed (:meth:`take_fused` takes the state reached) but for the key of the
        kept LU factors (:attr:`_lu_key`), brought up to date by a call with substeps."""
        cm, m = self._compiled or self.compiled, self.model  # (the view made once: callers are on the compiled path)
        kept = m.kept
        at = None  # (the caller's layout when it gives ``out``)
        if out is None:
            ptos = _NO_PTOS if ptos is None else ptos
            at = self._offsets(len(ptos))
            nn = m.n + len(kept)
            if self._lu is None or self._lu.shape[0] != nn:
                self._lu, self._piv = np.empty((nn, nn)), np.zeros(nn, dtype=np.int64)
            out = np.empty(at[-1] if outputs else at[11])
        key = self._lu_key
        have = False
        if substeps > 0 and key is not None:
            hs = h / substeps
            have = key[0] == hs and (key[1] is kept or bool(np.array_equal(key[1], kept)))
        if consistent and substeps == 0:  # a consistent acceleration only: the state's v' and lambda not read
            vdot, lam, a = np.zeros(m.n), np.zeros(len(kept)), None
        else:
            vdot, lam, a = self.vdot, self.lam, self.a
        pose = self.pose if pose is None else pose
        settings = self.settings
        delta = self._delta
        if delta is None:  # (a state saved by an earlier version)
            c = self.coef
            delta = self._delta = float(c.alpha_m - c.alpha_f)
        ip, fp = cm.plan()  # PTO commands and angle references of now
        status, done, iterations, retries, keep, stiff = kernels.ga_macro_step(
            ip, fp, pose.r, pose.R, self.v if v is None else v, vdot, vdot if a is None else a, lam,
            self.inputs if inputs is None else inputs, cm.refs, float(h), substeps, self._coef,
            float(settings.newton_tolerance), self.length, int(settings.max_iterations), self._lu, self._piv, have,
            consistent, shift,
            0.0 if settings.restart == "acceleration" else delta,
            _NO_PTOS if ptos is None else ptos, _NO_ENERGY if energy is None else energy, out)
        if substeps > 0:  # the kept factors: valid for this step size and these rows while the call keeps them
            if done == 0:
                if status != 0:
                    self._lu_key = None  # the factors may have been overwritten
            elif not keep:
                self._lu_key = None
            elif not have or key[1] is not kept:
                self._lu_key = (h / substeps, kept)
        return status, done, iterations, retries, keep, stiff, out, at

    def take_fused(self, out: np.ndarray, at: np.ndarray, views: tuple | None = None) -> list[float]:
        """The state reached by :meth:`fused` (``t`` and ``steps`` are the caller's): v', lambda, pose, v, a (views
        of ``out``: ``views`` if given, made by :meth:`fused_views`, else new ones), the angle references' commit,
        the row quality and the end powers. Returns the call's energy sums and the powers at the end (dissipated,
        external work, PTO energy; dissipated, supplied and PTO power), :meth:`fused`'s ``energy`` of the next
        step."""
        self.vdot, self.lam, self.pose, self.v, self.a, refs, springs, quality, powers = \
            views or self.fused_views(out, at)
        self._compiled.commit(refs)  # (the compiled view fused used)
        self._quality = (self.steps, out.item(quality))
        sums = out[powers - 3:powers + 3].tolist()  # (the energy sums just before the powers: macro_layout)
        # the powers at the new state (MultibodySimulator.powers), valid until a restart or the next step
        self.end_powers = (self.steps, sums[3], sums[4], springs)
        return sums

    def fused_views(self, out: np.ndarray, at: np.ndarray) -> tuple:
        """What :meth:`take_fused` takes from :meth:`fused`'s ``out``: views of v', lambda, pose, v, a, the angle
        references and the springs' dissipated powers, and the positions of the kept rows' quality and of the
        powers."""
        nb = self.model.N
        return (out[at[0]:at[1]], out[at[1]:at[2]], Pose(out[at[2]:at[3]].reshape(nb, 3),
                                                         out[at[3]:at[4]].reshape(nb, 3, 3)),
                out[at[4]:at[5]], out[at[5]:at[6]], out[at[6]:at[7]], out[at[9]:at[10]], int(at[10]), int(at[8]))

    def _offsets(self, ptos: int = 0) -> np.ndarray:
        """Offsets of :meth:`fused`'s output (:func:`mbd_fmu.kernels.macro_layout`) for the current kept rows and
        ``ptos`` PTOs."""
        m = self.model
        cached = getattr(self, "_layout", None)
        if cached is not None and cached[0] is m.kept and cached[1] == ptos:
            return cached[2]
        cm = self.compiled
        nb, ne = m.N, len(cm.springs)
        at = _macro_layout(m.n, len(m.kept), nb, len(cm.refs), ne,
                           6 * nb + 3 + 6 * len(m.joints) + 2 * len(cm.coordinates) + ne, ptos)
        self._layout = (m.kept, ptos, at)
        return at

    def _kept_quality(self) -> float:
        _, _, _, _, _, _, out, at = self.fused(0.0, 0)
        return float(out[at[10]])

    def acceleration(self, pose: Pose, v: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray]:
        """Consistent ``v'`` and ``lambda`` (kept rows); on the compiled path by :meth:`fused`."""
        if self.compiled is None:
            return super().acceleration(pose, v, t)
        status, _, _, _, _, _, out, at = self.fused(0.0, 0, consistent=True, pose=pose, v=np.asarray(v, float))
        if status == 3:
            raise np.linalg.LinAlgError("singular mass or constraint matrix (consistent acceleration)")
        return out[at[0]:at[1]], out[at[1]:at[2]]


class Index1(Formulation):
    """Index-1 DAE by explicit RKMK with projection onto the constraint manifold (module docstring)."""

    def step(self, h: float) -> None:
        self.check_model()
        kept = self.model.kept
        self.reselect_rows()
        m = self.model
        tab = TABLEAUS[self.settings.integrator]
        cm = self.compiled
        if cm is not None:  # the whole step in one compiled call (kernels.rkmk_index1)
            vdot = self.vdot if m.kept is kept else self.acceleration(self.pose, self.v, self.t)[0]
            ok, r1, rot1, v1, vd1, lam1, refs = kernels.rkmk_index1(
                *cm.plan(), self.pose.r, self.pose.R, self.v, vdot, self.inputs, cm.refs, h, *_tableau_arrays(tab),
                1e-3 * self.settings.newton_tolerance * self.length, self.settings.max_iterations)
            if not ok:
                raise ConvergenceError(f"position projection did not converge at t = {self.t + h:g} s")
            if not np.all(np.isfinite(vd1)):
                raise np.linalg.LinAlgError("singular mass or constraint matrix (consistent acceleration)")
            self.pose, self.v, self.vdot, self.lam = Pose(r1, rot1), v1, vd1, lam1
            self.t += h
            self.steps += 1
            cm.commit(refs)
            return
        # the first stage is at the current state, whose consistent acceleration is known (same rows)
        known = self.vdot if m.kept is kept else None

        def rates(pose: Pose, v: np.ndarray, t: float):
            if pose is self.pose and known is not None:
                return v, known
            return v, self.acceleration(pose, v, t)[0]

        pose, v, _ = rkmk_step(tab, self.pose, self.v, self.t, h, rates, m.full)
        self.pose, self.v = self.project(pose, v, self.t + h)
        self.vdot, self.lam = self.acceleration(self.pose, self.v, self.t + h)
        self._finish(h)

    def project(self, pose: Pose, v: np.ndarray, t: float) -> tuple[Pose, np.ndarray]:
        """Nearest consistent position and velocity in the mass metric (the compiled path's
        :func:`~mbd_fmu.kernels.project_positions` and :func:`~mbd_fmu.kernels.consistent_state`): simplified
        Newton on Phi = 0 with the mass matrix and Jacobian of the first iterate (the step's drift is tiny: one
        iteration is usual), then v -= M^-1 C^T (C M^-1 C^T)^-1 (C v - rhs_v) with M and C at the projected pose."""
        m = self.model
        tol = 1e-3 * self.settings.newton_tolerance * self.length
        solver = None
        for _ in range(self.settings.max_iterations):
            ev = m.constraint(m.kin(pose, v, t), gamma=False)
            if ev.phi.size == 0 or np.abs(ev.phi).max() <= tol:
                break
            if solver is None:
                winv_ct = np.linalg.solve(m.mass_matrix(pose), ev.jac.T)
                solver = winv_ct, lu_factor(ev.jac @ winv_ct, check_finite=False)
            pose = pose.retract(m.full(-solver[0] @ lu_solve(solver[1], ev.phi, check_finite=False)))
        else:
            raise ConvergenceError(f"position projection did not converge at t = {t:g} s")
        if ev.phi.size:
            c = ev.jac
            winv_ct = np.linalg.solve(m.mass_matrix(pose), c.T)
            v = v - winv_ct @ np.linalg.solve(c @ winv_ct, c @ v - ev.rhs_v)
        return pose, v


class NullSpace(Formulation):
    """Reduced ODE by null-space (Maggi) projection with coordinate partitioning (module docstring)."""

    def __init__(self, model: MultibodyModel, settings: Settings) -> None:
        super().__init__(model, settings)
        self.dep = self.ind = None
        self.quality = 0.0
        self.repartitions = 0
        self._known = None  # independent accelerations at the current state (partition, v_s')
        self._ratio = 0.0  # compiled path: the partition's quality at the current pose
        self._order: tuple | None = None  # compiled path: C_d's row and column order and bandwidths

    def initialize(self, pose: Pose, v: np.ndarray, t: float, inputs: np.ndarray | None = None) -> None:
        super().initialize(pose, v, t, inputs)
        self._known = None

    def on_restart(self) -> None:
        super().on_restart()
        self._known = None

    def _choose_partition(self, c: np.ndarray) -> None:
        r = c.shape[0]
        _, _, piv = qr(c, pivoting=True, mode="economic")
        self.dep, self.ind = np.sort(piv[:r]), np.sort(piv[r:])
        self.quality = self._pivot_ratio(c)
        self.repartitions += 1

    def _pivot_ratio(self, c: np.ndarray) -> float:
        if not len(self.dep):
            return 1.0
        u = np.abs(np.diag(lu_factor(c[:, self.dep])[0]))
        return float(u.min() / max(np.max(np.abs(c)), 1e-300))

    def basis(self, c: np.ndarray) -> tuple[np.ndarray, Factorized | None]:
        """P (n, n - r) for the current partition and C_d ready for solves (None without constraints)."""
        n = self.model.n
        p = np.zeros((n, len(self.ind)))
        p[self.ind, np.arange(len(self.ind))] = 1.0
        if not len(self.dep):
            return p, None
        cd = Factorized(c[:, self.dep])
        p[self.dep] = -cd.solve(c[:, self.ind])
        return p, cd

    def reduced_acceleration(self, pose: Pose, vs: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Full velocity, full acceleration and the independent accelerations at ``(pose, v_s)``."""
        m = self.model
        ev = m.constraint(m.kin(pose, np.zeros(m.n), t), gamma=False)
        p, cd = self.basis(ev.jac)
        v = p @ vs
        if cd is not None:
            v[self.dep] += cd.solve(ev.rhs_v)
        k = m.kin(pose, v, t)
        rho = np.zeros(m.n)
        if cd is not None:
            rho[self.dep] = cd.solve(m.constraint_gamma(k))
        mass = m.mass_matrix(pose)
        f = m.forces(k, self.inputs)
        vsd = np.linalg.solve(p.T @ mass @ p, p.T @ (f - mass @ rho))
        return v, p @ vsd + rho, vsd

    def step(self, h: float) -> None:
        self.check_model()
        kept = self.model.kept
        self.reselect_rows()
        if self.model.kept is not kept:
            self.dep = self._known = None
        if self.compiled is not None:
            self._compiled_step(h)
            return
        m = self.model
        c = m.constraint(m.kin(self.pose, self.v, self.t), gamma=False).jac
        if c.shape[0] and (self.dep is None or self._pivot_ratio(c) < 0.1 * self.quality):
            self._choose_partition(c)
            self._known = None
        elif self.dep is None:
            self.dep, self.ind = np.arange(0), np.arange(m.n)
        tab = TABLEAUS[self.settings.integrator]
        known = self._known

        def rates(pose: Pose, vs: np.ndarray, t: float):
            if pose is self.pose and known is not None:  # first stage: the current state, already evaluated
                return self.v, known
            v, _, vsd = self.reduced_acceleration(pose, vs, t)
            return v, vsd

        pose, vs, _ = rkmk_step(tab, self.pose, self.v[self.ind], self.t, h, rates, m.full)
        self.pose = self.correct_dependent(pose, self.t + h)
        self.v, self.vdot, self._known = self.reduced_acceleration(self.pose, vs, self.t + h)
        self.lam = self.multipliers()
        self._finish(h)

    def _compiled_step(self, h: float) -> None:
        """The step in one compiled call (:func:`mbd_fmu.nullspace_kernels.nullspace_step`: the same method, the
        reduced accelerations from the banded saddle-point solve); the partition is chosen as on the Python path
        and its quality measured by the banded LU of C_d (module docstring of :mod:`mbd_fmu.nullspace_kernels`)."""
        from . import nullspace_kernels as nk

        cm, m = self.compiled, self.model
        plan = cm.plan()
        order = getattr(self, "_order", None)  # (absent from states saved by earlier versions)
        if self.dep is None or order is None or (len(self.dep) and self._ratio < 0.1 * self.quality):
            c = m.constraint(m.kin(self.pose, self.v, self.t), gamma=False).jac
            if c.shape[0]:
                r = c.shape[0]
                _, _, piv = qr(c, pivoting=True, mode="economic")
                self.dep, self.ind = np.sort(piv[:r]), np.sort(piv[r:])
                self.repartitions += 1
            else:
                self.dep, self.ind = np.arange(0), np.arange(m.n)
            order = self._order = cm.dependent_order(self.dep)
            self.quality = self._ratio = nk.partition_quality(*plan, self.pose.r, self.pose.R, cm.refs, self.t,
                                                              self.dep, *order)
        tab = TABLEAUS[self.settings.integrator]
        ok, r1, rot1, v1, vd1, lam1, refs, ratio = nk.nullspace_step(
            *plan, self.pose.r, self.pose.R, self.v, self.vdot, self.inputs, cm.refs, self.t, h, *_tableau_arrays(tab),
            self.dep, self.ind, *order, 1e-3 * self.settings.newton_tolerance * self.length,
            self.settings.max_iterations)
        if not ok:
            raise ConvergenceError(f"dependent coordinates did not converge at t = {self.t + h:g} s")
        if not np.all(np.isfinite(vd1)):
            raise np.linalg.LinAlgError("singular mass or constraint matrix (consistent acceleration)")
        self.pose, self.v, self.vdot, self.lam, self._ratio = Pose(r1, rot1), v1, vd1, lam1, ratio
        self._known = None
        self.t += h
        self.steps += 1
        cm.commit(refs)

    def correct_dependent(self, pose: Pose, t: float) -> Pose:
        """Newton on the dependent positions with the independent ones held."""
        m = self.model
        if not len(self.dep):
            return pose
        tol = 1e-3 * self.settings.newton_tolerance * self.length
        for _ in range(self.settings.max_iterations):
            ev = m.constraint(m.kin(pose, np.zeros(m.n), t), gamma=False)
            if np.abs(ev.phi).max() <= tol:
                return pose
            delta = np.zeros(m.n)
            delta[self.dep] = -np.linalg.solve(ev.jac[:, self.dep], ev.phi)
            pose = pose.retract(m.full(delta))
        raise ConvergenceError(f"dependent coordinates did not converge at t = {t:g} s")

    def multipliers(self) -> np.ndarray:
        """lambda from the dependent rows of C^T lambda = f - M v' (reactions)."""
        m = self.model
        k = m.kin(self.pose, self.v, self.t)
        ev = m.constraint(k, gamma=False)
        if not ev.phi.size:
            return np.zeros(0)
        res = m.forces(k, self.inputs) - m.mass_matrix(self.pose) @ self.vdot
        return np.linalg.solve(ev.jac[:, self.dep].T, res[self.dep])


_TABLEAU_ARRAYS: dict = {}


def _tableau_arrays(tab) -> tuple[np.ndarray, np.ndarray]:
    """(a, b) of a Butcher tableau as arrays (for the compiled step), built once per method."""
    if id(tab) not in _TABLEAU_ARRAYS:
        _TABLEAU_ARRAYS[id(tab)] = (np.array(tab.a, dtype=float).reshape(len(tab.b), -1), np.array(tab.b, dtype=float))
    return _TABLEAU_ARRAYS[id(tab)]


# ``[[S, C^T], [C, 0]]``: the kernels' function, called as plain Python on this path
_saddle_point = getattr(kernels.saddle, "py_func", kernels.saddle)


def _saddle_parts(model: MultibodyModel, inputs: np.ndarray, pose: Pose, v: np.ndarray,
                  t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """M, f, C (kept rows) and gamma of the saddle-point system ``[[M, C^T], [C, 0]] [v'; lambda] = [f; gamma]``."""
    k = model.kin(pose, v, t)
    ev = model.constraint(k)
    return model.mass_matrix(pose, k), model.forces(k, inputs), ev.jac, ev.gamma


def _saddle_residual(model: MultibodyModel, inputs: np.ndarray, pose: Pose, v: np.ndarray, t: float,
                     x: np.ndarray) -> np.ndarray:
    """``[f - M v' - C^T lambda; gamma - C v']`` at (pose, v, t) for x = (v', lambda) (kernels.saddle_residual)."""
    mass, f, jac, gamma = _saddle_parts(model, inputs, pose, v, t)
    n = model.n
    return np.concatenate([f - mass @ x[:n] - jac.T @ x[n:], gamma - jac @ x[:n]])


def _row_quality(rows: np.ndarray) -> float:
    """Smallest singular value of the row-normalised rows (how independent they are)."""
    scale = np.maximum(np.linalg.norm(rows, axis=1), 1e-300)
    return float(np.linalg.svd(rows / scale[:, None], compute_uv=False).min())


def make_formulation(model: MultibodyModel, settings: Settings) -> Formulation:
    return {"index3": Index3, "index1": Index1, "nullspace": NullSpace}[settings.formulation](model, settings)
