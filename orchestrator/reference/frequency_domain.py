"""Exact linear frequency-domain response of a scene: the reference for time-domain runs.

For each frequency omega the complex motion amplitudes X (per metre of wave amplitude,
``exp(+i omega t)`` convention) solve

    Z(omega) X = F_exc(omega),
    Z = -omega^2 (M + A(omega)) + i omega (B(omega) + B_visc + C_pto) + C_hs + K_pto,

with M the rigid-body mass matrix, A and B the database's added mass and radiation damping
(linearly interpolated in omega), B_visc the bodies' linear viscous damping (quadratic drag is not
linear and is left out), C_hs the hydrostatic stiffness and the PTOs' damping and
stiffness, all restricted to the scene's active degrees of freedom (the same coordinates as the
time-domain multibody model). The mean power of a PTO of damping c on a coordinate with
amplitude X is (1/2) omega^2 c |X|^2 per square metre of wave amplitude.

``radiation="impulse_response"`` replaces A(omega), B(omega) by the coefficients that the
time-domain model actually uses: A_inf plus the Fourier transform of the truncated, sampled
impulse response K (trapezoidal rule, step dt, length T_K). That is the exact answer of the
time-domain model in the limit of a vanishing coupling error, used to measure the master's
convergence order without the database's own truncation error.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy.linalg import block_diag

from hydro_fmu.radiation import impulse_response, kernel_table
from hydro_fmu.waves import group_velocity
from orchestrator.scene import Scene


@dataclass
class FrequencyResponse:
    """Linear response of a scene, per metre of wave amplitude (``exp(+i omega t)`` convention).

    Attributes:
        omega: frequencies (Nw,), rad/s.
        coordinates: (body, dof) of each column of ``rao``.
        rao: complex motion per metre of wave amplitude (Nw, n).
        pto_power: mean absorbed power per PTO name, W per m^2 of wave amplitude (Nw,).
        form: ``dae`` (multipliers solved with the motion) or ``ode`` (null-space reduced).
        heading_deg: wave heading (degrees).
        multipliers: dynamic Lagrange multipliers of the independent constraint rows (Nw, r), N per m.
        joint_rao: per joint, its coordinates' RAOs (Nw, k) (rad/m or m/m), names in ``joint_coordinates``.
        reaction_rao: per joint, force (N/m) and moment about the joint point (N m/m) on body 2
            from body 1, world frame (Nw, 6): the dynamic part, about the static reaction.
        incident_power: incident wave power per metre of crest, W/m per m^2 of amplitude (Nw,).
    """

    omega: np.ndarray
    coordinates: list[tuple[str, int]]
    rao: np.ndarray
    pto_power: dict[str, np.ndarray]
    form: str = "ode"
    heading_deg: float = 0.0
    multipliers: np.ndarray | None = None
    joint_rao: dict[str, np.ndarray] = field(default_factory=dict)
    joint_coordinates: dict[str, list[str]] = field(default_factory=dict)
    reaction_rao: dict[str, np.ndarray] = field(default_factory=dict)
    incident_power: np.ndarray | None = None

    def body_rao(self, body: str) -> np.ndarray:
        """RAO of ``body`` as (Nw, 6), zero for inactive degrees of freedom."""
        out = np.zeros((len(self.omega), 6), complex)
        for j, (b, d) in enumerate(self.coordinates):
            if b == body:
                out[:, d] = self.rao[:, j]
        return out

    def capture_width(self, pto: str) -> np.ndarray:
        """Mean PTO power over the incident power per metre of crest (m), (Nw,)."""
        return self.pto_power[pto] / self.incident_power


def radiation_coefficients_from_irf(
    scene: Scene, omega: np.ndarray, dt: float, duration: float, omega_cut: float = np.inf
) -> tuple[np.ndarray, np.ndarray]:
    """A(omega), B(omega) (Nw, m, m) on the hydro coordinates implied by the truncated impulse response.

    K is evaluated at step ``dt`` over ``duration`` and Fourier-transformed by the trapezoidal
    rule: B = int K cos(w t) dt, A = A_inf - (1/w) int K sin(w t) dt. Above ``omega_cut`` (where
    the sampled transform would alias) A = A_inf and B = 0. For complex ``omega`` the same formulas
    give the analytic continuation (the kernel is finite): ``-w^2 A + i w B = -w^2 A_inf + i w
    int K exp(-i w t) dt`` is the radiation part of the time-domain model's Laplace-domain impedance
    at ``s = i w`` (``orchestrator.reference.decay``).
    """
    t, k = scene_kernel(scene, dt, duration)
    idx = scene.hydro_index()
    return kernel_coefficients(t, k, scene.hdb.added_mass_inf[np.ix_(idx, idx)], omega, omega_cut)


def state_space_coefficients(scene: Scene, omega: np.ndarray, dt: float | None = None) -> tuple[np.ndarray,
                                                                                                 np.ndarray]:
    """A(omega), B(omega) (Nw, m, m) on the hydro coordinates of the scene's state-space radiation model: the fit's
    transfer function K^(w) = C (i w I - A)^-1 B (``hydro_fmu.state_space``); B = Re K^, A = A_inf + Im K^ / w. A fit
    that left a block to the convolution makes the whole model the convolution (the hydro model's
    ``state_space`` is None): then the transform of the kernel sampled at ``dt`` (default the macro step).
    The fit is made again here (the hydro FMU makes its own, the same)."""
    dt = dt or scene.scenario.simulation.step
    model = scene.hydro_model(dt=dt)
    idx = scene.hydro_index()
    a_inf = scene.hdb.added_mass_inf[np.ix_(idx, idx)]
    fit = model.state_space
    if fit is None:
        t, kernel = scene_kernel(scene, dt, scene.scenario.hydro.irf_duration)
        a_c, b_c = kernel_coefficients(t, kernel, np.zeros_like(a_inf), omega)
        k = b_c + 1j * omega[:, None, None] * a_c  # int K exp(-i w t) dt = B - i int K sin = B + i w A
    else:
        k = fit.transfer(omega) if fit.order else np.zeros((len(omega), len(idx), len(idx)), complex)
    return a_inf[None] + k.imag / omega[:, None, None], k.real


def scene_kernel(scene: Scene, dt: float, duration: float) -> tuple[np.ndarray, np.ndarray]:
    """Times (s) and the radiation impulse response K (nt, m, m) on the hydro coordinates, sampled as
    the time-domain model samples it (``hydro.irf_d_omega``, ``hydro.damping_tail``, the fitted tail correction)."""
    idx = scene.hydro_index()
    hdb = scene.hdb
    t = np.arange(max(2, int(np.ceil(duration / dt)) + 1)) * dt
    h = scene.scenario.hydro
    correction = scene.tail_correction()
    if correction is not None:
        correction = (correction[0], correction[1][:, idx][:, :, idx])
    table = kernel_table(hdb.omega, hdb.radiation_damping[:, idx][:, :, idx], d_omega=h.irf_d_omega,
                         tail_exponent=h.damping_tail, tail_correction=correction)
    return t, impulse_response(*table, t)


def kernel_coefficients(t: np.ndarray, k: np.ndarray, a_inf: np.ndarray, omega: np.ndarray,
                        omega_cut: float = np.inf) -> tuple[np.ndarray, np.ndarray]:
    """A(omega), B(omega) of the sampled kernel ``k`` at times ``t`` (:func:`radiation_coefficients_from_irf`)."""
    dt = t[1] - t[0]
    w = np.full(len(t), dt)
    w[0] = w[-1] = dt / 2
    dtype = complex if np.iscomplexobj(omega) else float
    a = np.broadcast_to(a_inf, (len(omega),) + a_inf.shape).astype(dtype)
    b = np.zeros_like(a)
    low = np.flatnonzero(np.real(omega) <= omega_cut)
    for chunk in np.array_split(low, max(1, len(low) // 1000)):
        wc = omega[chunk]
        b[chunk] = np.einsum("wt,tij->wij", np.cos(np.outer(wc, t)) * w, k)
        a[chunk] -= np.einsum("wt,tij->wij", np.sin(np.outer(wc, t)) * w, k) / wc[:, None, None]
    return a, b


@dataclass
class LinearModel:
    """Z(omega) and the excitation of a scene on its multibody coordinates.

    Attributes:
        omega: (Nw,) rad/s; impedance: Z (Nw, d, d) and excitation (Nw, d) per metre of amplitude,
            reduced to the constraint null space for constrained scenes (d = n - r); stiffness: the
            reduced static stiffness; system: the multibody model.
        full_impedance, full_excitation: the same on all n generalised coordinates (Nw, n, n), (Nw, n).
        constraint: the independent rows of the linearised constraint Jacobian C (r, n).
        basis: null space P of C (n, d): motion = P @ reduced solution (None without constraints).
        pto_rows: PTO name -> (coordinate row on the n coordinates, damping, the PTO element or None).
        joints: joint name -> (coordinate names, their rows (k, n), reaction map (6, r) from multipliers).
    """

    omega: np.ndarray
    impedance: np.ndarray
    excitation: np.ndarray
    stiffness: np.ndarray
    system: object
    basis: np.ndarray | None = None
    coordinates: list | None = None
    pto_rows: dict | None = None
    full_impedance: np.ndarray | None = None
    full_excitation: np.ndarray | None = None
    constraint: np.ndarray | None = None
    joints: dict = field(default_factory=dict)


def linear_model(scene: Scene, omega: np.ndarray, *, radiation: str = "database",
                 dt: float | None = None, omega_cut: float = np.inf,
                 heading_deg: float | None = None) -> LinearModel:
    """Assemble Z(omega) = -w^2 (M + A) + i w (B + C_pto) + C_hs + K_pto and F_exc (module docstring).

    ``radiation``: ``database`` (A, B interpolated from the database) or ``impulse_response``
    (the coefficients of the sampled, truncated impulse response at step ``dt``, default the
    scenario's macro step; above ``omega_cut`` A = A_inf and B = 0). ``heading_deg``: wave heading,
    default the scenario's.
    """
    omega = np.asarray(omega, dtype=float)
    heading = scene.scenario.waves.heading_deg if heading_deg is None else heading_deg
    if scene.scenario.formulation != "linear":
        return _constrained_linear_model(scene, omega, radiation=radiation, dt=dt, omega_cut=omega_cut,
                                         heading=heading)
    mech = mechanical_matrices(scene)
    system, rows = mech.system, mech.rows
    z, f, stiffness = _impedance(scene, omega, mech.mass, mech.damping, mech.stiffness, rows,
                                 radiation=radiation, dt=dt, omega_cut=omega_cut, heading=heading)
    pto_rows = {}
    for p in system.ptos:
        row = np.zeros(system.n)
        row[system.coordinate_index(p.body, p.dof)] = 1.0
        pto_rows[p.name] = (row, p.damping, None)
    return LinearModel(omega, z, f, stiffness, system, coordinates=list(system.coordinates), pto_rows=pto_rows,
                       full_impedance=z, full_excitation=f, constraint=np.zeros((0, system.n)))


def _constrained_linear_model(scene: Scene, omega: np.ndarray, *, radiation: str, dt: float | None,
                              omega_cut: float, heading: float) -> LinearModel:
    """Z(omega) of a scene with joints, from the multibody linearisation (``mbd_fmu.linearize``):
    ``Z = -w^2 (M + A) + i w (B + D) + C_hs + K`` on the generalised coordinates, ``K`` including the
    geometric stiffness of the static loads (gravity, buoyancy) and reactions, with the independent
    rows ``C`` of the constraint Jacobian and its null space ``P`` (reduced: ``P^T Z P``)."""
    mech = mechanical_matrices(scene)
    sim, model, lin, rows = mech.simulator, mech.system, mech.linearization, mech.rows
    pose = scene.linearisation_pose(model)
    z, f, stiffness = _impedance(scene, omega, mech.mass, mech.damping, mech.stiffness, rows,
                                 radiation=radiation, dt=dt, omega_cut=omega_cut, heading=heading)
    p = lin.null_space
    kin = model.kin(pose, np.zeros(model.n))
    pto_rows = {pto.name: (_coordinate_row(model, pto.coordinate, kin), pto.damping, pto) for pto in sim.ptos}
    return LinearModel(omega, p.T @ z @ p, f @ p, p.T @ stiffness @ p, model, p, list(model.coordinates), pto_rows,
                       full_impedance=z, full_excitation=f, constraint=lin.constraint_jacobian,
                       joints=_joint_maps(model, kin))


@dataclass
class MechanicalMatrices:
    """The multibody side of a scene about equilibrium on its n generalised coordinates (no hydrodynamics).

    Attributes:
        mass: structural M (n, n), without A_inf; damping: D (PTOs, dampers); stiffness: K (PTOs, springs
            and, for constrained scenes, the geometric stiffness of the static loads and reactions).
        rows: the coordinate of each of ``scene.hydro_coordinates`` among the n.
        basis: null space P (n, d) of the linearised constraints (None for the ``linear`` formulation).
        system: the multibody model; simulator, linearization: for constrained scenes (else None).
    """

    mass: np.ndarray
    damping: np.ndarray
    stiffness: np.ndarray
    rows: list[int]
    basis: np.ndarray | None
    system: object
    simulator: object = None
    linearization: object = None


def mechanical_matrices(scene: Scene) -> MechanicalMatrices:
    """M, D, K of the scene's multibody model about equilibrium (``mbd_fmu.linearize`` if constrained, about the
    static equilibrium when the scene asks for it: ``Scene.linearisation_pose``)."""
    if scene.scenario.formulation == "linear":
        system = scene.multibody_system(added_mass=False)
        rows = [system.coordinate_index(b, d) for b, d in scene.hydro_coordinates]
        return MechanicalMatrices(system.structural_mass, system.damping, system.stiffness, rows, None, system)
    from mbd_fmu.linearize import linearize

    sim = scene.multibody_simulator(added_mass=False)
    lin = linearize(sim.model, scene.linearisation_pose(sim.model))
    rows = [sim.model.slot_of(b, d) for b, d in scene.hydro_coordinates]
    return MechanicalMatrices(lin.mass, lin.damping, lin.stiffness, rows, lin.null_space, sim.model, sim, lin)


def _impedance(scene: Scene, omega: np.ndarray, mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray,
               rows: list[int], *, radiation: str, dt: float | None, omega_cut: float, heading: float,
               coefficients: tuple[np.ndarray, np.ndarray] | None = None,
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``Z = -w^2 (M + A) + i w (D + B + B_visc) + K + C_hs``, the excitation (Nw, n) and the static
    stiffness ``K + C_hs``, with the hydrodynamics (switched as the scenario says) on coordinates ``rows``.
    ``coefficients``: A, B on the hydro coordinates, already computed (complex ``omega``: required, the
    impulse response's continuation; the database is tabulated on real frequencies only)."""
    hdb = scene.hdb
    switches = scene.scenario.hydro
    idx = scene.hydro_index()
    X = None if np.iscomplexobj(omega) else hdb.interpolate(omega, np.radians(heading))[2]
    if coefficients is not None:
        A, B = coefficients
    elif radiation == "impulse_response":
        A, B = radiation_coefficients_from_irf(
            scene, omega, dt or scene.scenario.simulation.step, switches.irf_duration, omega_cut)
    elif radiation == "database":
        A, B, _ = hdb.interpolate(omega, np.radians(heading))
        A, B = A[:, idx][:, :, idx], B[:, idx][:, :, idx]
    elif radiation == "state_space":
        A, B = state_space_coefficients(scene, omega, dt)
    else:
        raise ValueError(f"radiation must be 'database', 'impulse_response' or 'state_space', not {radiation!r}")
    if not switches.radiation:  # memory force off: only A_inf remains (in the multibody mass matrix)
        A = np.broadcast_to(hdb.added_mass_inf[np.ix_(idx, idx)], A.shape)
        B = np.zeros_like(B)
    viscous = scene.viscous() if switches.viscous else None
    if viscous is not None:  # the linear part of the viscous force (quadratic drag is not linear: left out)
        B = B + np.diag(viscous.linear)[None]
    stiffness = stiffness.copy()
    if switches.hydrostatics:
        stiffness[np.ix_(rows, rows)] += block_diag(*hdb.hydrostatic_stiffness)[np.ix_(idx, idx)]
    w = omega[:, None, None]
    z = -w**2 * mass + 1j * w * damping + stiffness
    z[np.ix_(np.arange(len(omega)), rows, rows)] += -w**2 * A + 1j * w * B
    f = np.zeros((len(omega), len(stiffness)), complex)
    if switches.excitation and X is not None:
        f[:, rows] = X[:, idx]
    return z, f, stiffness


