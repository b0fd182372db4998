"""Write the scenario files of the InWave+H paper's node/link-arm arrays, 4N3LA and 9N9LA, from their geometry.

    python scenarios/data/arrays/generate.py          # rewrites scenarios/array_4n3la.toml, array_9n9la.toml

Every number of the two scenes is derived here, by trigonometry, from the InWave+H paper's Table 2 (the
4N3LA node positions), the link-arm length of 1.4 m and the estimates listed in ``NODE``,
``ARM``, ``MOORING`` and ``PTO`` below (docs/arrays.md says where each comes from). A test checks
that the committed scenario files are what this script writes.

Layout (plan view, waves along +x; labels ours, as the InWave+H paper's Figure 9 is not in our copy):

* 4N3LA ("Squid"): the centre node C1 and the three nodes S1, S2, S3 at 1.4 m from it, 120 deg
  apart (Table 2); link arms LA1 = C1-S1, LA2 = C1-S2, LA3 = C1-S3. S2 is the rear node.
* 9N9LA ("Hex"): a honeycomb cell of side 1.4 m upstream of C1. Its six vertices alternate
  between three-arm nodes C1, C2, C3 (arms at 0, 120, 240 deg) and two-arm nodes D1, D2, D3
  (arms at 60, 180, 300 deg); each C node carries a third arm out of the hexagon to a one-arm
  node S. C1 and S2 (and LA2 = C1-S2) are where they are in 4N3LA; D1, D2 take the places of
  4N3LA's S3, S1. The six hexagon nodes and six hexagon link arms are the closed loop.

Spherical joints sit at the node's vertical axis, at the link arms' depth (0.4 m), at both ends of
every arm (node centres 1.4 m apart: the arm length). The joint frame of each (arm, node) joint
has x along the arm (from the arm's centre outwards to this node), z up; its coordinates are the
rotation vector of the node relative to the arm in that frame: [relative roll, pitch, yaw]. Two
PTOs per joint act on coordinates 2 (pitch) and 3 (yaw).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
SCENARIOS = HERE.parent.parent

ARM_LENGTH = 1.4  # m, the InWave+H paper (link-arm length estimate; also the node spacing of Table 2)
ARM_DEPTH = 0.4  # m, the InWave+H paper: link-arm centre of gravity at 0.4 m depth; the joints on the same line
NODE_CG_DEPTH = 0.3  # m, the InWave+H paper Table 2 (CoG z = -0.3 for every node)
RHO, G = 1000.0, 9.81  # fresh water (tank-scale device)

# 4N3LA node positions, the InWave+H paper Table 2 (x, y) in m, as printed: rounded to 1 cm.
TABLE_2 = {"S3": (0.0, 0.0), "C1": (0.7, -1.21), "S1": (0.0, -2.42), "S2": (2.1, -1.21)}
# The trigonometry behind them: S3 at the origin, C1 at 1.4 m and -60 deg, S1 and S2 at 1.4 m from C1
# at 240 and 0 deg (so 1.21 is 1.4 sin 60 = 1.2124). The scenes use the unrounded values: with the
# rounded ones the three arms are 1.3979, 1.3979 and 1.4 m long and 0.05 deg off 120 deg apart, and
# the mooring pretension no longer balances at C1 (the reference pose is not an equilibrium).
C1 = np.array([0.0, 0.0]) + ARM_LENGTH * np.array([math.cos(math.radians(-60)), math.sin(math.radians(-60))])


@dataclass(frozen=True)
class NodeEstimate:
    """A node as a vertical cylinder (the InWave+H paper's Figure 10 gives dimensions we do not have: estimates)."""

    radius: float = 0.25  # m
    draft: float = 0.5  # m (below the cg at 0.3 m depth: centre of buoyancy 0.05 m above the cg)
    height: float = 0.7  # m, whole height (0.2 m freeboard) for the inertia
    panel_size: float = 0.085  # m: 19 panels round, 6 down, 3 across the bottom (171 per node)
    # Linear viscous damping (surge..yaw): about 5 % of critical in heave, roll and pitch. Potential flow
    # alone damps this deep float's heave by 1.2 % of critical at its resonance (3.8 rad/s) and its pitch
    # by less than 1 %; tank floats of this size see several per cent from viscous losses.
    linear_damping: tuple[float, ...] = (20.0, 20.0, 50.0, 2.5, 2.5, 1.0)  # N s/m, N m s/rad

    def panels_round(self) -> int:
        """Sides of the polygon Capytaine meshes the cylinder with (hydro_fmu.bem._primitive_mesh)."""
        return max(12, math.ceil(2 * math.pi * self.radius / self.panel_size))

    def volume(self) -> float:
        """Displaced volume of the meshed (polygonal) cylinder, m^3: what the database holds."""
        n = self.panels_round()
        return 0.5 * n * self.radius**2 * math.sin(2 * math.pi / n) * self.draft

    def inertia(self, mass: float) -> list[float]:
        """Solid cylinder of the whole height about its centre (kg m^2): Ixx = Iyy, Izz."""
        side = mass * (3 * self.radius**2 + self.height**2) / 12
        return [side, side, mass * self.radius**2 / 2]


@dataclass(frozen=True)
class ArmEstimate:
    """A link arm: a neutrally buoyant tube (the InWave+H paper gives no mass: estimate)."""

    mass: float = 10.0  # kg (a 0.1 m tube of 1.4 m displaces about 11 l)
    radius: float = 0.05  # m, for the axial inertia

    def inertia_world(self, direction: np.ndarray) -> list[float]:
        """Thin tube about its centre, world axes: [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] (kg m^2)."""
        axial, transverse = self.mass * self.radius**2 / 2, self.mass * ARM_LENGTH**2 / 12
        u = direction / np.linalg.norm(direction)
        tensor = transverse * np.eye(3) + (axial - transverse) * np.outer(u, u)
        return [tensor[0, 0], tensor[1, 1], tensor[2, 2], tensor[0, 1], tensor[0, 2], tensor[1, 2]]


@dataclass(frozen=True)
class SpinHold:
    """A weak rotary spring-damper on the relative roll (about the arm) at one end of each arm. Two spherical
    joints leave an arm free to spin about its own axis: a mode of zero stiffness and damping that the
    second-order part of the pitch and yaw PTO torques drives (their rotation-vector Jacobians mix in the
    roll). Small against the PTOs and the nodes' roll stiffness (77 N m/rad)."""

    stiffness: float = 2.0  # N m/rad
    damping: float = 1.0  # N m s/rad


@dataclass(frozen=True)
class MooringEstimate:
    """A taut mooring line of two rope segments joined at a point mass ("rope connection points as
    3D mass elements", the InWave+H paper), radially outwards from the array at 45 deg down to an anchor."""

    horizontal: float = 3.0  # m from fairlead to anchor
    depth: float = 3.0  # m from fairlead down to anchor
    tension: float = 60.0  # N pretension (the lines stay taut in the scenes' seas)
    stiffness: float = 1000.0  # N/m per segment (EA / segment length)
    damping: float = 100.0  # N s/m per segment (damps the lines' axial mode and the array's slow drift on them)
    point_mass: float = 5.0  # kg, neutrally buoyant connection (shackle and float)

    @property
    def segment(self) -> float:
        return 0.5 * math.hypot(self.horizontal, self.depth)

    @property
    def vertical_pull(self) -> float:
        """Downward pull of one line on its node (N)."""
        return self.tension * self.depth / math.hypot(self.horizontal, self.depth)

    @property
    def free_length(self) -> float:
        return self.segment - self.tension / self.stiffness


@dataclass(frozen=True)
class PtoEstimate:
    """Baseline penalty PTO on relative pitch and yaw (the InWave+H paper: "similar efforts to the hydrostatic
    stiffness and radiation damping"): a node's pitch hydrostatic stiffness rho g (I_wp + V (z_b - z_g))
    and about its pitch radiation damping near the pitch resonance (docs/arrays.md)."""

    stiffness: float = 80.0  # N m/rad
    damping: float = 4.0  # N m s/rad


NODE, ARM, MOORING, PTO, SPIN = NodeEstimate(), ArmEstimate(), MooringEstimate(), PtoEstimate(), SpinHold()


def polar(angle_deg: float, length: float = ARM_LENGTH) -> np.ndarray:
    a = math.radians(angle_deg)
    return length * np.array([math.cos(a), math.sin(a)])


def layout_4n3la() -> tuple[dict[str, np.ndarray], list[tuple[str, str, str]], list[str]]:
    """Node positions (x, y), link arms (name, node, node) and moored nodes of 4N3LA (Table 2, unrounded)."""
    nodes = {"S3": np.zeros(2), "C1": C1, "S1": C1 + polar(240), "S2": C1 + polar(0)}
    arms = [("LA1", "C1", "S1"), ("LA2", "C1", "S2"), ("LA3", "C1", "S3")]
    return nodes, arms, ["S1", "S2", "S3"]


def layout_9n9la() -> tuple[dict[str, np.ndarray], list[tuple[str, str, str]], list[str]]:
    """Node positions, link arms and moored nodes of 9N9LA (module docstring), from C1 and the arm length.

    From C1 the honeycomb steps along 120 and 240 deg to D1 and D2 (4N3LA's S3 and S1), from D1 and
    D2 along 180 deg to C2 and C3, from C2 along 240 deg to D3; S nodes leave C2 at 120 deg and C3
    at 240 deg (C1's is S2 at 0 deg).
    """
    c1 = C1
    d1, d2 = c1 + polar(120), c1 + polar(240)
    c2, c3 = d1 + polar(180), d2 + polar(180)
    d3 = c2 + polar(240)
    nodes = {"C1": c1, "C2": c2, "C3": c3, "D1": d1, "D2": d2, "D3": d3,
             "S1": c3 + polar(240), "S2": c1 + polar(0), "S3": c2 + polar(120)}
    arms = [("LA1", "C1", "D2"), ("LA2", "C1", "S2"), ("LA3", "C1", "D1"), ("LA4", "C2", "S3"),
            ("LA5", "D1", "C2"), ("LA6", "C2", "D3"), ("LA7", "D3", "C3"), ("LA8", "C3", "S1"),
            ("LA9", "C3", "D2")]
    return nodes, arms, ["S1", "S2", "S3", "D1", "D2", "D3"]


def fmt(v: float) -> str:
    r = round(float(v), 10)
    return repr(0.0 if r == 0 else r)


def vec(values) -> str:
    return "[" + ", ".join(fmt(v) for v in values) + "]"


def scenario_text(name: str, layout, header: str, waves: str, simulation: str, hydro_grid: str) -> str:
    nodes, arms, moored = layout
    centre = np.mean([nodes[n] for n in moored], axis=0)
    volume = NODE.volume()
    out = [header.rstrip(), f'name = "{name}"', ""]
    out += [simulation.strip(), "", "[environment]", f"rho = {fmt(RHO)}", f"g = {fmt(G)}",
            "water_depth = inf        # deep water (the tank depth is not given; finite depth is 5x dearer)",
            "", waves.strip(), "", "[hydro]", hydro_grid.strip(),
            "headings_deg = [0.0]",
            "irf_duration = 60.0     # s: node-to-node kernels outlast 15 s (docs/arrays.md: kernel vs database)",
            "irf_d_omega = 0.02      # B resampled for the impulse response",
            "damping_tail = 3.0      # B continued as B(12) (12/omega)^3 above the database",
            'added_mass_inf = "ogilvie"', "",
            "[rao]", "omega = { start = 0.5, stop = 12.0, step = 0.05 }   # the sea's range: irregular statistics", "",
            "[multibody]", 'formulation = "index3"', "spectral_radius = 0.8", ""]
    for n, xy in nodes.items():
        cg = [xy[0], xy[1], -NODE_CG_DEPTH]
        mass = RHO * volume - (MOORING.vertical_pull / G if n in moored else 0.0)
        out += ["[[bodies]]", f'name = "{n}"', f"cg = {vec(cg)}", f"mass = {fmt(mass)}",
                f"inertia = {vec(NODE.inertia(mass))}", f"linear_damping = {vec(NODE.linear_damping)}",
                "[bodies.geometry]", 'shape = "vertical_cylinder"', f"radius = {fmt(NODE.radius)}",
                f"draft = {fmt(NODE.draft)}", f"position = {vec([xy[0], xy[1], 0.0])}",
                f"panel_size = {fmt(NODE.panel_size)}", ""]
    for a, n1, n2 in arms:
        p1, p2 = nodes[n1], nodes[n2]
        mid = (p1 + p2) / 2
        d = np.array([*(p2 - p1), 0.0])
        out += ["[[bodies]]", f'name = "{a}"', f"cg = {vec([mid[0], mid[1], -ARM_DEPTH])}",
                f"mass = {fmt(ARM.mass)}", f"inertia = {vec(ARM.inertia_world(d))}", "hydro = false",
                f"buoyancy = {fmt(ARM.mass * G)}    # neutrally buoyant", ""]
    joints, ptos = [], []
    for a, n1, n2 in arms:
        for n, other in ((n1, n2), (n2, n1)):
            p, q = nodes[n], nodes[other]
            outward = np.array([*(p - q), 0.0]) / np.linalg.norm(p - q)
            j = f"{a}_{n}"
            joints += ["[[joints]]", f'name = "{j}"', 'kind = "spherical"', f'body1 = "{a}"', f'body2 = "{n}"',
                       f"position = {vec([p[0], p[1], -ARM_DEPTH])}", "axis = [0.0, 0.0, 1.0]",
                       f"axis2 = {vec(outward)}", ""]
            for k, dof in ((2, "pitch"), (3, "yaw")):
                ptos += ["[[ptos]]", f'name = "{j}_{dof}"', f'body = "{n}"', f'joint = "{j}"',
                         f"joint_coordinate = {k}", f"stiffness = {fmt(PTO.stiffness)}",
                         f"damping = {fmt(PTO.damping)}", ""]
    moorings, forces = [], []
    for a, n1, _ in arms:
        forces += ["[[forces]]", f'name = "{a}_spin"', 'kind = "rotary_spring_damper"', f'joint = "{a}_{n1}"',
                   f"stiffness = {fmt(SPIN.stiffness)}", f"damping = {fmt(SPIN.damping)}", ""]
    for n in moored:
        p = nodes[n]
        e = (p - centre) / np.linalg.norm(p - centre)
        fair = np.array([p[0], p[1], -ARM_DEPTH])
        anchor = fair + np.array([*(MOORING.horizontal * e), -MOORING.depth])
        mid = (fair + anchor) / 2
        pm = f"{n}_line"
        moorings += ["[[bodies]]", f'name = "{pm}"', f"cg = {vec(mid)}", f"mass = {fmt(MOORING.point_mass)}",
                     "point_mass = true", 'dofs = ["surge", "sway", "heave"]', "hydro = false",
                     f"buoyancy = {fmt(MOORING.point_mass * G)}    # neutrally buoyant", ""]
        for seg, (b1, q1, b2, q2) in (("upper", (n, fair, pm, mid)), ("lower", ("ground", anchor, pm, mid))):
            forces += ["[[forces]]", f'name = "{n}_rope_{seg}"', 'kind = "rope"', f'body1 = "{b1}"',
                       f'body2 = "{b2}"', f"point1 = {vec(q1)}", f"point2 = {vec(q2)}",
                       f"stiffness = {fmt(MOORING.stiffness)}", f"damping = {fmt(MOORING.damping)}",
                       f"free_length = {fmt(MOORING.free_length)}", ""]
    return "\n".join(out + moorings + joints + ptos + forces).rstrip() + "\n"


HEADER = """# {title}: the InWave+H paper (section IV, Table 2), node/link-arm {what}.
# GENERATED by scenarios/data/arrays/generate.py (edit that script, not this file); docs/arrays.md
# explains every number. Nodes: vertical cylinders r = 0.25 m, draft 0.5 m, cg 0.3 m deep (Table 2;
# dimensions estimated, Figure 10 is not in our copy), hydrodynamics on the nodes only. Link arms
# 1.4 m, neutrally buoyant, cg 0.4 m deep, no hydrodynamics; spherical joints at both ends with
# penalty PTOs (stiffness, damping) on the relative pitch and yaw; taut rope moorings of two
# segments with a neutrally buoyant point mass at each connection.
"""

SIMULATION = """[simulation]
duration = {duration}
step = 0.025            # s: Tp / 64
extrapolation = 2
steady_periods = 10
"""

IRREGULAR = """[waves]
kind = "irregular"
spectrum = "jonswap"
hs = 0.06               # m (tank scale; the ropes stay taut)
tp = 1.6                # s, near the nodes' heave and pitch resonances
omega_max = 12.0        # rad/s: the databases' top (1.4 % of the spectrum's energy lies above)
seed = 3
"""

GRID_4 = "omega = { start = 0.1, stop = 12.0, step = 0.1 }   # 171 panels per node, 5 per wavelength at 12 rad/s"
GRID_9 = ("omega = { start = 0.2, stop = 12.0, step = 0.2 }   # 0.2 rad/s keeps the 54-DOF database small "
          "(docs/arrays.md: the 4N3LA database at 0.1 and 0.2 rad/s)\n"
          "omega_refine = [{ start = 4.0, stop = 6.6, step = 0.05 }]   # the hexagon's interaction resonances "
          "near 4.7 and 6.2 rad/s (docs/arrays.md)")


# Mean power against one PTO's stiffness and damping: `wec-cosim sweep` of main's Dask sweep (issue 18,
# docs/sweeps.md), whose `[sweep.grid]` names one PTO per key. The grid sweeps the rear node's relative
# pitch PTO (LA2_S2_pitch, the largest mean power of the twelve), the other eleven at the baseline. The file
# lives here, not in scenarios/, because this branch's schema has the older one-key `[sweep]` (no `grid`):
# it is meant for the code after the merge with main.
PTO_STUDY = "array_4n3la_pto_study"
PTO_STUDY_PTO = "LA2_S2_pitch"
PTO_STUDY_GRID = f"""
# `wec-cosim sweep scenarios/data/arrays/{PTO_STUDY}.toml --out results/{PTO_STUDY}.h5`:
# mean power of every PTO and their total in the irregular sea against {PTO_STUDY_PTO}'s stiffness and
# damping around the baseline {PTO.stiffness:g} N m/rad, {PTO.damping:g} N m s/rad (exact frequency domain;
# `--method time_domain` co-simulates each case, 300 s each).
[sweep]
method = "frequency_domain"
[sweep.grid]
ptos.{PTO_STUDY_PTO}.stiffness = {{stiffness}}   # N m/rad
ptos.{PTO_STUDY_PTO}.damping = {{damping}}   # N m s/rad
"""


def pto_study_text(text_4n3la: str) -> str:
    """The 4N3LA scenario with its own name, the committed database one folder up, and the PTO grid."""
    text = text_4n3la.replace('name = "array_4n3la"', f'name = "{PTO_STUDY}"', 1)
    text = text.replace("[hydro]\n", '[hydro]\ncache_dir = "../../hydro_cache"   # scenarios/hydro_cache\n', 1)
    grid = PTO_STUDY_GRID.format(stiffness=vec([0.0, PTO.stiffness, 2 * PTO.stiffness]),
                                 damping=vec([PTO.damping / 2, PTO.damping, 2 * PTO.damping, 4 * PTO.damping]))
    return text + grid


def main() -> None:
    files = {
        "array_4n3la.toml": scenario_text(
            "array_4n3la", layout_4n3la(), HEADER.format(title="4N3LA", what="device: 4 nodes, 3 link arms"),
            IRREGULAR, SIMULATION.format(duration="300.0"), GRID_4),
        "array_9n9la.toml": scenario_text(
            "array_9n9la", layout_9n9la(),
            HEADER.format(title="9N9LA", what="array: 9 nodes, 9 link arms, a hexagonal closed loop"),
            IRREGULAR, SIMULATION.format(duration="120.0"), GRID_9),
    }
    for name, text in files.items():
        (SCENARIOS / name).write_text(text)
        print(f"wrote {SCENARIOS / name}")
    study = SCENARIOS / "data" / "arrays" / f"{PTO_STUDY}.toml"
    study.parent.mkdir(parents=True, exist_ok=True)
    study.write_text(pto_study_text(files["array_4n3la.toml"]))
    print(f"wrote {study}")


if __name__ == "__main__":
    main()
