"""Argument checks of the transport functions: numbers in range, and the settings of a swarm run."""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from .. import _arrays
from ._tables import SHARING_CODES
from .gases import Gas

# Allowed ranges of a swarm's field and gas: generous, finite ends that no swarm study comes near, so an absurd
# value (a units slip, an exponent typo) is refused before any work instead of running into overflow or a runaway
# (the sources of the margins: :func:`validate_swarm_setup`, :func:`check_reduced_frequency`)
MAX_REDUCED_FIELD = 1e6  # Td
MAX_REDUCED_MAGNETIC_FIELD = 1e6  # Hx
MAX_GAS_TEMPERATURE = 1e5  # K
REDUCED_FREQUENCY_RANGE = (1e-20, 1e-8)  # rad m^3/s, or 0 for a static field
# what a field slower than the range's low end is (the swarm follows it): said when one is refused
QUASI_STATIC = "a slower field is quasi-static: scan its E/N values with a static field instead"



def real_in_range(value, name, low=-math.inf, high=math.inf, *, inclusive=(False, False), length=None):
    """``value`` as a float (a vector if ``length`` is given) in the range from ``low`` to ``high``.

    Bools and non-numbers raise TypeError; a wrong shape, NaN or a value out of range raise ValueError
    naming ``name`` and the range. The ends are open by default, so infinities are refused.
    """
    array = _arrays.as_float_array(value, name)  # refuses bools
    shape = () if length is None else (length,)
    if array.shape != shape:
        what = "a single number" if length is None else f"a {length}-vector"
        raise ValueError(f"{name} must be {what}; got shape {array.shape}")
    _arrays.require_in_range(array, name, low, high, inclusive=inclusive)
    return float(array) if length is None else array


def integer_in_range(value, name, low, high=None):
    """``value`` as an int in [low, high] (no upper end if ``high`` is None); a whole float such as 1e6 counts
    (as :func:`collisionkit._params.check_integer` takes it), bools are refused."""
    allowed = f">= {low}" if high is None else f"in [{low}, {high}]"
    if isinstance(value, float) and value.is_integer() and abs(value) < 2**53:
        value = int(value)
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an integer {allowed}; got {value!r}")
    if not (value >= low and (high is None or value <= high)):
        raise ValueError(f"{name} must be an integer {allowed}; got {value}")
    return int(value)


def validate_swarm_setup(gas, reduced_field, reduced_magnetic_field, gas_temperature, seed, mass, charge,
                         initial_energy):
    """Check the arguments shared by :func:`~collisionkit.transport.swarm.simulate_swarm` and
    :func:`~collisionkit.transport.swarm.trace_trajectories`.

    Notes
    -----
    The upper ends are far beyond practice, so that only a slip is refused:
    E/N <= 1e6 Td (:data:`MAX_REDUCED_FIELD`) is ten times the highest E/N of
    breakdown at low pressure-gap products, about 1e5 Td (Phelps and
    Petrovic, Plasma Sources Sci. Technol. 8, R21 (1999)); B/N <= 1e6 Hx is a
    thousand times the highest of magnetised swarm studies, about 1e3 Hx
    (Dujko et al., J. Phys. D 41, 245205 (2008)); a gas temperature <= 1e5 K
    is three times the hottest thermal plasmas (arcs, about 3e4 K).
    """
    if not isinstance(gas, Gas):
        raise TypeError("gas must be a Gas (e.g. from collisionkit.transport.gases or read_lxcat); "
                        f"got {type(gas).__name__}")
    real_in_range(reduced_field, "reduced_field (E/N, Td)", 0.0, MAX_REDUCED_FIELD, inclusive=(True, True))
    real_in_range(reduced_magnetic_field, "reduced_magnetic_field (B/N, Hx)", 0.0, MAX_REDUCED_MAGNETIC_FIELD,
                  inclusive=(True, True))
    real_in_range(gas_temperature, "gas_temperature (K)", 0.0, MAX_GAS_TEMPERATURE, inclusive=(True, True))
    integer_in_range(seed, "seed", 0)
    real_in_range(mass, "mass (kg)", 0.0)
    real_in_range(charge, "charge (C)")
    if initial_energy is not None:  # None: the single-energy power balance picks it
        real_in_range(initial_energy, "initial_energy (eV)", 0.0)


