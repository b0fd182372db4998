"""Master algorithms: step co-simulation components and move data between them.

:class:`JacobiMaster` - fixed-step Jacobi (parallel) coupling.

At every communication point t_n the master *resolves* the outputs: it reads the outputs of the
components without direct feedthrough (their outputs are states, e.g. the multibody motion),
sets the inputs of the feedthrough components from them (the hydrodynamics FMU, whose force
depends on the current motion) and reads those. All components then step from t_n to t_n + h
at once, each with inputs built from data at t_n and before.

Input extrapolation. An FMI 2 co-simulation slave built with PythonFMU holds its inputs constant
over a step (it cannot take input derivatives), so the master chooses that constant. For inputs
of components without feedthrough it uses the *average over the step* of the polynomial of
degree p through the last p + 1 communication values (p = ``extrapolation``):

* p = 0: u_n (zero-order hold); the input lags by h/2: global error O(h);
* p = 1: u_n + (u_n - u_{n-1})/2;  p = 2: u_n + (u_n - u_{n-1})/2 + 5/12 (u_n - 2u_{n-1} + u_{n-2}).

For p >= 1 the step average is right to O(h^2) or better, but the input is still constant
within the step, which leaves a local error O(h^3) in the position of a second-order system:
the global error is O(h^2) for p = 1 and p = 2 (p = 2 has the smaller constant). Inputs of
feedthrough components are the exact samples at t_n (they are set during resolution).

Stability: the added-mass coupling is kept out of the exchanged force (A_inf sits in the
multibody mass matrix), so what is exchanged explicitly is stiffness (hydrostatics) and damping
(radiation memory). Their explicit treatment adds an O((omega h)^2) per-step growth that the
physical damping outweighs at the step sizes used (h <= T/20 for the fastest resolved mode).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from .components import Port
from .errors import MasterError
from .scene import Connection


def step_average_weights(tau: Sequence[float], h: float) -> np.ndarray:
    """Weights w_j with sum_j w_j u(tau_j) = (1/h) int_0^h p(s) ds for the interpolant p.

    ``tau`` are the sample times relative to the current time (0, -h1, -h1-h2, ...).
    """
    tau = np.asarray(tau, dtype=float)
    m = len(tau)
    vander = tau[:, None] ** np.arange(m)[None, :]
    moments = h ** np.arange(m) / (np.arange(m) + 1.0)
    return np.linalg.solve(vander.T, moments)


@dataclass
class _Wiring:
    """Inputs of one component and where each value comes from."""

    port: Port | None
    sources: list[tuple[str, np.ndarray, np.ndarray]]  # (source component, input positions, output positions)


class JacobiMaster:
    """Fixed-step Jacobi master with step-averaged input extrapolation (see the module docstring).

    Args:
        components: components by name (:mod:`orchestrator.components`).
        connections: output -> input links.
        extrapolation: order p in 0, 1, 2.
        observe: extra outputs to read at every communication point, per component.
    """

    def __init__(
        self,
        components: dict,
        connections: list[Connection],
        extrapolation: int = 2,
        observe: dict[str, list[str]] | None = None,
    ) -> None:
        if extrapolation not in (0, 1, 2):
            raise ValueError("extrapolation order must be 0, 1 or 2")
        self.components = components
        self.extrapolation = extrapolation
        self.order = self._evaluation_order(connections)
        # Outputs read at every point: connected ones first, then observed ones.
        names: dict[str, list[str]] = {c: [] for c in components}
        for link in connections:
            if link.source_variable not in names[link.source]:
                names[link.source].append(link.source_variable)
        for c, extra in (observe or {}).items():
            names[c] += [n for n in extra if n not in names[c]]
        self.output_names = names
        self.output_ports = {c: components[c].port(n) for c, n in names.items()}
        self.outputs = {c: np.zeros(len(n)) for c, n in names.items()}
        self.wiring = {c: self._wire(c, connections) for c in components}
        self.history: dict[str, deque] = {c: deque(maxlen=3) for c in components}
        self.time = 0.0
        self._weights_cache: dict[tuple, np.ndarray] = {}

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
                    + ": a Jacobi master cannot resolve it")
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

    # ------------------------------------------------------------------ stepping
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
        for name, values in (parameters or {}).items():
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

    def _gather(self, name: str) -> np.ndarray:
        w = self.wiring[name]
        u = np.empty(len(w.port.vrs))
        for src, pos, out in w.sources:
            u[pos] = self.outputs[src][out]
        return u

    def _resolve(self) -> None:
        """Outputs at the current time; inputs of feedthrough components set to current samples."""
        for name in self.order:
            comp = self.components[name]
            if comp.feedthrough and self.wiring[name].port is not None:
                comp.set_reals(self.wiring[name].port, self._gather(name))
            self.outputs[name] = comp.get_reals(self.output_ports[name])
            bad = ~np.isfinite(self.outputs[name])
            if bad.any():
                var = self.output_names[name][int(np.argmax(bad))]
                raise MasterError(
                    f"{name}: output {var} is not finite at t = {self.time:g} s; the coupled system "
                    "diverged or was given invalid inputs (try a smaller step, or check the scenario)")
        # Input samples at this time, complete now that every output is known.
        for name in self.order:
            if self.wiring[name].port is not None:
                self.history[name].appendleft((self.time, self._gather(name)))

    def _hold_value(self, name: str, h: float) -> np.ndarray:
        hist = self.history[name]
        p = min(self.extrapolation, len(hist) - 1)
        if p == 0:
            return hist[0][1]
        tau = tuple(round(hist[j][0] - self.time, 12) for j in range(p + 1))
        key = (tau, h)
        w = self._weights_cache.get(key)
        if w is None:
            w = step_average_weights(tau, h)
            if len(self._weights_cache) > 64:
                self._weights_cache.clear()
            self._weights_cache[key] = w
        out = w[0] * hist[0][1]
        for j in range(1, p + 1):
            out += w[j] * hist[j][1]
        return out

    def step(self, h: float, end_time: float | None = None) -> None:
        """One macro step of length ``h``; ``end_time`` (default time + h) avoids round-off drift."""
        for name in self.order:
            comp, w = self.components[name], self.wiring[name]
            if w.port is not None and not comp.feedthrough:
                comp.set_reals(w.port, self._hold_value(name, h))
        for name in self.order:
            self.components[name].do_step(self.time, h)
        self.time = self.time + h if end_time is None else end_time
        self._resolve()

    def run(self, stop_time: float, h: float, observer: Callable[[float, dict], None] | None = None) -> None:
        """Step to ``stop_time`` with macro step ``h``; ``observer(t, outputs)`` after each step."""
        n = int(round((stop_time - self.time) / h))
        t0 = self.time
        if observer is not None:
            observer(self.time, self.outputs)
        for k in range(1, n + 1):
            self.step(h, t0 + k * h)
            if observer is not None:
                observer(self.time, self.outputs)

    # ------------------------------------------------------------------ checkpoints
    def checkpoint(self) -> dict:
        """Everything needed to continue from the current time: serialised component states
        (integrator history included), the input history of the extrapolation, the outputs."""
        blobs = {}
        for name, comp in self.components.items():
            state = comp.get_state()
            blobs[name] = comp.serialize_state(state)
            comp.free_state(state)
        return {
            "time": self.time,
            "states": blobs,
            "history": {c: [(t, u.copy()) for t, u in h] for c, h in self.history.items()},
            "outputs": {c: o.copy() for c, o in self.outputs.items()},
        }

    def restore(self, checkpoint: dict) -> None:
        """Return to a :meth:`checkpoint` (same components, same connections)."""
        for name, comp in self.components.items():
            state = comp.deserialize_state(checkpoint["states"][name])
            comp.set_state(state)
            comp.free_state(state)
        self.time = checkpoint["time"]
        for c, h in checkpoint["history"].items():
            self.history[c].clear()
            self.history[c].extend((t, u.copy()) for t, u in h)
        self.outputs = {c: o.copy() for c, o in checkpoint["outputs"].items()}

    def terminate(self) -> None:
        for c in self.components.values():
            c.terminate()
