"""Master algorithms: step co-simulation components and move data between them.

Roles. A component whose outputs depend directly on its inputs (``feedthrough``, from the FMU's
``ModelStructure``; here the hydrodynamics FMU) is a *sampler*: its inputs are values at the
communication points, its step only commits them. A component without feedthrough (the multibody
FMU) *integrates*: PythonFMU slaves hold every input constant over a step (no input derivatives),
so the master chooses that constant, the step average of a polynomial of degree
``p = extrapolation`` through known input values.

Masters (all steps of length h from t_n to t_{n+1}; measured orders in ``docs/masters.md``):

* :class:`JacobiMaster` - every component steps at once with inputs built from data at t_n and
  before. Integrator inputs: step average of the polynomial through u_n, u_{n-1}, ... (an
  *extrapolation*); p = 0 is a zero-order hold (global error O(h)), p = 1 and 2 give O(h^2) (a
  constant input leaves a local O(h^3) position error in a second-order system). Explicit:
  stable while the exchanged coupling is weak (stiffness and memory damping, A_inf in the
  multibody mass matrix).
* :class:`GaussSeidelMaster` - samplers step first, then their outputs at t_{n+1} are computed
  from the integrators' outputs *predicted* at t_{n+1} (point extrapolation of degree p), and the
  integrators step with the step average of the polynomial through u_{n+1}, u_n, ... (an
  *interpolation*). Same orders as Jacobi (1 for p = 0, 2 otherwise), smaller constants.
* :class:`~orchestrator.cosim.iterative_master.IterativeMaster` - as Gauss-Seidel, but the integrators'
  outputs at t_{n+1} are iterated to consistency with rollback through
  ``fmi2GetFMUstate``/``fmi2SetFMUstate``: fixed point with Aitken's dynamic relaxation
  (``solver="aitken"``) or the interface quasi-Newton IQN-ILS
  (Degroote et al. 2009, least-squares secant model from the residual differences of the current
  and ``reuse`` previous steps; ``solver="iqn_ils"``). Converged, it is the implicit scheme whose
  integrator input is the step average of the interpolant through the consistent u_{n+1}:
  order 1 (p = 0) or 2; stable for strong coupling as long as the solver converges. Convergence test, on the
  residual r = y - x of the integrators' outputs y at t_{n+1} from the iterate x: for every interface variable i,
  |r_i| <= max(``tolerance`` S_i, ``precision``), S_i the largest magnitude reached so far (at any communication
  point or in y) by the interface variables of i's kind (the same FMU and unit: positions of every body against
  each other, velocities likewise; a fixed body's round-off is measured against the moving bodies, not against
  itself), ``precision`` the integrating FMU's own accuracy (10 times its Newton tolerance times the scene's
  length scale for the constrained formulations, none for the linear model): below it the iterates only carry
  that solver's noise. The solvers' least squares and dot products weigh each variable by 1 / S_i. Iteration
  cap ``max_iterations`` (a :class:`MasterError` beyond it).
* :class:`SimpleJacobiMaster` - the fixed-step Jacobi of generic FMI hosts (fmpy's SSP
  simulator, libcosim's fixedStep): zero-order hold, outputs read right after each step (a
  feedthrough output then uses the inputs of the previous point). Kept to check exported SSP
  files against; first order.

Added-mass handling (:class:`AddedMassForce`, the force -A_inf a on the integrators' force
inputs when A_inf is *not* in the multibody mass matrix): ``explicit`` uses the previous step's
mean acceleration (mode b: unstable whenever A_inf exceeds the structural mass, at any step);
``interface`` uses the current step's mean acceleration (v_{n+1} - v_n)/h of the iterate (mode
c, iterative masters only). In interface mode the step is solved by Newton's method on the
interface, whose Jacobian is assembled from the known -A_inf/h (exact) and the components'
sensitivities measured by finite differences through rollback (interface-Jacobian coupling,
Sicklinger et al. 2014); for linear components one Newton update per step is exact.

Step sizes come from a controller (:mod:`orchestrator.cosim.step_control`): fixed, or energy-based
adaptive (the ECCO idea).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from orchestrator.errors import MasterError
from orchestrator.fmi.components import Port
from orchestrator.scene import Connection

from .step_control import Bond, EnergyStepController, FixedStepController, StepController

__all__ = ["Bond", "EnergyStepController", "FixedStepController", "StepController"]


def step_average_weights(tau: Sequence[float], h: float) -> np.ndarray:
    """Weights w_j with sum_j w_j u(tau_j) = (1/h) int_0^h p(s) ds for the interpolant p.

    ``tau`` are the sample times relative to the current time (0, -h1, -h1-h2, ... for an
    extrapolation; h, 0, -h1, ... for an interpolation over the step).
    """
    tau = np.asarray(tau, dtype=float)
    m = len(tau)
    vander = tau[:, None] ** np.arange(m)[None, :]
    moments = h ** np.arange(m) / (np.arange(m) + 1.0)
    return np.linalg.solve(vander.T, moments)


def point_weights(tau: Sequence[float], s: float) -> np.ndarray:
    """Weights w_j with sum_j w_j u(tau_j) = p(s) for the interpolant p through (tau_j, u_j)."""
    tau = np.asarray(tau, dtype=float)
    m = len(tau)
    vander = tau[:, None] ** np.arange(m)[None, :]
    return np.linalg.solve(vander.T, s ** np.arange(m))


@dataclass
class MasterSettings:
    """How a master steps (see the module docstring)."""

    extrapolation: int = 2
    tolerance: float = 1e-10
    max_iterations: int = 50
    relaxation: float = 0.5
    reuse: int = 4
    divergence_limit: float = 1e8
    energy_scale: float = 1.0  # J: the scene's own energy scale (weight of its bodies times a length)
    precision: float = 0.0  # iterative masters: absolute accuracy of the integrating FMU's outputs (its solver's)


@dataclass
class AddedMassForce:
    """-A_inf a added to the integrators' force inputs (added-mass modes b and c).

    Attributes:
        matrix: A_inf (m, m) on the listed coordinates.
        force_inputs: (component, input name) of each coordinate's force.
        velocity_outputs: (component, output name) of each coordinate's velocity.
        mode: ``explicit`` (previous step's acceleration) or ``interface`` (this step's, solved).
    """

    matrix: np.ndarray
    force_inputs: list[tuple[str, str]]
    velocity_outputs: list[tuple[str, str]]
    mode: str = "explicit"


@dataclass
class _Wiring:
    """Inputs of one component and where each value comes from."""

    port: Port | None
    sources: list[tuple[str, np.ndarray, np.ndarray]]  # (source component, input positions, output positions)

    def __post_init__(self) -> None:
        # One source feeding every input in order (the usual wiring): the inputs are one take of its outputs.
        self.direct = (len(self.sources) == 1 and self.port is not None
                       and np.array_equal(self.sources[0][1], np.arange(len(self.port.vrs))))


@dataclass
class _StepRecord:
    """What the step controller needs after a step: integrator inputs used, end-point data."""

    h: float = 0.0
    inputs: dict[str, np.ndarray] = field(default_factory=dict)


class Master:
    """Common machinery: roles, wiring, resolution at a point, histories, checkpoints."""

    name = "master"
    predicts = False  # keeps the integrators' output history (predictions, explicit added mass)
    iterates = False  # keeps each interface variable's running maximum (convergence scale)

    def __init__(
        self,
        components: dict,
        connections: list[Connection],
        extrapolation: int = 2,
        observe: dict[str, list[str]] | None = None,
        *,
        settings: MasterSettings | None = None,
        added_mass: AddedMassForce | None = None,
        parameters: dict[str, dict[str, float]] | None = None,
    ) -> None:
        self.settings = settings or MasterSettings(extrapolation=extrapolation)
        self.initial_parameters = parameters or {}  # set at every initialisation (before ``initialize``'s own)
        if self.settings.extrapolation not in (0, 1, 2):
            raise ValueError("extrapolation order must be 0, 1 or 2")
        self.extrapolation = self.settings.extrapolation
        self.components = components
        self.connections = list(connections)
        self.order = self._evaluation_order(connections)
        self.samplers = [c for c in self.order if components[c].feedthrough]
        self.integrators = [c for c in self.order if not components[c].feedthrough]
        names: dict[str, list[str]] = {c: [] for c in components}
        for link in connections:
            if link.source_variable not in names[link.source]:
                names[link.source].append(link.source_variable)
        self.n_connected = {c: len(n) for c, n in names.items()}
        if added_mass is not None:
            for comp, var in added_mass.velocity_outputs:
                if var not in names[comp]:
                    names[comp].append(var)
                    self.n_connected[comp] += 1
        for c, extra in (observe or {}).items():
            names[c] += [n for n in extra if n not in names[c]]
        self.output_names = names
        self.output_ports = {c: components[c].port(n) for c, n in names.items()}
        self.outputs = {c: np.zeros(len(n)) for c, n in names.items()}
        self.wiring = {c: self._wire(c, connections) for c in components}
        self.history: dict[str, deque] = {c: deque(maxlen=3) for c in components}  # input samples
        self.output_history: deque = deque(maxlen=3)  # (t, {integrator: outputs})
        self.time = 0.0
        self.added_mass = self._prepare_added_mass(added_mass)
        self.last_step = _StepRecord()
        self.iterations: list[int] = []
        self._scale: dict[str, np.ndarray] = {}
        self._weights_cache: dict[tuple, np.ndarray] = {}
        self._weights_seen: dict[tuple, np.ndarray] = {}  # exact key -> the rounded key's weights
        self._divergence_limits: dict[str, np.ndarray] = {}  # per component, from its first outputs (_limits)
        self._inverse_limits: dict[str, np.ndarray] = {}  # their inverses (Master._read)

    # ------------------------------------------------------------------ set-up
    def _evaluation_order(self, connections: list[Connection]) -> list[str]:
        """Components without feedthrough first, then feedthrough ones in dependency order."""
        comps = self.components
        ordered = [c for c in comps if not comps[c].feedthrough]
        pending = [c for c in comps if comps[c].feedthrough]
        while pending:
            ready = [c for c in pending
                     if all(link.source in ordered for link in connections if link.target == c)]
            if not ready:
                raise MasterError(
                    "algebraic loop between feedthrough components " + ", ".join(pending)
                    + ": no master here can resolve it")
            ordered += ready
            pending = [c for c in pending if c not in ready]
        return ordered

    def _wire(self, name: str, connections: list[Connection]) -> _Wiring:
        links = [link for link in connections if link.target == name]
        if not links:
            return _Wiring(None, [])
        port = self.components[name].port([link.target_variable for link in links])
        sources = []
        for src in dict.fromkeys(link.source for link in links):
            pos = [i for i, link in enumerate(links) if link.source == src]
            out = [self.output_names[src].index(links[i].source_variable) for i in pos]
            sources.append((src, np.array(pos), np.array(out)))
        return _Wiring(port, sources)

    def _prepare_added_mass(self, am: AddedMassForce | None) -> dict | None:
        if am is None:
            return None
        if am.mode == "interface" and not self.iterates:
            raise MasterError("the interface added-mass mode is solved within each step: it needs an iterative "
                              "master (aitken or iqn_ils)")
        comps = {c for c, _ in am.force_inputs}
        if len(comps) != 1 or comps != {c for c, _ in am.velocity_outputs}:
            raise MasterError("the added-mass force must act on the inputs of one integrating component")
        comp = comps.pop()
        port = self.wiring[comp].port
        inputs = [port.names.index(v) for _, v in am.force_inputs]
        outputs = [self.output_names[comp].index(v) for _, v in am.velocity_outputs]
        return {"component": comp, "matrix": np.asarray(am.matrix, dtype=float), "inputs": np.array(inputs),
                "outputs": np.array(outputs), "mode": am.mode}

    # ------------------------------------------------------------------ initialisation
    def initialize(
        self,
        start_time: float,
        stop_time: float | None = None,
        parameter_links: list[Connection] = (),
        parameters: dict[str, dict[str, float]] | None = None,
    ) -> None:
        """Initialise every component, copy calculated parameters, resolve outputs at t0."""
        self.time = start_time
        for c in self.components.values():
            c.setup(start_time, stop_time)
        merged = {c: dict(v) for c, v in self.initial_parameters.items()}
        for name, values in (parameters or {}).items():
            merged.setdefault(name, {}).update(values)
        for name, values in merged.items():
            comp = self.components[name]
            comp.set_reals(comp.port(list(values)), np.array(list(values.values()), dtype=float))
        for c in self.components.values():
            c.enter_initialization()
        for src, dst in {(link.source, link.target) for link in parameter_links}:
            links = [link for link in parameter_links if (link.source, link.target) == (src, dst)]
            values = self.components[src].get_reals(self.components[src].port([lk.source_variable for lk in links]))
            self.components[dst].set_reals(self.components[dst].port([lk.target_variable for lk in links]), values)
        for c in self.components.values():
            c.exit_initialization()
        self._resolve()

    # ------------------------------------------------------------------ data movement
    def _gather(self, name: str, outputs: dict[str, np.ndarray]) -> np.ndarray:
        w = self.wiring[name]
        if w.direct:
            src, _, out = w.sources[0]
            return outputs[src].take(out)
        u = np.empty(len(w.port.vrs))
        for src, pos, out in w.sources:
            u[pos] = outputs[src][out]
        return u

    def _limits(self, name: str, values: np.ndarray) -> np.ndarray:
        """Divergence limit of each output of ``name``, relative to the scene's own scales: ``divergence_limit``
        times the larger of 1 and the output's first value (static loads, large bodies), and for energies
        (``energy.*``) also the scene's energy scale (``energy_scale``: energies start at zero)."""
        limits = self._divergence_limits
        if name not in limits:
            scale = np.maximum(1.0, np.where(np.isfinite(values), np.abs(values), 1.0))
            energy = np.array([v.startswith("energy.") for v in self.output_names[name]], dtype=bool)
            if energy.any():
                scale[energy] = max(float(scale[energy].max()), self.settings.energy_scale)
            limits[name] = self.settings.divergence_limit * scale
        return limits[name]

    def _read(self, name: str) -> np.ndarray:
        values = self.components[name].get_reals(self.output_ports[name])
        inverse = self._inverse_limits.get(name)
        if inverse is None:
            inverse = self._inverse_limits[name] = 1.0 / self._limits(name, values)
        # The sum of |value| / limit is at most 1 only if every value is within its limit (the terms are >= 0);
        # NaN and infinities make it NaN or infinite (comparison false). One dot product per read; the test
        # value by value runs only when the sum says it may fail.
        if not np.dot(np.abs(values), inverse) <= 1.0:
            limit = self._divergence_limits[name]
            bad = ~(np.abs(values) <= limit)
            if not bad.any():
                return values
            k = int(np.argmax(bad))
            var = self.output_names[name][k]
            what = "is not finite" if not np.isfinite(values[k]) else (
                f"exceeds {limit[k]:g} in magnitude (divergence_limit times its scale in this scene)")
            raise MasterError(
                f"{name}: output {var} {what} at t = {self.time:g} s; the coupled system diverged or was "
                "given invalid inputs (try a smaller step, or check the scenario)")
        return values

    def _evaluate_samplers(self, outputs: dict[str, np.ndarray]) -> None:
        """Set the samplers' inputs from ``outputs`` and read their outputs into it."""
        for name in self.samplers:
            if self.wiring[name].port is not None:
                self.components[name].set_reals(self.wiring[name].port, self._gather(name, outputs))
            outputs[name] = self._read(name)

    def _resolve(self) -> None:
        """Outputs at the current time; inputs of feedthrough components set to current samples."""
        for name in self.integrators:
            self.outputs[name] = self._read(name)
        self._evaluate_samplers(self.outputs)
        for name in self.integrators:
            if self.wiring[name].port is not None:
                self.history[name].appendleft((self.time, self._gather(name, self.outputs)))
        if self.predicts or self.added_mass is not None:
            self.output_history.appendleft((self.time, {c: self.outputs[c].copy() for c in self.integrators}))
        if self.iterates:
            for c in self.integrators:
                scale = np.abs(self.outputs[c][: self.n_connected[c]])
                self._scale[c] = np.maximum(self._scale.get(c, scale), scale)

    def _weights(self, tau: tuple[float, ...], h: float, point: float | None = None) -> np.ndarray:
        """Cached: with fixed steps the same few weight vectors serve the whole run.

        The weights are computed from the rounded key itself, never from the first unrounded
        times that produced it: the cache is then a pure function of its key, so a run resumed
        from a checkpoint (empty cache) uses bit for bit the weights of an uninterrupted run."""
        w = self._weights_seen.get((tau, h, point))  # the exact times: a handful of round-off variants per run
        if w is not None:
            return w
        key = (tuple([round(x, 12) for x in tau]), round(h, 12), point)
        w = self._weights_cache.get(key)
        if w is None:
            tau_k, h_k = key[0], key[1]
            w = step_average_weights(tau_k, h_k) if point is None else point_weights(tau_k, point)
            if len(self._weights_cache) > 256:
                self._weights_cache.clear()
            self._weights_cache[key] = w
        if len(self._weights_seen) > 1024:
            self._weights_seen.clear()
        self._weights_seen[(tau, h, point)] = w
        return w

    def _extrapolated_input(self, name: str, h: float) -> np.ndarray:
        """Step average over [t_n, t_n + h] of the polynomial through the last p + 1 input samples."""
        hist = self.history[name]
        p = min(self.extrapolation, len(hist) - 1)
        if p == 0:
            return hist[0][1].copy()
        now = self.time
        samples = [hist[j] for j in range(p + 1)]
        w = self._weights(tuple([t - now for t, _ in samples]), h)
        return np.dot(w, [u for _, u in samples])

    def _interpolated_input(self, name: str, h: float, u_next: np.ndarray) -> np.ndarray:
        """Step average of the polynomial through u_{n+1} (given) and the last p input samples."""
        hist = self.history[name]
        p = min(self.extrapolation, len(hist))
        if p == 0:
            return u_next.copy()
        tau = (h,) + tuple(hist[j][0] - self.time for j in range(p))
        w = self._weights(tau, h)
        return w[0] * u_next + sum(w[j + 1] * hist[j][1] for j in range(p))

    def _predicted_outputs(self, h: float) -> dict[str, np.ndarray]:
        """Integrators' outputs at t_n + h by point extrapolation of degree p (p = 0: hold)."""
        hist = self.output_history
        p = min(self.extrapolation, len(hist) - 1)
        if p == 0:
            return {c: v.copy() for c, v in hist[0][1].items()}
        w = self._weights(tuple(hist[j][0] - self.time for j in range(p + 1)), h, point=h)
        return {c: sum(w[j] * hist[j][1][c] for j in range(p + 1)) for c in self.integrators}

    def _apply_added_mass(self, name: str, u: np.ndarray, h: float, y_next: dict | None) -> np.ndarray:
        am = self.added_mass
        if am is None or am["component"] != name:
            return u
        v_now = self.outputs[name][am["outputs"]]
        if am["mode"] == "explicit":
            if len(self.output_history) < 2:
                return u
            (t0, y0), (t1, y1) = self.output_history[0], self.output_history[1]
            accel = (y0[name][am["outputs"]] - y1[name][am["outputs"]]) / (t0 - t1)
        else:
            accel = (y_next[name][am["outputs"]] - v_now) / h
        u = u.copy()
        u[am["inputs"]] -= am["matrix"] @ accel
        return u

    def _set_integrator_inputs(self, name: str, u: np.ndarray) -> None:
        self.components[name].set_reals(self.wiring[name].port, u)
        self.last_step.inputs[name] = u

    # ------------------------------------------------------------------ stepping
    def step(self, h: float, end_time: float | None = None) -> None:  # pragma: no cover - abstract
        raise NotImplementedError

    def _finish_step(self, h: float, end_time: float | None) -> None:
        self.last_step.h = h
        self.time = self.time + h if end_time is None else end_time
        self._resolve()

    def run(
        self,
        stop_time: float,
        h: float,
        observer: Callable[[float, dict], None] | None = None,
        controller: StepController | None = None,
        observe_start: bool = True,
    ) -> None:
        """Step to ``stop_time`` with macro step ``h`` (or the ``controller``'s steps);
        ``observer(t, outputs)`` after each step and, with ``observe_start``, at the start."""
        if controller is None:
            controller = FixedStepController(h, self.time)
        if observer is not None and observe_start:
            observer(self.time, self.outputs)
        if controller.steps == 0:
            controller.begin(self)
        while controller.remaining(self.time, stop_time):
            h_k, t_end = controller.next_step(self.time, stop_time)
            self.step(h_k, t_end)
            controller.accept(self)
            if observer is not None:
                observer(self.time, self.outputs)

    # ------------------------------------------------------------------ checkpoints
    def _state(self) -> dict:
        return {
            "time": self.time,
            "history": {c: [(t, u.copy()) for t, u in h] for c, h in self.history.items()},
            "output_history": [(t, {c: v.copy() for c, v in y.items()}) for t, y in self.output_history],
            "outputs": {c: o.copy() for c, o in self.outputs.items()},
            "scale": {c: s.copy() for c, s in self._scale.items()},
        }

    def _set_state(self, state: dict) -> None:
        self.time = state["time"]
        for c, h in state["history"].items():
            self.history[c].clear()
            self.history[c].extend((t, u.copy()) for t, u in h)
        self.output_history.clear()
        self.output_history.extend((t, {c: v.copy() for c, v in y.items()}) for t, y in state["output_history"])
        self.outputs = {c: o.copy() for c, o in state["outputs"].items()}
        self._scale = {c: s.copy() for c, s in state["scale"].items()}

    def checkpoint(self) -> dict:
        """Everything needed to continue from the current time: serialised component states
        (integrator history included), the master's histories and solver memory, the outputs."""
        blobs = {}
        for name, comp in self.components.items():
            state = comp.get_state()
            blobs[name] = comp.serialize_state(state)
            comp.free_state(state)
        return {"states": blobs, "master": self._state()}

    def restore(self, checkpoint: dict) -> None:
        """Return to a :meth:`checkpoint` (same components, same connections)."""
        for name, comp in self.components.items():
            state = comp.deserialize_state(checkpoint["states"][name])
            comp.set_state(state)
            comp.free_state(state)
        self._set_state(checkpoint["master"])

    def terminate(self) -> None:
        for c in self.components.values():
            c.terminate()


