r"""What a :class:`~collisionkit.edmd.Sampler` records at each block's end, and the observables its records give.

:func:`block_start` takes the totals a block is measured against,
:func:`record_block` appends the block's values to the sampler's records
(:data:`RECORDS`, and :data:`SHEAR_RECORDS` under shear) and accumulates
its speeds, pair distances and displacements; :func:`observables` turns
the records of the blocks done into the fields of a
:class:`~collisionkit.edmd.Measurement`: block means with standard errors,
g(r) with its contact value, the diffusion coefficient, the mean free time
and path, and, under shear, the stress, viscosity and energy budget.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .._kernels import edmd as _k
from . import _msd, _pair_distribution
from ._transport import transport_measurement
from .homogeneity import shear_mode_energy
from .theory import _ball_volume

# what the sampler records at the end of each block (temperature: kT at the end; temperature_mean: its time average)
# potential_energy: the time average of the square wells' potential energy per particle (0 for hard spheres)
RECORDS = ("temperature", "temperature_mean", "compressibility", "pressure", "frequency", "time", "msd", "msd_groups",
           "potential_energy")
# and, in a mixture, each species' kT over the mixture's at the block's end (T_a / T: equipartition gives 1)
MIXTURE_RECORDS = ("species_temperature",)
# and, under shear, the xy element of the pressure tensor (kinetic plus collisional), its collisional part and the
# energy the thermostat removed
SHEAR_RECORDS = ("shear_stress", "collisional_shear_stress", "thermostat_energy")
# and, of rough spheres, the rotational kT over the translational at the block's end, T_r / T
ROUGH_RECORDS = ("temperature_ratio",)
# and, at rest in a periodic box without gravity, the box-scale shear flows' energy over a homogeneous gas's share
# at the block's end (:func:`~collisionkit.edmd.shear_mode_energy`: about 1 while the gas stays homogeneous)
HOMOGENEITY_RECORDS = ("shear_mode_energy",)


def homogeneity_measurable(system) -> bool:
    """True if ``system``'s homogeneity can be measured: 2D or 3D, every axis periodic, no shear, no gravity."""
    return (system.dim >= 2 and system.shear_rate == 0.0 and bool(np.all(system.periodic))
            and not np.any(system.geom[_k.G_GRAVITY] != 0.0))


def block_start(system) -> dict:
    """The system's totals at the start of a block: virial, collisions, time, shear totals, thermostat energy.

    Examples
    --------
    >>> from collisionkit.edmd import HardSphereSystem
    >>> system = HardSphereSystem([[1.0, 1.0], [1.0, 5.0]], [[1.0, 0.0], [1.0, 0.0]], 0.5, 10.0)
    >>> block_start(system)["collisions"], block_start(system)["shear"] is None
    (0, True)
    """
    return {"virial": system.virial, "collisions": system.collisions, "time": system.elapsed,
            "shear": shear_totals(system), "thermostat": system.thermostat_energy, "wells": system.well_energy_time()}


