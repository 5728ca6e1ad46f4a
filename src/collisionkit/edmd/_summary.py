r"""The summary of an EDMD run (:meth:`~collisionkit.edmd.EdmdRun.summary`): measurement, theory, parameters.

The measurement's values with their errors, the equation of state and
Enskog's collision rate of an elastic run, Enskog's transport coefficients
and the Yeh-Hummer correction of a transport run, the event engine that ran
(``engine``: "lists" or "cells"), and the parameters that rerun it. A
mixture's species' temperatures (``temperature_species``, T_a / T) come
with the theory's at rest: equipartition if elastic, the homogeneous
cooling state's if not (``temperature_species_theory``). A gas that cools
at rest gives its cooling rate per collision (``cooling_rate``, -d ln T /
dC) beside Haff's law or the mixture's cooling state's
(``cooling_rate_theory``); with a restitution law (one species), beside the
Maxwellian rate of :func:`~collisionkit.edmd.maxwellian_cooling_rate` at
each block's kT, averaged over the blocks as the measured rate is (and the
error of the measured rate from the blocks' scatter about it).

Rough spheres (a tangential restitution) add the rotational temperature at
the end and the blocks' mean ratio of the rotational to the translational kT
at their ends, ``temperature_ratio``; a gas of one species with a constant
restitution compares it, and its cooling rate, with the Maxwellian theory of
rough spheres followed block by block from the first block's end
(:func:`~collisionkit.edmd.rough_cooling`: the transient towards the
homogeneous cooling state, or to equipartition if elastic, included), the
errors coming from the blocks' residuals.

A sheared run's theory is taken at ``temperature_mean``, the time average
of kT over the measurement (the viscous heating raises kT between the
thermostat's rescalings: the final kT is not what the stress was measured
at), and its energy budget since the start is given in parts:
``energy_lost_total`` (the kinetic energy at the start minus now) =
``energy_lost_collisions_total`` (inelastic collisions) +
``thermostat_energy_total`` (removed by the thermostat) -
``viscous_heating_total`` (the flow's work, :math:`-G V \int P_{xy} dt`;
:mod:`._shear`).

:func:`cooling_note` says what the averages of an inelastic run (or the
temperature of a heated sheared one) mean.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from .homogeneity import VORTICES, box_instability, cooling_state_shear_energy, homogeneity_summary
from .mixture_theory import (
    MIXTURE_EQUATION_OF_STATE, homogeneous_cooling_rate, homogeneous_cooling_temperatures, mixture_collision_frequency,
    mixture_compressibility, mixture_contact_values,
)
from ._msd import block_error
from ._rotation import rotational_degrees
from .restitution_laws import maxwellian_cooling_rate
from .rough_theory import rough_cooling, rough_cooling_matrix
from .theory import (
    carnahan_starling, cooling_state_a2, enskog_collision_frequency, enskog_transport, hansen_goos, henderson,
    yeh_hummer_correction,
)

# kT above which an inelastic run with an elastic floor is reported as not cooled (under 1 % of the energy lost)
BARELY_COOLED = 0.99


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
        "restitution_law": p.restitution_law,
        "seed": p.seed,
        "blocks": p.blocks,
        "equilibration_collisions": run.equilibrated,
        # with wells the equilibration's rescaling changes the energy: only the collisions' own loss is a loss
        "energy_lost_total": (run.initial_energy - system.total_kinetic_energy() if p.well_width is None
                              else system.energy_lost),
        "elastic": p.elastic,
        "elastic_below": system.elastic_below,
        "engine": system.engine,  # the one that ran: "lists" or "cells" (parameters' "auto" resolved)
    }
    sheared = p.shear_rate != 0.0
    # kT of the theory: the measurement's time average under shear (unknown if resumed from a checkpoint written
    # before it was recorded), else (elastic: constant) the final kT
    kT = measurement.temperature_mean if sheared else math.nan
    kT = kT if math.isfinite(kT) else measurement.temperature
    if p.well_width is not None:
        # by the parameters, not by value: a run whose pairs never met a well still reports U/N = 0 +- 0
        result |= {key: getattr(measurement, key) for key in (
            "potential_energy", "potential_energy_error", "temperature_mean", "temperature_mean_error")}
        deepest = float(np.max(p.well_depth))  # (a matrix: T* of the deepest well)
        result |= {"well_width": p.well_width, "well_depth": p.well_depth, "reduced_temperature":
                   measurement.temperature_mean / deepest} | {f"well_{kind}": count for kind, count in
                                                                  system.well_events.items()}
    elif p.elastic and p.fractions is not None:  # a mixture: its equation of state
        result |= _mixture_theory(p, measurement, kT if sheared else 1.0)
    elif p.elastic:  # hard spheres: the equation of state
        name, equation = equation_of_state(p.dim)
        eta, Z = measurement.packing_fraction, measurement.compressibility_factor
        theory = float(equation(eta))
        result |= {
            "theory": name,
            "compressibility_factor_theory": theory,
            "compressibility_factor_relative_deviation": Z / theory - 1.0,
            "compressibility_factor_deviation_sigmas": _in_sigmas(Z - theory, measurement.compressibility_factor_error),
            "collision_frequency_from_pressure": float(enskog_collision_frequency(Z, p.dim, kT=kT)),
            "collision_frequency_theory": float(enskog_collision_frequency(theory, p.dim, kT=kT if sheared else 1.0)),
        }
        if p.dim == 3:
            result["compressibility_factor_carnahan_starling"] = float(carnahan_starling(eta))
    if measurement.contact_values is not None:  # a mixture's partial g(r) at contact (null: no fit possible)
        result["contact_values"] = _nested(measurement.contact_values)
        result["contact_values_error"] = _nested(measurement.contact_values_error)
    if "cooling_rate" in result and not sheared:  # a cooling gas: Haff's law, or the mixture's cooling state
        result |= _cooling_theory(p, result, measurement, system.elastic_below)
    if "shear_mode_energy" in result and not sheared:  # a cooling gas: the dilute theory of its shear instability
        result |= homogeneity_theory(p, system, measurement)
    if p.tangential_restitution is not None:
        result |= _rough_summary(p, system, measurement, result, run.initial_energy)
    if "sonine_a2" in result and p.fractions is None and p.restitution_law == "constant" and (
            p.tangential_restitution is None or p.elastic):
        # Maxwell's distribution (0) in equilibrium (wells too), the cooling state's first Sonine correction if not
        result["sonine_a2_theory"] = 0.0 if p.elastic else float(cooling_state_a2(p.restitution, p.dim))
    if measurement.species_temperatures is not None:  # each species' kT over the mixture's
        result |= _species_temperatures(p, measurement)
    if measurement.species_diffusion is not None:  # each species' self-diffusion coefficient
        result["self_diffusion_species"] = _nested([measurement.species_diffusion])[0]
        result["self_diffusion_species_error"] = _nested([measurement.species_diffusion_error])[0]
    if p.fractions is not None:
        result["species_counts"] = list(p.species_counts)
        if p.diameters is not None and len(set(p.diameters)) > 1:  # unlike diameters: no one contact distance
            del result["contact_value"], result["contact_value_error"]
    if measurement.transport is not None:
        result |= _transport_summary(run, measurement)
    if sheared:
        result |= _shear_summary(run, measurement, kT, result["energy_lost_total"])
    if run.trajectory is not None:
        result["trajectory_frames"] = run.frames
    result["files"] = [str(path) for path in files]
    result["parameters"] = p.to_dict()
    return result


def _mixture_theory(p, measurement, kT: float) -> dict[str, Any]:
    """Z against the mixture's equation of state (BMCSL, SYH) and Enskog's collision frequency with its contacts."""
    # the composition as run: the fractions rounded to whole particles
    species = ([count / p.particles for count in p.species_counts], p.diameters or (1.0,) * len(p.fractions))
    eta, Z = measurement.packing_fraction, measurement.compressibility_factor
    theory = mixture_compressibility(eta, *species, dim=p.dim)
    return {
        "theory": MIXTURE_EQUATION_OF_STATE[p.dim],
        "compressibility_factor_theory": theory,
        "compressibility_factor_relative_deviation": Z / theory - 1.0,
        "compressibility_factor_deviation_sigmas": _in_sigmas(Z - theory, measurement.compressibility_factor_error),
        "collision_frequency_theory": mixture_collision_frequency(eta, *species, p.masses or 1.0, p.dim, kT),
        "contact_values_theory": mixture_contact_values(eta, *species, dim=p.dim).tolist(),
    }


def _cooling_theory(p, result, measurement, elastic_below: float) -> dict[str, Any]:
    """The homogeneous cooling state's -d ln T / dC beside the measured: (1 - e^2) / d for one species; with a
    restitution law (one species) the Maxwellian rate at each block's kT, averaged as the measured rate is."""
    if p.restitution_law != "constant":  # (one species: the Maxwellian rate; none for mixtures)
        return {} if len(p.species_counts) > 1 else _law_cooling_theory(p, measurement, elastic_below)
    kinds = len(p.species_counts)
    composition = [count / p.particles for count in p.species_counts]
    theory = homogeneous_cooling_rate(p.packing_fraction, composition, p.diameters or (1.0,) * kinds,
                                      p.masses or 1.0, p.restitution, p.dim)
    return {"cooling_rate_theory": theory, "cooling_rate_deviation_sigmas":
            _in_sigmas(result["cooling_rate"] - theory, result["cooling_rate_error"])}


