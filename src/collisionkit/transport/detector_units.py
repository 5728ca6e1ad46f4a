r"""Swarm coefficients in a gas detector's units: E in V/cm at a pressure and temperature, Magboltz's columns.

Gaseous-detector work (Magboltz, Garfield++) states a gas at a pressure p
and temperature T, the field in V/cm, and the electrons' drift and spread
per unit drift length. With the ideal gas's :math:`N = p / (k_B T)`:

* :math:`E/N` in Td is :math:`E / N \cdot 10^{21}` (:func:`reduced_fields`);
* the drift velocity in cm/us is the bulk drift along E (1 m/s = 1e-4
  cm/us);
* the longitudinal and transverse diffusion "coefficients" in
  :math:`\sqrt{\mathrm{cm}}` are the spread of a swarm per square root of
  its drift length, :math:`\sigma/\sqrt{x} = \sqrt{2D/W}` with the bulk
  :math:`D = (ND)/N` and bulk W (Garfield++'s convention; times 1e4 for the
  um/sqrt(cm) of detector papers);
* the Townsend and attachment coefficients in 1/cm are the steady-state
  Townsend :math:`\alpha/N` and :math:`\eta/N` times N.

Errors are propagated from the swarm's: the diffusion's as the relative
error of D / W, with the correlation of D and W over the swarm's independent
groups (``drift_diffusion_L_correlation``, ``..._T_...``; independent in
results saved before it), halved by the square root.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import constants

from .._params import check_real
from .swarm_result import SwarmResult

__all__ = ["TORR", "detector_coefficients", "gas_number_density", "reduced_fields"]

TORR = constants.atm / 760.0  # Pa
TOWNSEND = 1e-21  # V m^2


def gas_number_density(pressure_torr: float, temperature: float) -> float:
    """N = p / (k_B T) in m^-3 for ``pressure_torr`` (Torr, > 0) and ``temperature`` (K, > 0).

    Examples
    --------
    >>> from collisionkit.transport import gas_number_density
    >>> round(gas_number_density(760.0, 273.15) / 2.686780111e25, 9)  # Loschmidt's constant (CODATA 2018)
    1.0
    """
    pressure = check_real("pressure (Torr)", pressure_torr, 0.0, 1e6, low_open=True)
    temperature = check_real("temperature (K)", temperature, 0.0, 1e5, low_open=True)
    return pressure * TORR / (constants.k * temperature)


def reduced_fields(field_v_per_cm, pressure_torr: float, temperature: float) -> np.ndarray:
    """E/N in Td of the fields E (V/cm) in a gas at ``pressure_torr`` and ``temperature`` (K).

    Examples
    --------
    >>> from collisionkit.transport import reduced_fields
    >>> reduced_fields([1000.0], 760.0, 293.15).round(4)  # 1 kV/cm at 1 atm and 20 C
    array([3.9944])
    """
    fields = np.atleast_1d(np.asarray(field_v_per_cm, dtype=float))
    if not np.all(np.isfinite(fields) & (fields >= 0.0)):
        raise ValueError(f"every field E must be a finite number >= 0 V/cm; got {fields[~(fields >= 0)][0]}")
    return fields * 100.0 / gas_number_density(pressure_torr, temperature) / TOWNSEND


def _sqrt_ratio(diffusion, diffusion_error, drift, drift_error, correlation=math.nan) -> tuple[float, float]:
    """sqrt(2 D / W) in sqrt(cm) and its error: half the relative error of D / W, sqrt(r_D^2 + r_W^2 - 2 rho r_D
    r_W) with the groups' correlation rho of D and W (0, independent, if unknown)."""
    if not (diffusion > 0 and drift > 0):
        return math.nan, math.nan
    value = math.sqrt(2.0 * diffusion / drift) * 10.0  # sqrt(m) -> sqrt(cm)
    rho = correlation if math.isfinite(correlation) else 0.0
    r_d, r_w = diffusion_error / diffusion, drift_error / drift
    relative = 0.5 * math.sqrt(max(r_d * r_d + r_w * r_w - 2.0 * rho * r_d * r_w, 0.0))
    return value, value * relative


def detector_coefficients(result: SwarmResult, pressure_torr: float, temperature: float | None = None) -> dict:
    """A swarm result (a static E) in a detector's units at ``pressure_torr``, each with its ``*_error``.

    Parameters
    ----------
    result : SwarmResult
    pressure_torr : float
        The gas pressure in Torr (760 = 1 atm).
    temperature : float, optional
        In K; default the result's gas temperature (which must then be > 0).

    Returns
    -------
    dict
        ``pressure_torr``, ``temperature``, ``field`` (V/cm), ``drift_velocity`` (cm/us),
        ``diffusion_L`` and ``diffusion_T`` (sqrt(cm)), ``townsend_alpha`` and ``attachment_eta`` (1/cm).

    Examples
    --------
    >>> from collisionkit.transport import detector_coefficients, maxwell_model, simulate_swarm
    >>> result = simulate_swarm(maxwell_model(1e-13), 10.0, particles=500, seed=1, tolerances={"mean_energy": 0.2},
    ...                         gas_temperature=300.0)
    >>> row = detector_coefficients(result, 760.0)
    >>> round(row["field"], 3), row["temperature"]    # 10 Td at 1 atm and 300 K, in V/cm
    (2446.313, 300.0)
    """
    if not isinstance(result, SwarmResult):
        raise TypeError(f"result must be a SwarmResult; got {type(result).__name__}")
    if result.reduced_magnetic_field != 0.0 or result.reduced_frequency != 0.0:
        raise ValueError("detector units take a static E without B (the drift along E)")
    temperature = result.gas_temperature if temperature is None else temperature
    density = gas_number_density(pressure_torr, temperature)
    drift = abs(float(result.drift_velocity_bulk[2]))
    drift_error = abs(float(result.drift_velocity_bulk_error[2]))
    longitudinal = _sqrt_ratio(result.diffusion_L_N / density, result.diffusion_L_N_error / density, drift,
                               drift_error, result.drift_diffusion_L_correlation)
    transverse = _sqrt_ratio(result.diffusion_T_N / density, result.diffusion_T_N_error / density, drift, drift_error,
                             result.drift_diffusion_T_correlation)
    per_cm = density / 100.0
    return {
        "pressure_torr": float(pressure_torr), "temperature": float(temperature),
        "field": result.reduced_field * TOWNSEND * density / 100.0,
        "drift_velocity": drift * 1e-4, "drift_velocity_error": drift_error * 1e-4,
        "diffusion_L": longitudinal[0], "diffusion_L_error": longitudinal[1],
        "diffusion_T": transverse[0], "diffusion_T_error": transverse[1],
        "townsend_alpha": result.alpha_N * per_cm, "townsend_alpha_error": result.alpha_N_error * per_cm,
        "attachment_eta": result.eta_N * per_cm, "attachment_eta_error": result.eta_N_error * per_cm,
    }
