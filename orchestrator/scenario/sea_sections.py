"""Scenario sections of the water and the hydrodynamics: environment, waves, the BEM frequency grid and the
hydrodynamic model settings."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from hydro_fmu.bem_symmetry import symmetry_error

from .schema import at_least_one, fraction, non_negative, option, positive


@dataclass
class EnvironmentSection:
    """Water and gravity."""

    rho: float = option(1025.0, unit="kg/m^3", check=positive, doc="water density")
    g: float = option(9.81, unit="m/s^2", check=positive, doc="gravitational acceleration")
    water_depth: float = option(math.inf, unit="m", check=positive, allow_inf=True,
                                doc="water depth; `inf` for deep water")


@dataclass
class WavesSection:
    """Incident waves."""

    kind: str = option("regular", choices=("regular", "still", "irregular", "elevation"),
                       doc="`regular` wave, `still` water, `irregular` sea from a spectrum, or an imported "
                           "`elevation` record")
    height: float = option(0.0, unit="m", check=non_negative, doc="regular wave height, crest to trough")
    period: float = option(0.0, unit="s", check=non_negative, doc="regular wave period")
    phase_deg: float = option(0.0, unit="deg", doc="phase of the elevation at the world origin")
    heading_deg: float = option(0.0, unit="deg", doc="direction of propagation, 0 = towards +x (main direction "
                                                     "of a spread sea)")
    ramp_time: float | None = option(
        None, unit="s", check=non_negative,
        doc="duration of the half-cosine start-up ramp; default three wave periods (regular), three peak "
            "periods (irregular), none (elevation record)")
    spectrum: str = option("jonswap", choices=("jonswap", "pierson_moskowitz", "bretschneider", "file"),
                           doc="irregular sea spectrum; `pierson_moskowitz` without `tp` is the fully developed "
                               "sea of height `hs`; `file` reads `spectrum_file`")
    hs: float = option(0.0, unit="m", check=non_negative, doc="significant wave height (irregular)")
    tp: float = option(0.0, unit="s", check=non_negative, doc="peak period (irregular)")
    gamma: float = option(3.3, check=at_least_one, doc="JONSWAP peak enhancement factor")
    spectrum_file: str = option("", doc="CSV spectrum with a header `omega,S` (rad/s, m^2 s/rad) or `f,S` "
                                        "(Hz, m^2/Hz), relative to the scenario file")
    discretisation: str = option("equal_frequency", choices=("equal_frequency", "equal_energy"),
                                 doc="how the spectrum is split into components")
    repeat_period: float = option(
        0.0, unit="s", check=non_negative,
        doc="equal frequency: the sea repeats after this time (frequency step 2 pi / repeat_period); "
            "default the simulated duration")
    n_components: int = option(200, check=positive, doc="equal energy: number of components")
    omega_min: float = option(0.0, unit="rad/s", check=non_negative,
                              doc="lowest component frequency; default 0.5 omega_p (file: the table's)")
    omega_max: float = option(
        0.0, unit="rad/s", check=non_negative,
        doc="highest component frequency; default 6 omega_p (file: the table's; elevation record: no cut)")
    seed: int = option(1, check=non_negative, doc="seed of the random phases (same seed, same sea)")
    spreading_s: float = option(0.0, check=non_negative,
                                doc="cos-2s directional spreading exponent; 0 = unidirectional")
    n_directions: int = option(1, check=positive, doc="number of directions of a spread sea")
    elevation_file: str = option("", doc="elevation record at the world origin, relative to the scenario file: a "
                                         "text table of time (s) and elevation (m) in two columns (whitespace, "
                                         "comma or semicolon; `%`/`#` comment lines and a header row allowed; more "
                                         "columns need a header naming `t` and `eta`), WEC-Sim's etaImport `.mat` "
                                         "file (one N x 2 array [time, elevation]) or HDF5 with datasets `t`, "
                                         "`eta`; the form found is named in the run's summary")
    time_dataset: str = option("t", doc="HDF5 elevation file: dataset of the times")
    elevation_dataset: str = option("eta", doc="HDF5 elevation file: dataset of the elevation")


@dataclass
class FrequencyGrid:
    """Uniform frequency grid."""

    start: float = option(unit="rad/s", check=positive, doc="first frequency")
    stop: float = option(unit="rad/s", check=positive, doc="last frequency")
    step: float = option(unit="rad/s", check=positive, doc="spacing")


@dataclass
class HydroSection:
    """Hydrodynamic database and force model."""

    database: str = option("", doc="BEMIO HDF5 file (path relative to the scenario file); "
                                   "if empty the database is computed with Capytaine from the bodies' geometry")
    cache_dir: str = option("hydro_cache", doc="folder of computed databases, relative to the scenario file")
    omega: FrequencyGrid = field(
        default_factory=lambda: FrequencyGrid(0.04, 4.0, 0.04),
        metadata={"doc": "BEM frequency grid (also the resolution of the radiation impulse response)"})
    omega_refine: list[FrequencyGrid] = field(
        default_factory=list,
        metadata={"doc": "extra BEM frequency grids merged into `omega`, e.g. a fine step across a narrow resonance "
                         "(a gap or moonpool) that the main grid would under-sample; see docs/hydrodynamics.md"})
    headings_deg: list[float] = option(factory=lambda: [0.0], unit="deg", doc="BEM wave headings")
    bem_method: str = option("indirect", choices=("indirect", "direct"), doc="Capytaine formulation")
    bem_symmetry: str = option(
        "none", check=symmetry_error,
        doc="`none`, `xOz`, `C<n>` or `D<n>`. `xOz`: every hydrodynamic body is mirror-symmetric about y = 0 and "
            "Capytaine solves on half meshes (panels crossing y = 0 are split; checked, an asymmetric body is an "
            "error); 2.3 times faster per frequency at 5400 panels. `C<n>`: the set of bodies is unchanged by a "
            "rotation of 360/n deg about the z axis (the bodies themselves need not be), `D<n>`: and by the mirror "
            "about y = 0; one solve on a wedge (half-wedge) of the scene, the results symmetric to round-off "
            "(docs/nenuphar.md)")
    irf_duration: float = option(60.0, unit="s", check=positive, doc="length of the radiation impulse response")
    irf_d_omega: float = option(
        0.0, unit="rad/s", check=non_negative,
        doc="frequency step of the impulse-response transform (B resampled by shape-preserving cubic "
            "interpolation); 0 = the database's grid")
    damping_tail: float = option(
        0.0, check=non_negative,
        doc="exponent n of the radiation damping's continuation above the database's last frequency Omega in the "
            "impulse response, B(omega) = B(Omega) (Omega/omega)^n (3: wall-sided bodies in surge); 0 = B cut at "
            "Omega; see docs/hydrodynamics.md")
    radiation_method: str = option("convolution", choices=("convolution", "state_space"),
                                   doc="radiation memory: direct convolution or fitted state space")
    state_space_tolerance: float = option(
        0.002, check=fraction,
        doc="state space: largest scaled error of the fitted impulse response; the lowest order that meets "
            "it is used")
    state_space_max_order: int = option(60, check=positive, doc="state space: highest order tried")
    excitation_method: str = option(
        "superposition", choices=("superposition", "convolution"),
        doc="wave excitation: frequency-domain superposition of the components, or convolution of the "
            "excitation impulse response with the elevation (non-causal, unidirectional seas)")
    excitation_irf_duration: float = option(30.0, unit="s", check=positive,
                                            doc="half-length of the excitation impulse response")
    excitation: bool = option(True, doc="compute the wave excitation force")
    radiation: bool = option(True, doc="compute the radiation memory force")
    hydrostatics: bool = option(True, doc="compute the hydrostatic force")
    viscous: bool = option(True, doc="compute the bodies' linear damping and quadratic drag")
    nonlinear_hydrostatics: bool = option(
        False, doc="hydrostatic force by pressure integration over the instantaneous wetted hull (large motions)")
    nonlinear_froude_krylov: bool = option(
        False, doc="Froude-Krylov force over the instantaneous wetted hull under the incident wave (the "
                   "database's diffraction part stays linear)")
    added_mass_inf: str = option(
        "bem", choices=("bem", "ogilvie", "kramers_kronig"),
        doc="infinite-frequency added mass: `bem` as the database gives it, or `ogilvie`: the least-squares value "
            "consistent with the database's A(omega) and the impulse response of its B(omega) (Ogilvie's relation), "
            "so that the time-domain radiation model reproduces A(omega); or `kramers_kronig`: A_inf and a "
            "correction of B's continuation above the database's last frequency fitted together to A(omega), for "
            "databases whose A inside the band feels damping above it (resonances just above the last frequency); "
            "see docs/hydrodynamics.md")
    check_tolerance: float = option(
        0.05, check=positive,
        doc="database checks: largest relative asymmetry of A and B, and negative eigenvalue of the scaled B")