def record_block(sampler, start, kT_after, kT, duration) -> None:
    """Append the block just run to ``sampler``'s records: kT at its end and mean, Z, P, frequency, time, MSD, shear.

    ``start`` is :func:`block_start` of the block, ``duration`` its time.
    Also adds the block end as an MSD time origin, a sample of the
    (peculiar) speeds and the pair distances for g(r).
    """
    system = sampler.system
    dim, count = system.dim, system.count
    virial = system.virial - start["virial"]
    record = sampler.records
    record["temperature"].append(kT_after)
    if "species_temperature" in record:
        record["species_temperature"].append(system.species_temperatures() / kT_after)
    if "temperature_ratio" in record:
        record["temperature_ratio"].append(system.rotational_temperature() / kT_after)
    if "shear_mode_energy" in record:
        record["shear_mode_energy"].append(shear_mode_energy(system.positions(), system.velocities(),
                                                             system.box[:dim], system.mass))
    record["temperature_mean"].append(kT)
    record["compressibility"].append(1.0 + virial / (dim * count * kT * duration))
    record["pressure"].append((count * kT + virial / (dim * duration)) / system.volume)
    record["frequency"].append(2.0 * (system.collisions - start["collisions"]) / (count * duration))
    record["potential_energy"].append(-(system.well_energy_time() - start["wells"]) / (count * duration))
    record["time"].append(system.elapsed - sampler.start_time)
    unwrapped = system.positions(unwrapped=True)
    axes = sampler._diffusion_axes()
    squared = np.sum((unwrapped[:, axes] - sampler.start_positions[:, axes]) ** 2, axis=1)
    record["msd"].append(float(np.mean(squared)))
    record["msd_groups"].append(_msd.group_means(squared))
    if system.shear_rate != 0.0:
        stress, collisional = shear_stresses(system, start["shear"], duration)
        record["shear_stress"].append(stress)
        record["collisional_shear_stress"].append(collisional)
        record["thermostat_energy"].append(system.thermostat_energy - start["thermostat"])
    if sampler.lag_msd is not None:
        sampler.lag_msd.add(unwrapped[:, axes], system.elapsed)
    # relative to the flow under shear (as kT is): lab-frame speeds grow with the box and the rate
    sampler.speeds.append(np.linalg.norm(system.peculiar_velocities(), axis=1))
    sampler.histogram += _pair_distribution.pair_histogram(system, sampler.r_max, sampler.histogram.size)
    if sampler.partial_histograms is not None:
        sampler.partial_histograms += _pair_distribution.partial_histograms(
            system, sampler.r_max, sampler.histogram.size, len(sampler.partial_histograms))


def shear_totals(system):
    """What the shear stress of a block is computed from: peculiar kinetic energy, energy lost and removed, stress."""
    if system.shear_rate == 0.0:
        return None
    return (system.kinetic_energy(), system.energy_lost, system.thermostat_energy,
            float(system.collisional_stress[0, 1]))


def shear_stresses(system, before, duration):
    r"""P_xy over a block (kinetic plus collisional) and its collisional part, from the exact energy balance.

    Over the block :math:`\Delta E + E_{lost} + E_{thermostat} = -G V \int
    P_{xy} dt` (see :mod:`._shear`): the total needs no sampling of the
    kinetic stress; the collisional part is the collisional stress sum's
    change over V t.
    """
    energy, lost, removed, stress = before
    work = (system.kinetic_energy() - energy) + (system.energy_lost - lost) + (system.thermostat_energy - removed)
    volume_time = system.volume * duration
    return (-work / (system.shear_rate * volume_time),
            (float(system.collisional_stress[0, 1]) - stress) / volume_time)