def _coordinate_row(model, coordinate, kin) -> np.ndarray:
    """Gradient of a scalar coordinate with respect to the model's generalised slots (n,)."""
    full = np.zeros(6 * (model.N + 1))
    full[coordinate.cols()] += coordinate.evaluate(kin)[1]
    return full[model.sel]


def _joint_maps(model, kin) -> dict:
    """Per joint: coordinate names, coordinate rows (k, n), and the (6, r) map from the multipliers of the
    kept constraint rows to the reaction force and moment (about the joint point) on body 2 from body 1."""
    from mbd_fmu.rotations import skew

    _, jf, _, _ = model.constraint_full(kin, gamma=False)
    position = {row: k for k, row in enumerate(model.kept)}
    out = {}
    for cj in model.joints:
        b2 = cj.m2.body
        kept = [r for r in cj.rows if r in position]
        reaction = np.zeros((6, len(model.kept)))
        if kept:
            gen = -jf[np.ix_(kept, range(6 * b2, 6 * b2 + 6))].T  # (6, k): wrench about the cg of body 2
            lever = skew(kin.rr[b2] - (kin.rr[b2] + kin.RR[b2] @ cj.m2.offset))
            transfer = np.block([[np.eye(3), np.zeros((3, 3))], [lever, np.eye(3)]])
            reaction[:, [position[r] for r in kept]] = transfer @ gen
        coords = np.array([_coordinate_row(model, c, kin) for c in cj.coordinates]).reshape(-1, model.n)
        out[cj.joint.name] = (list(cj.coordinate_names), coords, reaction)
    return out


