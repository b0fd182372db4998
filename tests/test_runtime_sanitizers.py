"""The runtime built with AddressSanitizer and UndefinedBehaviorSanitizer, fed valid and mutated input.

The runtime's sources (native/src) and a driver (tests/native/hydro_driver.c) are compiled with
``-fsanitize=address,undefined`` into one executable; the driver loads every file it is given and drives each model
that loads through every entry point of the C API (outputs, linearisation, steps, state save/load with a truncated
and a corrupted state, clone, copy, free). The inputs: valid runtime data of synthetic models covering every
concept and of bundled scenes, and 300 mutations of them (truncations, flipped bytes in the header, directory and
data, NaN and infinity written into arrays, huge counts and extents, extents off by one, random method codes and
counts). Every mutated input must be refused with a message or run; none may crash, read or write out of bounds,
leak or hit undefined behaviour (the sanitizers abort the driver on the first report). Skipped, with the reason,
only when the compiler cannot build a sanitized program.
"""

from __future__ import annotations

import os
import shutil
import struct
import subprocess
from pathlib import Path

import numpy as np
import pytest

from fmu_base import runtime_data

from .hydro_runtime_cases import arrays, box_corners

ROOT = Path(__file__).resolve().parent.parent
FLAGS = ["-std=c11", "-g", "-O1", "-fno-omit-frame-pointer", "-fsanitize=address,undefined",
         "-fno-sanitize-recover=all"]
MUTATIONS = 300


def _compiler() -> str | None:
    return os.environ.get("CC") or shutil.which("gcc") or shutil.which("cc") or shutil.which("clang")


@pytest.fixture(scope="module")
def driver(tmp_path_factory: pytest.TempPathFactory) -> Path:
    compiler = _compiler()
    if compiler is None:
        pytest.skip("no C compiler on PATH (set CC): the sanitizer build cannot be made")
    folder = tmp_path_factory.mktemp("sanitized")
    probe = folder / "probe.c"
    probe.write_text("int main(void) { return 0; }\n")
    made = subprocess.run([compiler, *FLAGS, str(probe), "-o", str(folder / "probe")], capture_output=True, text=True)
    ran = made.returncode == 0 and subprocess.run([str(folder / "probe")], capture_output=True).returncode == 0
    if not ran:
        pytest.skip(f"{compiler} cannot build and run a program with -fsanitize=address,undefined "
                    f"({(made.stderr or 'the probe did not run').strip()[:200]})")
    sources = sorted(str(p) for p in (ROOT / "native" / "src").rglob("*.c"))
    target = folder / "hydro_driver"
    build = subprocess.run([compiler, *FLAGS, "-Wall", "-Wextra", "-I", str(ROOT / "native" / "include"), *sources,
                            str(ROOT / "tests" / "native" / "hydro_driver.c"), "-lm", "-o", str(target)],
                           capture_output=True, text=True)
    assert build.returncode == 0, build.stderr
    assert "warning" not in build.stderr, build.stderr
    return target


