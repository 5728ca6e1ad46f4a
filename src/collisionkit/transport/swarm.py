"""Swarm simulation: a cloud of charged particles drifting through a gas in E (and B) fields.

Krasov's trajectory algorithm (sec. 5.5: a random free path, exact motion
under the force, a collision, a new direction) with energy-dependent cross
sections through null collisions (Skullerud 1968); the kernels are in
:mod:`collisionkit._kernels.transport`. This module checks the arguments and
makes the field's record; the run is set up in ``_swarm_setup``, the run
itself (stepping, population control, the end of the transient) is in
``_swarm_run``, the estimators below in ``_estimators`` and the result in
:mod:`collisionkit.transport.swarm_result`.

Observables (Robson, Ness, White, Dujko; e.g. Dujko et al., J. Phys. D 41,
245205 (2008)) over the steady-state window, from per-step sums:

* flux drift velocity ``W_flux = <v>``; flux diffusion
  ``D_flux,zz = <z v_z> - <z><v_z>`` (transverse: the mean of xx and yy);
* bulk drift velocity ``W_bulk = d<r>/dt`` and bulk diffusion
  ``D_bulk,zz = (1/2) d(<z^2> - <z>^2)/dt`` (least-squares slopes);
* rate coefficients ``k_j = (collisions j) / (N x particle time)``;
  effective ionization / attachment frequencies the same without ``1/N``;
  a superelastic inverse is a process of its own (``label (superelastic)``);
* Townsend coefficients ``alpha/N``, ``eta/N`` of steady-state Townsend
  conditions from the bulk coefficients (:mod:`collisionkit.transport.townsend`);
* mean energy and the energy distribution;
* the full 3x3 flux and bulk diffusion tensors (:mod:`._tensors`) in the
  frame of E along z and B in the y-z plane at ``field_angle`` from E; in an
  oscillating field E0 cos(omega t), the mean energy and flux drift
  velocity resolved in phase over the period, and their cycle averages
  (:mod:`._periodic`).

Statistical errors come from independent groups: particles are dealt into
``groups`` groups with their own random streams (``SeedSequence.spawn``),
ionization children stay in their parent's group, every quantity is
estimated per group, and the error is the standard error of the group
mean. The result does not depend on the number of threads.
"""

from __future__ import annotations

import math
import warnings
from typing import NamedTuple

import numpy as np
from scipy import constants

from .._arrays import seed_value
from .._kernels import transport as _k
from ._initial import balanced_energy
from ._periodic import DEFAULT_PHASES
from ._swarm_run import STEPS_PER_CHUNK, Stepper, SwarmRun, initial_swarm
from ._swarm_setup import new_run, run_to_steady_state, with_field_settings
from ._tables import SHARING_CODES, build_tables
from ._waveform import half_wave_antisymmetric, shaped_record, waveform_knots, waveform_peak, waveform_rms
from ._validation import (
    MAX_REDUCED_FIELD, check_reduced_frequency, integer_in_range, reachable_tolerances, real_in_range,
    validate_swarm_setup, validated_run_settings,
)
from .gases import Gas
from .swarm_result import SwarmResult

__all__ = ["SwarmResult", "simulate_swarm", "trace_trajectories", "diffusion_error_floor", "magnetic_direction",
           "DEFAULT_TOLERANCES", "TOWNSEND", "HUXLEY", "REFERENCE_DENSITY"]

TOWNSEND = 1e-21  # V m^2
HUXLEY = 1e-27  # T m^3
REFERENCE_DENSITY = 1e24  # m^-3; N-scaled results do not depend on it
DEFAULT_TOLERANCES = {"mean_energy": 2e-3, "drift_velocity_bulk": 2e-3, "diffusion_L_N": 2e-2, "diffusion_T_N": 2e-2}
# Count the trial collisions at which the true collision rate exceeded the trial bound (the null-collision
# method is exact only if that never happens) and report them as ``extras["bound_violations"]``. Off by
# default (it evaluates every process at every trial); the tests switch it on.
CHECK_BOUND = False

# Components of the position spread behind each bulk diffusion coefficient (z; x and y)
DIFFUSION_COMPONENTS = {"diffusion_L_N": 1, "diffusion_T_N": 2}
# warn only well below the floor: its constant depends on the window (measured 0.9-1.2 sqrt(2 / N) for D_L)
FLOOR_MARGIN = 0.7


