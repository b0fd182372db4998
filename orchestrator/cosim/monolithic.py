"""Monolithic mode: the scene's physics stepped in one process without FMI, strongly coupled.

The reference for the co-simulation error and for the cost of the FMI interface. Same physics
objects as the FMUs (:class:`hydro_fmu.model.HydroModel`, the multibody model of
:meth:`Scene.multibody_system`, A_inf in its mass matrix), same radiation grid (the macro step).

Method: each step from t_n to t_{n+1} = t_n + h solves, for the state z_{n+1} = (q, q'),

    z_{n+1} = Step_h(z_n, (F_n + F_{n+1}(z_{n+1})) / 2),

with Step_h the multibody model's exact step for a force held over the step and F_{n+1} the
hydrodynamic force at t_{n+1} given the end-of-step motion (hydrostatics, the newest sample of
the radiation convolution, excitation). The implicit equation is solved by Newton's method with
the Jacobian of the right-hand side measured once per step size by finite differences (exact
for the linear model: one update converges; the residual is checked every step, tolerance
1e-12 relative, at the cost of one more multibody step; the force at the accepted state is the
next step's F_n). Cost per step: two multibody steps and two hydrodynamic force evaluations.
Second order (trapezoidal average of the force over the step; the convolution is trapezoidal too);
A-stable for the linear model, whatever the ratio of A_inf to mass, since nothing is explicit.
"""

from __future__ import annotations

import copy

import numpy as np

from fmu_base import state_codec
from orchestrator.errors import MasterError, WecCosimError
from orchestrator.scene import HYDRO, MBD, Scene

from .masters import Master
from .step_control import FixedStepController


