"""The scene's hydrodynamic database: read (BEMIO file) or computed (Capytaine, cached), matched to the
scenario's bodies, environment and wave range, its A_inf fitted when asked (Ogilvie, Kramers-Kronig)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from hydro_fmu.bem import BemBody, BemSettings, BodyGeometry, cached_database, frequency_grid, merged_grid
from hydro_fmu.bemio import read_bemio
from hydro_fmu.hdb import HydroDatabase, HydroDatabaseError
from orchestrator.errors import ScenarioError
from orchestrator.progress import BemProgress
from orchestrator.scenario import DOFS, Scenario
from orchestrator.scenario.body_sections import BodySection

from .fit_cache import cached_fit


def bem_inputs(scenario: Scenario) -> tuple[list[BemBody], BemSettings]:
    """Capytaine inputs of the scenario's hydrodynamic bodies."""
    bodies = []
    for b in scenario.hydro_bodies:
        g = b.geometry
        mesh_file = str(scenario.resolve(g.mesh_file)) if g.shape == "mesh" else ""
        geometry = BodyGeometry(shape=g.shape, radius=g.radius, draft=g.draft, size=tuple(g.size),
                                mesh_file=mesh_file, position=tuple(g.position), panel_size=g.panel_size,
                                lid=g.lid, rotation_deg=tuple(g.rotation_deg), profile=tuple(map(tuple, g.profile)),
                                dry_segments=tuple(g.dry_segments), sides=g.sides)
        bodies.append(BemBody(b.name, geometry, tuple(b.cg)))
    h, env = scenario.hydro, scenario.environment
    settings = BemSettings(
        omega=merged_grid(*(frequency_grid(g.start, g.stop, g.step) for g in [h.omega, *h.omega_refine])),
        headings_deg=tuple(h.headings_deg),
        rho=env.rho, g=env.g, water_depth=env.water_depth, method=h.bem_method,
        symmetry=h.bem_symmetry,
    )
    return bodies, settings


def load_database(scenario: Scenario, *, refresh: bool = False, log=print,
                  progress: bool = False) -> tuple[HydroDatabase, Path]:
    """The scenario's database (file named in the scenario, or Capytaine through the cache).

    A Capytaine solve is announced in ``log`` and, with ``progress``, shown frequency by frequency
    on standard error (:class:`BemProgress`)."""
    if not scenario.hydro_bodies:
        raise ScenarioError(f"{scenario.file}: no body has hydrodynamics")
    if scenario.hydro.database:
        path = scenario.resolve(scenario.hydro.database)
        hdb = read_bemio(path)
    else:
        bodies, settings = bem_inputs(scenario)
        cache = scenario.resolve(scenario.hydro.cache_dir)
        shown = BemProgress(len(settings.headings_deg), log=log, enabled=progress)
        try:
            hdb, path, computed = cached_database(bodies, settings, cache, refresh=refresh, progress=shown,
                                                  log=(lambda m: log(f"warning: {m}")) if log is not None else None)
        finally:
            shown.close()
        if log is not None:
            log(f"computed hydrodynamic database {path} in {shown.elapsed:.0f} s" if computed
                else f"cached hydrodynamic database {path}")
    sub = _match_bodies(scenario, hdb)
    sub = _about_centres_of_gravity(scenario, sub, log)
    _check_parts(scenario, sub)
    _check_coefficients(scenario, sub)
    if scenario.hydro.added_mass_inf == "ogilvie":
        sub = _ogilvie(scenario, sub, log)
    elif scenario.hydro.added_mass_inf == "kramers_kronig":
        sub = _kramers_kronig(scenario, sub, log)
    return sub, path


TAIL_CORRECTION = "damping_tail_correction"  # HydroDatabase.extra key: (nodes, values) of the fitted tail


