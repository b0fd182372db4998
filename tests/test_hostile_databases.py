"""Generated damaged BEMIO databases: every required group and dataset of a real database (the cylinder's,
written by ``write_bemio``) deleted, replaced by the other kind of object, by an external link, by a soft link
to itself, by text, or declared terabytes large; junk bytes written over the file's metadata at seeded places.

Each case runs ``wec-cosim run`` on a scenario whose ``hydro.database`` is the damaged file: exit status 2 and one
paragraph naming the file and the object, never a traceback. Junk bytes may land on bytes HDF5 does not use; then
the file must read as the original did (nothing silently changed). Junk cases run in a forked child, so a crash in
HDF5's C library would show as a negative status.
"""

from __future__ import annotations

import random
import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest

from hydro_fmu.bemio import read_bemio, write_bemio
from hydro_fmu.hdf5_reading import MAX_DATASET_BYTES

from .hostile import Case, check, cylinder, run_forked
from .test_malformed_generated import _materialise, run_in_process

SEED = 35
JUNK_CASES = 12

# Objects a BEMIO reader cannot do without (WEC-Sim's readBEMIOH5 reads the same); the others are optional.
REQUIRED = ("simulation_parameters", "simulation_parameters/w", "simulation_parameters/wave_dir",
            "simulation_parameters/water_depth", "body1", "body1/properties", "body1/properties/name",
            "body1/properties/cg", "body1/properties/cb", "body1/properties/disp_vol", "body1/hydro_coeffs",
            "body1/hydro_coeffs/linear_restoring_stiffness", "body1/hydro_coeffs/added_mass",
            "body1/hydro_coeffs/added_mass/all", "body1/hydro_coeffs/added_mass/inf_freq",
            "body1/hydro_coeffs/radiation_damping", "body1/hydro_coeffs/radiation_damping/all",
            "body1/hydro_coeffs/excitation", "body1/hydro_coeffs/excitation/re", "body1/hydro_coeffs/excitation/im")
NUMERIC = ("simulation_parameters/rho", "simulation_parameters/g", "body1/properties/dof")


@pytest.fixture(scope="module")
def original(tmp_path_factory) -> Path:
    """The cylinder's database as a BEMIO file."""
    from orchestrator.scenario import load_scenario
    from orchestrator.scene import load_database

    from .conftest import SCENARIOS

    hdb, _ = load_database(load_scenario(SCENARIOS / "cylinder_regular.toml"), log=None)
    return write_bemio(hdb, tmp_path_factory.mktemp("bemio") / "cylinder.h5")


def _replace(name: str, make) -> callable:  # noqa: ANN001
    def damage(f: h5py.File) -> None:
        del f[name]
        make(f, name)
    return damage


def _delete(name: str) -> callable:
    def damage(f: h5py.File) -> None:
        del f[name]
    return damage