def valid_inputs() -> dict[str, bytes]:
    """Runtime data covering every concept: convolution memory with superposition, record, drag and linear
    hydrostatics; state space with the excitation convolution of components; the wetted box with the nonlinear
    Froude-Krylov force in a spread sea at finite depth; the excitation convolution of a record."""
    rng = np.random.default_rng(1)
    two = [(0, 2), (0, 4)]
    common = {"omega": [0.7, 1.3], "amplitude": [0.5 + 0.2j, 0.1 - 0.3j]}
    tau = np.arange(-10, 11) * 0.1
    out = {
        "convolution": arrays(two, ramp=2.0, excitation=1, radiation=1, hydrostatics=1, **common,
                              excitation_coefficients=rng.normal(size=(2, 2, 2)) * 1e4,
                              radiation_kernel=rng.normal(size=(15, 2, 2)) * 1e3, radiation_block_points=4,
                              hydrostatics_stiffness=np.eye(2) * 1e5, viscous_linear=np.ones(2),
                              viscous_quadratic=np.ones(2), record_dt=0.2, record_eta=np.sin(np.arange(20.0)),
                              model_added_mass_inf=np.eye(2)),
        "state_space": arrays(two, excitation=2, radiation=2, **common, excitation_tau=tau,
                              excitation_kernel=rng.normal(size=(21, 2)), radiation_a=-np.eye(3) + 0.1,
                              radiation_b=rng.normal(size=(3, 2)), radiation_c=rng.normal(size=(2, 3))),
        "pressure": arrays([(0, 0), (0, 2), (0, 4), (1, 2)], excitation=1, hydrostatics=2, froude_krylov=1, **common,
                           waves_heading=[0.0, 0.5], waves_wavenumber=[0.05, 0.17],
                           excitation_coefficients=np.zeros((2, 4, 2)), environment_rho=1025.0, environment_g=9.81,
                           environment_depth=20.0, bodies_cg=[[0.0, 0.0, -0.5], [6.0, 0.0, -0.5]],
                           mesh_corners=np.concatenate([box_corners(4, 2, 3), box_corners(2, 2, 2)]),
                           mesh_faces=[12, 12]),
        "record_convolution": arrays(two, excitation=2, excitation_tau=tau, excitation_kernel=np.ones((21, 2)),
                                     record_dt=0.1, record_eta=np.cos(np.arange(50.0))),
    }
    return {name: runtime_data.write("hydro", a) for name, a in out.items()}


def _entries(data: bytes) -> list[tuple[int, int, int]]:
    """(directory position, dtype, ndim) of each array."""
    count = struct.unpack_from("<I", data, 12)[0]
    return [(48 + 128 * k, data[48 + 128 * k + 64], data[48 + 128 * k + 65]) for k in range(count)]


