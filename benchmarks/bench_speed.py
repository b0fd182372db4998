"""Speed of the constrained multibody against a compiled engine (Exudyn), side by side in one run.

Three parts (issue 15), each timed in this one process so that the ratios hold on a loaded machine:

1. The issue's table: a rod pendulum (one rigid body, revolute joint to the ground, released
   horizontal) and a planar parallelogram four-bar (three bars, four revolute joints, one degree of
   freedom), 1 ms step, generalised-alpha with spectral radius 0.8, by this project (index-3,
   compiled path, and the Python path for reference) and by Exudyn 1.13.6 (index-3 generalised-alpha,
   3D rigid body for the pendulum, 2D rigid bodies for the four-bar); microseconds per step (whole run
   / steps, minimum of several runs) and the error at t = 1 s against the exact answer (the ODE of the
   single degree of freedom solved to 1e-13 by DOP853): cg position error for the pendulum (m),
   crank angle error for the four-bar (rad). Wall-clock and process CPU time are both reported, the
   engines alternating run by run; on a loaded machine the CPU-time ratio is the steadier figure.
2. N floating bodies (N = 1, 2, 4, 8, 16, 32): a row of 1 m cubes of 1000 kg, each on a linear
   hydrostatic-like mooring (heave 1e4 N/m, roll and pitch 1e4 N m/rad, weak surge, sway, yaw),
   neighbours hinged about y; a different wave-like heave force on each body held over each 0.01 s step
   (the co-simulation case: a new input every step, so the formulation restarts every step); microseconds
   per step of each formulation (index-3, index-1 and null-space, RK4 for the latter two), and of index-3
   with the increment restart (``Settings(restart="increment")``: one consistent-acceleration solve per
   restart instead of the default's two, whose second also evaluates the model at two shifted poses).
3. The hinge barge (scenarios/hinge_barge.toml, default settings: index-3, 0.02 s macro step,
   0.01 s multibody step, both FMUs through fmpy): real-time factor of the stepping loop and the steady
   surge, heave and pitch errors against the exact frequency-domain answer (the compiled path through fmpy: the
   median and range of 7 runs, the target's row), compiled and Python paths, and
   the compiled path with the slaves called in-process (the FMI layer's share); the stepping loop's
   process CPU time is reported beside the wall clock (the steadier figure on a loaded machine); last, the
   compiled path with one multibody step per macro step (max_step 0.02 s): what the scenario's substeps buy.
   Then seed 000's F3OF decay test 3 (scenarios/f3of_dt3.toml as bundled: index-3, 0.1 s step, three
   bodies, two hinges) over 1500 s: the same figures, and the errors of the period and damping ratio of its
   two free modes fitted to the run (``orchestrator.reference.decay.fit_decay``, 300 s to the end, after the radiation
   kernel) against the linear model's roots (``orchestrator.reference.decay.natural_modes``, as
   tests/test_f3of.py does).
   Then seed 000's 4N3LA and 9N9LA node/link-arm arrays, 20 s of their bundled irregular sea: real-time
   factors on the compiled and the Python path (issue 15: the seed 000 scenarios join the benchmark).

4. The hinge barge against the issue's starting point on this machine: ``wec-cosim run
   scenarios/hinge_barge.toml`` (its printed real-time factor of the stepping loop, through fmpy) by the packages
   and scenario of git revision ``--baseline`` (default a1984a6, main when issue 15 was filed) and by this tree,
   in alternating processes; the ratio of their medians is the speed-up independent of the machine's own speed
   (the issue's target RTF 100 from its RTF 11.6 asks for 8.6x).

Run: python benchmarks/bench_speed.py --out benchmarks/results/speed.txt   (about 5-10 min)
     python benchmarks/bench_speed.py --sections 3                          (part 3 only)
"""

from __future__ import annotations

import argparse
import os

# One BLAS thread: on a loaded 2-core machine OpenBLAS helper threads spin and make the dense solves of the
# Python and null-space paths slower and noisier (docs/multibody.md); set before numpy is imported.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from benchmarks.common import cpu_model, load, revision_tree, write_report  # noqa: E402
from mbd_fmu.bodies import RigidBody  # noqa: E402
from mbd_fmu.formulations import Settings  # noqa: E402
from mbd_fmu.joints import Joint  # noqa: E402
from mbd_fmu.model import MultibodyModel  # noqa: E402
from mbd_fmu.rotations import exp_so3  # noqa: E402
from mbd_fmu.simulator import MultibodySimulator  # noqa: E402
from wec_cosim.benchreport.scaling import floating_row  # noqa: E402

