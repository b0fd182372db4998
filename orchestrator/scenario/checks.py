"""Checks of a scenario that involve several keys (names that must exist, counts that must match, settings
that exclude each other), run after the schema has converted every key."""

from __future__ import annotations

import math

from mbd_fmu.spec_checks import ModelError, direction, distance_problem, inertia_problem, universal_axes_problem
from orchestrator.errors import ScenarioError

from . import input_checks
from .body_sections import BodySection
from .scenario import Scenario


def check_scenario(s: Scenario) -> None:
    """Checks that involve several keys."""
    f = str(s.file)
    if not s.bodies:
        raise ScenarioError(f"{f}: [[bodies]] is empty; a scene needs at least one body")
    _unique(f, "bodies", [b.name for b in s.bodies])
    _unique(f, "ptos", [p.name for p in s.ptos])
    _unique(f, "bodies/ptos", [b.name for b in s.bodies] + [p.name for p in s.ptos])
    for i, b in enumerate(s.bodies):
        where = f"{f}: bodies[{i}] ({b.name})"
        if not b.dofs:
            raise ScenarioError(f"{where}: dofs is empty; give at least one degree of freedom")
        _unique(f, f"bodies[{i}].dofs", b.dofs)
        for key in ("initial_displacement", "initial_velocity"):
            if len(getattr(b, key)) != 6:
                raise ScenarioError(f"{where}: {key} needs 6 values (surge..yaw), got {len(getattr(b, key))}")
        if b.inertia is not None and len(b.inertia) not in (3, 6):
            raise ScenarioError(f"{where}: inertia needs 3 or 6 values, got {len(b.inertia)}")
        if b.inertia is not None and any(v <= 0 for v in b.inertia[:3]):
            raise ScenarioError(f"{where}: the principal moments of inertia must be positive")
        if b.inertia is not None and not b.point_mass and any(d in b.dofs for d in ("roll", "pitch", "yaw")):
            problem = inertia_problem(inertia_tensor(b.inertia))
            if problem:
                raise ScenarioError(f"{where}: inertia {list(b.inertia)}: {problem}")
        if any(d in b.dofs for d in ("roll", "pitch", "yaw")) and b.inertia is None:
            raise ScenarioError(f"{where}: rotational dofs are active but no inertia is given")
        if b.hydro and not s.hydro.database and b.geometry is None:
            raise ScenarioError(
                f"{where}: a hydrodynamic body needs a [bodies.geometry] table, or set [hydro].database, "
                "or hydro = false")
        if b.geometry is not None:
            _check_geometry(s, b, where)
        if not b.hydro and b.mass is None:
            raise ScenarioError(f"{where}: a body without hydrodynamics needs an explicit mass")
    names = {b.name: b for b in s.bodies}
    for i, p in enumerate(s.ptos):
        where = f"{f}: ptos[{i}] ({p.name})"
        if p.body not in names:
            raise ScenarioError(f"{where}: body {p.body!r} is not defined (bodies: {', '.join(names)})")
        if not (p.joint or p.point) and not p.dof:
            raise ScenarioError(f"{where}: give the dof the PTO acts on (or a joint, or point and point2)")
        if not (p.joint or p.body2 or p.point) and p.dof not in names[p.body].dofs:
            raise ScenarioError(f"{where}: dof {p.dof!r} is not active on body {p.body!r}")
        if p.nonlinear and s.formulation == "linear":
            raise ScenarioError(f"{where}: friction_force, quadratic_damping and force_limit make the PTO law "
                                "nonlinear; the 'linear' multibody formulation cannot take it: set "
                                "multibody.formulation = 'index3' (or remove the key)")
    _check_multibody(s, f, names)
    _check_waves(s)
    _check_hydro(s)
    if s.hydro.database and not s.resolve(s.hydro.database).is_file():
        raise ScenarioError(f"{f}: hydro.database: file {s.resolve(s.hydro.database)} does not exist")
    for key, g in [("hydro.omega", s.hydro.omega)] + [
            (f"hydro.omega_refine[{i}]", r) for i, r in enumerate(s.hydro.omega_refine)]:
        if g.stop <= g.start:
            raise ScenarioError(f"{f}: {key}: stop must be larger than start")
    if s.rao.omega is not None and s.rao.omega.stop < s.rao.omega.start:
        raise ScenarioError(f"{f}: rao.omega: stop must not be smaller than start")
    check_simulation(s)
    input_checks.check_limits(s)
    input_checks.check_files(s)