def diffusion_error_floor(name: str, particles: int) -> float:
    r"""Relative error below which a bulk diffusion coefficient of ``particles`` does not go, however long the run.

    The bulk coefficient is the growth rate of the swarm's spread,
    ``D = (1/2) d Var(z)/dt``. The sample variance of N walkers that have
    spread to ``Var = 2 D t`` scatters by ``Var sqrt(2 / N)``, in proportion
    to ``t``, so the least-squares slope keeps a relative error of about
    ``sqrt(2 / N)`` (``sqrt(1 / N)`` for the transverse coefficient, which
    averages two axes) instead of falling as ``1 / sqrt(t)``: exactly
    ``sqrt(6/5) sqrt(2 / N)`` for walkers fitted from the start of their
    spreading, more for a window that starts later. The value returned is
    ``sqrt(2 / N)`` (per axis), a lower bound. Reid's ramp at 1 Td: 3.7 % at
    N = 2000 after 5e7 and 2e8 collisions alike.

    Examples
    --------
    >>> from collisionkit.transport.swarm import diffusion_error_floor
    >>> round(diffusion_error_floor("diffusion_L_N", 20000), 4)
    0.01
    """
    if name not in DIFFUSION_COMPONENTS:
        raise ValueError(f"name must be one of {sorted(DIFFUSION_COMPONENTS)}; got {name!r}")
    return math.sqrt(2.0 / (DIFFUSION_COMPONENTS[name] * integer_in_range(particles, "particles", 1)))


def _warn_unreachable_diffusion(tolerances, particles, defaults):
    """One warning naming the diffusion tolerances that lie well below the error floor only more particles lower."""
    out_of_reach = []
    needed = 0
    for name, tolerance in tolerances.items():
        if name in DIFFUSION_COMPONENTS:
            floor = diffusion_error_floor(name, particles)
            if tolerance < FLOOR_MARGIN * floor:
                out_of_reach.append(f"{name} {tolerance:g} (floor about {floor:.2g})")
                needed = max(needed, math.ceil(2.0 / (DIFFUSION_COMPONENTS[name] * tolerance**2)))
    if out_of_reach:
        which = "the default tolerances" if defaults else "tolerances"
        warnings.warn(f"{which} for {', '.join(out_of_reach)} are out of reach of {particles} particles: the error "
                      "of a bulk diffusion coefficient stops falling with run length at about sqrt(2 / particles) "
                      "(sqrt(1 / particles) transverse), so the run will likely use its whole collision budget; "
                      f"use particles >= {needed} or a looser diffusion tolerance", stacklevel=3)


def _require_collisions(tables):
    """ValueError if no process of the gas can ever happen: every cross section and rate coefficient zero."""
    if not (np.any(tables.bound > 0.0) or np.any(tables.const_max > 0.0)):
        raise ValueError("every cross section and rate coefficient of the gas is zero: no particle can ever collide, "
                         "and a driven swarm would run away for ever (an all-zero block, such as ELASTIC, in a "
                         "cross-section file, or a units slip?)")


def magnetic_direction(field_angle: float) -> np.ndarray:
    """Unit vector of B at ``field_angle`` degrees from E in the swarm frame: ``(0, sin psi, cos psi)``.

    The frame is right-handed with E along +z and B in the y-z plane, so
    90 degrees puts B along +y (E x B along -x) and 0 along E.

    Examples
    --------
    >>> from collisionkit.transport.swarm import magnetic_direction
    >>> [round(float(c), 12) for c in magnetic_direction(90.0)], [round(float(c), 12) for c in magnetic_direction(60.0)]
    ([0.0, 1.0, 0.0], [0.0, 0.866025403784, 0.5])
    """
    psi = math.radians(field_angle)
    return np.array([0.0, math.sin(psi), math.cos(psi)])


def _field_record(reduced_field, reduced_magnetic_field, density, mass, charge, gravity, field_angle=90.0):
    """The kernel's field record of E/N (Td, along +z), B/N (Hx, at ``field_angle`` degrees from E in the y-z
    plane: :func:`magnetic_direction`) and gravity, for ``charge / mass``."""
    electric = np.array([0.0, 0.0, reduced_field * TOWNSEND * density])
    magnetic = reduced_magnetic_field * HUXLEY * density * magnetic_direction(field_angle)
    acceleration = charge * electric / mass + np.asarray(gravity, dtype=float)
    return _k.derived_field(acceleration, charge * magnetic / mass)