def _kramers_kronig(scenario: Scenario, hdb: HydroDatabase, log) -> HydroDatabase:
    """The database with A_inf and a correction of B's continuation fitted to its A(omega)
    (:func:`hydro_fmu.radiation.kramers_kronig_tail`) on the degrees of freedom the scene uses (the continued B
    is made positive semi-definite on them together); the correction, zero on the other DOFs, is kept in
    ``extra``."""
    import dataclasses

    from hydro_fmu import radiation
    from hydro_fmu.radiation import KramersKronigTail, kramers_kronig_tail

    h = scenario.hydro
    index = np.array(_scene_dofs(scenario))
    block = np.ix_(index, index)
    inputs = {"omega": hdb.omega, "added_mass": hdb.added_mass[:, index][:, :, index],
              "damping": hdb.radiation_damping[:, index][:, :, index], "duration": h.irf_duration,
              "d_omega": h.irf_d_omega, "tail_exponent": h.damping_tail}

    def fit_now() -> dict:
        fit = kramers_kronig_tail(inputs["omega"], inputs["added_mass"], inputs["damping"], h.irf_duration,
                                  d_omega=h.irf_d_omega, tail_exponent=h.damping_tail)
        return dataclasses.asdict(fit)

    stored = cached_fit("kramers_kronig", inputs, radiation.__file__, fit_now)
    fit = KramersKronigTail(**{k: (float(v) if v.ndim == 0 else v) for k, v in stored.items()})
    change = float(np.max(np.abs(fit.added_mass_inf - hdb.added_mass_inf[block])) /
                   np.max(np.abs(hdb.added_mass_inf[block])))
    if log is not None:
        log(f"A_inf and B above {hdb.omega[-1]:g} rad/s fitted to A(omega) (Kramers-Kronig): A_inf changes by "
            f"{100 * change:.2g} % of the largest entry; misfit of A over the frequency grid {100 * fit.spread:.2g} % "
            f"({100 * fit.spread_without:.2g} % with A_inf alone)"
            + (f"; negative eigenvalues of the fitted B, down to {100 * fit.negative:.2g} % of its largest, set to 0"
               if fit.negative > 1e-3 else ""))
    a_inf = hdb.added_mass_inf.copy()
    a_inf[block] = fit.added_mass_inf
    values = np.zeros((len(fit.nodes),) + hdb.added_mass_inf.shape)
    values[(slice(None),) + block] = fit.values
    extra = {**hdb.extra, TAIL_CORRECTION: (fit.nodes, values)}
    return dataclasses.replace(hdb, added_mass_inf=a_inf, extra=extra,
                               source=f"{hdb.source} (A_inf and B tail: Kramers-Kronig fit)")


def _scene_dofs(scenario: Scenario) -> list[int]:
    """Indices of the scene's hydrodynamic degrees of freedom in the database (6 per body, scenario order)."""
    return [6 * i + DOFS.index(d) for i, b in enumerate(scenario.hydro_bodies) for d in sorted_dofs(b)]


def _ogilvie(scenario: Scenario, hdb: HydroDatabase, log) -> HydroDatabase:
    """The database with A_inf replaced by the value consistent with its A(omega) and B(omega)."""
    import dataclasses

    from hydro_fmu import radiation
    from hydro_fmu.radiation import ogilvie_added_mass_inf

    h = scenario.hydro

    def fit_now() -> dict:
        a_inf, spread = ogilvie_added_mass_inf(hdb.omega, hdb.added_mass, hdb.radiation_damping, h.irf_duration,
                                               d_omega=h.irf_d_omega, tail_exponent=h.damping_tail)
        return {"added_mass_inf": a_inf, "spread": spread}

    stored = cached_fit("ogilvie", {"omega": hdb.omega, "added_mass": hdb.added_mass, "damping": hdb.radiation_damping,
                                    "duration": h.irf_duration, "d_omega": h.irf_d_omega,
                                    "tail_exponent": h.damping_tail}, radiation.__file__, fit_now)
    a_inf, spread = stored["added_mass_inf"], float(stored["spread"])
    change = float(np.max(np.abs(a_inf - hdb.added_mass_inf)) / np.max(np.abs(hdb.added_mass_inf)))
    if log is not None:
        log(f"A_inf from Ogilvie's relation: largest change {100 * change:.2g} % of the largest entry; "
            f"spread over the frequency grid {100 * spread:.2g} %")
    return dataclasses.replace(hdb, added_mass_inf=a_inf, source=f"{hdb.source} (A_inf: Ogilvie fit)")


def _check_coefficients(scenario: Scenario, hdb: HydroDatabase) -> None:
    """Symmetry and positive damping on the degrees of freedom the scene uses (HydroDatabaseError)."""
    problems = hdb.check_physics(np.array(_scene_dofs(scenario)), scenario.hydro.check_tolerance)
    if problems:
        raise HydroDatabaseError(
            "; ".join(problems) + f" (tolerance hydro.check_tolerance = {scenario.hydro.check_tolerance:g} "
            f"in {scenario.file}; raise it only if you trust the data)")