def _whole_steps(s: Scenario) -> None:
    """A duration that is not a whole number of steps is rounded to the nearest whole number of steps (at least
    one): the radiation memory and the masters run on whole steps, and a shortened last step would leave that grid.
    The scenario keeps a note (``_duration_note``), which the run's summary prints."""
    sim = s.simulation
    n = sim.duration / sim.step
    whole = max(1, round(n))
    if abs(n - whole) > 1e-6 * max(1.0, n):
        requested = sim.duration
        sim.duration = whole * sim.step
        s._duration_note = (
            f"simulation.duration = {requested:g} s is not a whole number of {sim.step:g} s steps: the run covers "
            f"{whole} steps, {sim.duration:.10g} s (the duration rounded to the nearest whole step)")


def check_simulation(s: Scenario) -> None:
    f = str(s.file)
    sim = s.simulation
    if sim.step > sim.duration:
        raise ScenarioError(f"{f}: simulation.step ({sim.step} s) is longer than the duration ({sim.duration} s)")
    _whole_steps(s)
    if sim.added_mass == "interface" and not sim.iterative:
        raise ScenarioError(
            f"{f}: simulation.added_mass = 'interface' solves the added-mass force within each step and needs an "
            f"iterative master; set simulation.master = 'iqn_ils' or 'aitken' (got {sim.master!r})")
    if sim.master == "monolithic" and (sim.added_mass != "mass_matrix" or sim.adaptive.enabled):
        raise ScenarioError(
            f"{f}: simulation.master = 'monolithic' steps the physics directly with A_inf in the mass matrix and a "
            "fixed step; remove simulation.added_mass and [simulation.adaptive] or choose a co-simulation master")
    if sim.master == "monolithic" and s.formulation != "linear":
        raise ScenarioError(
            f"{f}: simulation.master = 'monolithic' steps only the linear multibody model (scenes without joints, "
            f"force elements, drivers, point masses or PTOs between bodies); this scene uses the {s.formulation!r} "
            "formulation: choose a co-simulation master (e.g. 'jacobi')")
    if not sim.resolve_feedthrough and (sim.master != "jacobi" or sim.extrapolation != 0):
        raise ScenarioError(
            f"{f}: simulation.resolve_feedthrough = false is the plain zero-order-hold Jacobi of generic FMI hosts; "
            f"it needs master = 'jacobi' and extrapolation = 0 (got {sim.master!r}, {sim.extrapolation})")
    if sim.interface == "linearised" and (sim.master != "jacobi" or sim.extrapolation != 0
                                          or sim.added_mass != "mass_matrix" or sim.adaptive.enabled):
        raise ScenarioError(
            f"{f}: simulation.interface = 'linearised' hands the multibody FMU an affine force model with its own "
            f"time rate, held over the step: it needs master = 'jacobi', extrapolation = 0, the default added_mass "
            f"and a fixed step (no [simulation.adaptive]) (got {sim.master!r}, {sim.extrapolation}, "
            f"{sim.added_mass!r})")
    if sim.error_tolerance and (sim.error_estimate == "none" or sim.adaptive.enabled
                                            or s.control.mode != "off"):
        raise ScenarioError(
            f"{f}: simulation.error_tolerance chooses a fixed macro step from the run's error estimate: it needs "
            "simulation.error_estimate = 'richardson', no [simulation.adaptive] and no [control]")
    a = sim.adaptive
    if a.enabled and a.max_step < sim.step:
        raise ScenarioError(f"{f}: simulation.adaptive.max_step ({a.max_step} s) is smaller than simulation.step "
                            f"({sim.step} s), the smallest step")
    if a.safety >= 1 or a.max_growth <= 1:
        raise ScenarioError(f"{f}: simulation.adaptive needs safety < 1 and max_growth > 1 "
                            f"(got {a.safety}, {a.max_growth})")
    _check_control(s)