def _huge(f: h5py.File, name: str) -> None:
    shape = (6, 6, MAX_DATASET_BYTES // 8)  # 36 GiB declared, nothing written
    f.create_dataset(name, shape=shape, dtype="f8")


def damage_cases() -> list[tuple[str, callable, list[str]]]:
    """(label, damage(f), fragments the message must hold) for every required object and mutation."""
    out = []
    for name in REQUIRED:
        full = "/" + name
        is_group = "/" not in name or name.rsplit("/", 1)[1] in (
            "properties", "hydro_coeffs", "added_mass", "radiation_damping", "excitation")
        out.append((f"{name} deleted", _delete(name), [full, "missing"]))
        out.append((f"{name} an external link", _replace(name, lambda f, n: f.__setitem__(
            n, h5py.ExternalLink("elsewhere.h5", "/data"))), [full, "external link"]))
        out.append((f"{name} a soft link to itself", _replace(name, lambda f, n: f.__setitem__(
            n, h5py.SoftLink("/" + n))), [full, "does not resolve"]))
        if is_group:
            out.append((f"{name} a dataset", _replace(name, lambda f, n: f.__setitem__(n, 1.0)),
                        [full, "expected a group"]))
        else:
            out.append((f"{name} a group", _replace(name, lambda f, n: f.create_group(n)),
                        [full, "expected a dataset"]))
            if name != "body1/properties/name":
                out.append((f"{name} text", _replace(name, lambda f, n: f.__setitem__(n, "water")),
                            [full, "'water', expected a number"]))
                out.append((f"{name} declared 36 GiB", _replace(name, _huge), [full, "GB"]))
    for name in NUMERIC:
        out.append((f"{name} text", _replace(name, lambda f, n: f.__setitem__(n, "water")),
                    ["/" + name, "'water', expected a number"]))
    return out


CASES = damage_cases()


def _scenario_with(database: Path) -> dict:
    return cylinder(hydro={"database": str(database)})


@pytest.mark.parametrize("label, damage, fragments", CASES, ids=[c[0] for c in CASES])
def test_a_damaged_database_is_one_clean_error(tmp_path, original, label, damage, fragments) -> None:
    db = tmp_path / "db.h5"
    shutil.copy(original, db)
    with h5py.File(db, "a") as f:
        damage(f)
    case = Case(label, ["run", "{dir}/s.toml", "--quiet", "--out", "{dir}/out.h5"], {"s.toml": _scenario_with(db)},
                [str(db), *fragments])
    code, stderr = run_in_process(_materialise(case, tmp_path))
    check(case, code, stderr, tmp_path)


def _metadata_spans(path: Path) -> list[tuple[int, int]]:
    """Byte ranges of the file that hold no dataset values (object headers, B-trees, heaps, the superblock)."""
    data = []
    with h5py.File(path, "r") as f:
        def visit(_: str, obj: object) -> None:
            if isinstance(obj, h5py.Dataset) and obj.id.get_offset() is not None:
                data.append((obj.id.get_offset(), obj.id.get_offset() + obj.id.get_storage_size()))
        f.visititems(visit)
    size, spans, start = path.stat().st_size, [], 0
    for a, b in sorted(data):
        if a > start:
            spans.append((start, a))
        start = max(start, b)
    if start < size:
        spans.append((start, size))
    return spans


def junk_cases(path: Path, n: int = JUNK_CASES) -> list[tuple[int, bytes]]:
    rng = random.Random(SEED)
    spans = [(a, b) for a, b in _metadata_spans(path) if b - a >= 16]
    out = []
    for _ in range(n):
        a, b = rng.choice(spans)
        start = rng.randrange(a, b - 8)
        length = min(b - start, rng.choice((4, 16, 64, 512)))
        out.append((start, bytes(rng.randrange(256) for _ in range(length))))
    return out


def test_junk_bytes_over_the_metadata_are_refused_or_change_nothing(tmp_path, original) -> None:
    """Seeded junk over bytes that hold no dataset values: ``wec-cosim hydro`` either refuses the file in one
    paragraph naming it, or reads the same coefficients as from the original (the junk fell on bytes HDF5 does
    not use). No case may crash, hang or read other numbers."""
    reference = read_bemio(original)
    outcomes = {"refused": 0, "unchanged": 0}
    for k, (offset, junk) in enumerate(junk_cases(original)):
        folder = tmp_path / f"junk{k}"
        folder.mkdir()
        db = folder / "db.h5"
        raw = bytearray(original.read_bytes())
        raw[offset:offset + len(junk)] = junk
        db.write_bytes(bytes(raw))
        case = Case(f"junk at byte {offset}", ["hydro", "{dir}/s.toml"], {"s.toml": _scenario_with(db)}, [str(db)])
        argv = _materialise(case, folder)

        def read_and_compare(argv: list[str] = argv, db: Path = db) -> int:
            from wec_cosim.cli import main

            code = main(argv)
            if code == 0:
                hdb = read_bemio(db)
                same = all(np.array_equal(getattr(hdb, key), getattr(reference, key)) for key in (
                    "omega", "added_mass", "radiation_damping", "added_mass_inf", "excitation",
                    "hydrostatic_stiffness", "cg", "cb", "displaced_volume"))
                return 0 if same else 3
            return code

        code, stderr, _ = run_forked([], call=read_and_compare)
        assert code != 3, f"{case.name}: the damaged file reads other coefficients"
        if code == 0:
            outcomes["unchanged"] += 1
            continue
        check(case, code, stderr, folder)
        outcomes["refused"] += 1
    assert outcomes["refused"] >= JUNK_CASES // 2, outcomes  # most junk over metadata must be seen