def _starting_energy(tables, density, mass, charge, reduced_magnetic_field, field_angle, gravity, reduced_field,
                     gas_temperature):
    """The default initial mean energy (eV): the Maxwellian power balance in the run's force and B."""
    electric = np.array([0.0, 0.0, reduced_field * TOWNSEND * density])
    force = charge * electric + mass * np.asarray(gravity, dtype=float)
    magnitude = float(np.linalg.norm(force))
    omega = charge * reduced_magnetic_field * HUXLEY * density / mass * magnetic_direction(field_angle)
    perpendicular = float(np.linalg.norm(np.cross(omega, force / magnitude))) if magnitude > 0.0 else 0.0
    return balanced_energy(tables, density, magnitude, perpendicular, mass, gas_temperature)


def _oscillating_record(reduced_field, reduced_magnetic_field, reduced_frequency, density, mass, charge, gravity,
                        field_angle):
    """The kernel's record of E/N cos(omega t) (amplitude in Td, along +z), a static B/N at ``field_angle`` and
    gravity: the static record of B and gravity extended by the oscillating force (:mod:`collisionkit._kernels.
    transport.oscillating`); ``omega = reduced_frequency x density``."""
    static = _field_record(0.0, reduced_magnetic_field, density, mass, charge, gravity, field_angle)
    amplitude = np.array([0.0, 0.0, charge * reduced_field * TOWNSEND * density / mass])
    return _k.oscillating_field(static, amplitude, reduced_frequency * density)


def _oscillating_tolerances(tolerances, defaults, gravity, symmetric=True):
    """The tolerances an oscillating field can meet: its cycle-averaged drift is zero by symmetry.

    E(t + T/2) = -E(t), and v -> -v maps the motion in -E (with the same B)
    onto that in E, collisions with an isotropic gas included: W(t + T/2) =
    -W(t), so a drift averaged over the cycle has no relative error to
    reach (without gravity, which breaks the symmetry). The default drift
    tolerance is dropped, an explicit one refused. A waveform that is not
    half-wave antisymmetric (``symmetric`` False) may drift on average: an
    explicit drift tolerance stands, the default one is dropped (the average
    may be near zero all the same).
    """
    if np.any(np.asarray(gravity) != 0.0):
        return tolerances
    drift = [name for name in tolerances if name.startswith("drift_velocity")]
    if not symmetric:
        return {name: value for name, value in tolerances.items() if not (defaults and name in drift)}
    if drift and not defaults:
        raise ValueError(f"tolerances[{drift[0]!r}] cannot be met in an oscillating field: the drift averaged over a "
                         "cycle is zero by symmetry (W(t + T/2) = -W(t)); leave it out")
    return {name: value for name, value in tolerances.items() if name not in drift}


def check_waveform_peak(waveform, reduced_field: float) -> None:
    """ValueError unless the waveform's samples are valid and its peak E/N, ``reduced_field`` max|E/E0|, is at most
    :data:`~collisionkit.transport._validation.MAX_REDUCED_FIELD` (the bound of a static E/N).

    Examples
    --------
    >>> check_waveform_peak([(0.0, 1.0), (1.0, -1.0)], 12.0)
    >>> check_waveform_peak([(0.0, 1e5), (1.0, -1.0)], 12.0)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: the waveform's peak E/N (...) is 1.2e+06 Td; it must be <= 1e+06 Td
    """
    waveform_knots(waveform)
    peak = waveform_peak(waveform)
    if reduced_field * peak > MAX_REDUCED_FIELD:
        raise ValueError(f"the waveform's peak E/N (the amplitude {reduced_field:g} Td times the largest |E/E0|, "
                         f"{peak:g}) is {reduced_field * peak:g} Td; it must be <= {MAX_REDUCED_FIELD:g} Td")


