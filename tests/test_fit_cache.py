"""The on-disk cache of the A_inf fits a scene load repeats (orchestrator/scene/fit_cache.py)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from orchestrator.scene import fit_cache
from orchestrator.scene.fit_cache import cached_fit


@pytest.fixture
def cache(tmp_path: Path, monkeypatch) -> Path:
    monkeypatch.setenv("WEC_COSIM_CACHE", str(tmp_path / "cache"))
    return tmp_path / "cache" / "fits"


def _code(tmp_path: Path, text: str = "x = 1\n") -> Path:
    path = tmp_path / "hydro_fmu" / "fit.py"
    path.parent.mkdir(exist_ok=True)
    path.write_text(text)
    return path


def test_a_fit_is_computed_once_per_input_and_code_and_read_back_exactly(cache: Path, tmp_path: Path) -> None:
    calls = []
    rng = np.random.default_rng(3)
    inputs = {"omega": np.linspace(0.1, 3.0, 40), "damping": rng.normal(size=(40, 2, 2)), "duration": 60.0}

    def compute() -> dict:
        calls.append(1)
        return {"added_mass_inf": inputs["damping"].sum(axis=0) / 3.0, "spread": 0.0123}

    code = _code(tmp_path)
    first = cached_fit("ogilvie", inputs, code, compute)
    again = cached_fit("ogilvie", {k: (v.copy() if isinstance(v, np.ndarray) else v) for k, v in inputs.items()},
                       code, compute)
    assert len(calls) == 1 and len(list(cache.glob("ogilvie-*.npz"))) == 1
    assert np.array_equal(again["added_mass_inf"], inputs["damping"].sum(axis=0) / 3.0)
    assert float(again["spread"]) == 0.0123 and again.keys() == first.keys()
    # Any other input value, setting or version of the code is another fit.
    changed = dict(inputs, damping=inputs["damping"].copy())
    changed["damping"][7, 1, 0] += 1e-12
    cached_fit("ogilvie", changed, code, compute)
    cached_fit("ogilvie", dict(inputs, duration=60.000001), code, compute)
    cached_fit("kramers_kronig", inputs, code, compute)
    _code(tmp_path, "x = 2\n")
    cached_fit("ogilvie", inputs, code, compute)
    assert len(calls) == 5


def test_a_corrupt_or_code_carrying_cache_file_is_computed_again(cache: Path, tmp_path: Path) -> None:
    code = _code(tmp_path)
    inputs = {"a": np.arange(5.0)}
    calls = []

    def compute() -> dict:
        calls.append(1)
        return {"value": np.arange(5.0) * 2}

    cached_fit("ogilvie", inputs, code, compute)
    (path,) = cache.glob("ogilvie-*.npz")
    path.write_bytes(b"PK\x03\x04 not an archive")
    assert np.array_equal(cached_fit("ogilvie", inputs, code, compute)["value"], np.arange(5.0) * 2)
    # An archive holding a pickled object is never unpickled (allow_pickle=False): computed again, replaced.
    np.savez(path, value=np.array([{"a": 1}], dtype=object))
    assert np.array_equal(cached_fit("ogilvie", inputs, code, compute)["value"], np.arange(5.0) * 2)
    assert len(calls) == 3
    assert np.array_equal(cached_fit("ogilvie", inputs, code, compute)["value"], np.arange(5.0) * 2)
    assert len(calls) == 3  # the replaced file is good


def test_an_unwritable_cache_leaves_the_fit_uncached(tmp_path: Path, monkeypatch) -> None:
    blocker = tmp_path / "not_a_folder"
    blocker.write_text("")
    monkeypatch.setenv("WEC_COSIM_CACHE", str(blocker))
    out = cached_fit("ogilvie", {"a": np.ones(3)}, _code(tmp_path), lambda: {"value": np.ones(3)})
    assert np.array_equal(out["value"], np.ones(3))
    with pytest.raises(TypeError, match="not numeric"):
        fit_cache.fit_key("ogilvie", {"a": None}, _code(tmp_path))


def test_a_scene_loads_the_same_ogilvie_added_mass_from_the_cache(cache: Path) -> None:
    """A_inf of a scene with ``added_mass_inf = "ogilvie"`` equals the direct computation, computed or cached."""
    from hydro_fmu.radiation import ogilvie_added_mass_inf
    from orchestrator.scenario import load_scenario
    from orchestrator.scene import load_database

    scenario = load_scenario(Path(__file__).parent.parent / "scenarios" / "nenuphar.toml")
    scenario.hydro.added_mass_inf = "bem"
    base, _ = load_database(scenario, log=None)
    scenario.hydro.added_mass_inf = "ogilvie"
    h = scenario.hydro
    direct, _ = ogilvie_added_mass_inf(base.omega, base.added_mass, base.radiation_damping, h.irf_duration,
                                       d_omega=h.irf_d_omega, tail_exponent=h.damping_tail)
    computed, _ = load_database(scenario, log=None)
    assert len(list(cache.glob("ogilvie-*.npz"))) == 1
    cached, _ = load_database(scenario, log=None)
    assert np.array_equal(computed.added_mass_inf, direct) and np.array_equal(cached.added_mass_inf, direct)
