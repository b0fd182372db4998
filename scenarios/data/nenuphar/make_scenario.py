"""Write ``scenarios/nenuphar.toml``: the Nenuphar of the Nenuphar paper (Table 1) with numbers computed here.

The device has the symmetry of a regular hexagon (six rotations by 60 deg and the mirrors), and
its tests check that the model keeps it to round-off; positions, axes and inertia tensors of the
six lateral bodies are therefore written from exact cos/sin with 17 significant digits, not
rounded by hand. Run from the repository root: ``python scenarios/data/nenuphar/make_scenario.py``.

Numbers from Table 1: hexagon 13.0 m across the flats (circumradius 7.5 m), lateral bodies
15.0 m x 7.5 m, gaps 1.3 m, draft 0.7 m, centres of gravity on the waterline (KG = draft), the
lateral centres of gravity 15.3 m from the axis, radii of gyration (3.4, 3.4, 4.8) m and
(2.2, 4.3, 4.8) m, fresh water (Table 2: 1000 kg/m^3). The rest (PTOs, tether, mooring lines, the
central body's ballast) is chosen here and documented in docs/nenuphar.md.
"""

from __future__ import annotations

import math
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
OUT = ROOT / "scenarios" / "nenuphar.toml"

APOTHEM = 6.5              # m, hexagon centre to side (13.0 m across the flats)
RADIUS = APOTHEM / math.cos(math.pi / 6)  # 7.5055 m to a corner; Table 1's 15.0 m "width" across the corners
GAP = 1.3                  # m, hexagon side to lateral body
LENGTH, WIDTH, DRAFT = 15.0, 7.5, 0.7
R_LATERAL = APOTHEM + GAP + LENGTH / 2   # 15.3 m: Table 1's xG, zG of the lateral bodies
R_HINGE = APOTHEM + GAP / 2             # hinge line in the middle of the gap, on the waterline
RHO = 1000.0
K_CENTRAL = (3.4, 3.4, 4.8)              # radii of gyration, Table 1
K_LATERAL = (2.2, 4.3, 4.8)              # about the lateral body's own axes (x radial)
CENTRAL_MASS = 42000.0     # kg: displacement 102.3 t less the lines' and the tether's pull (docs/nenuphar.md)
HINGE_DAMPING = 2.0e6      # N m s/rad, each hinge PTO
HEAVE_DAMPING = 2.0e5      # N s/m, the central heave PTO
DEPTH = 1000.0             # m, Table 2 (anchors and tether foot on the sea bed)
TETHER_STIFFNESS = 2.0e4   # N/m
TETHER_TENSION = 1.0e5     # N at equilibrium
LINE = {"anchor_radius": 600.0, "length": 1175.0, "weight": 50.0, "ea": 1.0e8}
PANEL = 1.0                # m; mesh convergence in docs/nenuphar.md


def g(x: float) -> str:
    return repr(float(x))


def vec(v) -> str:
    return "[" + ", ".join(g(x) for x in v) + "]"


def lateral_inertia(theta: float) -> list[float]:
    """[Ixx, Iyy, Izz, Ixy, Ixz, Iyz] in world axes of a lateral body at angle theta (kg m^2)."""
    mass = RHO * LENGTH * WIDTH * DRAFT
    i_local = [mass * k * k for k in K_LATERAL]
    c, s = math.cos(theta), math.sin(theta)
    ixx = c * c * i_local[0] + s * s * i_local[1]
    iyy = s * s * i_local[0] + c * c * i_local[1]
    ixy = c * s * (i_local[0] - i_local[1])
    return [ixx, iyy, i_local[2], ixy, 0.0, 0.0]