class MonolithicMaster:
    """Same interface as the co-simulation masters (initialize, step, run, outputs, checkpoint)."""

    name = "monolithic"
    run = Master.run

    def __init__(self, scene: Scene, observe: dict[str, list[str]], tolerance: float = 1e-12) -> None:
        s = scene.scenario
        self.scene = scene
        self.system = scene.multibody_system(added_mass=True)
        self.hydro = scene.hydro_model(dt=s.simulation.step)  # every hydro option, as the hydro FMU
        self.rows = np.array([self.system.coordinate_index(b, d) for b, d in scene.hydro_coordinates])
        self.n = self.system.n
        self.tolerance = tolerance
        self.output_names = {MBD: list(observe.get(MBD, [])), HYDRO: list(observe.get(HYDRO, []))}
        self._positions = self._output_positions()
        self.outputs = {MBD: np.zeros(len(self.output_names[MBD])), HYDRO: np.zeros(len(self.output_names[HYDRO]))}
        self.time = 0.0
        self.force = np.zeros(len(self.rows))
        self._newton: dict[float, np.ndarray] = {}
        self.iterations: list[int] = []

    def _output_positions(self) -> dict[str, np.ndarray]:
        coords = self.system.coordinates
        n, names = self.n, {}
        for j, (b, d) in enumerate(coords):
            names[f"{b}.x[{d + 1}]"] = j
            names[f"{b}.v[{d + 1}]"] = n + j
        for k, p in enumerate(self.system.ptos):
            names[f"{p.name}.force"] = 2 * n + k
            names[f"{p.name}.power"] = 2 * n + len(self.system.ptos) + k
        hydro = {f"{b}.F[{d + 1}]": j for j, (b, d) in enumerate(self.scene.hydro_coordinates)}
        hydro["wave.elevation"] = len(self.rows)
        try:
            return {MBD: np.array([names[v] for v in self.output_names[MBD]], dtype=int),
                    HYDRO: np.array([hydro[v] for v in self.output_names[HYDRO]], dtype=int)}
        except KeyError as exc:
            raise MasterError(f"monolithic mode has no output {exc.args[0]!r}") from None

    # ------------------------------------------------------------------ stepping
    def initialize(self, start_time: float, stop_time: float | None = None, parameter_links=(),
                   parameters=None) -> None:
        self.time = start_time
        self.hydro.start_time = start_time
        self._update_outputs()

    def _hydro_force(self, t: float, z: np.ndarray) -> np.ndarray:
        n = self.n
        return self.hydro.forces(t, z[:n][self.rows], z[n:][self.rows]).total

    def _apply(self, z0: np.ndarray, h: float, force: np.ndarray) -> np.ndarray:
        n = self.n
        self.system.set_state(z0[:n], z0[n:])
        full = np.zeros(n)
        full[self.rows] = force
        self.system.step(h, full)
        return np.concatenate([self.system.q, self.system.qd])

    def _map(self, z: np.ndarray, z0: np.ndarray, t1: float, h: float) -> np.ndarray:
        return self._apply(z0, h, 0.5 * (self.force + self._hydro_force(t1, z)))

    def _newton_matrix(self, z0: np.ndarray, t1: float, h: float, g0: np.ndarray, z: np.ndarray) -> np.ndarray:
        m = len(z)
        jac = np.empty((m, m))
        for j in range(m):
            dz = np.zeros(m)
            dz[j] = 1e-6 * max(1.0, abs(z[j]))
            jac[:, j] = (self._map(z + dz, z0, t1, h) - g0) / dz[j]
        return np.linalg.inv(np.eye(m) - jac)

    def step(self, h: float, end_time: float | None = None) -> None:
        n = self.n
        t0 = self.time
        t1 = t0 + h if end_time is None else end_time
        z0 = np.concatenate([self.system.q, self.system.qd])
        self.hydro.advance(t0, h, z0[n:][self.rows].copy())
        z = z0  # Newton's start (the map is affine: one update is exact whatever the start)
        g = self._map(z, z0, t1, h)
        if h not in self._newton:
            self._newton[h] = self._newton_matrix(z0, t1, h, g, z)
        k = 0
        scale = max(1e-12, float(np.max(np.abs(g))))
        while True:
            k += 1
            z = z + self._newton[h] @ (g - z)
            force = self._hydro_force(t1, z)  # kept: the next step's F_n when z is accepted
            g = self._apply(z0, h, 0.5 * (self.force + force))
            if np.max(np.abs(g - z)) <= self.tolerance * scale:
                break
            if k >= 20:
                raise MasterError(f"monolithic: Newton iteration did not converge at t = {t0:g} s")
        self.iterations.append(k)
        self.system.set_state(z[:n], z[n:])
        self.time = t1
        self._update_outputs(force)

    def _update_outputs(self, force: np.ndarray | None = None) -> None:
        z = np.concatenate([self.system.q, self.system.qd])
        self.force = self._hydro_force(self.time, z) if force is None else force
        if not np.all(np.isfinite(z)) or not np.all(np.isfinite(self.force)):
            raise MasterError(f"monolithic: the state is not finite at t = {self.time:g} s")
        mbd = np.concatenate([z, self.system.pto_forces(), self.system.pto_powers()]) if self.system.ptos else z
        hydro = np.concatenate([self.force, [self.hydro.elevation(self.time)]])
        self.outputs = {MBD: mbd[self._positions[MBD]], HYDRO: hydro[self._positions[HYDRO]]}

    # ------------------------------------------------------------------ checkpoints
    def checkpoint(self) -> dict:
        state = state_codec.encode({"system": self.system, "hydro": self.hydro})
        return {"states": {"monolithic": state},
                "master": {"time": self.time, "force": self.force.copy(),
                           "outputs": copy.deepcopy(self.outputs),
                           # Newton matrices measured at the first step of each size: measured again at
                           # another state they differ in the last bits, and so would a resumed run
                           "newton": [[h, m.copy()] for h, m in self._newton.items()]}}

    def restore(self, checkpoint: dict) -> None:
        template = copy.deepcopy({"system": self.system, "hydro": self.hydro})
        try:
            state = state_codec.decode(checkpoint["states"]["monolithic"], template)
            self.system, self.hydro = state["system"], state["hydro"]
        except (state_codec.StateFormatError, KeyError, TypeError) as exc:
            raise WecCosimError(f"monolithic state in the checkpoint cannot be used: {exc}") from None
        m = checkpoint["master"]
        self.time, self.force, self.outputs = m["time"], m["force"].copy(), copy.deepcopy(m["outputs"])
        self._newton = {float(h): np.array(matrix, dtype=float) for h, matrix in m.get("newton", [])}

    def terminate(self) -> None:
        pass


__all__ = ["MonolithicMaster", "FixedStepController"]