def solve(scene: Scene, omega: np.ndarray, *, form: str = "ode", heading_deg: float | None = None,
          radiation: str = "database", dt: float | None = None) -> FrequencyResponse:
    """Response of ``scene`` at ``omega`` (rad/s) to unit-amplitude waves at ``heading_deg`` (default the scene's).

    ``form="dae"`` solves the bordered system ``[[Z, C^T], [C, 0]] [X; L] = [F; 0]`` for the motion
    and the dynamic multipliers together; ``form="ode"`` solves ``P^T Z P y = P^T F``, ``X = P y`` on
    the null space ``P`` of the independent constraint rows ``C`` and recovers the multipliers from
    ``C^T L = F - Z X`` (least squares; exact, the residual lies in the range of ``C^T``). Both are
    the same linear system; they agree to round-off.
    """
    model = linear_model(scene, omega, radiation=radiation, dt=dt, heading_deg=heading_deg)
    z, f, c = model.full_impedance, model.full_excitation, model.constraint
    n, r = z.shape[1], c.shape[0]
    if form == "dae":
        big = np.zeros((len(model.omega), n + r, n + r), complex)
        big[:, :n, :n] = z
        big[:, :n, n:] = c.T
        big[:, n:, :n] = c
        rhs = np.concatenate([f, np.zeros((len(model.omega), r))], axis=1)
        sol = np.linalg.solve(big, rhs[..., None])[..., 0]
        rao, lam = sol[:, :n], sol[:, n:]
    elif form == "ode":
        y = np.linalg.solve(model.impedance, model.excitation[..., None])[..., 0]
        rao = y @ model.basis.T if model.basis is not None else y
        residual = f - np.einsum("wij,wj->wi", z, rao)
        lam = np.linalg.lstsq(c.T, residual.T, rcond=None)[0].T if r else np.zeros((len(model.omega), 0))
    else:
        raise ValueError(f"form must be 'dae' or 'ode', not {form!r}")
    power = {name: 0.5 * model.omega**2 * damping * np.abs(rao @ row) ** 2
             for name, (row, damping, _) in model.pto_rows.items()}
    joint_rao = {name: rao @ rows.T for name, (_, rows, _) in model.joints.items()}
    reactions = {name: lam @ reaction.T for name, (_, _, reaction) in model.joints.items()}
    heading = scene.scenario.waves.heading_deg if heading_deg is None else heading_deg
    return FrequencyResponse(model.omega, model.coordinates, rao, power, form, heading, lam, joint_rao,
                             {name: names for name, (names, _, _) in model.joints.items()}, reactions,
                             incident_wave_power(scene, model.omega))