def observables(sampler) -> dict:
    """The fields of the :class:`~collisionkit.edmd.Measurement` of ``sampler``'s finished blocks (at least 2).

    Examples
    --------
    >>> from collisionkit.edmd import Sampler, lattice, maxwell_boltzmann, HardSphereSystem
    >>> import numpy as np
    >>> positions, box = lattice("square", 10, 0.3)
    >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
    >>> sampler = Sampler(system, collisions=4000, blocks=2)
    >>> while not sampler.finished:
    ...     sampler.run_block()
    >>> fields = observables(sampler)
    >>> fields["collisions"], fields["rdf"].shape
    (4000, (500,))
    """
    system, dim, count = sampler.system, sampler.system.dim, sampler.system.count
    record = sampler.records
    centres, rdf = _pair_distribution_function(sampler)
    speeds = np.concatenate(sampler.speeds)
    omega = float(np.mean(record["frequency"]))
    mean_speed = float(np.mean(speeds))
    msd_time = np.concatenate([[0.0], record["time"]])
    msd = np.concatenate([[0.0], record["msd"]])
    axes = len(sampler._diffusion_axes())
    from_lags = sampler.lag_msd.diffusion(axes) if sampler.lag_msd is not None else None
    diffusion, diffusion_error = from_lags or _msd.diffusion_from_msd(msd_time, msd, record["msd_groups"], axes)
    omega_error = _msd.block_error(record["frequency"])
    diameter = 2.0 * float(np.max(system.radius))
    ideal = sampler.done * count * ((count - 1) / system.volume) * _shells(sampler)  # ordered pairs at g = 1
    contact, contact_error = _pair_distribution.contact_value(centres, rdf, sampler.histogram, diameter, ideal)
    if np.ptp(system.radius) > 0:  # unlike diameters: g(r) sums pairs of several contact distances
        contact = contact_error = math.nan
    mixture = _partial_functions(sampler, centres)
    by_species = sampler.lag_msd.species_diffusion(axes) if sampler.lag_msd is not None else None
    if by_species is not None:
        mixture |= {"species_diffusion": by_species[0], "species_diffusion_error": by_species[1]}
    if "species_temperature" in record:
        mixture |= _species_temperatures(np.asarray(record["species_temperature"], dtype=float))
    if "shear_mode_energy" in record:  # (with the mixture's fields, though any run at rest has it)
        mixture["block_shear_mode_energy"] = np.asarray(record["shear_mode_energy"], dtype=float)
    if "temperature_ratio" in record:  # rough spheres
        ratios = np.asarray(record["temperature_ratio"], dtype=float)
        mixture |= {"temperature_ratio": float(np.mean(ratios)), "temperature_ratio_error": _msd.block_error(ratios),
                    "block_temperature_ratio": ratios}
    cooling, cooling_error = _cooling_rate(sampler)
    durations = np.diff(msd_time)
    block_kT = np.asarray(record["temperature_mean"], dtype=float)
    temperature_mean = float(np.sum(block_kT * durations) / np.sum(durations))
    return dict(
        dim=dim,
        particles=count,
        packing_fraction=system.packing_fraction,
        collisions=sampler.per_block * sampler.done,
        time=float(msd_time[-1]),
        wall_seconds=sampler.wall_seconds,
        temperature=float(record["temperature"][-1]),
        compressibility_factor=float(np.mean(record["compressibility"])),
        compressibility_factor_error=_msd.block_error(record["compressibility"]),
        pressure=float(np.mean(record["pressure"])),
        pressure_error=_msd.block_error(record["pressure"]),
        collision_frequency=omega,
        collision_frequency_error=omega_error,
        mean_free_time=1.0 / omega,
        mean_free_time_error=omega_error / omega**2,
        **_mean_free_path(sampler, mean_speed, omega, omega_error, math.isfinite(cooling)),
        mean_speed=mean_speed,
        diffusion_coefficient=diffusion,
        diffusion_coefficient_error=diffusion_error,
        energy_lost=float(system.energy_lost - sampler.start_lost),
        potential_energy=float(np.mean(record["potential_energy"])),
        potential_energy_error=_msd.block_error(record["potential_energy"]),
        contact_value=contact,
        contact_value_error=contact_error,
        cooling_rate=cooling,
        cooling_rate_error=cooling_error,
        **_sonine_a2(sampler),
        **mixture,
        speeds=speeds,
        rdf_r=centres,
        rdf=rdf,
        msd_time=msd_time,
        msd=msd,
        block_temperature=np.asarray(record["temperature"]),
        block_compressibility=np.asarray(record["compressibility"]),
        block_frequency=np.asarray(record["frequency"]),
        temperature_mean=temperature_mean,
        temperature_mean_error=_msd.block_error(block_kT),
        block_temperature_mean=block_kT,
        transport=None if sampler.transport is None else transport_measurement(
            sampler.transport, sampler.done, 1.0 / omega, system.volume, count,
            None if system.well_width is None else temperature_mean),
        **shear_results(system.shear_rate, record, system.volume * durations),
    )


def _species_temperatures(ratios) -> dict:
    """Each species' T_a / T: the mean and standard error over the blocks that recorded it (those of a checkpoint
    saved before the record existed are NaN: left out), and every block's."""
    known = ratios[np.all(np.isfinite(ratios), axis=1)]
    if not len(known):
        return {"species_temperatures": np.full(ratios.shape[1], math.nan), "block_species_temperatures": ratios,
                "species_temperatures_error": np.full(ratios.shape[1], math.nan)}
    return {"species_temperatures": np.mean(known, axis=0), "block_species_temperatures": ratios,
            "species_temperatures_error": np.array([_msd.block_error(column) for column in known.T])}