def validated_run_settings(particles, groups, gravity, sharing, tolerances, collision_budget, max_seconds,
                           collisions_per_sample, min_samples, energy_bins, threads, progress, *, known_tolerances):
    """Check the run settings of :func:`~collisionkit.transport.swarm.simulate_swarm`; return ``gravity`` as a
    float 3-vector. ``tolerances`` may name only the keys of ``known_tolerances``."""
    integer_in_range(groups, "groups", 4, 1024)
    integer_in_range(particles, f"particles (8 per group, {groups} groups)", 8 * groups)
    gravity = real_in_range(gravity, "gravity (m/s^2)", length=3)
    if not (isinstance(sharing, str) and sharing in SHARING_CODES):
        raise ValueError(f"sharing must be one of {sorted(SHARING_CODES)}; got {sharing!r}")
    if not isinstance(tolerances, Mapping):
        raise TypeError(f"tolerances must be a dict of target relative errors; got {type(tolerances).__name__}")
    unknown = set(tolerances) - set(known_tolerances)
    if unknown:
        raise ValueError(f"tolerances keys must be among {sorted(known_tolerances)}; got {sorted(unknown)}")
    for key, value in tolerances.items():
        real_in_range(value, f"tolerances[{key!r}]", 0.0)
    real_in_range(collision_budget, "collision_budget", 0.0)
    real_in_range(max_seconds, "max_seconds", 0.0, inclusive=(False, True))
    real_in_range(collisions_per_sample, "collisions_per_sample", 0.0)
    integer_in_range(min_samples, "min_samples", 1)
    integer_in_range(energy_bins, "energy_bins", 1)
    if threads is not None:
        integer_in_range(threads, "threads", 1)
    if progress is not None and not callable(progress):
        raise TypeError(f"progress must be a callable or None; got {type(progress).__name__}")
    return gravity


def reachable_tolerances(tolerances, defaults, reduced_field, charge, gravity, gas_temperature):
    """The tolerances a swarm can meet; an undriven one (no field on its charge, no gravity) is refused or thermal.

    Nothing heats an undriven swarm: in a gas at 0 K it cools without end (no
    steady state, so the run would use its whole budget); in a warm gas it
    thermalises, and its drift is zero by symmetry, so a relative error of
    the drift can never be reached: the default drift tolerance is dropped,
    an explicit one refused.
    """
    driven = (reduced_field > 0.0 and charge != 0.0) or bool(np.any(np.asarray(gravity) != 0.0))
    if driven:
        return dict(tolerances)
    if gas_temperature == 0.0:
        raise ValueError("nothing heats this swarm (reduced_field = 0 or charge = 0, and no gravity) and the gas is "
                         "at 0 K: it cools without end, with no steady state; give reduced_field > 0 or "
                         "gas_temperature > 0")
    drift = [name for name in tolerances if name.startswith("drift_velocity")]
    if drift and not defaults:
        raise ValueError(f"tolerances[{drift[0]!r}] cannot be met: the drift of a swarm without a field or gravity "
                         "is zero by symmetry (no relative error); leave it out")
    return {name: value for name, value in tolerances.items() if name not in drift}


def check_reduced_frequency(value, name="reduced_frequency (omega/N, rad m^3/s)") -> float:
    """omega/N as a float: 0 (a static field) or in :data:`REDUCED_FREQUENCY_RANGE`, else a ValueError naming ``name``.

    The ends leave every practical field inside: 50 Hz at 1 atm is 1.3e-23
    (far below: the swarm follows such a field quasi-statically, run it
    static at each E/N), 13.56 MHz at 1 atm 3.5e-18, 2.45 GHz at 0.1 mTorr
    4.8e-9. The upper end, 1e-8, is 50 times the electron cyclotron frequency
    per molecule, omega_c/N = (e/m_e) B/N = 1.76e-16 B/N[Hx], at the largest
    B/N allowed (1e6 Hx), and 1e4 times the collision frequency per molecule
    of any electron (nu/N = sigma v <~ 1e-12 m^3/s), where the field no
    longer heats the swarm (its effective value falls as nu/omega: Margenau,
    Phys. Rev. 69, 508 (1946)). At the lower end, 1e-20, a sample interval
    (at least a sixteenth of the period, :mod:`._periodic`) holds
    2 pi (nu/N) / (16 omega/N) ~ 4e4 collisions a particle at nu/N = 1e-14
    m^3/s; much below it the step's trial budget (2^20 a particle) runs out.

    Examples
    --------
    >>> check_reduced_frequency(0), check_reduced_frequency(2e-14)
    (0.0, 2e-14)
    >>> check_reduced_frequency(1e-300)
    Traceback (most recent call last):
    ...
    ValueError: reduced_frequency (omega/N, rad m^3/s) must be 0 (a static field) or in [1e-20, 1e-08]; got 1e-300 \
(a slower field is quasi-static: scan its E/N values with a static field instead)
    """
    value = real_in_range(value, name, 0.0, inclusive=(True, False))
    low, high = REDUCED_FREQUENCY_RANGE
    if value != 0.0 and not low <= value <= high:
        slow = f" ({QUASI_STATIC})" if value < low else ""
        raise ValueError(f"{name} must be 0 (a static field) or in [{low:g}, {high:g}]; got {value:g}{slow}")
    return value