G = 9.81
H = 1e-3
RHO = 0.8
T_END = 1.0
BASELINE = "a1984a6"  # main when issue 15 was filed (its table's "now" column: hinge barge RTF 11.6)
ROD_INERTIA = np.diag([1 / 12, 1 / 12, 1e-6])  # 1 kg, 1 m thin rod along its z axis


class _Clock:
    """Wall and process CPU time since creation: on a loaded machine the CPU time is the steadier figure."""

    def __init__(self) -> None:
        self.wall, self.cpu = time.perf_counter(), time.process_time()

    def per(self, steps: int) -> np.ndarray:
        return np.array([time.perf_counter() - self.wall, time.process_time() - self.cpu]) / steps


# ---------------------------------------------------------------------------------------------- exact answers
def exact_pendulum(t: float) -> np.ndarray:
    """Cg of the rod pendulum (pivot at the origin, released horizontal along +x) at ``t``."""
    sol = solve_ivp(lambda _, y: [y[1], -1.5 * G * np.sin(y[0])], (0, t), [np.pi / 2, 0.0], method="DOP853",
                    rtol=1e-13, atol=1e-13)
    phi = sol.y[0, -1]  # from the downward vertical
    return 0.5 * np.array([np.sin(phi), 0.0, -np.cos(phi)])


def exact_crank(t: float) -> float:
    """Crank angle of the parallelogram four-bar: (5/3) theta'' = -2 g cos theta, theta(0) = pi/2, theta' = -1."""
    sol = solve_ivp(lambda _, y: [y[1], -1.2 * G * np.cos(y[0])], (0, t), [np.pi / 2, -1.0], method="DOP853",
                    rtol=1e-13, atol=1e-13)
    return float(sol.y[0, -1])


# ---------------------------------------------------------------------------------------------- this project
def pendulum_model():
    b = RigidBody("rod", 1.0, ROD_INERTIA, [0, 0, -0.5])
    model = MultibodyModel([b], [Joint("pivot", "revolute", None, "rod", (0, 0, 0), (0, 1, 0))], gravity=(0, 0, -G))
    rot = exp_so3(np.array([0, -np.pi / 2, 0]))
    pose = model.reference.copy()
    pose.r, pose.R = (rot @ np.array([0, 0, -0.5]))[None], rot[None]
    return model, pose, np.zeros(model.n)


def four_bar_model():
    inertia = np.diag([1 / 12, 1e-6, 1 / 12])  # bars along y (cranks); the coupler's is turned below
    bodies = [RigidBody(f"crank{i}", 1.0, inertia, [i, 0.5, 0], (0, 1, 5)) for i in range(2)]
    bodies.append(RigidBody("coupler", 1.0, np.diag([1e-6, 1 / 12, 1 / 12]), [0.5, 1, 0], (0, 1, 5)))
    ax = (0, 0, 1)
    joints = [Joint("g0", "revolute", None, "crank0", (0, 0, 0), ax),
              Joint("g1", "revolute", None, "crank1", (1, 0, 0), ax),
              Joint("c0", "revolute", "crank0", "coupler", (0, 1, 0), ax),
              Joint("c1", "revolute", "crank1", "coupler", (1, 1, 0), ax)]
    model = MultibodyModel(bodies, joints, gravity=(0, -G, 0))
    v6 = np.array([[0.5, 0, 0, 0, 0, -1.0], [0.5, 0, 0, 0, 0, -1.0], [1.0, 0, 0, 0, 0, 0]])
    return model, model.reference.copy(), np.array([v6[model.index(b), d] for b, d in model.coordinates])


def run_ours(build, formulation: str, h: float, steps: int, compiled: bool = True, inputs=None,
             restart: str = "consistent"):
    """(seconds per step, simulator at the end)."""
    model, pose, v = build()
    sim = MultibodySimulator(model, Settings(formulation, spectral_radius=RHO, restart=restart))
    if not compiled:
        sim.formulation.python_path = True
    sim.start(pose, v)
    clock = _Clock()
    for k in range(steps):
        sim.advance(h, None if inputs is None else inputs(k * h, model))
    return clock.per(steps), sim