def _check_control(s: Scenario) -> None:
    c, f = s.control, str(s.file)
    if c.mode == "off":
        return
    from orchestrator.control.protocol import valid_run_id

    if not valid_run_id(c.run_id or s.name):
        raise ScenarioError(f"{f}: control.run_id {c.run_id or s.name!r} may hold only letters, digits, _ and -")
    period = c.period or s.simulation.step
    ratio = period / s.simulation.step
    if abs(ratio - round(ratio)) > 1e-9 * ratio or round(ratio) < 1:
        raise ScenarioError(f"{f}: control.period ({period} s) must be a whole number of macro steps "
                            f"(simulation.step = {s.simulation.step} s)")
    names = [p.name for p in s.ptos]
    for p in c.ptos:
        if p not in names:
            raise ScenarioError(f"{f}: control.ptos: PTO {p!r} is not defined (ptos: {', '.join(names) or 'none'})")
    if not names:
        raise ScenarioError(f"{f}: control is on but the scene has no PTO to drive")
    sim = s.simulation
    if sim.master == "monolithic" or sim.adaptive.enabled or sim.added_mass != "mass_matrix":
        raise ScenarioError(
            f"{f}: [control] drives the PTO inputs of the multibody FMU at a fixed period: it needs a co-simulation "
            "master (not 'monolithic'), fixed steps (no [simulation.adaptive]) and added_mass = 'mass_matrix'")
    input_checks.check_control(s)


def _check_waves(s: Scenario) -> None:
    f, w = str(s.file), s.waves
    if w.kind == "regular" and not (w.period > 0 and w.height > 0):
        raise ScenarioError(f"{f}: [waves] kind = 'regular' needs a positive height and period")
    if w.kind == "irregular":
        if w.spectrum == "file":
            if not w.spectrum_file:
                raise ScenarioError(f"{f}: [waves] spectrum = 'file' needs spectrum_file")
            if not s.resolve(w.spectrum_file).is_file():
                raise ScenarioError(f"{f}: waves.spectrum_file: file {s.resolve(w.spectrum_file)} does not exist")
        else:
            if not w.hs > 0:
                raise ScenarioError(f"{f}: [waves] kind = 'irregular' needs a positive hs")
            if not w.tp > 0 and w.spectrum != "pierson_moskowitz":
                raise ScenarioError(f"{f}: [waves] spectrum = {w.spectrum!r} needs a positive tp")
        if w.omega_max and w.omega_max <= w.omega_min:
            raise ScenarioError(f"{f}: waves.omega_max must be larger than waves.omega_min")
    if w.kind == "elevation":
        if not w.elevation_file:
            raise ScenarioError(f"{f}: [waves] kind = 'elevation' needs elevation_file")
        path = s.resolve(w.elevation_file)
        if not path.is_file():
            raise ScenarioError(f"{f}: waves.elevation_file: file {path} does not exist")
        # Any name: .h5/.hdf5 is HDF5, .mat WEC-Sim's MATLAB file, anything else a text table (the reader says which
        # form it found, or what is wrong with the file).
    if w.spreading_s > 0 and w.kind != "irregular":
        raise ScenarioError(f"{f}: waves.spreading_s applies to irregular seas only")
    if w.spreading_s > 0 and s.hydro.excitation_method == "convolution":
        raise ScenarioError(f"{f}: hydro.excitation_method = 'convolution' needs a unidirectional sea "
                            "(waves.spreading_s = 0): the elevation at one point does not determine a spread sea")


def _check_hydro(s: Scenario) -> None:
    f, h = str(s.file), s.hydro
    if (h.nonlinear_hydrostatics or h.nonlinear_froude_krylov):
        for b in s.hydro_bodies:
            if b.geometry is None:
                raise ScenarioError(
                    f"{f}: bodies[{s.bodies.index(b)}] ({b.name}): the nonlinear hydrostatic/Froude-Krylov force "
                    "integrates pressure over the hull: give a [bodies.geometry] table")
    if h.nonlinear_froude_krylov and h.excitation_method == "convolution":
        raise ScenarioError(f"{f}: hydro.nonlinear_froude_krylov needs hydro.excitation_method = 'superposition'")
    for i, b in enumerate(s.bodies):
        drag = (b.drag_coefficient, b.drag_area)
        if (drag[0] is None) != (drag[1] is None):
            raise ScenarioError(f"{f}: bodies[{i}] ({b.name}): drag_coefficient and drag_area go together")
        if any(v is not None for v in (b.linear_damping, *drag)) and not b.hydro:
            raise ScenarioError(f"{f}: bodies[{i}] ({b.name}): viscous forces belong to the hydro FMU; the body has "
                                "hydro = false")
        for key in ("linear_damping", "drag_coefficient", "drag_area"):
            values = getattr(b, key)
            if values is not None and any(v < 0 for v in values):
                raise ScenarioError(f"{f}: bodies[{i}] ({b.name}): {key} must not be negative")


