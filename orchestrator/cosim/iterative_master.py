"""The iterative master: Gauss-Seidel iterated to consistency with rollback (Aitken or IQN-ILS, or Newton on the
interface in the added-mass ``interface`` mode). The method, its order and its stability are described with the
other masters in :mod:`orchestrator.cosim.masters`; :func:`orchestrator.cosim.masters.make_master` builds it by name
(``aitken``, ``iqn_ils``)."""

from __future__ import annotations

from collections import deque

import numpy as np

from orchestrator.errors import MasterError

from .masters import GaussSeidelMaster

# IQN-ILS's filter: a secant column whose part independent of the columns kept before it is below this fraction of
# its norm is dropped (nearly dependent data, mostly from earlier steps, make the least squares ill-conditioned:
# measured on the hinge barge and F3OF DT3, 1e-4 takes 2-3 evaluations per step where 1e-10 took 3-7)
FILTER = 1e-4


class IterativeMaster(GaussSeidelMaster):
    """Gauss-Seidel iterated to convergence with rollback (module docstring).

    The unknowns are the integrators' connected outputs at t_{n+1}; one evaluation restores the
    integrators' states at t_n, evaluates the samplers with the iterate, steps the integrators
    and reads their outputs. Samplers step once per macro step (their step consumes only the
    samples at t_n, known exactly).
    """

    iterates = True

    def __init__(self, *args, solver: str = "iqn_ils", **kwargs) -> None:
        super().__init__(*args, **kwargs)
        if solver not in ("aitken", "iqn_ils"):
            raise ValueError("solver must be 'aitken' or 'iqn_ils'")
        self.solver = solver
        self.name = solver
        self._omega = self.settings.relaxation
        self._past: deque = deque(maxlen=max(0, self.settings.reuse))  # (V, W) of previous steps
        self._jacobians: dict[tuple, np.ndarray] = {}  # interface mode: inverse Newton matrices by (h, weights)
        self._slices = {}
        k = 0
        for c in self.integrators:
            n = self.n_connected[c]
            self._slices[c] = slice(k, k + n)
            k += n
        self._n = k
        # Each interface variable's kind: its component and unit (m, rad, m/s, rad/s from the FMU's model
        # description; a variable without a unit is a kind of its own). The convergence test and the solvers'
        # least squares measure a variable against the largest magnitude of its kind (_variable_scales).
        kinds: dict[tuple, int] = {}
        self._kind = np.array([kinds.setdefault((c, self.components[c].variables[v].unit or v)
                                                if v in getattr(self.components[c], "variables", {}) else (c, v),
                                                len(kinds))
                               for c in self.integrators for v in self.output_names[c][: self.n_connected[c]]],
                              dtype=int)
        self._n_kinds = len(kinds)
        self._kind_index = [np.flatnonzero(self._kind == k) for k in range(self._n_kinds)]
        self._running: np.ndarray | None = None  # the interface variables' running maxima at t_n (step)

    # -------------------------------------------------------------- vector <-> component dicts
    def _pack(self, y: dict[str, np.ndarray]) -> np.ndarray:
        return np.concatenate([y[c][: self.n_connected[c]] for c in self.integrators]) if self._n else np.zeros(0)

    def _unpack(self, x: np.ndarray) -> dict[str, np.ndarray]:
        return {c: x[self._slices[c]] for c in self.integrators}

    def _save_integrators(self) -> dict:
        return {c: self.components[c].get_state() for c in self.integrators}

    def _rollback(self, states: dict) -> None:
        for c, s in states.items():
            self.components[c].set_state(s)

    def _free(self, states: dict) -> None:
        for c, s in states.items():
            self.components[c].free_state(s)

    def _evaluate(self, x: np.ndarray, h: float, states: dict, first: bool) -> tuple[np.ndarray, dict]:
        if not first:
            self._rollback(states)
        new = self._step_integrators(h, self._unpack(x))
        return self._pack(new), new

    def _variable_scales(self, y: np.ndarray) -> np.ndarray:
        """S_i: the largest magnitude of any interface variable of i's kind (component and unit) over the run so
        far and in ``y`` (the running maxima are taken at every communication point), at least ``precision`` /
        ``tolerance`` (the integrating FMU's own accuracy: no iteration gets below it)."""
        if not self._n:
            return np.zeros(0)
        running = self._running
        if running is None or len(running) != self._n:
            running = self._running = np.concatenate([self._scale[c] for c in self.integrators])
        running = np.maximum(running, np.abs(y))
        floor = self.settings.precision / self.settings.tolerance
        per_kind = np.array([max(float(running[idx].max()), floor) for idx in self._kind_index])
        return per_kind[self._kind]

    def _scaled_residual(self, r: np.ndarray, y: np.ndarray) -> np.ndarray:
        """|r_i| / S_i (:meth:`_variable_scales`); a variable whose kind has not moved yet (S_i = 0) counts 0 if
        its residual is exactly 0, else infinite."""
        s = self._variable_scales(y)
        return np.where(s > 0, np.abs(r) / np.where(s > 0, s, 1.0), np.where(r == 0, 0.0, np.inf))

    def _converged(self, r: np.ndarray, y: np.ndarray) -> bool:
        """The convergence test: |r_i| <= max(``tolerance`` S_i, ``precision``) for every interface variable i
        (module docstring of :mod:`orchestrator.cosim.masters`)."""
        return bool(np.all(np.abs(r) <= self.settings.tolerance * self._variable_scales(y)))

    def _weights_of(self, y: np.ndarray) -> np.ndarray:
        """1 / S_i (1 where S_i = 0): the solvers' least squares and dot products in units of each kind's scale."""
        s = self._variable_scales(y)
        return np.where(s > 0, 1.0 / np.where(s > 0, s, 1.0), 1.0)

    def step(self, h: float, end_time: float | None = None) -> None:
        t = self.time
        for name in self.samplers:
            self.components[name].do_step(t, h)
        self._running = None  # the running maxima changed at the last point (_resolve)
        states = self._save_integrators()
        try:
            x = self._pack(self._predicted_outputs(h))
            if self.added_mass is not None and self.added_mass["mode"] == "interface":
                iterations = self._newton(x, h, states)
            else:
                iterations = self._quasi_newton(x, h, states)
        finally:
            self._free(states)
        self.iterations.append(iterations)
        self._finish_step(h, end_time)

    def _fail(self, k: int, r: np.ndarray, y: np.ndarray) -> None:
        rel = self._scaled_residual(r, y)
        j = int(np.argmax(rel))
        names = [v for c in self.integrators for v in self.output_names[c][: self.n_connected[c]]]
        hint = ("use master = 'iqn_ils'" if self.solver == "aitken" else "reduce the step")
        raise MasterError(
            f"{self.solver}: the coupling iteration did not converge at t = {self.time:g} s within "
            f"{k} iterations (largest residual {rel[j]:.3g} of the scale of its kind, at {names[j]}; tolerance "
            f"{self.settings.tolerance:g}); raise simulation.max_iterations, loosen simulation.tolerance or {hint}")

    def _quasi_newton(self, x: np.ndarray, h: float, states: dict) -> int:
        """Aitken-relaxed fixed point or IQN-ILS; returns the number of evaluations."""
        cap = self.settings.max_iterations
        rs, ys = [], []
        for k in range(1, cap + 1):
            y, _ = self._evaluate(x, h, states, first=(k == 1))
            r = y - x
            if self._converged(r, y):
                self._remember(rs, ys, r, y)
                return k
            if self.solver == "aitken":
                if rs:
                    d = self._weights_of(y)
                    dr = d * (r - rs[-1])
                    denom = float(dr @ dr)
                    if denom > 0:
                        self._omega = float(np.clip(-self._omega * ((d * rs[-1]) @ dr) / denom, -2.0, 2.0))
                x_new = x + self._omega * r
            else:
                x_new = self._iqn_update(x, r, y, rs, ys)
            rs.append(r)
            ys.append(y)
            x = x_new
        self._fail(cap, r, y)
        return cap

    def _iqn_update(self, x: np.ndarray, r: np.ndarray, y: np.ndarray, rs: list, ys: list) -> np.ndarray:
        """x_{k+1} = y_k + W c with c = argmin |D (V c + r_k)| (V, W: differences to the latest residual and output,
        this step's columns first, then those of previous steps; D = 1 / S the kinds' scales), V's columns filtered
        for independence (:func:`_independent_columns`) and the least squares solved through V's QR factors."""
        columns = [r - ri for ri in reversed(rs)]
        outputs = [y - yi for yi in reversed(ys)]
        if not columns and not self._past:
            return x + self.settings.relaxation * r
        d = self._weights_of(y)
        v = np.column_stack(columns + [p[0] for p in self._past]) if columns else \
            np.column_stack([p[0] for p in self._past])
        w = np.column_stack(outputs + [p[1] for p in self._past]) if outputs else \
            np.column_stack([p[1] for p in self._past])
        v = d[:, None] * v  # residual differences in units of each kind's scale
        q, rr = np.linalg.qr(v)
        if v.shape[1] <= self._n and np.all(np.abs(np.diag(rr)) > FILTER * np.sqrt(np.einsum("ij,ij->j", v, v))):
            keep = slice(None)  # every column independent (the usual case): the filter keeps them all
        else:
            keep = _independent_columns(v, self._n)
            if not keep:  # every secant column zero (the residual repeated exactly): a relaxed fixed-point step
                return x + self.settings.relaxation * r
            q, rr = np.linalg.qr(v[:, keep])
        c = np.linalg.solve(rr, -(q.T @ (d * r)))
        return y + w[:, keep] @ c

    def _remember(self, rs: list, ys: list, r: np.ndarray, y: np.ndarray) -> None:
        if self.solver == "iqn_ils" and rs and self.settings.reuse > 0:
            v = np.column_stack([r - ri for ri in reversed(rs)])
            w = np.column_stack([y - yi for yi in reversed(ys)])
            self._past.appendleft((v, w))

    # -------------------------------------------------------------- interface Newton (mode c)
    def _newton(self, x: np.ndarray, h: float, states: dict) -> int:
        """Newton on R(x) = S(x) - x with J = dS/dx - I, dS/dx from finite differences through
        rollback (measured at the first step and whenever an update fails to contract), A_inf
        entering through the interface map exactly. Returns the number of evaluations."""
        cap = self.settings.max_iterations
        key = (round(h, 12), tuple(len(self.history[c]) for c in self.integrators))
        y, _ = self._evaluate(x, h, states, first=True)
        r = y - x
        evaluations = 1
        refreshed = False
        while not self._converged(r, y):
            if evaluations >= cap:
                self._fail(evaluations, r, y)
            if key not in self._jacobians:
                if len(self._jacobians) > 16:
                    self._jacobians.clear()
                self._jacobians[key] = self._measure_newton_matrix(x, y, h, states)
                evaluations += self._n
                refreshed = True
            x_new = x - self._jacobians[key] @ r
            y_new, _ = self._evaluate(x_new, h, states, first=False)
            r_new = y_new - x_new
            evaluations += 1
            if np.linalg.norm(r_new) > 0.5 * np.linalg.norm(r) and not refreshed:
                del self._jacobians[key]  # stale Jacobian: measure again at this point
            x, y, r = x_new, y_new, r_new
        return evaluations

    def _measure_newton_matrix(self, x: np.ndarray, y: np.ndarray, h: float, states: dict) -> np.ndarray:
        """Inverse of J = dS/dx - I by one-sided finite differences (exact for an affine S, whatever
        the increment, so the increment is taken large against round-off: 1e-4 of the variable's scale,
        at least 1e-4 in SI units)."""
        n = self._n
        scale = self._variable_scales(x)
        jac = np.empty((n, n))
        for j in range(n):
            dx = 1e-4 * max(scale[j], 1.0)
            xp = x.copy()
            xp[j] += dx
            yp, _ = self._evaluate(xp, h, states, first=False)
            jac[:, j] = (yp - y) / dx
        return np.linalg.inv(jac - np.eye(n))

    def _state(self) -> dict:
        out = super()._state()
        out["solver"] = {"omega": self._omega, "past": [(v.copy(), w.copy()) for v, w in self._past],
                         "jacobians": {k: v.copy() for k, v in self._jacobians.items()}}
        return out

    def _set_state(self, state: dict) -> None:
        super()._set_state(state)
        s = state["solver"]
        self._omega = s["omega"]
        self._past.clear()
        self._past.extend((v.copy(), w.copy()) for v, w in s["past"])
        self._jacobians = {k: v.copy() for k, v in s["jacobians"].items()}


def _independent_columns(columns: np.ndarray, limit: int, eps: float = FILTER) -> list[int]:
    """Indices of the columns of ``columns`` (n, k) kept by IQN-ILS's filter: in order (newest first), each kept if
    its part orthogonal to those already kept is larger than ``eps`` times its norm; at most ``limit``."""
    n, k = columns.shape
    basis = np.empty((n, min(limit, k, n)))
    keep: list[int] = []
    norms = np.sqrt(np.einsum("ij,ij->j", columns, columns))
    for i in range(k):
        if norms[i] == 0:
            continue
        col = columns[:, i]
        m = len(keep)
        rest = col - basis[:, :m] @ (basis[:, :m].T @ col) if m else col
        rest = rest - basis[:, :m] @ (basis[:, :m].T @ rest) if m else rest  # twice is enough (Kahan)
        rn = float(np.sqrt(rest @ rest))
        if rn > eps * norms[i]:
            basis[:, m] = rest / rn
            keep.append(i)
            if len(keep) == basis.shape[1]:
                break
    return keep