def pendulum_error(sim) -> float:
    return float(np.linalg.norm(sim.formulation.pose.r[0] - exact_pendulum(sim.time)))


def crank_error(sim) -> float:
    f = sim.formulation
    tip = f.pose.r[0] + f.pose.R[0] @ np.array([0, 0.5, 0])
    return abs(float(np.arctan2(tip[1], tip[0])) - exact_crank(sim.time))


# ---------------------------------------------------------------------------------------------- Exudyn
def _exudyn_settings(exu, steps: int, h: float):
    s = exu.SimulationSettings()
    s.timeIntegration.numberOfSteps = steps
    s.timeIntegration.endTime = steps * h
    s.timeIntegration.generalizedAlpha.spectralRadius = RHO
    s.timeIntegration.verboseMode = 0
    s.solutionSettings.writeSolutionToFile = False
    s.displayComputationTime = False
    s.displayStatistics = False
    return s


def exudyn_pendulum(h: float, steps: int):
    """(seconds per step, cg error at the end) of Exudyn's rod pendulum."""
    import exudyn as exu
    from exudyn.utilities import RigidBodyInertia

    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.CreateGround()
    rot = exp_so3(np.array([0, -np.pi / 2, 0]))
    body = mbs.CreateRigidBody(inertia=RigidBodyInertia(1.0, ROD_INERTIA), referencePosition=[0.5, 0, 0],
                               referenceRotationMatrix=rot.tolist(), gravity=[0, 0, -G])
    mbs.CreateRevoluteJoint(bodyNumbers=[ground, body], position=[0, 0, 0], axis=[0, 1, 0], useGlobalFrame=True)
    node = mbs.GetObject(body)["nodeNumber"]
    mbs.Assemble()
    clock = _Clock()
    mbs.SolveDynamic(_exudyn_settings(exu, steps, h))
    dt = clock.per(steps)
    r = np.array(mbs.GetNodeOutput(node, exu.OutputVariableType.Position))
    return dt, float(np.linalg.norm(r - exact_pendulum(steps * h)))


def exudyn_four_bar(h: float, steps: int):
    """(seconds per step, crank angle error at the end) of Exudyn's planar four-bar (2D rigid bodies)."""
    import exudyn as exu
    import exudyn.itemInterface as ei

    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.AddObject(ei.ObjectGround())
    bars = []
    for pos, v, phi in (((0.0, 0.5), (0.5, 0.0, -1.0), 0.0), ((1.0, 0.5), (0.5, 0.0, -1.0), 0.0),
                        ((0.5, 1.0), (1.0, 0.0, 0.0), 0.0)):
        node = mbs.AddNode(ei.NodeRigidBody2D(referenceCoordinates=[pos[0], pos[1], phi],
                                              initialVelocities=list(v)))
        obj = mbs.AddObject(ei.ObjectRigidBody2D(physicsMass=1.0, physicsInertia=1 / 12, nodeNumber=node))
        mass = mbs.AddMarker(ei.MarkerBodyMass(bodyNumber=obj))
        mbs.AddLoad(ei.LoadMassProportional(markerNumber=mass, loadVector=[0, -G, 0]))
        bars.append((node, obj))

    def marker(obj, local):
        return mbs.AddMarker(ei.MarkerBodyPosition(bodyNumber=obj, localPosition=list(local) + [0.0]))

    pairs = [(marker(ground, (0, 0)), marker(bars[0][1], (0, -0.5))),
             (marker(ground, (1, 0)), marker(bars[1][1], (0, -0.5))),
             (marker(bars[0][1], (0, 0.5)), marker(bars[2][1], (-0.5, 0))),
             (marker(bars[1][1], (0, 0.5)), marker(bars[2][1], (0.5, 0)))]
    for m1, m2 in pairs:
        mbs.AddObject(ei.ObjectJointRevolute2D(markerNumbers=[m1, m2]))
    mbs.Assemble()
    clock = _Clock()
    mbs.SolveDynamic(_exudyn_settings(exu, steps, h))
    dt = clock.per(steps)
    x, y, phi = mbs.GetNodeOutput(bars[0][0], exu.OutputVariableType.Coordinates)[:3]
    # crank 0's cg moved by (x, y) from (0, 0.5) and turned by phi from +90 degrees
    return dt, abs(np.pi / 2 + phi - exact_crank(steps * h))