def _check_multibody(s: Scenario, f: str, names: dict) -> None:
    """Joints, force elements, drivers and multibody PTOs: names, references, required keys."""
    bodies_or_ground = set(names) | {"ground"}
    _unique(f, "joints/forces/drivers/ptos/bodies",
            [b.name for b in s.bodies] + [x.name for x in s.joints + s.forces + s.drivers + s.ptos])
    joints = {j.name: j for j in s.joints}

    def body(where: str, key: str, value: str, ground: bool = True) -> None:
        allowed = bodies_or_ground if ground else set(names)
        if value not in allowed:
            raise ScenarioError(f"{where}: {key} {value!r} is not a defined body"
                                f"{' or ground' if ground else ''} (bodies: {', '.join(names)})")

    def vec(where: str, key: str, value: list, n: int = 3) -> None:
        if len(value) != n:
            raise ScenarioError(f"{where}: {key} needs {n} values (x, y, z), got {len(value)}")

    for i, j in enumerate(s.joints):
        where = f"{f}: joints[{i}] ({j.name})"
        body(where, "body1", j.body1)
        body(where, "body2", j.body2, ground=False)
        if j.body1 == j.body2:
            raise ScenarioError(f"{where}: body1 and body2 are the same body {j.body2!r}")
        if not any(j.axis):
            raise ScenarioError(f"{where}: axis must not be zero")
        if j.axis2:
            vec(where, "axis2", j.axis2)
        if j.kind == "distance":
            vec(where, "position2", j.position2)
        if j.kind == "universal" and not j.axis2:
            raise ScenarioError(f"{where}: a universal joint needs axis2 (the cross axis on body2)")
        try:  # directions of any scale; two axes of a universal joint at a right angle; a distance of two points
            direction(j.axis, "axis")
            if j.axis2:
                direction(j.axis2, "axis2")
            problem = (universal_axes_problem(j.axis, j.axis2) if j.kind == "universal"
                       else distance_problem(j.position, j.position2) if j.kind == "distance" else None)
        except ModelError as exc:
            problem = str(exc)
        if problem:
            raise ScenarioError(f"{where}: {problem}")
    for i, e in enumerate(s.forces):
        where = f"{f}: forces[{i}] ({e.name})"
        if e.kind in ("spring_damper", "rope", "bushing"):
            body(where, "body1", e.body1)
            body(where, "body2", e.body2, ground=False)
        if e.kind in ("spring_damper", "rope"):
            vec(where, "point1", e.point1)
            vec(where, "point2", e.point2)
        if e.kind in ("rotary_spring_damper", "friction") and e.joint not in joints:
            raise ScenarioError(f"{where}: joint {e.joint!r} is not defined (joints: {', '.join(joints) or 'none'})")
        if e.kind in ("bushing", "mooring"):
            if e.kind == "bushing":
                vec(where, "position", e.position)
            sizes = (6,) if e.kind == "bushing" else (6, 36)
            for key in ("stiffness_matrix", "damping_matrix"):
                value = getattr(e, key)
                if value and len(value) not in sizes:
                    raise ScenarioError(f"{where}: {key} needs {' or '.join(map(str, sizes))} values, got {len(value)}")
        if e.kind in ("mooring", "catenary"):
            body(where, "body", e.body, ground=False)
        if e.kind == "catenary":
            vec(where, "fairlead", e.fairlead)
            vec(where, "anchor", e.anchor)
            for key in ("length", "weight", "ea"):
                if getattr(e, key) <= 0:
                    raise ScenarioError(f"{where}: a catenary line needs a positive {key}")
    _check_mooring_lines(s, f)
    for i, d in enumerate(s.drivers):
        where = f"{f}: drivers[{i}] ({d.name})"
        if bool(d.joint) == bool(d.body):
            raise ScenarioError(f"{where}: give either joint or body (with dof)")
        if d.joint and d.joint not in joints:
            raise ScenarioError(f"{where}: joint {d.joint!r} is not defined")
        if d.body:
            body(where, "body", d.body, ground=False)
            if d.dof not in names[d.body].dofs:
                raise ScenarioError(f"{where}: dof {d.dof!r} is not active on body {d.body!r}")
        if d.function == "table" and (len(d.times) < 2 or len(d.times) != len(d.values)):
            raise ScenarioError(f"{where}: a table needs times and values of the same length (at least 2)")
    for i, p in enumerate(s.ptos):
        where = f"{f}: ptos[{i}] ({p.name})"
        if p.joint and p.joint not in joints:
            raise ScenarioError(f"{where}: joint {p.joint!r} is not defined (joints: {', '.join(joints) or 'none'})")
        if p.joint:
            from mbd_fmu.joints import JOINT_COORDINATE_UNITS

            kind = joints[p.joint].kind
            count = len(JOINT_COORDINATE_UNITS[kind])
            if not count:
                raise ScenarioError(f"{where}: a PTO needs a joint with a coordinate, not a {kind} joint")
            if p.joint_coordinate > count:
                raise ScenarioError(f"{where}: joint_coordinate = {p.joint_coordinate} but a {kind} joint has "
                                    f"{count} coordinate{'s' if count > 1 else ''} (1..{count})")
        if p.body2:
            body(where, "body2", p.body2)
        if p.point or p.point2:
            vec(where, "point", p.point)
            vec(where, "point2", p.point2)
        elif p.body2:
            vec(where, "position", p.position)
    if s.formulation == "linear" and s.multibody.static_equilibrium:
        raise ScenarioError(f"{f}: multibody.static_equilibrium needs a nonlinear formulation (index3, index1 or "
                            "nullspace); the linear model assumes the reference pose is the equilibrium")
    if s.formulation == "linear" and (s.joints or s.forces or s.drivers or any(b.point_mass for b in s.bodies)
                                      or any(p.joint or p.body2 or p.point for p in s.ptos)):
        raise ScenarioError(f"{f}: multibody.formulation = 'linear' supports bodies on selected DOFs with PTOs to the "
                            "ground only; use index3, index1 or nullspace for joints, forces, drivers and point masses")
    for i, b in enumerate(s.bodies):
        if b.point_mass and any(d in b.dofs for d in ("roll", "pitch", "yaw")):
            raise ScenarioError(f"{f}: bodies[{i}] ({b.name}): a point mass has no rotational dofs; "
                                "set dofs to translations only")


