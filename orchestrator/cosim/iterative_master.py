"""The iterative master: Gauss-Seidel iterated to consistency with rollback (Aitken or IQN-ILS, or Newton on the
interface in the added-mass ``interface`` mode). The method, its order and its stability are described with the
other masters in :mod:`orchestrator.cosim.masters`; :func:`orchestrator.cosim.masters.make_master` builds it by name
(``aitken``, ``iqn_ils``)."""

from __future__ import annotations

from collections import deque

import numpy as np

from orchestrator.errors import MasterError

from .masters import GaussSeidelMaster


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

    def _converged(self, r: np.ndarray, y: np.ndarray) -> bool:
        scale = np.maximum(np.concatenate([self._scale[c] for c in self.integrators]), np.abs(y))
        scale = np.maximum(scale, 1e-12 * max(1.0, float(np.max(scale, initial=0.0))))
        return float(np.max(np.abs(r) / np.maximum(scale, 1e-300), initial=0.0)) <= self.settings.tolerance

    def step(self, h: float, end_time: float | None = None) -> None:
        t = self.time
        for name in self.samplers:
            self.components[name].do_step(t, h)
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
        scale = np.maximum(np.concatenate([self._scale[c] for c in self.integrators]), np.abs(y))
        rel = float(np.max(np.abs(r) / np.maximum(scale, 1e-300)))
        hint = ("use master = 'iqn_ils'" if self.solver == "aitken" else "reduce the step")
        raise MasterError(
            f"{self.solver}: the coupling iteration did not converge at t = {self.time:g} s within "
            f"{k} iterations (relative residual {rel:.3g}, tolerance {self.settings.tolerance:g}); "
            f"raise simulation.max_iterations, loosen simulation.tolerance or {hint}")

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
                    dr = r - rs[-1]
                    denom = float(dr @ dr)
                    if denom > 0:
                        self._omega = float(np.clip(-self._omega * (rs[-1] @ dr) / denom, -2.0, 2.0))
                x_new = x + self._omega * r
            else:
                x_new = self._iqn_update(x, r, y, rs, ys)
            rs.append(r)
            ys.append(y)
            x = x_new
        self._fail(cap, r, y)
        return cap

    def _iqn_update(self, x: np.ndarray, r: np.ndarray, y: np.ndarray, rs: list, ys: list) -> np.ndarray:
        """x_{k+1} = y_k + W c with c = argmin |V c + r_k| (V, W: differences to the latest
        residual and output, this step's columns first, then those of previous steps)."""
        vs = [r - ri for ri in reversed(rs)]
        ws = [y - yi for yi in reversed(ys)]
        for v_old, w_old in self._past:
            vs += list(v_old.T)
            ws += list(w_old.T)
        if not vs:
            return x + self.settings.relaxation * r
        keep = _independent_columns(vs, self._n)
        v = np.column_stack([vs[i] for i in keep])
        w = np.column_stack([ws[i] for i in keep])
        c = np.linalg.lstsq(v, -r, rcond=None)[0]
        return y + w @ c

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
        scale = np.maximum(np.concatenate([self._scale[c] for c in self.integrators]), np.abs(x))
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


def _independent_columns(columns: list[np.ndarray], limit: int, eps: float = 1e-10) -> list[int]:
    """Indices of the columns kept by IQN-ILS's filter: in order (newest first), each kept if its
    part orthogonal to those already kept is larger than ``eps`` times its norm; at most ``limit``."""
    basis: list[np.ndarray] = []
    keep = []
    for i, col in enumerate(columns):
        norm = float(np.linalg.norm(col))
        if norm == 0:
            continue
        rest = col.copy()
        for b in basis:
            rest -= (b @ rest) * b
        rn = float(np.linalg.norm(rest))
        if rn > eps * norm:
            basis.append(rest / rn)
            keep.append(i)
            if len(keep) == limit:
                break
    return keep