def _law_cooling_theory(p, measurement, elastic_below: float) -> dict[str, Any]:
    """A restitution law's Maxwellian -d ln T / dC, block by block at the geometric mean of its ends' kT.

    The rate falls as the gas cools, so the blocks' rates differ by more than
    their noise, and their scatter overstates the error of their mean (5 %
    against a seed-to-seed scatter of 0.3 % for viscoelastic spheres at u_c =
    1e3): the error of ``cooling_rate`` and the deviation in sigmas are taken
    from the blocks' residuals, measured minus theory, whose scatter is the
    noise alone.
    """
    ends = np.asarray(measurement.block_temperature, dtype=float)
    per_block = 2.0 * (p.collisions // p.blocks) / p.particles  # collisions per particle in a block
    measured = -np.diff(np.log(ends)) / per_block
    mass = p.masses[0] if p.masses else 1.0
    restitution = p.restitution if not isinstance(p.restitution, tuple) else p.restitution[0][0]
    theory = maxwellian_cooling_rate(np.sqrt(ends[:-1] * ends[1:]), p.dim, mass, p.restitution_law, restitution,
                                     p.law_speed, p.law_exponent, elastic_below)
    residuals = measured - theory
    error = block_error(residuals)
    return {"cooling_rate_error": error, "cooling_rate_theory": float(np.mean(theory)),
            "cooling_rate_deviation_sigmas": _in_sigmas(float(np.mean(residuals)), error)}


def _rough_summary(p, system, measurement, result, initial_energy: float) -> dict[str, Any]:
    """Rough spheres: the rotational kT at the end, and beside the blocks' mean T_r / T (``temperature_ratio``, from
    the measurement) the theory's where there is one (one species of constant restitution: :func:`_rough_theory`),
    with the kT the energy gives at equipartition if perfectly rough and elastic (``temperature_theory``). Smooth
    contacts (beta = -1) never turn the spins: T_r / T has no theory, the cooling is Haff's."""
    rough = {"tangential_restitution": p.tangential_restitution, "inertia_factor": system.inertia_factor,
             "friction": p.friction, "rotational_temperature": system.rotational_temperature()}
    if p.tangential_restitution == -1.0:
        return rough
    if p.elastic:  # every degree of freedom shares the energy: 2 E / ((d + f) N)
        degrees = system.dim + rotational_degrees(system.dim)
        rough["temperature_theory"] = 2.0 * initial_energy / (degrees * system.count)
    if len(p.species_counts) > 1 or p.restitution_law != "constant" or p.friction is not None:  # no theory here
        no_theory = {"cooling_rate_theory": math.nan, "cooling_rate_deviation_sigmas": math.nan}
        return rough | ({} if p.elastic else no_theory)
    return rough | _rough_theory(p, system, measurement, "cooling_rate" in result)


def _rough_theory(p, system, measurement, cooling: bool) -> dict[str, Any]:
    """T_r / T and the cooling rate of the Maxwellian theory (:func:`~collisionkit.edmd.rough_cooling`) block by
    block, from the first block's end: the transient towards the cooling state (or equipartition) included.

    The theory's values are the blocks' means as the measured ones are; the errors of the measured ones, and the
    deviations in sigmas, come from the blocks' residuals (measured minus theory), whose scatter is the noise alone
    while the blocks' own values drift through a transient. They leave out the slow variation from run to run that
    long-lived flows of a cooling gas bring (measured: T_r / T scatters 1.2-1.6 times its error over 12 seeds).
    """
    restitution = p.restitution if not isinstance(p.restitution, tuple) else p.restitution[0][0]
    ends = np.asarray(measurement.block_temperature, dtype=float)
    ratios = np.asarray(measurement.block_temperature_ratio, dtype=float)
    per_block = 2.0 * (p.collisions // p.blocks) / p.particles  # collisions per particle in a block
    T, T_r = rough_cooling(ends[0], ratios[0] * ends[0], per_block * np.arange(ends.size), restitution,
                           p.tangential_restitution, system.inertia_factor, p.dim)
    predicted = T_r / T
    residuals = ratios[1:] - predicted[1:]
    # a deviation of T_r / T from the theory's relaxes at the gap between the matrix's rates: the blocks' residuals
    # are correlated by rho = exp(-gap L) over a block of L collisions per particle, which widens the error of their
    # mean by sqrt((1 + rho) / (1 - rho)) (an AR(1) series)
    modes = np.sort(np.linalg.eigvals(rough_cooling_matrix(restitution, p.tangential_restitution,
                                                           system.inertia_factor, p.dim)).real)
    rho = math.exp(-(modes[1] - modes[0]) * per_block)
    widening = math.sqrt((1.0 + rho) / (1.0 - rho)) if rho < 1.0 else math.nan  # (no relaxation: no error known)
    error = block_error(residuals) * widening * residuals.size / ratios.size  # (the mean over all blocks: block 0's
    # residual is 0 by construction)
    if residuals.size < 2:  # two blocks: one residual, no scatter; the measurement's own errors stay
        error = measurement.temperature_ratio_error
    result = {"temperature_ratio_error": error, "temperature_ratio_theory": float(np.mean(predicted)),
              "temperature_ratio_deviation_sigmas": _in_sigmas(float(np.mean(ratios - predicted)), error)}
    if cooling and residuals.size < 2:
        result |= {"cooling_rate_theory": float(np.mean(-np.diff(np.log(T)) / per_block)),
                   "cooling_rate_deviation_sigmas": math.nan}
    elif cooling:
        rates = -np.diff(np.log(T)) / per_block
        rate_residuals = -np.diff(np.log(ends)) / per_block - rates
        rate_error = block_error(rate_residuals)
        result |= {"cooling_rate_error": rate_error, "cooling_rate_theory": float(np.mean(rates)),
                   "cooling_rate_deviation_sigmas": _in_sigmas(float(np.mean(rate_residuals)), rate_error)}
    return result


def _species_temperatures(p, measurement) -> dict[str, Any]:
    """Each species' T_a / T, and (at rest) the theory's: equipartition if elastic, else the homogeneous cooling
    state's (Garzo & Dufty 1999)."""
    result = {"temperature_species": _nested([measurement.species_temperatures])[0],
              "temperature_species_error": _nested([measurement.species_temperatures_error])[0]}
    rough_losses = p.tangential_restitution is not None and p.tangential_restitution != -1.0
    if p.shear_rate == 0.0 and p.fractions is not None and p.restitution_law == "constant" and not (
            rough_losses and not p.elastic):  # (an inelastic rough mixture: no theory here)
        composition = [count / p.particles for count in p.species_counts]
        theory = homogeneous_cooling_temperatures(p.packing_fraction, composition, p.diameters or (1.0,) * len(
            composition), p.masses or 1.0, p.restitution, p.dim)
        result["temperature_species_theory"] = theory.tolist()
    return result


def _nested(values) -> list:
    """A matrix as nested lists, NaN as None (JSON's null)."""
    return [[None if not math.isfinite(value) else float(value) for value in row] for row in values]


def _enskog(run, measurement, kT=None) -> dict[str, float]:
    """Enskog's coefficients of equal spheres or discs (unit diameter and mass) at the run's packing fraction
    and ``kT`` (default: the measured final temperature)."""
    kT = measurement.temperature if kT is None else kT
    return enskog_transport(measurement.packing_fraction, kT=kT, dim=run.parameters.dim)


def _shear_summary(run, measurement, kT: float, lost_total: float) -> dict[str, Any]:
    r"""The thermostat, Enskog's viscosity at ``kT`` (the mean) and the energy budget of a sheared run since its start.

    The budget is exact (:mod:`._shear`): the loss in collisions and the
    thermostat's energy are the engine's sums, the heating is what closes
    :math:`\Delta E + E_{lost} + E_{thermostat} = -G V \int P_{xy} dt`.
    """
    system = run.system
    collisions, thermostat = system.energy_lost, system.thermostat_energy
    result = {}
    if run.parameters.fractions is None:  # the zero-rate limit of one species' viscosity, at the mean kT
        result["shear_viscosity_enskog"] = _enskog(run, measurement, kT)["shear_viscosity"]
    return result | {
        "thermostat": run.parameters.thermostat,
        # G in units of the measured collision frequency per particle: shear thinning sets in beyond about 0.1
        "reduced_shear_rate": run.parameters.shear_rate / measurement.collision_frequency,
        "energy_lost_collisions_total": collisions,
        "thermostat_energy_total": thermostat,
        "viscous_heating_total": collisions + thermostat - lost_total,
    }


def _transport_summary(run, measurement) -> dict[str, Any]:
    """Enskog's transport coefficients (hard spheres) and, asked for, D corrected to the infinite system (Yeh-Hummer).

    Square wells and mixtures get no Enskog keys (its theory here is of one
    species of hard spheres); wells the correction at the measured mean kT
    (theirs changes at every capture).
    """
    p, transport = run.parameters, measurement.transport
    result = {}
    if p.well_width is None and p.fractions is None:
        enskog = _enskog(run, measurement)
        result = {f"{key}_enskog": enskog[key] for key in
                  ("shear_viscosity", "bulk_viscosity", "thermal_conductivity", "self_diffusion")}
    eta, eta_error = transport.shear_viscosity, transport.shear_viscosity_error
    if p.yeh_hummer:
        correction = error = math.nan  # a viscosity measured <= 0 (noise) gives no correction
        kT = measurement.temperature if p.well_width is None else measurement.temperature_mean
        if eta > 0:
            correction = float(yeh_hummer_correction(eta, float(run.system.box[0]), kT))
            error = math.hypot(measurement.diffusion_coefficient_error, correction * eta_error / eta)
        result |= {"yeh_hummer_correction": correction,
                   "self_diffusion_infinite": measurement.diffusion_coefficient + correction,
                   "self_diffusion_infinite_error": error}
    return result


def cooling_note(run) -> str | None:
    """What an inelastic ``run``'s averages mean, or an elastic sheared run's temperature; else None.

    The note of :meth:`~collisionkit.edmd.EdmdRun.cooling_note`, which
    shows each case.

    Examples
    --------
    >>> from collisionkit.edmd import EdmdParameters, EdmdRun
    >>> cooling_note(EdmdRun(EdmdParameters(dim=2, particles=64, initial="square", seed=1))) is None
    True
    """
    if run.parameters.elastic:
        return None if run.sampler is None or run.sampler.done < 2 else _heating_note(run)
    system, law = run.system, run.parameters.restitution_law
    kT = system.temperature()
    inelastic = "restitution < 1" if law == "constant" else f"the {law} restitution law"
    particles = "spheres" if system.dim == 3 else "discs"
    if system.rough and run.parameters.restitution_law == "constant" and np.all(np.asarray(system.restitution) == 1):
        inelastic = "rough contacts (tangential restitution between -1 and 1)"
    elif system.rough and system.tangential_restitution != -1.0:
        inelastic += " and rough contacts"
    elastic = "elastic and smooth" if system.rough else "elastic"
    if run.parameters.shear_rate != 0.0:
        compare = "; compare with granular_shear_flow (dilute gas)" if law == "constant" else ""
        return (f"{inelastic} under shear: the viscous heating of the flow balances the collisional cooling "
                f"in a steady state (kT from 1 to {kT:.3g}){compare}")
    if system.elastic_below > 0 and kT > BARELY_COOLED:
        return (f"{inelastic}, but the gas barely cooled (kT from 1 to {kT:.3g}): contacts slower than "
                f"--elastic-below {system.elastic_below:.3g} are {elastic}, and nearly all were; this is the run of "
                "an elastic gas")
    how = "homogeneous cooling, Haff's law" if law == "constant" else "homogeneous cooling, its rate falling with kT"
    if system.rough and system.tangential_restitution != -1.0:
        how = f"homogeneous cooling of rough {particles}, translation and rotation"
    theory = (_homogeneity_note(run) if law == "constant" or len(run.parameters.species_counts) == 1 else
              "no cooling theory is given for a mixture with a restitution law")
    note = (f"{inelastic}: the gas cooled as it ran ({how}), kT from 1 to {kT:.3g}; "
            f"Z, the collision frequency and D are averages over a cooling state, not equilibrium values; {theory}")
    if system.elastic_below > 0 and kT < 100.0 * system.elastic_below**2:
        note += (f". It reached the elastic floor: contacts slower than --elastic-below {system.elastic_below:.3g} "
                 f"are {elastic} (against inelastic collapse), and the late blocks measure that, not the cooling: a run "
                 "of fewer --collisions follows the cooling itself")
    return note


def homogeneity_theory(p, system, measurement) -> dict[str, Any]:
    """The dilute theory's critical box (:func:`~collisionkit.edmd.homogeneity.box_instability`) and, in a stable
    box, the homogeneity verdict against the cooling state's enhanced shear flows
    (:func:`~collisionkit.edmd.homogeneity.cooling_state_shear_energy`) instead of an uncorrelated gas's."""
    found = box_instability(p, system.box)
    if found is None:
        return {}
    if found["shear_mode_growth"] < 0.0:
        expected = cooling_state_shear_energy(found["box_length"], found["shear_instability_length"])
        per_block = 2.0 * measurement.collisions / (measurement.particles * measurement.block_shear_mode_energy.size)
        found |= homogeneity_summary(measurement.block_shear_mode_energy, p.dim, p.particles, per_block, expected)
    return found


def _homogeneity_note(run) -> str:
    """Whether the cooling gas stayed homogeneous, as the cooling theory assumes: measured in a periodic box
    (:mod:`~collisionkit.edmd.homogeneity`), else the assumption stated."""
    measurement = run.measurement() if run.sampler is not None and run.sampler.done >= 2 else None
    measured = {} if measurement is None else measurement.summary()
    if "homogeneous" not in measured:
        return "the cooling theory assumes the gas stayed homogeneous, which a dense or large one does not (clusters)"
    return homogeneity_wording(measured | homogeneity_theory(run.parameters, run.system, measurement), run.parameters)


def homogeneity_wording(measured: dict, p) -> str:
    """The note's words on a cooling run's homogeneity from its summary keys (``measured``) and parameters ``p``."""
    threshold, most, expected = (measured[key] for key in (
        "shear_mode_energy_threshold", "shear_mode_energy_max", "shear_mode_energy_expected"))
    compared = ("an uncorrelated gas's share" if expected == 1.0 else
                f"an uncorrelated gas's share (allowing for this box's cooling state, {expected:.2g} times it)")
    if measured["homogeneous"]:
        return (f"it stayed homogeneous, as the cooling theory assumes: its box-scale shear flows, the first to grow "
                f"in a large box, kept below {threshold:.3g} times {compared} (at most {most:.3g})")
    lost = measured["homogeneity_lost_after"]
    when = f"by C = {lost:.3g} collisions per particle measured"
    first_block = 2.0 * (p.collisions // p.blocks) / p.particles  # collisions per particle
    if math.isclose(lost, first_block) and p.equilibration > 0 and not p.elastic_equilibration:
        when += f" (after {2.0 * p.equilibration / p.particles:.3g} of equilibration, which cooled it too)"
    growing = measured.get("shear_mode_growth", 1.0) > 0.0  # (no theory: it may grow)
    advice = ("a smaller box, a restitution closer to 1 or fewer collisions keep it homogeneous"
              + ("" if p.elastic_equilibration else ", and --elastic-equilibration starts the cooling with the "
                 "measurement") if growing else
              "a smaller box or a restitution closer to 1 keep it further from the instability")
    if measured["shear_flow_energy_fraction"] >= VORTICES:
        return (f"it did not stay homogeneous: {when}, its box-scale shear flows held more than {threshold:.3g} "
                f"times {compared}, at most {most:.3g}, {measured['shear_flow_energy_fraction']:.0%} of the kinetic "
                f"energy (vortices, then clusters), and the homogeneous cooling theory holds only before that; {advice}")
    return (f"its box-scale shear flows rose above {threshold:.3g} times {compared} ({when}, at most {most:.3g}, "
            f"{measured['shear_flow_energy_fraction']:.1%} of the kinetic energy): the box is near or past the size at "
            f"which a cooling gas's shear flows grow into vortices, and the homogeneous cooling theory may be off by "
            f"some per cent; {advice}")


def _heating_note(run) -> str | None:
    """What the temperature of an elastic sheared run means, if the flow heated it by more than 5 % on average."""
    p, m = run.parameters, run.measurement()
    if p.shear_rate == 0.0 or not p.elastic or not m.temperature_mean > 1.05:
        return None
    reduced = p.shear_rate / m.collision_frequency
    where = "between the thermostat's rescalings (every 4 N pair collisions)" if p.thermostat else "(no thermostat)"
    note = (f"the flow heats the fluid {where}: kT averaged {m.temperature_mean:.3g}, the temperature the viscosity "
            f"and Enskog's value are taken at; reduced shear rate G / collision frequency {reduced:.2g}")
    if reduced > 0.1:
        note += (": beyond about 0.1 the fluid shear-thins, its viscosity below Enskog's G -> 0 value (0.97 of it at "
                 "0.09 for spheres at eta 0.3, 0.9 at 0.18 for discs)")
    return note