def simulate_swarm(
    gas: Gas,
    reduced_field: float,
    *,
    reduced_magnetic_field: float = 0.0,
    field_angle: float = 90.0,
    reduced_frequency: float = 0.0,
    phases: int = DEFAULT_PHASES,
    waveform=None,
    gas_temperature: float = 300.0,
    particles: int = 20_000,
    groups: int = 16,
    seed: int = 0,
    mass: float = constants.m_e,
    charge: float = -constants.e,
    gravity=(0.0, 0.0, 0.0),
    sharing: str = "equal",
    initial_energy: float | None = None,
    tolerances: dict | None = None,
    collision_budget: float = 2e9,
    max_seconds: float = math.inf,
    collisions_per_sample: float = 20.0,
    min_samples: int = 4 * STEPS_PER_CHUNK,
    energy_bins: int = 200,
    threads: int | None = None,
    progress=None,
) -> SwarmResult:
    r"""Run a swarm to steady state and measure its transport coefficients.

    Parameters
    ----------
    gas : Gas
        Target gas (see :mod:`collisionkit.transport.gases`, :mod:`~collisionkit.transport.lxcat`).
    reduced_field : float
        E/N in Td, in [0, 1e6]; E points along +z. With ``reduced_frequency``
        the amplitude E0/N of E(t) = E0 cos(omega t). The ranges of E/N, B/N,
        omega/N and the gas temperature are generous finite ends, far beyond
        practice (:mod:`collisionkit.transport._validation`).
    reduced_magnetic_field : float
        B/N in Hx, in [0, 1e6], static, at ``field_angle`` from E in the y-z plane.
    field_angle : float
        Angle psi between E and B in degrees, in [0, 180] (90 by default:
        crossed fields). The frame is right-handed with E along +z and
        ``B = |B| (0, sin psi, cos psi)`` (:func:`magnetic_direction`); the
        drift velocities and diffusion tensors of the result are in it.
    reduced_frequency : float
        omega/N in rad m^3/s: 0, the default, a static field, or in [1e-20, 1e-8]:
        E(t) = E0 cos(omega t), the result resolved in phase (``phases``
        points over the period) and averaged over the cycle. The motion
        between collisions is exact (:mod:`collisionkit._kernels.transport.oscillating`),
        cyclotron resonance included.
    phases : int
        Points of the phase grid of an oscillating field (4 to 256).
    waveform : sequence of (u, f) pairs or None
        A periodic field of any shape instead of the cosine:
        E(t) = E0 f(omega t / 2 pi), with ``reduced_field`` E0/N and
        ``reduced_frequency`` omega/N (> 0); f is linear between the samples
        (u the fraction of the period, 0 to 1, non-decreasing, the same u
        twice a jump; f = E/E0, |f| <= 1e6, the peak E/N at most 1e6 Td) and periodic
        (:mod:`collisionkit.transport._waveform`). The motion is exact,
        with a static B at ``field_angle`` or without
        (:mod:`collisionkit._kernels.transport.waveform_magnetic`). The
        cycle-averaged drift's default tolerance is dropped.
    gas_temperature : float
        K, in [0, 1e5] (300 by default). The targets move with the gas's Maxwellian
        and the reversible excitations' upper levels are populated by
        Boltzmann (superelastic collisions,
        :mod:`collisionkit.transport.superelastic`); 0 puts the targets at
        rest with every level empty, as the model-gas benchmarks assume.
    particles, groups : int
        Particles (>= 8 groups) and independent groups (errors; 4 to 1024).
        The transient runs with 1/16 of the particles (at least 64 a
        group); when it ends each is cloned (fresh random streams) up to
        ``particles``, which then measure.
    seed : int or numpy.random.Generator
        Seed of the streams (>= 0), or a Generator that draws one.
    mass, charge : float
        Projectile (kg > 0, C); an electron by default.
    gravity : 3-vector
        Extra uniform acceleration (m/s^2, finite).
    sharing : {"equal", "uniform"}
        Energy sharing between the two electrons after ionization.
    initial_energy : float or None
        Mean energy (eV, > 0) of the initial Maxwellian; by default the
        energy at which the power balance of a Maxwellian swarm closes
        (``collisionkit.transport._initial.balanced_energy``: 3/2 kT with
        no field, within about 35 % of the steady mean energy in a field),
        so that the transient is short.
    tolerances : dict
        Target relative errors (> 0) of ``mean_energy``, ``drift_velocity_bulk``,
        ``diffusion_L_N``, ``diffusion_T_N``; the run stops when all are met,
        or at ``collision_budget`` real collisions, or after ``max_seconds``
        (both > 0; ``result.converged`` tells which). The error of a bulk
        diffusion coefficient stops falling with run length near
        :func:`diffusion_error_floor` (about ``sqrt(2 / particles)``): a
        diffusion tolerance well below it warns. A swarm with no field
        on its charge and no gravity needs ``gas_temperature > 0`` (else it
        cools forever); it thermalises with zero drift, so it takes no drift
        tolerance (the default one is dropped).
    collisions_per_sample : float
        Mean real collisions per particle between samples (> 0).
    min_samples : int
        Samples after the transient before convergence is tested (>= 1).
    energy_bins : int
        Bins of the energy distribution (>= 1).
    threads : int
        Worker threads (>= 1; default: all cores); results do not depend on it.
    progress : callable
        Called with the fraction of the collision budget used so far.

    Returns
    -------
    SwarmResult

    Raises
    ------
    TypeError
        If ``gas`` is not a :class:`Gas`, or an argument is not a number of the
        right kind (bools are refused).
    ValueError
        If an argument is out of its range (the message names it and the
        range), or every cross section and rate coefficient is zero.
    RuntimeError
        If the swarm cannot be advanced: a particle runs away to unbounded
        energy (cross sections zero or tiny over the energies it reaches),
        or every particle was attached. The message names the likely cause.

    Notes
    -----
    The transient ends when the chunk-averaged mean energy of the last
    chunks shows no trend (its change over three chunks is below three
    standard errors or 1e-3 relative).

    Examples
    --------
    Maxwell model, W = qE/(mu nu) exactly:

    >>> from collisionkit.transport import maxwell_model, simulate_swarm
    >>> me = 9.1093837e-31
    >>> r = simulate_swarm(maxwell_model(1e-13, mass=10 * me), 10.0, particles=1000, seed=1,
    ...                    tolerances={"drift_velocity_bulk": 0.02}, threads=1)
    >>> exact = 1.602176634e-19 * 10e-21 * 1e24 / (me * 10 / 11 * 1e11)  # qE / (mu nu)
    >>> bool(abs(abs(r.drift_velocity_flux[2]) / exact - 1) < 0.03)
    True
    """
    defaults = tolerances is None
    tolerances = DEFAULT_TOLERANCES if defaults else tolerances
    seed = seed_value(seed)
    _check_field_and_projectile(gas, reduced_field, reduced_magnetic_field, field_angle, reduced_frequency, phases,
                                gas_temperature, seed, mass, charge, initial_energy)
    gravity = validated_run_settings(particles, groups, gravity, sharing, tolerances, collision_budget, max_seconds,
                                     collisions_per_sample, min_samples, energy_bins, threads, progress,
                                     known_tolerances=DEFAULT_TOLERANCES)
    tolerances = reachable_tolerances(tolerances, tolerances is DEFAULT_TOLERANCES, reduced_field, charge, gravity,
                                      gas_temperature)
    _check_waveform(waveform, reduced_frequency, reduced_field)
    oscillating = reduced_frequency > 0.0 and reduced_field > 0.0 and charge != 0.0
    if oscillating:
        symmetric = waveform is None or half_wave_antisymmetric(waveform)
        tolerances = _oscillating_tolerances(tolerances, defaults, gravity, symmetric)
    tables = build_tables(gas, mass, gas_temperature)
    _require_collisions(tables)
    _warn_unreachable_diffusion(tolerances, particles, defaults)
    field = _Field(reduced_field, reduced_magnetic_field, field_angle, reduced_frequency, waveform, gravity,
                   oscillating)
    field_record = _run_field_record(field, mass, charge)
    if initial_energy is None:
        initial_energy = _default_initial_energy(tables, field, mass, charge, gas_temperature)
    run, stepper = new_run(tables, field_record, oscillating, reduced_frequency, particles, groups, seed, mass,
                           initial_energy, sharing, threads, phases, REFERENCE_DENSITY, CHECK_BOUND)
    result = run_to_steady_state(run, stepper, collisions_per_sample, tolerances, collision_budget, max_seconds,
                                 min_samples, energy_bins, progress,
                                 (reduced_field, reduced_magnetic_field, gas_temperature, particles))
    return with_field_settings(result, field_angle, reduced_frequency, waveform)