def _sonine_a2(sampler) -> dict:
    """The velocity distribution's fourth cumulant a2 = d/(d+2) <v^4>/<v^2>^2 - 1 at each block's end, its mean
    and standard error; none under shear (the distribution is not isotropic) or with unlike masses."""
    system = sampler.system
    if system.shear_rate != 0.0 or np.ptp(system.mass) > 0 or not sampler.speeds:
        return {}
    dim = system.dim
    values = [dim / (dim + 2.0) * np.mean(speeds**4) / np.mean(speeds**2) ** 2 - 1.0 for speeds in sampler.speeds]
    return {"sonine_a2": float(np.mean(values)), "sonine_a2_error": _msd.block_error(values),
            "block_sonine_a2": np.asarray(values)}


def block_rows(measurement) -> list[dict]:
    """A row per block of ``measurement``: its number, the collisions per particle C and the time at its end,
    then every ``block_*`` series of the measurement (a species' series as ``name[a]``) and the MSD.

    Examples
    --------
    >>> from collisionkit.edmd import measure, random_fluid
    >>> rows = block_rows(measure(random_fluid(2, 100, 0.2, seed=1), collisions=2000, blocks=4))
    >>> len(rows), rows[-1]["block"], rows[-1]["collisions_per_particle"]
    (4, 4, 40.0)
    """
    series = {field.name.removeprefix("block_"): getattr(measurement, field.name)
              for field in dataclasses.fields(measurement) if field.name.startswith("block_")}
    series = {name: np.asarray(values, dtype=float) for name, values in series.items() if values is not None}
    blocks = len(measurement.block_temperature)
    per_block = 2.0 * measurement.collisions / (measurement.particles * blocks)
    rows = []
    for index in range(blocks):
        row = {"block": index + 1, "collisions_per_particle": per_block * (index + 1),
               "time": float(measurement.msd_time[index + 1])}
        for name, values in series.items():
            if values.ndim == 1:
                row[name] = float(values[index])
            else:
                row |= {f"{name}[{kind}]": float(value) for kind, value in enumerate(values[index])}
        row["msd"] = float(measurement.msd[index + 1])
        rows.append(row)
    return rows


def _mean_free_path(sampler, mean_speed, omega, omega_error, cooling: bool) -> dict:
    """The mean free path: the mean speed over the collision frequency; for a cooling gas block by block.

    A cooling gas's speeds and collision rate fall with sqrt(kT) (their ratio does not), so their means over the
    run are no pair. Each block after the first gives v / omega from the geometric mean of the mean speeds at its
    ends, sqrt(v_k-1 v_k), and its collision frequency: exactly the mean free path times sinh(x) / x,
    x = ln(kT_k-1 / kT_k) / 4, if kT falls exponentially in the collisions and the distribution keeps its shape
    (the homogeneous cooling state), which is taken out; the blocks' mean, with their standard error.
    """
    if not cooling:
        return {"mean_free_path": mean_speed / omega, "mean_free_path_error": mean_speed * omega_error / omega**2}
    speeds = np.array([np.mean(block) for block in sampler.speeds])
    shrink = np.log(np.asarray(sampler.records["temperature"][:-1]) / sampler.records["temperature"][1:]) / 4.0
    factor = np.where(shrink != 0, shrink / np.sinh(np.where(shrink != 0, shrink, 1.0)), 1.0)  # (x / sinh x -> 1)
    paths = np.sqrt(speeds[:-1] * speeds[1:]) / np.asarray(sampler.records["frequency"][1:]) * factor
    return {"mean_free_path": float(np.mean(paths)), "mean_free_path_error": _msd.block_error(paths)}