def _match_bodies(scenario: Scenario, hdb: HydroDatabase) -> HydroDatabase:
    """Database restricted to the scenario's hydrodynamic bodies, in scenario order, checked."""
    names = [b.name for b in scenario.hydro_bodies]
    if all(n in hdb.body_names for n in names):
        sub = hdb.select_bodies(names)
    elif len(hdb.body_names) == len(names):
        sub = hdb.select_bodies(hdb.body_names)
        sub.body_names = names
    else:
        raise ScenarioError(
            f"{scenario.file}: the database {hdb.source} has bodies {hdb.body_names}, "
            f"which do not match the scenario's hydrodynamic bodies {names}")
    env = scenario.environment
    for key in ("rho", "g"):
        if not math.isclose(getattr(hdb, key), getattr(env, key), rel_tol=1e-6):
            raise ScenarioError(
                f"{scenario.file}: environment.{key} = {getattr(env, key)} but the database "
                f"{hdb.source} was computed with {key} = {getattr(hdb, key)}")
    depth, wanted = float(hdb.water_depth), float(env.water_depth)
    if not (depth == wanted or math.isclose(depth, wanted, rel_tol=1e-6)):
        raise ScenarioError(
            f"{scenario.file}: environment.water_depth = {wanted:g} m but the database {hdb.source} was computed for "
            f"a water depth of {depth:g} m: waves and coefficients would disagree. Set environment.water_depth = "
            f"{_toml_number(depth)} to use this database, or give a database computed for {wanted:g} m")
    return sub


def _toml_number(value: float) -> str:
    return "inf" if math.isinf(value) else f"{value:g}"


def _about_centres_of_gravity(scenario: Scenario, hdb: HydroDatabase, log) -> HydroDatabase:
    """The database with its coefficients about the scenario's centres of gravity: a BEMIO file's coefficients are
    about each body's reference point (its ``cg`` in the file); where a body's cg differs from it by more than 1 mm
    they are moved by the rigid-body transformation (:mod:`hydro_fmu.reference_point`), and ``log`` says so."""
    from hydro_fmu.reference_point import moved_to

    cgs = np.array([b.cg for b in scenario.hydro_bodies], dtype=float)
    far = np.linalg.norm(hdb.cg - cgs, axis=1) > 1e-3
    if not far.any():
        return hdb
    if log is not None:
        for i in np.flatnonzero(far):
            log(f"body {hdb.body_names[i]!r}: the database {hdb.source} is about {_point(hdb.cg[i])}, the body's cg is "
                f"{_point(cgs[i])}: its coefficients are moved to the cg (rigid-body transformation of A, B, the "
                "excitation and the hydrostatic stiffness)")
    return moved_to(hdb, np.where(far[:, None], cgs, hdb.cg))


def _point(p: np.ndarray) -> str:
    return "(" + ", ".join(f"{v:g}" for v in p) + ") m"


def _check_parts(scenario: Scenario, hdb: HydroDatabase) -> None:
    """A scene that needs the diffraction part of the excitation (hydro.nonlinear_froude_krylov) refuses a database
    without it, naming why it is missing."""
    from hydro_fmu.bemio import EXCITATION_PARTS

    if scenario.hydro.nonlinear_froude_krylov and hdb.diffraction is None:
        why = hdb.extra.get(EXCITATION_PARTS) or f"the database {hdb.source} has no Froude-Krylov/diffraction parts"
        raise ScenarioError(
            f"{scenario.file}: hydro.nonlinear_froude_krylov = true needs the diffraction (scattering) part of the "
            f"excitation, but {why}. Set hydro.nonlinear_froude_krylov = false, or give a database with both parts "
            "(leave hydro.database empty to compute one with Capytaine from the bodies' geometry)")


def sorted_dofs(b: BodySection) -> list[str]:
    return sorted(b.dofs, key=DOFS.index)


def check_wave_range(scenario: Scenario, hdb: HydroDatabase, path: Path) -> None:
    """Regular wave periods (waves, steady; each case of a sweep has its own) and an irregular sea's peak
    inside the database's frequency range: outside it every coefficient would be extrapolated (errors of "+nan %")."""
    w, f = scenario.waves, scenario.file
    lo, hi = float(hdb.omega[0]), float(hdb.omega[-1])
    periods = []
    if w.kind == "regular":
        periods.append(("waves.period", w.period))
    periods += [(f"steady.periods[{i}]", p) for i, p in enumerate(scenario.steady.periods)]
    if w.kind == "irregular" and w.tp > 0:
        periods.append(("waves.tp", w.tp))
    for key, period in periods:
        omega = 2 * np.pi / period
        if not lo <= omega <= hi:
            raise ScenarioError(
                f"{f}: {key} = {period:g} s ({omega:.4g} rad/s) is outside the hydrodynamic database's frequency range "
                f"{lo:.4g}..{hi:.4g} rad/s (periods {2 * np.pi / hi:.4g}..{2 * np.pi / lo:.4g} s, {path}); choose a "
                "period in that range or extend hydro.omega")