# ---------------------------------------------------------------------------------------------- N bodies
_HEAVE: dict = {}


def wave_inputs(t: float, model) -> np.ndarray:
    """A wave-like heave force on each body, a new value every step (slots looked up once per model)."""
    if id(model) not in _HEAVE:
        _HEAVE.clear()
        _HEAVE[id(model)] = np.array([model.slot_of(f"b{i}", 2) for i in range(model.N)])
    f = np.zeros(model.n)
    f[_HEAVE[id(model)]] = 2e3 * np.sin(2.0 * t - 0.7 * np.arange(model.N))
    return f


# ---------------------------------------------------------------------------------------------- hinge barge
def run_scene(name: str, compiled: bool, duration: float | None, in_process: bool = False,
              max_step: float | None = None):
    """(wall and CPU real-time factors of the stepping loop, the run's result, its results) of a bundled
    scenario, through fmpy unless ``in_process``; ``duration`` None: the scenario's own; ``max_step``: the
    multibody substep instead of the scenario's."""
    from orchestrator.cosim import masters
    from orchestrator.cosim.simulation import run_scenario
    from orchestrator.results import read_results
    from orchestrator.scenario import load_scenario

    s = load_scenario(ROOT / "scenarios" / f"{name}.toml")
    if duration is not None:
        s.simulation.duration = duration
    if max_step is not None:
        s.multibody.max_step = max_step
    env = dict(os.environ)
    if not compiled:
        os.environ["WEC_COSIM_NO_JIT"] = "1"
    run, cpu = masters.Master.run, []

    def timed(self, *args, **kwargs):  # noqa: ANN001, ANN002, ANN003, ANN202 - the stepping loop's CPU time
        start = time.process_time()
        try:
            return run(self, *args, **kwargs)
        finally:
            cpu.append(time.process_time() - start)

    masters.Master.run = timed
    try:
        with tempfile.TemporaryDirectory() as tmp:
            result = run_scenario(s, Path(tmp) / "run.h5", progress=False, log=None, in_process=in_process)
            data = read_results(result.path)
    finally:
        masters.Master.run = run
        os.environ.clear()
        os.environ.update(env)
    sim = s.simulation.duration
    return (sim / result.wall_time, sim / cpu[-1]), result, data


def hinge_barge(compiled: bool, duration: float, in_process: bool = False,
                max_step: float | None = None) -> tuple[tuple[float, float], list]:
    """((wall, CPU) real-time factors of the stepping loop, comparisons with the frequency-domain answer)."""
    rtf, result, _ = run_scene("hinge_barge", compiled, duration, in_process, max_step)
    return rtf, result.comparisons


def f3of_dt3_errors(data: dict, window_start: float = 20.0) -> list[tuple[float, float]]:
    """F3OF DT3: (period, damping ratio) relative errors of its two free modes fitted from ``window_start`` to the
    end of the run against the linear model's roots (``wec_cosim.benchreport.errors.decay_modes``, as
    tests/test_f3of.py)."""
    from orchestrator.scenario import load_scenario
    from orchestrator.scene import load_scene
    from wec_cosim.benchreport.errors import decay_modes

    return decay_modes(load_scene(load_scenario(ROOT / "scenarios" / "f3of_dt3.toml"), log=None), data, window_start)