def _cooling_rate(sampler) -> tuple[float, float]:
    """-d ln kT / dC with its standard error, C the collisions per particle (2 per pair collision / N), from the
    blocks after the first; NaN without energy lost, under shear or gravity, or with fewer than 3 blocks.

    Each block from one block end to the next gives -ln(kT_k / kT_k-1) / dC, their mean the rate over those blocks
    (Haff's law: a constant in a homogeneous cooling gas). The energy a collision takes is random, so ln kT wanders
    about Haff's line as a random walk: the blocks' rates are independent, their points on the line are not (a
    least-squares slope's error came out 2 to 3.5 times smaller than the scatter of repeated runs).
    """
    system, record = sampler.system, sampler.records
    falling = np.any(system.geom[_k.G_GRAVITY] != 0.0)
    if sampler.done < 3 or system.shear_rate != 0.0 or falling or not system.energy_lost > sampler.start_lost:
        return math.nan, math.nan
    per_block = 2.0 * sampler.per_block / system.count
    rates = -np.diff(np.log(np.asarray(record["temperature"], dtype=float))) / per_block
    return float(np.mean(rates)), _msd.block_error(rates)


def _pair_distribution_function(sampler):
    """The bin centres and g(r) of ``sampler``'s pair-distance histogram over the blocks done."""
    system, count = sampler.system, sampler.system.count
    edges = np.linspace(0.0, sampler.r_max, sampler.histogram.size + 1)
    centres = 0.5 * (edges[1:] + edges[:-1])
    # ordered pairs: each of the N particles sees the other N - 1 at density (N - 1) / V
    rdf = sampler.histogram / (sampler.done * count * ((count - 1) / system.volume) * _shells(sampler))
    return centres, rdf


def _shells(sampler):
    """The volumes of the g(r) bins' shells."""
    edges = np.linspace(0.0, sampler.r_max, sampler.histogram.size + 1)
    return _ball_volume(edges[1:], sampler.system.dim) - _ball_volume(edges[:-1], sampler.system.dim)


def _partial_functions(sampler, centres) -> dict:
    """A mixture's partial g_ab(r) and their contact values g_ab(r_a + r_b) with errors (none for one species).

    g_ab(r) = H_ab / (blocks N_a n_b' V_shell) with n_b' = (N_b - delta_ab) / V:
    each particle of a sees those of b (the others of a) at that density.
    """
    if sampler.partial_histograms is None:
        return {}
    system = sampler.system
    species, radius = np.asarray(system.species), np.asarray(system.radius)
    kinds = len(sampler.partial_histograms)
    counts = np.bincount(species, minlength=kinds).astype(float)
    edges = np.linspace(0.0, sampler.r_max, sampler.histogram.size + 1)
    shells = _ball_volume(edges[1:], system.dim) - _ball_volume(edges[:-1], system.dim)
    partners = (counts[None, :] - np.eye(kinds)) / system.volume
    ideal = sampler.done * counts[:, None, None] * partners[:, :, None] * shells  # pairs at g = 1, [a, b]
    with np.errstate(invalid="ignore", divide="ignore"):
        rdf = sampler.partial_histograms / ideal
    contact = np.full((kinds, kinds), math.nan)
    error = np.full((kinds, kinds), math.nan)
    for a, b in np.ndindex(kinds, kinds):
        if counts[a] > 0 and counts[b] > (a == b):
            distance = float(radius[species == a][0] + radius[species == b][0])
            # the cross pairs counted once each: the fit's Poisson weights take the histogram counted twice
            twice = 1.0 if a == b else 2.0
            contact[a, b], error[a, b] = _pair_distribution.contact_value(
                centres, rdf[a, b], sampler.partial_histograms[a, b] * twice, distance, ideal[a, b] * twice)
    return {"partial_rdf": rdf, "contact_values": contact, "contact_values_error": error}


def shear_results(rate, record, volume_times):
    """The Measurement's shear fields from the block records (none without shear); V t of each block given."""
    if rate == 0.0:
        return {}
    stress, collisional = np.asarray(record["shear_stress"]), np.asarray(record["collisional_shear_stress"])
    return {"shear_rate": rate, "thermostat_energy": float(np.sum(record["thermostat_energy"])),
            "viscous_heating": -rate * float(np.sum(stress * volume_times)),
            "shear_stress": float(np.mean(stress)), "shear_stress_error": _msd.block_error(stress),
            "collisional_shear_stress": float(np.mean(collisional)),
            "collisional_shear_stress_error": _msd.block_error(collisional),
            "shear_viscosity": -float(np.mean(stress)) / rate, "shear_viscosity_error": _msd.block_error(stress) / rate}
