"""MoorDyn lines inside the multibody model (mbd_fmu.moordyn_lines): the static shape against the elastic
catenary's closed form, the coupling's convergence order, state copies and plain-data round trips, errors.

The lines are the RM3 scene's: three 258 m chains (983.54 N/m submerged, EA 4.9e8 N) from fairleads on
a column (radius 3 m, z = -21 m) to anchors at radius 250 m on a 70 m sea bed."""

from __future__ import annotations

import copy
import math
import pickle

import numpy as np
import pytest

from mbd_fmu.moordyn_lines import MoorDynError, MoorDynSystem
from mbd_fmu.moorings import catenary_tensions
from mbd_fmu.spec import build_simulator

WEIGHT, EA, LENGTH, SPAN, HEIGHT = 983.54, 4.9e8, 258.0, 247.0, 49.0
H_QS, V_QS = catenary_tensions(SPAN, HEIGHT, LENGTH, WEIGHT, EA)
MASS = 3.0e6  # about RM3's surge mass with added mass


def lines(model: str = "moordyn", segments: int = 20) -> list[dict]:
    out = []
    for i, az in enumerate((0.0, 120.0, 240.0)):
        c, s = math.cos(math.radians(az)), math.sin(math.radians(az))
        out.append({"kind": "catenary", "name": f"line{i + 1}", "body": "buoy", "fairlead": [3 * c, 3 * s, -21.0],
                    "anchor": [250 * c, 250 * s, -70.0], "length": LENGTH, "weight": WEIGHT, "ea": EA,
                    "model": model, "diameter": 0.137, "segments": segments, "drag_normal": 1.2, "drag_axial": 0.4,
                    "added_mass_normal": 1.0, "added_mass_axial": 0.0, "internal_damping": 0.8})
    return out


def spec(step: float, *, model: str = "moordyn", surge: float = 5.0, time_step: float = 0.001) -> dict:
    """A buoy in surge and heave on the three lines, buoyancy = weight + the lines' vertical pretension."""
    return {"bodies": [{"name": "buoy", "mass": MASS, "inertia": np.eye(3).tolist(), "cg": [0.0, 0.0, -21.29],
                        "dofs": [0, 2], "x0": [surge, 0, 0, 0, 0, 0], "v0": [0.0] * 6,
                        "static_load": [0.0, 0.0, MASS * 9.81 + 3 * V_QS, 0.0, 0.0, 0.0]}],
            "joints": [], "forces": lines(model), "ptos": [], "drivers": [], "hydro_bodies": [],
            "hydro_coordinates": [], "gravity": [0.0, 0.0, -9.81],
            "multibody": {"formulation": "index3", "max_step": step},
            "moordyn": {"time_step": time_step, "scheme": "RK2", "seabed_stiffness": 3e6, "seabed_damping": 3e5,
                        "ic_time": 60.0, "ic_tolerance": 1e-3, "rho": 1000.0, "g": 9.81}}


def system_of(sim) -> MoorDynSystem:
    return sim.model.elements[0].system


def test_rest_tensions_equal_the_elastic_catenary() -> None:
    """At rest MoorDyn's fairlead forces equal Jonkman's closed-form elastic catenary with sea-bed contact
    (same length, weight, EA, anchor, fairlead, sea bed) within 1 %, and stay there over 10 s (the buoy has
    no heave stiffness but the lines': it settles 3 cm lower on the 0.2 % difference)."""
    sim = build_simulator(spec(0.05, surge=0.0, time_step=0.004))
    lines_ = system_of(sim)
    for _ in range(2):
        f = lines_.force
        horizontal, vertical = np.hypot(f[:, 0], f[:, 1]), -f[:, 2]
        np.testing.assert_allclose(horizontal, H_QS, rtol=0.01)
        np.testing.assert_allclose(vertical, V_QS, rtol=0.01)
        sim.advance(10.0)


def test_coupling_converges_at_second_order() -> None:
    """Surge decay from 5 m over 8 s with multibody steps h = 0.16, 0.08, 0.04 against h = 0.02 (MoorDyn's own
    step fixed): the error falls at least threefold per halving (second order: fourfold)."""
    runs = {}
    for h in (0.16, 0.08, 0.04, 0.02):
        sim = build_simulator(spec(h))
        sim.advance(8.0)
        runs[h] = sim.displacement()
    errors = [np.abs(runs[h] - runs[0.02]).max() for h in (0.16, 0.08, 0.04)]
    assert errors[0] / errors[1] > 3 and errors[1] / errors[2] > 3, errors
    assert errors[0] < 2e-3  # 5 m decay: the coarsest step is already accurate
    assert abs(runs[0.02][0] - 5.0) > 1.0  # it moved


def test_copies_and_data_round_trips_restore_the_lines_exactly() -> None:
    """A deep copy (an FMU state) and a pickled copy (a serialised FMU state, restored into a new MoorDyn
    instance) continue exactly as the original; copies used in turn share one MoorDyn instance correctly."""
    sim = build_simulator(spec(0.05, time_step=0.004))
    sim.advance(2.0)
    saved = copy.deepcopy(sim)
    data = pickle.dumps(saved)
    state = system_of(saved).__getstate__()
    assert state["moordyn_state"].dtype == np.uint8 and state["moordyn_state"].size > 1000
    assert all(isinstance(v, (str, float, int, np.ndarray, list, dict)) for v in state.values())  # plain data

    def history(s, n: int = 10) -> np.ndarray:
        out = []
        for _ in range(n):
            s.advance(0.1)
            out.append(np.concatenate([s.displacement(), system_of(s).force.ravel()]))
        return np.array(out)

    first = history(sim)
    second = history(copy.deepcopy(saved))
    third = history(pickle.loads(data))
    np.testing.assert_array_equal(second, first)
    np.testing.assert_array_equal(third, first)
    # the data decoded onto a live copy that has moved on (how a data-only FMU-state codec restores):
    # same MoorDyn state, same next step as the saved lines
    reference, live = copy.deepcopy(saved), copy.deepcopy(saved)
    live.advance(0.5)
    system_of(live).__setstate__(system_of(saved).__getstate__())
    assert system_of(live).serialized() == system_of(reference).serialized()
    for s_ in (reference, live):
        system_of(s_).advance(reference.kin.__class__(reference.formulation.pose, np.zeros(12), reference.time + 0.1))
    np.testing.assert_array_equal(system_of(live).force, system_of(reference).force)
    # two copies stepped alternately (ownership of the live instance moves back and forth)
    a, b = copy.deepcopy(saved), copy.deepcopy(saved)
    alternated = [np.concatenate([history(a, 1), history(b, 1)]) for _ in range(5)]
    np.testing.assert_array_equal(np.array([x[0] for x in alternated]), first[:5])
    np.testing.assert_array_equal(np.array([x[1] for x in alternated]), first[:5])


def test_moordyn_failure_reaches_the_user_as_its_message() -> None:
    """A MoorDyn step beyond the lines' Courant limit blows up: the error says when and what MoorDyn saw."""
    sim = build_simulator(spec(0.05, time_step=0.012))
    with pytest.raises(MoorDynError, match="MoorDyn failed at t = .* s: .*NaN"):
        sim.advance(5.0)