# ---------------------------------------------------------------------------------------------- report
def best(fn, repeats: int):
    """Minimum (wall, CPU) seconds of ``repeats`` runs of ``fn() -> ((wall, cpu), extra)`` and the last extra."""
    out = [fn() for _ in range(repeats)]
    return np.min([o[0] for o in out], axis=0), out[-1][1]


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", default="", help="also write the report to this file")
    p.add_argument("--quick", action="store_true", help="fewer repeats and steps (a smoke run)")
    p.add_argument("--sections", default="1234", help="which parts to run (default 1234: all)")
    p.add_argument("--baseline", default=BASELINE, help=f"git revision of part 4 (default {BASELINE}: main when "
                   "issue 15 was filed)")
    args = p.parse_args()
    repeats = 1 if args.quick else 5
    steps = int(T_END / H)
    lines = [f"# command: python benchmarks/bench_speed.py {' '.join(sys.argv[1:])}".rstrip(),
             f"# machine: {platform.node()}, {platform.machine()}, {cpu_model()}, {os.cpu_count()} cores, python "
             f"{platform.python_version()}, numpy {np.__version__}; load average at start "
             f"{load()}; OPENBLAS_NUM_THREADS="
             f"{os.environ.get('OPENBLAS_NUM_THREADS')}"]
    try:
        import exudyn
        import numba

        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                                cwd=ROOT).stdout.strip()
        lines.append(f"# exudyn {exudyn.__version__}, numba {numba.__version__}; git {commit}")
    except ImportError as exc:
        lines.append(f"# {exc}")
    t_start = time.perf_counter()
    # warm the compiled kernels (loaded from the on-disk cache, or compiled once) outside the timings
    run_ours(pendulum_model, "index3", H, 2)
    lines.append(f"# kernels ready in {time.perf_counter() - t_start:.2f} s (cache load or first compilation)")

    if "1" in args.sections:
        section_1(lines, repeats, steps)
    if "2" in args.sections:
        section_2(lines, repeats, args.quick)
    if "3" in args.sections:
        section_3(lines, args.quick)
    if "4" in args.sections:
        section_4(lines, args.baseline, 1 if args.quick else 3)
    lines.append(f"# load average at the end {load()}; "
                 f"benchmark wall time {time.perf_counter() - t_start:.0f} s")
    write_report(lines, args.out)


def section_1(lines: list[str], repeats: int, steps: int) -> None:
    lines += ["", "## 1. Issue table: project vs Exudyn, h = 1 ms, spectral radius 0.8, 1 s simulated; us per step "
              f"(minimum of {repeats} runs, the engines alternating), wall clock and process CPU time",
              f"{'mechanism':<12}{'engine':<22}{'wall us':>9}{'ratio':>7}{'CPU us':>9}{'ratio':>7}{'error at 1 s':>15}"]
    for name, build, err, exu in (("pendulum", pendulum_model, pendulum_error, exudyn_pendulum),
                                  ("four-bar", four_bar_model, crank_error, exudyn_four_bar)):
        runs = {"exu": [], "fast": []}
        for _ in range(repeats):  # alternate, so that both see the same load
            runs["exu"].append(exu(H, steps))
            runs["fast"].append(run_ours(build, "index3", H, steps))
        t_exu, e_exu = np.min([r[0] for r in runs["exu"]], axis=0), runs["exu"][-1][1]
        t_fast, sim = np.min([r[0] for r in runs["fast"]], axis=0), runs["fast"][-1][1]
        t_py, sim_py = run_ours(build, "index3", H, steps, compiled=False)
        for engine, t, e in (("exudyn 1.13.6", t_exu, e_exu), ("project compiled", t_fast, err(sim)),
                             ("project python path", t_py, err(sim_py))):
            lines.append(f"{name:<12}{engine:<22}{t[0] * 1e6:9.1f}{t[0] / t_exu[0]:7.2f}{t[1] * 1e6:9.1f}"
                         f"{t[1] / t_exu[1]:7.2f}{e:15.3e}")
        print("\n".join(lines[-3:]), flush=True)
    lines.append(f"# load average now {load()}")