def incident_wave_power(scene: Scene, omega: np.ndarray) -> np.ndarray:
    """Energy flux of a regular wave per metre of crest and per m^2 of amplitude, W/m: (1/2) rho g c_g."""
    hdb = scene.hdb
    return 0.5 * hdb.rho * hdb.g * group_velocity(omega, hdb.water_depth, hdb.g)


def free_decay(
    scene: Scene,
    t: np.ndarray,
    x0: np.ndarray,
    *,
    radiation: str = "impulse_response",
    omega_max: float = 60.0,
    d_omega: float = 1e-3,
    kernel_dt: float | None = None,
) -> np.ndarray:
    """Exact free decay x(t) (len(t), n) of the linear scene from displacement ``x0`` at rest.

    The Laplace transform of the Cummins equation with x(0) = x0, x'(0) = 0 is
    X(s) = x0/s - Z(s)^-1 K x0 / s (K the static stiffness, hydrostatics and PTOs), so

        x(t) = x0 - (1/pi) int_0^inf Re[(exp(i w t) - 1)/(i w) Z(w)^-1] dw K x0,

    evaluated by the trapezoidal rule on [0, omega_max] with step ``d_omega`` (the integrand
    decays like w^-3 above the resonances; at w = 0 it equals t Z(0)^-1). The rule is also
    evaluated on every other frequency; a difference above 1e-3 of the initial displacement
    raises a warning (lightly damped modes need a finer ``d_omega``). With
    ``radiation="impulse_response"`` Z uses the coefficients of the continuous, truncated impulse
    response (evaluated at ``kernel_dt``, default pi / (20 w_max) for the database's highest
    frequency w_max, and taken as A_inf, B = 0 above 2 w_max where the truncated kernel's
    transform is only its Gibbs ripple): the exact answer of the time-domain model itself.
    """
    t = np.asarray(t, dtype=float)
    x0 = np.asarray(x0, dtype=float)
    omega = np.arange(1, int(round(omega_max / d_omega)) + 1) * d_omega
    w_db = float(scene.hdb.omega[-1])
    model = linear_model(scene, omega, radiation=radiation, dt=kernel_dt or np.pi / (20 * w_db),
                         omega_cut=2 * w_db)
    kx0 = model.stiffness @ x0
    g = np.linalg.solve(model.impedance, np.broadcast_to(kx0, omega.shape + kx0.shape)[..., None])[..., 0]
    g0 = np.linalg.lstsq(model.stiffness, kx0, rcond=None)[0]  # Z(0)^-1 K x0, the integrand's w -> 0 limit
    fine = _decay_integral(omega, g, g0, t, d_omega)
    # The same rule on every other frequency (step 2 d_omega) costs nothing more and shows whether
    # the grid resolves the resonance peaks: lightly damped modes need a finer step.
    coarse = _decay_integral(omega[1::2], g[1::2], g0, t, 2 * d_omega)
    scale = max(float(np.max(np.abs(x0))), 1e-300)
    gap = float(np.max(np.abs(fine - coarse))) / scale
    if gap > 1e-3:
        warnings.warn(
            f"free_decay: the frequency step {d_omega:g} rad/s does not resolve the response (halving the "
            f"rule changes it by {gap:.2g} of the initial displacement); pass a smaller d_omega", stacklevel=2)
    return x0 - fine / np.pi


