"""What a user receives besides the code: the licence pyproject names, a citation file and a changelog of this
version, ``wec-cosim --version``, and the dependencies that something needs."""

from __future__ import annotations

import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parent.parent
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]


def test_the_licence_file_is_the_mit_licence_pyproject_names() -> None:
    assert PROJECT["license"] == "MIT"
    text = (ROOT / "LICENSE").read_text()
    assert text.startswith("MIT License") and "Permission is hereby granted, free of charge" in text
    assert 'THE SOFTWARE IS PROVIDED "AS IS"' in text


def test_citation_and_changelog_name_this_version() -> None:
    citation = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    assert citation["cff-version"] == "1.2.0"
    assert str(citation["version"]) == PROJECT["version"] and citation["license"] == "MIT"
    assert citation["title"] and citation["authors"] and citation["message"]
    changelog = (ROOT / "CHANGELOG.md").read_text()
    assert f"## [{PROJECT['version']}]" in changelog


def test_version_option_prints_the_installed_version() -> None:
    done = subprocess.run([sys.executable, "-m", "wec_cosim", "--version"], capture_output=True, text=True,
                          timeout=120, check=True)
    assert done.stdout.strip() == f"wec-cosim {PROJECT['version']}"


def test_meshio_is_what_reads_a_vtk_mesh_file(tmp_path: Path) -> None:
    """meshio is a dependency because Capytaine reads the mesh formats other than .obj and .stl (which our own
    readers take) through it: a unit cube written by hand as a legacy VTK file reads as 12 triangles enclosing
    1 m^3 (divergence theorem), and without meshio Capytaine refuses the format."""
    import numpy as np

    from hydro_fmu.meshes import read_mesh

    corners = [(x, y, z) for z in (0, 1) for y in (0, 1) for x in (0, 1)]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]  # outward
    lines = ["# vtk DataFile Version 4.2", "unit cube", "ASCII", "DATASET UNSTRUCTURED_GRID",
             f"POINTS {len(corners)} double", *(f"{x} {y} {z}" for x, y, z in corners),
             f"CELLS {len(quads)} {5 * len(quads)}", *("4 " + " ".join(map(str, q)) for q in quads),
             f"CELL_TYPES {len(quads)}", *(["9"] * len(quads))]
    path = tmp_path / "cube.vtk"
    path.write_text("\n".join(lines) + "\n")
    mesh = read_mesh(path)
    assert mesh.n_faces == 12
    v = mesh.vertices[mesh.faces]
    volume = np.sum(np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2]))) / 6
    assert volume == pytest.approx(1.0, rel=1e-12)
    code = ("import sys; sys.modules['meshio'] = None\n"
            "from hydro_fmu.meshes import read_mesh\n"
            "from hydro_fmu.hdb import HydroDatabaseError\n"
            "try:\n    read_mesh(sys.argv[1])\nexcept HydroDatabaseError as exc:\n    print('refused', exc)\n")
    done = subprocess.run([sys.executable, "-c", code, str(path)], capture_output=True, text=True, timeout=120)
    assert done.stdout.startswith("refused"), done.stdout + done.stderr
