"""Cost per step of the multibody formulations against the number of bodies, and against Exudyn.

Mechanism: an open chain of N uniform links (1 m, 1 kg, thin rods) hanging from the ground, joined
by revolute joints about y, under gravity, released from 30 degrees (6 N coordinates, 5 N
constraint equations, N degrees of freedom). For each formulation the median wall time per step
over a run is measured side by side in one process; Exudyn (if importable; a benchmark-only
comparison, not a dependency) runs the same chain with its generalised-alpha index-3 solver.

Run: python benchmarks/bench_multibody.py [--quick] > benchmarks/results/multibody.txt
"""

from __future__ import annotations

import argparse
import platform
import sys
import time

import numpy as np

from mbd_fmu.bodies import RigidBody
from mbd_fmu.formulations import Settings
from mbd_fmu.joints import Joint
from mbd_fmu.model import MultibodyModel
from mbd_fmu.rotations import exp_so3
from mbd_fmu.simulator import MultibodySimulator

G = 9.81
TILT = np.radians(30.0)


def chain(n: int) -> tuple[MultibodyModel, object]:
    """Chain hanging along -z at equilibrium; start pose rotated by 30 deg about y about the pivot."""
    u = np.array([0.0, 0.0, 1.0])
    inertia = 1.0 / 12 * (np.eye(3) - np.outer(u, u)) + 1e-3 * np.outer(u, u)
    bodies = [RigidBody(f"link{i}", 1.0, inertia, [0, 0, -(i + 0.5)]) for i in range(n)]
    joints = [Joint("j0", "revolute", None, "link0", (0, 0, 0), (0, 1, 0))]
    joints += [Joint(f"j{i}", "revolute", f"link{i - 1}", f"link{i}", (0, 0, -i), (0, 1, 0)) for i in range(1, n)]
    model = MultibodyModel(bodies, joints, gravity=(0, 0, -G))
    rot = exp_so3(np.array([0.0, TILT, 0.0]))
    pose = model.reference.copy()
    pose.r = (rot @ pose.r.T).T
    pose.R = np.repeat(rot[None], n, axis=0)
    return model, pose


def ours(n: int, formulation: str, h: float, steps: int) -> float:
    model, pose = chain(n)
    sim = MultibodySimulator(model, Settings(formulation, spectral_radius=0.8))
    sim.start(pose, np.zeros(model.n))
    times = []
    for _ in range(steps):
        t0 = time.perf_counter()
        sim.advance(h)
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def exudyn_chain(n: int, h: float, steps: int) -> float | None:
    try:
        import exudyn as exu
        from exudyn.utilities import InertiaCuboid
    except ImportError:
        return None
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.CreateGround()
    rot = exp_so3(np.array([0.0, TILT, 0.0]))
    inertia = InertiaCuboid(1.0e4, sideLengths=[0.01, 0.01, 1.0])  # 1 kg, thin: close to our rod
    previous = ground
    for i in range(n):
        centre = rot @ np.array([0.0, 0.0, -(i + 0.5)])
        body = mbs.CreateRigidBody(inertia=inertia, referencePosition=list(centre),
                                   referenceRotationMatrix=rot.tolist(), gravity=[0, 0, -G])
        pivot = rot @ np.array([0.0, 0.0, -float(i)])
        mbs.CreateRevoluteJoint(bodyNumbers=[previous, body], position=list(pivot), axis=[0, 1, 0],
                                useGlobalFrame=True)
        previous = body
    mbs.Assemble()
    settings = exu.SimulationSettings()
    settings.timeIntegration.numberOfSteps = steps
    settings.timeIntegration.endTime = steps * h
    settings.timeIntegration.generalizedAlpha.spectralRadius = 0.8
    settings.timeIntegration.verboseMode = 0
    settings.solutionSettings.writeSolutionToFile = False
    settings.displayComputationTime = False
    settings.displayStatistics = False
    t0 = time.perf_counter()
    mbs.SolveDynamic(settings)
    return (time.perf_counter() - t0) / steps


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--quick", action="store_true", help="fewer steps")
    args = p.parse_args()
    h = 1e-3
    sizes = (1, 2, 5, 10, 20, 40)
    print(f"# command: python benchmarks/bench_multibody.py{' --quick' if args.quick else ''}")
    print(f"# python {platform.python_version()}, numpy {np.__version__}, {platform.machine()}; "
          f"h = {h} s; median wall time per step (ms)")
    try:
        import exudyn

        print(f"# exudyn {exudyn.__version__}")
    except ImportError:
        print("# exudyn: not installed (pip install exudyn to add the comparison)")
    print(f"{'bodies':>7}{'coords':>8}{'index3':>10}{'index1':>10}{'nullspace':>11}{'exudyn':>10}")
    for n in sizes:
        steps = max(10, (60 if args.quick else 300) // n)
        row = [ours(n, f, h, steps) * 1e3 for f in ("index3", "index1", "nullspace")]
        ex = exudyn_chain(n, h, 10 * steps)
        ex_text = f"{ex * 1e3:10.3f}" if ex is not None else f"{'-':>10}"
        print(f"{n:7d}{6 * n:8d}{row[0]:10.3f}{row[1]:10.3f}{row[2]:11.3f}{ex_text}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