def _decay_integral(omega: np.ndarray, g: np.ndarray, g0: np.ndarray, t: np.ndarray, d_omega: float) -> np.ndarray:
    """Trapezoidal int_0^w_max Re[(exp(i w t) - 1)/(i w) g(w)] dw for each t (grid w = d_omega, 2 d_omega, ...)."""
    weights = np.full(len(omega), d_omega)
    weights[-1] = d_omega / 2
    out = np.empty((len(t), g.shape[1]))
    for k, tk in enumerate(t):
        kernel = (np.exp(1j * omega * tk) - 1.0) / (1j * omega)
        out[k] = np.real((kernel * weights) @ g) + 0.5 * d_omega * tk * g0
    return out


@dataclass
class IrregularResponse:
    """Linear response statistics in an irregular, unidirectional sea (spectral superposition).

    Attributes:
        omega: the RAO grid (rad/s); wave_spectrum: S(omega) on it (m^2 s/rad).
        response_spectra: |RAO|^2 S per coordinate (Nw, n); significant_response: 4 sqrt(m0) per
            coordinate (crest-to-trough, m or rad); mean_power: per PTO, sum of 2 S(omega) P(omega) domega (W);
        incident_power: rho g int S c_g domega (W/m); hs: 4 sqrt(m0) of the sea on the grid (m);
        fraction_on_grid: m0 of the sea on the grid over its m0 on (0, 50 omega_max) (below 0.99: extend the grid).
    """

    omega: np.ndarray
    wave_spectrum: np.ndarray
    response_spectra: np.ndarray
    significant_response: np.ndarray
    mean_power: dict[str, float]
    incident_power: float
    hs: float
    fraction_on_grid: float


def irregular_response(fd: FrequencyResponse, spectrum) -> IrregularResponse:
    """Statistics of the linear response ``fd`` (per metre of amplitude) in a sea of one-sided spectrum
    ``spectrum(omega)``: component amplitudes a^2 = 2 S domega, integrals by the trapezoidal rule."""
    w = fd.omega
    s = np.asarray(spectrum(w), dtype=float)
    response = np.abs(fd.rao) ** 2 * s[:, None]
    m0 = np.trapezoid(s, w)
    wide = np.linspace(1e-3, 50 * w[-1], 200_001)
    total = np.trapezoid(np.asarray(spectrum(wide), float), wide)
    power = {name: float(np.trapezoid(2 * s * p, w)) for name, p in fd.pto_power.items()}
    return IrregularResponse(w, s, response, 4 * np.sqrt(np.trapezoid(response, w, axis=0)), power,
                             float(np.trapezoid(2 * s * fd.incident_power, w)), 4 * math.sqrt(m0),
                             float(m0 / total) if total > 0 else 1.0)
