"""The summary of an EDMD run (:meth:`~collisionkit.edmd.EdmdRun.summary`): measurement, theory, parameters.

The measurement's values with their errors, the equation of state and
Enskog's collision rate of an elastic run, Enskog's transport coefficients
and the Yeh-Hummer correction of a transport run, and the parameters that
rerun it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

from .theory import (
    carnahan_starling, enskog_collision_frequency, enskog_transport, hansen_goos, henderson, yeh_hummer_correction,
)


def equation_of_state(dim: int) -> tuple[str, Callable]:
    """The reference equation of state of hard spheres (Hansen-Goos 2016) or discs (Henderson 1975).

    Examples
    --------
    >>> name, Z = equation_of_state(3)
    >>> name, round(float(Z(0.3)), 3)
    ('Hansen-Goos (2016)', 3.984)
    """
    return ("Hansen-Goos (2016)", hansen_goos) if dim == 3 else ("Henderson (1975)", henderson)


def _in_sigmas(difference: float, error: float) -> float:
    return difference / error if error > 0 else math.nan


def edmd_summary(run, measurement, files: Sequence = ()) -> dict[str, Any]:
    """The edmd command's JSON summary: the measurement, the comparison with theory, the parameters."""
    p, system = run.parameters, run.system
    result = measurement.summary()
    result |= {
        "initial": p.initial,
        "restitution": p.restitution,
        "seed": p.seed,
        "blocks": p.blocks,
        "equilibration_collisions": run.equilibrated,
        "energy_lost_total": run.initial_energy - system.kinetic_energy(),
        "elastic": p.restitution == 1.0,
        "elastic_below": system.elastic_below,
    }
    if p.restitution == 1.0:
        name, equation = equation_of_state(p.dim)
        eta, Z = measurement.packing_fraction, measurement.compressibility_factor
        theory = float(equation(eta))
        result |= {
            "theory": name,
            "compressibility_factor_theory": theory,
            "compressibility_factor_relative_deviation": Z / theory - 1.0,
            "compressibility_factor_deviation_sigmas": _in_sigmas(Z - theory, measurement.compressibility_factor_error),
            "collision_frequency_from_pressure": float(enskog_collision_frequency(Z, p.dim, kT=measurement.temperature)),
            "collision_frequency_theory": float(enskog_collision_frequency(theory, p.dim, kT=1.0)),
        }
        if p.dim == 3:
            result["compressibility_factor_carnahan_starling"] = float(carnahan_starling(eta))
    if measurement.transport is not None:
        result |= _transport_summary(run, measurement)
    if p.shear_rate != 0.0:
        result["thermostat"] = p.thermostat
        # the zero-rate limit of the sheared fluid's viscosity, at the measured temperature
        result["shear_viscosity_enskog"] = _enskog(run, measurement)["shear_viscosity"]
    if run.trajectory is not None:
        result["trajectory_frames"] = run.frames
    result["files"] = [str(path) for path in files]
    result["parameters"] = p.to_dict()
    return result


def _enskog(run, measurement) -> dict[str, float]:
    """Enskog's coefficients of equal spheres or discs (unit diameter and mass) at the run's packing fraction
    and measured temperature."""
    return enskog_transport(measurement.packing_fraction, kT=measurement.temperature, dim=run.parameters.dim)


def _transport_summary(run, measurement) -> dict[str, Any]:
    """Enskog's transport coefficients and, asked for, D corrected to the infinite system (Yeh-Hummer)."""
    p, transport = run.parameters, measurement.transport
    enskog = _enskog(run, measurement)
    result = {f"{key}_enskog": enskog[key] for key in
              ("shear_viscosity", "bulk_viscosity", "thermal_conductivity", "self_diffusion")}
    eta, eta_error = transport.shear_viscosity, transport.shear_viscosity_error
    if p.yeh_hummer:
        correction = error = math.nan  # a viscosity measured <= 0 (noise) gives no correction
        if eta > 0:
            correction = float(yeh_hummer_correction(eta, float(run.system.box[0]), measurement.temperature))
            error = math.hypot(measurement.diffusion_coefficient_error, correction * eta_error / eta)
        result |= {"yeh_hummer_correction": correction,
                   "self_diffusion_infinite": measurement.diffusion_coefficient + correction,
                   "self_diffusion_infinite_error": error}
    return result
