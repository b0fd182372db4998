"""Scenario files (TOML): the whole document.

One scenario file describes a scene (bodies, PTOs, waves, environment, hydrodynamics) and how
to run it. The same file drives ``wec-cosim run`` (time domain), ``wec-cosim rao`` (frequency
domain), ``wec-cosim hydro`` (database) and ``wec-cosim build-fmus``. Every key, unit and
default is in ``docs/scenario.md``, generated from this module (``python -m orchestrator.scenario``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from .body_sections import BodySection, PtoSection
from .multibody_sections import DriverSection, ForceSection, JointSection, MooringLinesSection, MultibodySection
from .run_sections import ControlSection, RaoSection, SimulationSection, SteadySection, SweepSection
from .schema import option
from .sea_sections import EnvironmentSection, HydroSection, WavesSection


@dataclass
class Scenario:
    """A scene and how to run it."""

    simulation: SimulationSection = field(metadata={"doc": "time-domain settings"})
    bodies: list[BodySection] = field(metadata={"doc": "rigid bodies"})
    name: str = option("", doc="scenario name; default the file name without extension")
    description: str = option("", doc="free text")
    environment: EnvironmentSection = field(default_factory=EnvironmentSection)
    waves: WavesSection = field(default_factory=WavesSection)
    hydro: HydroSection = field(default_factory=HydroSection)
    ptos: list[PtoSection] = field(default_factory=list, metadata={"doc": "power take-offs"})
    multibody: MultibodySection = field(default_factory=MultibodySection)
    joints: list[JointSection] = field(default_factory=list, metadata={"doc": "joints"})
    forces: list[ForceSection] = field(default_factory=list, metadata={"doc": "force elements"})
    drivers: list[DriverSection] = field(default_factory=list, metadata={"doc": "prescribed motion"})
    mooring_lines: MooringLinesSection = field(default_factory=MooringLinesSection,
                                               metadata={"doc": "mooring-line model of the `catenary` forces"})
    rao: RaoSection = field(default_factory=RaoSection)
    steady: SteadySection = field(default_factory=SteadySection, metadata={"doc": "pseudo-spectral steady state"})
    control: ControlSection = field(default_factory=ControlSection)
    sweep: SweepSection = field(default_factory=SweepSection, metadata={"doc": "sweeps and power matrices"})
    _file: Path = field(default=Path("scenario.toml"), init=False, repr=False)
    _text: str = field(default="", init=False, repr=False)
    _overrides: list[str] = field(default_factory=list, init=False, repr=False)  # `wec-cosim run --set` items
    _duration_note: str = field(default="", init=False, repr=False)  # duration rounded to whole steps (checks.py)

    @property
    def file(self) -> Path:
        return self._file

    @property
    def text(self) -> str:
        return self._text

    @property
    def folder(self) -> Path:
        return self._file.parent

    def resolve(self, relative: str) -> Path:
        """A path from the scenario file, relative to the scenario's folder."""
        p = Path(relative).expanduser()
        return p if p.is_absolute() else self.folder / p

    def body(self, name: str) -> BodySection:
        return next(b for b in self.bodies if b.name == name)

    @property
    def hydro_bodies(self) -> list[BodySection]:
        return [b for b in self.bodies if b.hydro]

    @property
    def formulation(self) -> str:
        """The multibody formulation, ``auto`` resolved."""
        f = self.multibody.formulation
        if f != "auto":
            return f
        simple = (not self.joints and not self.forces and not self.drivers and not self.mooring_lines.moordyn_file
                  and not any(b.point_mass for b in self.bodies)
                  and all(not (p.joint or p.body2 or p.point or p.nonlinear) for p in self.ptos))
        return "linear" if simple else "index3"

    @property
    def ramp_time(self) -> float:
        w = self.waves
        if w.ramp_time is not None:
            return w.ramp_time
        if w.kind == "regular":
            return 3.0 * w.period
        if w.kind == "irregular" and w.spectrum != "file":
            return 3.0 * (w.tp if w.tp > 0 else 2 * math.pi / (0.4 * math.sqrt(self.environment.g / max(w.hs, 1e-9))))
        return 0.0