def mutate(data: bytes, rng: np.random.Generator) -> bytes:
    """One random corruption of a valid input (module docstring)."""
    b = bytearray(data)
    entries = _entries(data)
    directory_end = 48 + 128 * len(entries)
    kind = int(rng.integers(9))
    position, dtype, ndim = entries[int(rng.integers(len(entries)))]
    offset, nbytes = struct.unpack_from("<QQ", b, position + 104)
    if kind == 0:  # truncated
        return bytes(b[: int(rng.integers(0, len(b)))])
    if kind == 1:  # bytes flipped anywhere
        for _ in range(int(rng.integers(1, 9))):
            b[int(rng.integers(len(b)))] ^= int(rng.integers(1, 256))
    elif kind == 2:  # bytes flipped in the header and directory
        for _ in range(int(rng.integers(1, 4))):
            b[int(rng.integers(directory_end))] ^= int(rng.integers(1, 256))
    elif kind == 3 and dtype == 1 and nbytes >= 8:  # NaN or infinity in a float array
        value = (float("nan"), float("inf"), float("-inf"))[int(rng.integers(3))]
        struct.pack_into("<d", b, offset + 8 * int(rng.integers(nbytes // 8)), value)
    elif kind == 4:  # a huge extent, size, offset or count
        huge = int((2**31, 2**40, 2**62, 2**64 - 1, 2**63 + 8)[int(rng.integers(5))])
        field = int(rng.integers(7))
        if field < 4:
            struct.pack_into("<Q", b, position + 72 + 8 * field, huge)
        elif field == 4:
            struct.pack_into("<Q", b, position + 104, huge)
        elif field == 5:
            struct.pack_into("<Q", b, position + 112, huge)
        else:
            struct.pack_into("<I", b, 12, huge % 2**32)
    elif kind == 5 and ndim > 0:  # an extent off by one, its size made consistent
        d = int(rng.integers(ndim))
        shape = list(struct.unpack_from("<4Q", b, position + 72))
        item = 1 if dtype == 3 else 8
        shape[d] = max(0, shape[d] + int(rng.choice([-1, 1])))
        struct.pack_into("<4Q", b, position + 72, *shape)
        struct.pack_into("<Q", b, position + 112, item * int(np.prod(shape[:ndim], dtype=object)))
    elif kind == 6 and dtype == 2 and nbytes >= 8:  # an integer (method code, count, index) changed
        value = int((-1, 0, 1, 2, 3, 7, 1000, 2**40, -(2**62))[int(rng.integers(9))])
        struct.pack_into("<q", b, offset + 8 * int(rng.integers(nbytes // 8)), value)
    elif kind == 7:  # the total size field
        struct.pack_into("<Q", b, 32, len(b) + int(rng.choice([-8, 8, 2**40])))
    else:  # bytes flipped in the data area
        for _ in range(int(rng.integers(1, 5))):
            b[int(rng.integers(directory_end, len(b)))] ^= int(rng.integers(1, 256))
    return bytes(b)


def test_sanitized_runtime_refuses_or_runs_every_mutated_input(driver: Path, tmp_path: Path) -> None:
    from hydro_fmu.runtime_input import runtime_input
    from orchestrator.scenario import load_scenario
    from orchestrator.scene import load_scene

    inputs = valid_inputs()
    inputs["cylinder_irregular"] = runtime_input(load_scene(load_scenario(ROOT / "scenarios" /
                                                                          "cylinder_irregular.toml"),
                                                            log=None).hydro_model())
    rng = np.random.default_rng(2029)
    files = []
    for name, data in inputs.items():
        path = tmp_path / f"valid_{name}.bin"
        path.write_bytes(data)
        files.append(path)
    bases = list(inputs.values())
    for k in range(MUTATIONS):
        path = tmp_path / f"mutated_{k:03d}.bin"
        path.write_bytes(mutate(bases[k % len(bases)], rng))
        files.append(path)
    env = {**os.environ, "ASAN_OPTIONS": "detect_leaks=1:halt_on_error=1:abort_on_error=0",
           "UBSAN_OPTIONS": "halt_on_error=1:print_stacktrace=1"}
    proc = subprocess.run([str(driver), *map(str, files)], capture_output=True, text=True, env=env, timeout=600)
    assert proc.returncode == 0, (proc.stdout[-3000:], proc.stderr[-5000:])
    assert "runtime error" not in proc.stderr and "Sanitizer" not in proc.stderr, proc.stderr[-5000:]
    lines = proc.stdout.splitlines()
    assert len(lines) == len(files)
    assert all(line.startswith("ok ") for line in lines[: len(inputs)]), lines[: len(inputs)]
    outcomes = [line.split(" ")[0] for line in lines[len(inputs):]]
    refused = sum(1 for o in outcomes if o == "refused:")
    assert set(outcomes) <= {"ok", "refused:"}
    assert refused >= MUTATIONS // 2, f"only {refused} of {MUTATIONS} mutations refused"
    assert all(len(line) > len("refused: runtime data: ") for line in lines if line.startswith("refused:"))


def test_the_avx2_clones_give_the_same_bits(tmp_path: Path) -> None:
    """The long sums run in eight fixed lanes, compiled for the baseline and for AVX2 (docs/runtime.md): built with
    the clones (the processor's choice) and without (-DWEC_NO_CLONES), the driver's hash of every output of every
    valid input is the same, bit for bit."""
    compiler = _compiler()
    if compiler is None:
        pytest.skip("no C compiler on PATH (set CC)")
    sources = sorted(str(p) for p in (ROOT / "native" / "src").rglob("*.c"))
    files = []
    for name, data in valid_inputs().items():
        files.append(tmp_path / f"{name}.bin")
        files[-1].write_bytes(data)
    outputs = []
    for flags in ([], ["-DWEC_NO_CLONES"]):
        target = tmp_path / f"driver{len(outputs)}"
        build = subprocess.run([compiler, "-std=c11", "-O2", *flags, "-I", str(ROOT / "native" / "include"), *sources,
                                str(ROOT / "tests" / "native" / "hydro_driver.c"), "-lm", "-o", str(target)],
                               capture_output=True, text=True)
        assert build.returncode == 0, build.stderr
        run = subprocess.run([str(target), *map(str, files)], capture_output=True, text=True, timeout=300)
        assert run.returncode == 0, run.stdout + run.stderr
        outputs.append(run.stdout)
    assert outputs[0] == outputs[1]
    assert outputs[0].count("ok ") == len(files)
