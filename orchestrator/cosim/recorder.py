"""The recorded series of a run: the master's output vectors mapped onto rows of the results file, and the
wave-to-wire energy account read back from those series."""

from __future__ import annotations

import numpy as np

from orchestrator.results.energy import wave_balance
from orchestrator.results.results_file import row_layout
from orchestrator.scenario import DOFS
from orchestrator.scene import HYDRO, MBD, Scene

from .masters import Master
from .monolithic import MonolithicMaster


class Recorder:
    """Maps the master's output vectors onto rows of the results file."""

    def __init__(self, scene: Scene, master: Master | MonolithicMaster) -> None:
        self.plan: list[tuple[str, str, np.ndarray, np.ndarray | None]] = []
        self.series: dict[str, tuple[int, ...]] = {"time": ()}
        names = master.output_names
        for b in scene.scenario.bodies:
            dofs = [DOFS.index(d) for d in b.dofs]
            for key, var, comp in (("displacement", "x", MBD), ("velocity", "v", MBD), ("hydro_force", "F", HYDRO)):
                if comp == HYDRO and not b.hydro:
                    continue
                out = [names[comp].index(f"{b.name}.{var}[{d + 1}]") for d in dofs]
                self._add(f"bodies/{b.name}/{key}", (6,), comp, out, dofs)
        for p in scene.scenario.ptos:
            self._add(f"ptos/{p.name}/force", (), MBD, [names[MBD].index(f"{p.name}.force")], None)
            self._add(f"ptos/{p.name}/power", (), MBD, [names[MBD].index(f"{p.name}.power")], None)
        self._add("wave/elevation", (), HYDRO, [names[HYDRO].index("wave.elevation")], None)
        for path, variables in self.multibody_series(scene).items():
            out = [names[MBD].index(v) for v in variables]
            self._add(path, () if path.startswith(("energy/", "mbd/")) else (len(out),), MBD, out, None)
        for path, variable in self.hydro_energy_series(scene).items():
            self._add(path, (), HYDRO, [names[HYDRO].index(variable)], None)
        self.wave_balance = bool(self.hydro_energy_series(scene))
        if self.wave_balance:
            self.series["energy/wave_balance"] = ()
        # One gather per component from its output vector into the flat row (results.row_layout)
        layout = row_layout(self.series)
        self.width = max(c.stop for c, _ in layout.values())
        gather: dict[str, tuple[list[int], list[int]]] = {}
        for name, comp, out, cols in self.plan:
            start = layout[name][0].start
            src, dest = gather.setdefault(comp, ([], []))
            src += out.tolist()
            dest += [start + k for k in (range(len(out)) if cols is None else cols.tolist())]
        self._gather = {c: (np.array(s, dtype=np.intp), np.array(d, dtype=np.intp)) for c, (s, d) in gather.items()}
        self._energy = {name: layout[name][0].start for name in layout if name.startswith("energy/")}
        self._balance = self._wave_balance_weights() if self.wave_balance else None
        written = {0}.union(*(d for _, d in gather.values()), [self._balance[0]] if self._balance else [])
        self._unwritten = np.array([k for k in range(self.width) if k not in written], dtype=np.intp)  # zeros

    def _wave_balance_weights(self) -> tuple[int, np.ndarray, np.ndarray]:
        """(column, term columns, weights): :func:`wave_balance` is a linear combination of the energy terms,
        so its weights are its values on unit rows; one dot product per row then evaluates it."""
        names = list(self._energy)
        weights = np.array([wave_balance({n: float(n == m) for n in names}) for m in names])
        used = np.flatnonzero(weights)
        columns = np.array([self._energy[names[k]] for k in used], dtype=np.intp)
        return self._energy["energy/wave_balance"], columns, weights[used]

    @staticmethod
    def multibody_series(scene: Scene) -> dict[str, list[str]]:
        """Results path -> multibody FMU outputs for the nonlinear formulations: per joint its coordinates,
        rates and reaction (force on body 2 from body 1 and moment about the joint point, world frame),
        each mooring line's fairlead force on its body, the energy account and the constraint violation."""
        s = scene.scenario
        if s.formulation == "linear":
            return {}
        from mbd_fmu.joints import JOINT_COORDINATE_UNITS

        out: dict[str, list[str]] = {}
        for j in s.joints:
            k = len(JOINT_COORDINATE_UNITS[j.kind])
            if k:
                out[f"joints/{j.name}/coordinate"] = [f"{j.name}.coordinate[{i + 1}]" for i in range(k)]
                out[f"joints/{j.name}/rate"] = [f"{j.name}.rate[{i + 1}]" for i in range(k)]
            out[f"joints/{j.name}/force"] = [f"{j.name}.force[{i + 1}]" for i in range(3)]
            out[f"joints/{j.name}/moment"] = [f"{j.name}.moment[{i + 1}]" for i in range(3)]
        for e in s.forces:
            if e.kind == "catenary":  # mooring lines: fairlead force on the body (world frame)
                out[f"forces/{e.name}/force"] = [f"{e.name}.force[{i + 1}]" for i in range(3)]
        from orchestrator.scene.moordyn_file import results_series

        out.update(results_series(s))  # a MoorDyn input file: coupled point forces, every line's end tensions
        for key in ("kinetic", "potential", "dissipated", "external_work", "pto", "balance"):
            out[f"energy/{key}"] = [f"energy.{key}"]
        out["mbd/constraint_violation"] = ["mbd.constraint_violation"]
        return out

    @staticmethod
    def hydro_energy_series(scene: Scene) -> dict[str, str]:
        """Results path -> hydro FMU output of the work of each hydrodynamic force component (nonlinear
        formulations, whose multibody FMU keeps the rest of the energy account)."""
        if scene.scenario.formulation == "linear":
            return {}
        from hydro_fmu.work import COMPONENTS

        return {f"energy/{c}": f"energy.{c}" for c in COMPONENTS}

    def _add(self, name: str, shape: tuple[int, ...], comp: str, out: list[int], cols: list[int] | None) -> None:
        self.series[name] = shape
        self.plan.append((name, comp, np.array(out), None if cols is None else np.array(cols)))

    @staticmethod
    def observed(scene: Scene) -> dict[str, list[str]]:
        """Outputs the master must read at each point for the results file."""
        mbd = [f"{b.name}.{v}[{DOFS.index(d) + 1}]" for b in scene.scenario.bodies for v in ("x", "v") for d in b.dofs]
        mbd += [f"{p.name}.{k}" for p in scene.scenario.ptos for k in ("force", "power")]
        mbd += [v for variables in Recorder.multibody_series(scene).values() for v in variables]
        hydro = [f"{b.name}.F[{DOFS.index(d) + 1}]" for b in scene.scenario.hydro_bodies for d in b.dofs]
        hydro += list(Recorder.hydro_energy_series(scene).values())
        return {MBD: mbd, HYDRO: hydro + ["wave.elevation"]}

    def values(self, t: float, outputs: dict[str, np.ndarray], out: np.ndarray | None = None) -> np.ndarray:
        """The recorded series of one point as one flat row (:func:`~orchestrator.results.results_file.row_layout` of
        :attr:`series`; DOFs a body does not have are zero), written into the first :attr:`width` columns of
        ``out`` if given (e.g. :meth:`~orchestrator.results.results_file.ResultsWriter.next_line`)."""
        if out is None:
            row = np.zeros(self.width)
        else:
            row = out[: self.width]
            if self._unwritten.size:
                row[self._unwritten] = 0.0
        row[0] = t
        for comp, (src, dest) in self._gather.items():
            row[dest] = outputs[comp][src]
        if self._balance is not None:
            column, terms, weights = self._balance
            row[column] = weights @ row[terms]
        return row