def section_2(lines: list[str], repeats: int, quick: bool) -> None:
    lines += ["", "## 2. N floating bodies (row of hinged cubes on moorings), h = 0.01 s, new input every step; "
              "us per step, wall and CPU (index-3 and index-1 compiled; null-space: Python stepping, compiled solves); "
              "'incr': index-3 with restart = 'increment' (one consistent-acceleration solve per restart instead of "
              "two, order 2 kept: tests/test_multibody_mechanisms.py; results differ from the default restart "
              "within the method's error, column 'diff': largest cg position difference after the run, m)",
              f"{'N':>4}{'coords':>8}{'index3':>10}{'cpu':>8}{'incr':>8}{'cpu':>8}{'diff':>9}{'index1':>10}{'cpu':>8}"
              f"{'nullspace':>10}{'cpu':>8}"]
    for n in (1, 2, 4, 8, 16, 32):
        k = max(20, 400 // n) if not quick else 20
        row, sims = [], []
        for f, restart in (("index3", "consistent"), ("index3", "increment"), ("index1", "consistent"),
                           ("nullspace", "consistent")):
            t, sim = best(lambda f=f, n=n, k=k, restart=restart: run_ours(
                lambda: floating_row(n), f, 0.01, k, inputs=wave_inputs, restart=restart), repeats)
            row.append(t)
            sims.append(sim)
        diff = float(np.abs(sims[0].formulation.pose.r - sims[1].formulation.pose.r).max())
        cells = [f"{r[0] * 1e6:10.0f}{r[1] * 1e6:8.0f}" for r in row]
        cells[1] = f"{row[1][0] * 1e6:8.0f}{row[1][1] * 1e6:8.0f}{diff:9.1e}"
        lines.append(f"{n:4d}{6 * n:8d}" + "".join(cells))
        print(lines[-1], flush=True)
    lines.append(f"# load average now {load()}")

    from benchmarks.bench_multibody import chain

    lines += ["", "## 2b. The issue's 40-body case: bench_multibody's hanging chain of 40 links on revolute joints, "
              "h = 1 ms, no input; us per step, wall and CPU",
              f"{'N':>4}{'coords':>8}{'index3':>10}{'cpu':>8}{'index1':>10}{'cpu':>8}{'nullspace':>10}{'cpu':>8}"]
    for n in (20, 40):
        k = 10 if quick else 60
        row = [best(lambda f=f, n=n, k=k: (run_ours(lambda: (*chain(n), np.zeros(6 * n)), f, H, k)[0], None),
                    min(repeats, 3))[0] for f in ("index3", "index1", "nullspace")]
        lines.append(f"{n:4d}{6 * n:8d}" + "".join(f"{r[0] * 1e6:10.0f}{r[1] * 1e6:8.0f}" for r in row))
        print(lines[-1], flush=True)
    lines.append(f"# load average now {load()}")


def section_3(lines: list[str], quick: bool) -> None:
    duration = 10.0 if quick else 40.0
    lines += ["", f"## 3. Hinge barge, default settings, {duration:g} s through fmpy: real-time factor of the stepping "
              "loop (wall clock; process CPU time) and steady errors against the frequency-domain answer",
              f"{'path':<30}{'RTF':>8}{'CPU':>7}  errors (amplitude %, phase deg)"]
    # The last row: the scenario's multibody substep (max_step 0.01 s, two per macro step) against one substep per
    # macro step, at the same macro step: what the substeps buy in accuracy and cost.
    # The target row (compiled, through fmpy) is run `runs` times: this VM's wall clock varies 30-60 % from run to
    # run, so its median and range are printed (the other rows: one run each).
    runs = 1 if quick else 7
    for label, compiled, in_process, max_step in (
            ("compiled", True, False, None), ("python", False, False, None),
            ("compiled, in-process slaves", True, True, None), ("compiled, max_step 0.02 s", True, False, 0.02)):
        samples = [hinge_barge(compiled, duration, in_process, max_step) for _ in range(runs if label == "compiled"
                                                                                        else 1)]
        wall, cpu = (np.array([rtfs[k] for rtfs, _ in samples]) for k in (0, 1))
        comps = samples[-1][1]
        errs = ", ".join(f"{c.label} {100 * c.amplitude_error:+.2f}%/{c.phase_error_deg:+.2f}" for c in comps
                         if any(k in c.label for k in ("surge", "heave", "pitch", "power")))
        lines.append(f"{label:<30}{np.median(wall):8.1f}{np.median(cpu):7.1f}  {errs}")
        print(lines[-1], flush=True)
        if len(samples) > 1:
            lines.append(f"{'':<30}(median of {len(samples)} runs; wall RTF {wall.min():.1f}-{wall.max():.1f}, "
                         f"CPU {cpu.min():.1f}-{cpu.max():.1f}: " + " ".join(f"{x:.1f}" for x in wall) + ")")
            print(lines[-1], flush=True)
    lines.append(f"# load average now {load()}")
    duration, start = (30.0, 20.0) if quick else (1500.0, 300.0)
    lines += ["", "## 3b. F3OF decay test 3 (seed 000), as bundled (index-3, 0.1 s step, 10 deg start) over "
              f"{duration:g} s through fmpy: real-time factor (target >= 100) and the two free modes' period and "
              f"damping-ratio errors against the linear model's roots (fit from {start:g} s to the end: after the "
              "240 s radiation kernel, "
              "whose start from rest moves the almost undamped mirror-wise mode's fitted damping by ~10 % when the "
              "window begins inside it; at the bundled 0.1 s step that mode's damping is ~3 % low, the step's error: "
              "benchmarks/bench_f3of_dt3_mirror.py, docs/f3of.md)",
              f"{'path':<30}{'RTF':>8}{'CPU':>7}  errors (period %, damping ratio %: same-way mode; mirror mode)"]
    for label, in_process in (("compiled", False), ("compiled, in-process slaves", True)):
        (rtf, rtf_cpu), _, data = run_scene("f3of_dt3", True, duration, in_process)
        errs = "; ".join(f"{100 * p:+.2f}%, {100 * d:+.1f}%" for p, d in f3of_dt3_errors(data, start))
        lines.append(f"{label:<30}{rtf:8.1f}{rtf_cpu:7.1f}  {errs}")
        print(lines[-1], flush=True)
    duration = 5.0 if quick else 20.0
    lines += ["", f"## 3c. Seed 000's node/link-arm arrays (scenarios/array_4n3la.toml, array_9n9la.toml as bundled: "
              f"index-3, 0.025 s step, irregular sea) over {duration:g} s through fmpy: real-time factor of the "
              "stepping loop on the compiled path (ropes, PTOs on the spherical joints' rotation-vector components) "
              "and on the Python path",
              f"{'scene':<16}{'path':<14}{'RTF':>8}{'CPU':>7}"]
    for name in ("array_4n3la", "array_9n9la"):
        for label, compiled in (("compiled", True), ("python", False)):
            (rtf, rtf_cpu), _, _ = run_scene(name, compiled, duration)
            lines.append(f"{name:<16}{label:<14}{rtf:8.2f}{rtf_cpu:7.2f}")
            print(lines[-1], flush=True)
    lines.append(f"# load average now {load()}")


def printed_rtf(tree: Path, out: Path) -> float:
    """The real-time factor that ``wec-cosim run scenarios/hinge_barge.toml`` prints when run from ``tree``'s
    packages and scenario (the stepping loop's wall clock, through fmpy)."""
    env = {**os.environ, "PYTHONPATH": str(tree)}
    entry = "wec_cosim.cli" if (tree / "wec_cosim" / "cli.py").is_file() else "orchestrator.cli"  # before the layout
    run = subprocess.run([sys.executable, "-m", entry, "run", "scenarios/hinge_barge.toml", "--out",
                          str(out)], cwd=tree, env=env, capture_output=True, text=True, check=True)
    return float(run.stdout.rsplit("real-time factor", 1)[1].split()[0])


def section_4(lines: list[str], baseline: str, rounds: int) -> None:
    lines += ["", f"## 4. Hinge barge against issue 15's starting point on this machine: `wec-cosim run "
              f"scenarios/hinge_barge.toml` (printed RTF, through fmpy) by revision {baseline} and by this tree, "
              f"{rounds} rounds in alternating processes",
              f"{'tree':<30}{'median RTF':>11}  runs"]
    rtfs: dict[str, list[float]] = {baseline: [], "this tree": []}
    with tempfile.TemporaryDirectory() as tmp:
        old = revision_tree(baseline, Path(tmp), ["fmu_base", "hydro_fmu", "mbd_fmu", "orchestrator",
                                                  "scenarios/hinge_barge.toml"])
        (old / "scenarios" / "hydro_cache").symlink_to(ROOT / "scenarios" / "hydro_cache")
        for _ in range(rounds):
            for label, tree in ((baseline, old), ("this tree", ROOT)):
                rtfs[label].append(printed_rtf(tree, Path(tmp) / "run.h5"))
    for label, values in rtfs.items():
        lines.append(f"{label:<30}{np.median(values):11.1f}  " + " ".join(f"{v:.1f}" for v in values))
    lines.append(f"{'speed-up (ratio of medians)':<30}{np.median(rtfs['this tree']) / np.median(rtfs[baseline]):11.1f}"
                 "  (issue 15 asks for 100 / 11.6 = 8.6)")
    print("\n".join(lines[-3:]), flush=True)
    lines.append(f"# load average now {load()}")


if __name__ == "__main__":
    main()