class JacobiMaster(Master):
    """Fixed-step Jacobi with step-averaged input extrapolation (module docstring)."""

    name = "jacobi"

    def step(self, h: float, end_time: float | None = None) -> None:
        """One macro step of length ``h``; ``end_time`` (default time + h) avoids round-off drift."""
        for name in self.integrators:
            if self.wiring[name].port is not None:
                u = self._apply_added_mass(name, self._extrapolated_input(name, h), h, None)
                self._set_integrator_inputs(name, u)
        t = self.time
        for name in self.order:
            self.components[name].do_step(t, h)
        self._finish_step(h, end_time)


class GaussSeidelMaster(Master):
    """Samplers first, integrators after them with interpolated inputs (module docstring)."""

    name = "gauss_seidel"
    predicts = True

    def step(self, h: float, end_time: float | None = None) -> None:
        t = self.time
        for name in self.samplers:
            self.components[name].do_step(t, h)
        predicted = self._predicted_outputs(h)
        self._step_integrators(h, predicted)
        self._finish_step(h, end_time)

    def _step_integrators(self, h: float, y_next: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """Evaluate the samplers at t_{n+1} with the integrators' outputs ``y_next``, step the
        integrators from t_n with the interpolated inputs; return their new outputs."""
        outputs = {c: self.outputs[c].copy() for c in self.components}
        for c in self.integrators:
            outputs[c][: len(y_next[c])] = y_next[c]
        self._evaluate_samplers(outputs)
        new = {}
        for name in self.integrators:
            if self.wiring[name].port is not None:
                u = self._interpolated_input(name, h, self._gather(name, outputs))
                self._set_integrator_inputs(name, self._apply_added_mass(name, u, h, y_next))
            self.components[name].do_step(self.time, h)
            new[name] = self._read(name)
        return new


class SimpleJacobiMaster(Master):
    """The fixed-step Jacobi of generic FMI hosts (fmpy's SSP simulator, libcosim fixedStep):
    every input is the source's output as read right after the previous step (zero-order hold,
    feedthrough outputs not re-evaluated with the new inputs). First order; for checking exported
    SSP files against other hosts."""

    name = "simple_jacobi"

    def _resolve(self) -> None:
        for name in self.order:
            self.outputs[name] = self._read(name)

    def step(self, h: float, end_time: float | None = None) -> None:
        for name in self.order:
            if self.wiring[name].port is not None:
                u = self._gather(name, self.outputs)
                self.components[name].set_reals(self.wiring[name].port, u)
                self.last_step.inputs[name] = u
        t = self.time
        for name in self.order:
            self.components[name].do_step(t, h)
        self.last_step.h = h
        self.time = self.time + h if end_time is None else end_time
        self._resolve()
