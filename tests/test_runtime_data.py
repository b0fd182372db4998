"""The runtime input container (fmu_base/runtime_data.py, native/src/common/data.c) and the hydro loader's checks:
written and read back exactly; every kind of corruption refused with a message that names the array and the
problem (never a crash: the same inputs mutated at random run under the sanitizers in test_runtime_sanitizers)."""

from __future__ import annotations

import struct

import numpy as np
import pytest

from fmu_base import runtime_data
from fmu_base.native import RuntimeCallError
from hydro_fmu.runtime import HydroRuntime

from .hydro_runtime_cases import arrays, box_corners

KERNEL = np.ones((6, 2, 2))


def good() -> dict[str, object]:
    return arrays([(0, 2), (0, 4)], radiation=1, radiation_kernel=KERNEL, radiation_block_points=8,
                  hydrostatics=1, hydrostatics_stiffness=np.eye(2))


def test_container_round_trip() -> None:
    values = {"a.b": np.arange(6.0).reshape(2, 3), "n": 7, "flags": np.array([1, 0, 1], dtype=np.uint8),
              "empty": np.zeros((0, 3)), "big": np.arange(24, dtype=np.int64).reshape(2, 3, 4)}
    data = runtime_data.write("test", values)
    kind, back = runtime_data.read(data, "test")
    assert kind == "test" and list(back) == list(values)
    for name, value in values.items():
        np.testing.assert_array_equal(back[name], np.asarray(value))
        assert back[name].shape == np.shape(value)
    assert runtime_data.write("test", values) == data  # deterministic bytes
    with pytest.raises(runtime_data.RuntimeDataError, match="dtype complex128"):
        runtime_data.write("test", {"z": np.ones(2, complex)})
    with pytest.raises(runtime_data.RuntimeDataError, match="name 'a b'"):
        runtime_data.write("test", {"a b": 1.0})


def _entry(data: bytes, name: str) -> int:
    count = struct.unpack_from("<I", data, 12)[0]
    for k in range(count):
        position = 48 + 128 * k
        if data[position:position + 64].rstrip(b"\0").decode() == name:
            return position
    raise KeyError(name)


def refused(data: bytes, *fragments: str) -> None:
    with pytest.raises(RuntimeCallError) as info:
        HydroRuntime(data)
    message = str(info.value)
    assert message.startswith("runtime data:")
    for fragment in fragments:
        assert fragment in message, message


def test_loader_refuses_corrupt_containers_with_a_message() -> None:
    data = runtime_data.write("hydro", good())
    HydroRuntime(data)  # the uncorrupted one loads
    for length in (0, 7, 47, 48, len(data) // 2, len(data) - 1):
        refused(data[:length], "bytes")
    refused(b"XECRTDAT" + data[8:], "magic")
    refused(data[:8] + struct.pack("<I", 2) + data[12:], "format version 2")
    refused(data[:16] + b"mbd".ljust(16, b"\0") + data[32:], 'of kind "mbd", expected "hydro"')
    refused(data[:12] + struct.pack("<I", 2**32 - 1) + data[16:], "4294967295 arrays announced")
    kernel = _entry(data, "radiation.kernel")
    huge = bytearray(data)
    struct.pack_into("<Q", huge, kernel + 72, 2**62)
    refused(bytes(huge), "'radiation.kernel'", "overflows")
    huge = bytearray(data)
    struct.pack_into("<Q", huge, kernel + 72, 2**40)
    refused(bytes(huge), "'radiation.kernel' declares")
    outside = bytearray(data)
    struct.pack_into("<Q", outside, kernel + 104, len(data) - 8)
    refused(bytes(outside), "'radiation.kernel'", "does not lie within")
    overlap = bytearray(data)
    struct.pack_into("<Q", overlap, kernel + 104, struct.unpack_from("<Q", data, _entry(data, "model.dofs") + 104)[0])
    refused(bytes(overlap), "overlap")
    renamed = bytearray(data)
    renamed[kernel:kernel + 64] = b"model.dt".ljust(64, b"\0")
    refused(bytes(renamed), "'model.dt' appears twice")


@pytest.mark.parametrize(("change", "fragments"), [
    ({"radiation.kernel": np.where(np.arange(24).reshape(6, 2, 2) == 13, np.nan, KERNEL)},
     ("'radiation.kernel'", "not finite", "element 13")),
    ({"model.dt": -0.1}, ("'model.dt' is -0.1, must be positive",)),
    ({"radiation.kernel": np.ones((6, 3, 3))}, ("'radiation.kernel' has extent 3 in dimension 1, expected 2",)),
    ({"radiation.method": 7}, ("'radiation.method' is 7, expected 0 to 2",)),
    ({"radiation.block_points": 0}, ("'radiation.block_points' is 0",)),
    ({"model.dofs": np.array([[0, 2], [0, 9]])}, ("'model.dofs' row 1 is (0, 9)",)),
    ({"model.dofs": np.array([[0, 2], [0, 2]])}, ("degree of freedom 2 of body 0 twice",)),
    ({"model.dt": None}, ("'model.dt' is missing",)),
    ({"hydrostatics.stiffness": np.eye(2, dtype=np.int64)}, ("'hydrostatics.stiffness' is int64, expected float64",)),
    ({"radiation.kernel": np.ones((1, 2, 2))}, ("at least two samples",)),
    ({"hydrostatics.method": 2, "environment.rho": 1025.0, "environment.g": 9.81, "environment.depth": -1.0,
      "bodies.cg": np.zeros((1, 3)), "mesh.corners": box_corners(1, 1, 1), "mesh.faces": [12]},
     ("'environment.depth' must be positive",)),
    ({"hydrostatics.method": 2, "environment.rho": 1025.0, "environment.g": 9.81, "environment.depth": np.inf,
      "bodies.cg": np.zeros((1, 3)), "mesh.corners": box_corners(1, 1, 1), "mesh.faces": [13]},
     ("'mesh.faces' gives body 0 13 faces",)),
    ({"excitation.method": 2, "froude_krylov.nonlinear": 1}, ("cannot be combined with a nonlinear Froude-Krylov",)),
    ({"model.dofs": np.array([[b, d] for b in range(1000) for d in range(6)][:5000]), "model.bodies": 834,
      "radiation.method": 0, "hydrostatics.method": 0},
     ("5000 degrees of freedom", "more working memory than this runtime allows")),
])
def test_loader_refuses_inconsistent_arrays_naming_them(change: dict, fragments: tuple[str, ...]) -> None:
    values = {**good(), **change}
    values = {k: v for k, v in values.items() if v is not None}
    refused(runtime_data.write("hydro", values), *fragments)