def _check_field_and_projectile(gas, reduced_field, reduced_magnetic_field, field_angle, reduced_frequency, phases,
                                gas_temperature, seed, mass, charge, initial_energy) -> None:
    """Check the gas, the fields and the projectile of :func:`simulate_swarm`, in the order of its signature.

    Parameters
    ----------
    gas, reduced_field, reduced_magnetic_field, field_angle, reduced_frequency, phases, gas_temperature, seed, \
mass, charge, initial_energy
        :func:`simulate_swarm`'s arguments of those names (``seed`` already an integer).

    Raises
    ------
    TypeError, ValueError
        At the first argument of the wrong kind or out of its range.

    Examples
    --------
    >>> from collisionkit.transport import reid_ramp
    >>> _check_field_and_projectile(reid_ramp(), 12.0, 0.0, 181.0, 0.0, 32, 300.0, 0, 9.1e-31, -1.6e-19, None)
    Traceback (most recent call last):
    ...
    ValueError: field_angle (degrees) must lie in [0.0, 180.0]; got 181.0
    """
    validate_swarm_setup(gas, reduced_field, reduced_magnetic_field, gas_temperature, seed, mass, charge,
                         initial_energy)
    real_in_range(field_angle, "field_angle (degrees)", 0.0, 180.0, inclusive=(True, True))
    check_reduced_frequency(reduced_frequency)
    integer_in_range(phases, "phases", 4, 256)