def main() -> None:
    out = [HEADER]
    mc = CENTRAL_MASS
    out.append(f"""
[[bodies]]
name = "central"
cg = [0.0, 0.0, 0.0]
mass = {g(mc)}
inertia = {vec([mc * k * k for k in K_CENTRAL])}
[bodies.geometry]
shape = "regular_prism"
sides = 6
radius = {g(RADIUS)}
draft = {g(DRAFT)}
panel_size = {g(PANEL)}
""")
    for k in range(6):
        th = math.radians(60 * k)
        c, s = math.cos(th), math.sin(th)
        cg = [R_LATERAL * c, R_LATERAL * s, 0.0]
        out.append(f"""
[[bodies]]
name = "lateral{k + 1}"
cg = {vec(cg)}
inertia = {vec(lateral_inertia(th))}
[bodies.geometry]
shape = "box"
size = {vec([LENGTH, WIDTH, 2 * DRAFT])}
position = {vec(cg)}
rotation_deg = [0.0, 0.0, {g(60 * k)}]
panel_size = {g(PANEL)}
""")
    for k in range(6):
        th = math.radians(60 * k)
        c, s = math.cos(th), math.sin(th)
        out.append(f"""
[[joints]]   # hinge {k + 1}: along the hexagon side; positive angle = lateral body {k + 1}'s outer end up
name = "hinge{k + 1}"
kind = "revolute"
body1 = "central"
body2 = "lateral{k + 1}"
position = {vec([R_HINGE * c, R_HINGE * s, 0.0])}
axis = {vec([s, -c, 0.0])}
""")
    for k in range(6):
        out.append(f"""
[[ptos]]     # hydraulic PTO across hinge {k + 1}: a linear rotary damper
name = "pto{k + 1}"
body = "lateral{k + 1}"
joint = "hinge{k + 1}"
damping = {g(HINGE_DAMPING)}
""")
    keel = [0.0, 0.0, -DRAFT]
    foot = [0.0, 0.0, -DEPTH]
    free = (DEPTH - DRAFT) - TETHER_TENSION / TETHER_STIFFNESS
    out.append(f"""
[[ptos]]     # central heave point absorber: linear generator between the keel and the tether's foot
name = "heave_pto"
body = "central"
point = {vec(keel)}
body2 = "ground"
point2 = {vec(foot)}
damping = {g(HEAVE_DAMPING)}

[[forces]]   # the tether: a taut elastic rope, {TETHER_TENSION / 1e3:g} kN at equilibrium
name = "tether"
kind = "rope"
body1 = "ground"
point1 = {vec(foot)}
body2 = "central"
point2 = {vec(keel)}
stiffness = {g(TETHER_STIFFNESS)}
free_length = {g(free)}
""")
    for k in range(6):
        th = math.radians(30 + 60 * k)  # to the hexagon's corners, between the lateral bodies
        c, s = math.cos(th), math.sin(th)
        ra = LINE["anchor_radius"]
        out.append(f"""
[[forces]]   # catenary mooring line {k + 1}, from the corner at {30 + 60 * k} deg
name = "line{k + 1}"
kind = "catenary"
body = "central"
fairlead = {vec([RADIUS * c, RADIUS * s, -DRAFT])}
anchor = {vec([ra * c, ra * s, -DEPTH])}
length = {g(LINE["length"])}
weight = {g(LINE["weight"])}
ea = {g(LINE["ea"])}
""")
    OUT.write_text("".join(out))
    print(f"wrote {OUT}")


HEADER = '''# Nenuphar seven-body wave energy converter of the Nenuphar paper (Table 1), written by
# scenarios/data/nenuphar/make_scenario.py (edit that file, not this one). docs/nenuphar.md says what
# comes from the paper and what is chosen here.
# Hexagonal central body (13.0 m across the flats, draft 0.7 m) and six lateral bodies (15.0 x 7.5 m,
# draft 0.7 m) 1.3 m off its sides on hinges 60 deg apart (axes along the sides), a linear rotary damper
# PTO across each hinge, a linear generator between the central body and a tether to the sea bed (1000 m,
# Table 2), six catenary mooring lines from the hexagon's corners. Lateral body k lies at 60 (k - 1) deg;
# at heading 0 the waves meet body 4 first and body 1 last (the paper's Figure 5).
name = "nenuphar"
description = "Nenuphar paper: hexagonal hub, six hinged rafts with rotary PTOs, tethered heave PTO, catenaries"

[simulation]
duration = 72.0          # s: 15 periods
step = 0.048             # s, T/100
steady_periods = 3

[environment]
rho = 1000.0             # Table 2
g = 9.81
water_depth = inf        # the paper's 1000 m: deep water for the BEM from 0.3 rad/s (kh > 9); anchors at z = -1000

[waves]
kind = "regular"
height = 1.0             # m: amplitude 0.5 m (the paper's first case)
period = 4.8             # s: the paper's Figure 6
heading_deg = 0.0

[hydro]
# Panels of 1.0 m (6.8 per wavelength at 3 rad/s): hull 1320 panels plus lids, solved on a twelfth of the scene
# (D6: the hub and the six rafts are unchanged by rotations of 60 deg and by the mirror y -> -y), 0.05-3.0 rad/s.
omega = { start = 0.05, stop = 3.0, step = 0.05 }
headings_deg = [0.0, 15.0, 30.0, 45.0, 60.0]
bem_symmetry = "D6"
bem_method = "direct"    # the indirect method's A and B of these thin hulls break reciprocity by 6-12 % (surge-pitch)
irf_duration = 60.0
damping_tail = 3.0
added_mass_inf = "ogilvie"  # A_inf consistent with A(omega) and B(omega): the time domain's own A(omega) then
                            # matches the database within 0.5 % at 3.5, 4.8 and 6.5 s (0.7-1.1 % with the BEM's)

[rao]
omega = { start = 0.2, stop = 3.0, step = 0.05 }
headings_deg = [0.0, 15.0, 30.0]

[multibody]
formulation = "index3"
spectral_radius = 0.8
static_equilibrium = true  # the lines and the tether pull the hub down: found and reported before waves start
'''

if __name__ == "__main__":
    main()