def _check_mooring_lines(s: Scenario, f: str) -> None:
    """MoorDyn lines: diameters, one sea bed, the axial Courant limit of MoorDyn's step."""
    m = s.mooring_lines
    if m.moordyn_file or m.coupled_bodies:
        _check_moordyn_file(s, f)
        return
    if m.model != "moordyn":
        return
    lines = [(i, e) for i, e in enumerate(s.forces) if e.kind == "catenary"]
    if not lines:
        raise ScenarioError(f"{f}: mooring_lines.model = 'moordyn' but the scene has no force of kind 'catenary'")
    depths = {round(e.anchor[2], 6) for _, e in lines}
    if len(depths) > 1:
        raise ScenarioError(f"{f}: mooring_lines.model = 'moordyn' needs every catenary anchor on one sea bed "
                            f"(anchor z: {sorted(depths)} m)")
    rho, g = s.environment.rho, s.environment.g
    for i, e in lines:
        where = f"{f}: forces[{i}] ({e.name})"
        if e.diameter <= 0:
            raise ScenarioError(f"{where}: mooring_lines.model = 'moordyn' needs the line's diameter (m)")
        if e.anchor[2] >= e.fairlead[2]:
            raise ScenarioError(f"{where}: the anchor must lie below the fairlead")
        mass = e.weight / g + rho * math.pi * e.diameter ** 2 / 4
        limit = e.length / e.segments / math.sqrt(e.ea / mass)
        if m.time_step > limit:
            raise ScenarioError(
                f"{f}: mooring_lines.time_step ({m.time_step:g} s) exceeds the axial Courant limit of line {e.name!r}, "
                f"{limit:.3g} s (segment {e.length / e.segments:.3g} m, axial wave speed {math.sqrt(e.ea / mass):.4g} "
                "m/s): MoorDyn's explicit scheme would blow up; reduce the step or the number of segments")


def inertia_tensor(values: list[float]) -> list[list[float]]:
    """The 3x3 inertia tensor (kg m^2) of a body's ``inertia`` key: [Ixx, Iyy, Izz] or [Ixx, Iyy, Izz, Ixy, Ixz,
    Iyz], the products being the tensor's off-diagonal entries."""
    ixx, iyy, izz, ixy, ixz, iyz = list(values) + [0.0] * (6 - len(values))
    return [[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]]