def _check_waveform(waveform, reduced_frequency, reduced_field) -> None:
    """ValueError unless ``waveform`` is None, or a valid one within the E/N bound in an oscillating field.

    Examples
    --------
    >>> _check_waveform(None, 0.0, 12.0)
    >>> _check_waveform([(0.0, 1.0), (1.0, -1.0)], 0.0, 12.0)
    Traceback (most recent call last):
    ...
    ValueError: waveform needs reduced_frequency > 0 (omega/N, rad m^3/s: the period is 2 pi / omega)
    """
    if waveform is not None:
        if reduced_frequency <= 0.0:
            raise ValueError("waveform needs reduced_frequency > 0 (omega/N, rad m^3/s: the period is 2 pi / omega)")
        check_waveform_peak(waveform, reduced_field)


class _Field(NamedTuple):
    """The field of a run, checked: E/N (Td; the amplitude if it oscillates), B/N (Hx) at ``field_angle`` degrees
    from E, omega/N (rad m^3/s), the waveform (or None), gravity (m/s^2) and whether it oscillates (omega/N, E/N
    and the charge not zero)."""

    reduced_field: float
    reduced_magnetic_field: float
    field_angle: float
    reduced_frequency: float
    waveform: object
    gravity: np.ndarray
    oscillating: bool


def _run_field_record(field: _Field, mass, charge):
    """The kernel's field record of a run: static, E0 cos(omega t), or a periodic waveform, with B and gravity.

    Parameters
    ----------
    field : _Field
        The run's field, checked.
    mass, charge : float
        The projectile's.

    Returns
    -------
    ndarray
        The record at :data:`REFERENCE_DENSITY`.

    Examples
    --------
    >>> field = _Field(10.0, 0.0, 90.0, 0.0, None, np.zeros(3), False)
    >>> bool(np.array_equal(_run_field_record(field, 9.1e-31, -1.6e-19),
    ...                     _field_record(10.0, 0.0, REFERENCE_DENSITY, 9.1e-31, -1.6e-19, np.zeros(3))))
    True
    """
    reduced_field, reduced_magnetic_field, field_angle, reduced_frequency, waveform, gravity, oscillating = field
    density = REFERENCE_DENSITY
    if oscillating and waveform is not None:
        amplitude = np.array([0.0, 0.0, charge * reduced_field * TOWNSEND * density / mass])
        return shaped_record(_field_record(0.0, reduced_magnetic_field, density, mass, charge, gravity, field_angle),
                             amplitude, 2.0 * math.pi / (reduced_frequency * density), waveform)
    if oscillating:
        return _oscillating_record(reduced_field, reduced_magnetic_field, reduced_frequency, density, mass, charge,
                                   gravity, field_angle)
    return _field_record(reduced_field, reduced_magnetic_field, density, mass, charge, gravity, field_angle)


def _default_initial_energy(tables, field: _Field, mass, charge, gas_temperature) -> float:
    """The initial mean energy (eV) of a run that gives none: :func:`_starting_energy` in the effective field.

    An oscillating field heats as its r.m.s. value does (omega << nu; less
    above: a start need not be exact): E0/sqrt(2) for the cosine, E0 times
    the waveform's r.m.s. value.

    Parameters
    ----------
    tables : KernelTables
        The gas's tables.
    field : _Field
        The run's field, checked.
    mass, charge, gas_temperature : float
        The projectile's and the gas's.

    Returns
    -------
    float

    Examples
    --------
    >>> from collisionkit.transport import reid_ramp
    >>> tables = build_tables(reid_ramp(), constants.m_e, 0.0)
    >>> static = _default_initial_energy(tables, _Field(12.0, 0.0, 90.0, 0.0, None, np.zeros(3), False), constants.m_e,
    ...                                  -constants.e, 0.0)
    >>> ac = _default_initial_energy(tables, _Field(12.0 * math.sqrt(2.0), 0.0, 90.0, 1e-13, None, np.zeros(3), True),
    ...                              constants.m_e, -constants.e, 0.0)
    >>> bool(abs(ac / static - 1) < 1e-12)
    True
    """
    reduced_field, reduced_magnetic_field, field_angle, _, waveform, gravity, oscillating = field
    effective_field = reduced_field / math.sqrt(2.0) if oscillating else reduced_field
    if oscillating and waveform is not None:
        effective_field = reduced_field * waveform_rms(waveform)
    return _starting_energy(tables, REFERENCE_DENSITY, mass, charge, reduced_magnetic_field, field_angle, gravity,
                            effective_field, gas_temperature)


def trace_trajectories(gas: Gas, reduced_field: float, *, particles: int = 5, collisions: float = 200.0,
                       points: int = 2000, reduced_magnetic_field: float = 0.0, seed: int = 0,
                       initial_energy: float = 1.0, gas_temperature: float = 300.0,
                       field_angle: float = 90.0) -> tuple[np.ndarray, np.ndarray]:
    """Positions of a few particles sampled on a uniform time grid (for plots).

    Returns ``(times, positions)`` with positions of shape (points, particles, 3);
    the run lasts about ``collisions`` real collisions per particle (finite, > 0).
    ``particles`` and ``points`` are integers >= 1; the other arguments are
    those of :func:`simulate_swarm` (an electron, no ionization children).

    Examples
    --------
    >>> from collisionkit.transport import reid_ramp
    >>> from collisionkit.transport.swarm import trace_trajectories
    >>> t, r = trace_trajectories(reid_ramp(), 12.0, particles=2, points=50, seed=1)
    >>> r.shape
    (50, 2, 3)
    """
    seed = seed_value(seed)
    validate_swarm_setup(gas, reduced_field, reduced_magnetic_field, gas_temperature, seed, constants.m_e,
                         -constants.e, initial_energy)
    integer_in_range(particles, "particles", 1)
    real_in_range(collisions, "collisions (per particle)", 0.0)
    integer_in_range(points, "points", 1)
    real_in_range(field_angle, "field_angle (degrees)", 0.0, 180.0, inclusive=(True, True))
    tables = build_tables(gas, constants.m_e, gas_temperature)
    _require_collisions(tables)
    field_record = _field_record(reduced_field, reduced_magnetic_field, REFERENCE_DENSITY, constants.m_e,
                                 -constants.e, (0.0, 0.0, 0.0), field_angle)
    swarm = initial_swarm(particles, 1, seed, constants.m_e, initial_energy)
    stepper = Stepper(tables, field_record, constants.m_e, REFERENCE_DENSITY, SHARING_CODES["equal"], 1, CHECK_BOUND)
    stepper.slots = 0  # children are not followed in a trace
    run = SwarmRun(stepper, swarm, 1, particles, None, tables, REFERENCE_DENSITY)
    run.conservative = True
    run.calibrate(collisions / points)
    positions = np.empty((points, particles, 3))
    for k in range(points):
        run.step()
        positions[k] = run.swarm.pos[:particles]
    return np.array(run.times), positions