def _check_moordyn_file(s: Scenario, f: str) -> None:
    """A MoorDyn input file: readable and usable, one scenario body per Coupled point, rho and g as the scenario's."""
    from mbd_fmu.moordyn_files import MoorDynFileError, read_moordyn_file

    m = s.mooring_lines
    if not m.moordyn_file:
        raise ScenarioError(f"{f}: mooring_lines.coupled_bodies is set but mooring_lines.moordyn_file is not; name the "
                            "MoorDyn input file")
    if any(e.kind == "catenary" for e in s.forces):
        raise ScenarioError(f"{f}: mooring_lines.moordyn_file and forces of kind 'catenary' together: put every line "
                            "in the MoorDyn file, or remove moordyn_file to use the catenary lines")
    try:
        md = read_moordyn_file(s.resolve(m.moordyn_file))
    except MoorDynFileError as exc:
        raise ScenarioError(f"{f}: mooring_lines.moordyn_file: {exc}") from None
    points = ", ".join(f"{pid} at ({', '.join(f'{v:g}' for v in p)})" for pid, p in md.coupled)
    if len(m.coupled_bodies) != len(md.coupled):
        raise ScenarioError(
            f"{f}: mooring_lines.coupled_bodies names {len(m.coupled_bodies)} bodies but {md.path} has "
            f"{len(md.coupled)} Coupled points ({points}); give one body per point, in the order of their IDs, e.g. "
            f"coupled_bodies = {[m.coupled_bodies[0] if m.coupled_bodies else s.bodies[0].name] * len(md.coupled)}")
    names = [b.name for b in s.bodies]
    for (pid, _), body in zip(md.coupled, m.coupled_bodies, strict=True):
        if body not in names:
            raise ScenarioError(f"{f}: mooring_lines.coupled_bodies: no body {body!r} for Coupled point {pid} of "
                                f"{md.path} (bodies: {', '.join(names)})")
    for key, value, name in (("wtrdnsty", s.environment.rho, "environment.rho"), ("g", s.environment.g,
                                                                                 "environment.g")):
        if key in md.options and not math.isclose(float(md.options[key]), value, rel_tol=1e-6):
            raise ScenarioError(
                f"{f}: {md.path} sets {key} = {md.options[key]} but {name} = {value:g}; make them equal (the run "
                "uses the scenario's value for both the bodies and the lines)")
    if s.formulation == "linear":
        raise ScenarioError(f"{f}: mooring_lines.moordyn_file needs a nonlinear multibody formulation; set "
                            "multibody.formulation = 'index3'")


def _check_geometry(s: Scenario, b: BodySection, where: str) -> None:
    g = b.geometry
    needs = {"vertical_cylinder": ("radius", "draft"), "sphere": ("radius",),
             "regular_prism": ("radius", "draft")}.get(g.shape, ())
    for key in needs:
        if getattr(g, key) <= 0:
            raise ScenarioError(f"{where}: geometry shape {g.shape!r} needs a positive {key}")
    if g.shape == "axisymmetric" and (len(g.profile) < 2 or any(r < 0 for r, _ in g.profile)):
        raise ScenarioError(f"{where}: geometry shape 'axisymmetric' needs profile = [[r, z], ...] with at least two "
                            "points and r >= 0")
    if any(not 0 <= i < len(g.profile) - 1 for i in g.dry_segments):
        raise ScenarioError(f"{where}: geometry dry_segments {g.dry_segments} must be indices of profile segments "
                            f"(0 to {len(g.profile) - 2})")
    if g.shape == "regular_prism" and g.sides < 3:
        raise ScenarioError(f"{where}: geometry shape 'regular_prism' needs sides >= 3")
    if g.shape == "box" and min(g.size) <= 0:
        raise ScenarioError(f"{where}: geometry shape 'box' needs size = [length, width, height], all positive")
    if g.shape == "mesh":
        if not g.mesh_file:
            raise ScenarioError(f"{where}: geometry shape 'mesh' needs mesh_file")
        if not s.resolve(g.mesh_file).is_file():
            raise ScenarioError(f"{where}: mesh_file {s.resolve(g.mesh_file)} does not exist")


def _unique(file: str, what: str, names: list[str]) -> None:
    """Names used once, and not twice with different case: they name files (databases in the cache, FMUs) and
    variables, and on file systems that ignore case (macOS, Windows) ``float`` and ``Float`` are one file."""
    seen: dict[str, str] = {}
    for n in names:
        if n in seen.values():
            raise ScenarioError(f"{file}: {what}: name {n!r} is used twice")
        if n.casefold() in seen:
            raise ScenarioError(f"{file}: {what}: names {seen[n.casefold()]!r} and {n!r} differ only in case; they "
                                "name files and FMU variables, which some file systems and tools do not tell apart: "
                                "give names that differ in more than case")
        seen[n.casefold()] = n
