"""What the ``edmd`` command shows and writes once the run is done: the table, the plots, the files and the summary."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ._common import Deliveries, print_table, say, warn

# the plots of --out (the Helfand moments with --transport only, the equation of state for elastic runs only, the
# cooling for a gas that cooled at rest only)
PLOTS = ("equation_of_state.png", "speed_distribution.png", "snapshot.png", "radial_distribution.png",
         "helfand_moments.png", "cooling.png")
OUT_FILES = (*PLOTS, "blocks.csv")  # what --out gets: the plots and the blocks' records (Measurement.block_table)


def _theory_column(result: dict) -> tuple[str, str, str, str]:
    """Reference values for Z, omega, kT and the energy lost: theory if elastic, trends if not.

    Under shear the flow's work heats an elastic fluid (the total "lost" is what the thermostat removed minus
    that heating): kT rises, or the thermostat brings it back to 1 every 4 N pair collisions.
    """
    if not result["elastic"]:
        from ..edmd.run import BARELY_COOLED

        if result.get("elastic_below") and result["temperature"] > BARELY_COOLED:  # the floor made it elastic
            return "elastic floor: nearly all contacts elastic", "", "barely cools (elastic floor)", "> 0 (small)"
        cools = "cools (Haff)" if result.get("restitution_law", "constant") == "constant" else "cools"
        if result.get("tangential_restitution") is not None:
            cools = "cools (rough spheres)"
        return "no equilibrium (inelastic)", "", cools, "> 0"
    if result.get("well_width"):
        return "(square wells: see the virial expansion)", "", "1 while equilibrating, then the mean below", "0 (elastic)"
    z = f"{result['compressibility_factor_theory']:.5g} ({result['theory']})"
    if "collision_frequency_from_pressure" in result:
        omega = f"{result['collision_frequency_from_pressure']:.5g} (Enskog, from Z)"
    else:  # a mixture: Enskog's rate with the equation of state's contact values
        omega = f"{result['collision_frequency_theory']:.5g} (Enskog, {result['theory'].split()[0]} contacts)"
    if result.get("shear_rate"):
        kT = "1 at each rescaling (thermostat)" if result["thermostat"] else "rises (viscous heating)"
        return z, omega, kT, "0 (elastic); total: " + ("thermostat - heating" if result["thermostat"] else "- heating")
    kT = "1 (elastic)"
    if "temperature_theory" in result:  # rough spheres sharing the energy with their spins
        kT = f"{result['temperature_theory']:.6g} (equipartition with the spins)"
    return z, omega, kT, "0 (elastic)"


def rows(result: dict) -> list[tuple[str, str, str]]:
    """The table's rows (quantity, measured, theory) of an edmd summary.

    Examples
    --------
    >>> from collisionkit.edmd import EdmdParameters, EdmdRun
    >>> run = EdmdRun(EdmdParameters(dim=2, particles=64, initial="square", collisions=400, blocks=2, seed=1))
    >>> rows(run.run().summary())[0][0]
    'compressibility factor Z = PV/NkT'
    """
    def pm(key):
        return f"{result[key]:.5g} ± {result[key + '_error']:.2g}"

    z, omega, kT, lost = _theory_column(result)
    contact = [("g(r) at contact", _pm_or_dash(result["contact_value"], result["contact_value_error"]),
                "" if _finite(result["contact_value"]) else "too few pairs near contact: more blocks or particles")
               ] if "contact_value" in result else []
    contact += _partial_contact_rows(result)
    return _shear_rows(result, pm) + _transport_rows(result, pm) + _well_rows(result, pm) + _species_rows(result) + [
        ("compressibility factor Z = PV/NkT", pm("compressibility_factor"), z),
        ("collision frequency per particle", pm("collision_frequency"), omega),
        ("temperature kT (final)", f"{result['temperature']:.6g}", kT),
        *_cooling_rows(result, pm),
        *_rotation_rows(result, pm),
        *_a2_rows(result, pm),
        ("mean free path", pm("mean_free_path"), ""),
        ("diffusion coefficient", pm("diffusion_coefficient"), "from the MSD"),
        *contact,
        ("energy lost (measurement / total)", f"{result['energy_lost']:.5g} / {result['energy_lost_total']:.5g}", lost),
        ("pair collisions (measured)", str(result["collisions"]), f"after {result['equilibration_collisions']} equilibration"),
        ("collisions per second", f"{result['collisions_per_second']:.4g}",
         f"wall clock, measurement (no compiling), {result['engine']} engine"),
    ]


def _rough_cooling(p, system, collisions, measurement):
    """Rough spheres' block-end kT_r and the Maxwellian theory's kT and kT_r from the first block end on (one species
    of constant restitution; kT_r alone otherwise): (theory kT or None, kT_r, theory kT_r or None); None if smooth."""
    if measurement.block_temperature_ratio is None:
        return None
    rotation = measurement.block_temperature_ratio * measurement.block_temperature
    if len(p.species_counts) > 1 or p.restitution_law != "constant" or p.tangential_restitution == -1.0 or \
            p.friction is not None:  # (as the summary: no theory there)
        return None, rotation, None
    from ..edmd import rough_cooling

    restitution = p.restitution if not isinstance(p.restitution, tuple) else p.restitution[0][0]
    T, T_r = rough_cooling(measurement.block_temperature[0], rotation[0], collisions - collisions[0], restitution,
                           p.tangential_restitution, system.inertia_factor, p.dim)
    return T, rotation, T_r


def _law_cooling(p, system, collisions, temperatures):
    """A restitution law's Maxwellian kT from the first block end on (one species), else None."""
    if p.restitution_law == "constant" or len(p.species_counts) > 1:
        return None
    from ..edmd import maxwellian_cooling

    restitution = p.restitution if not isinstance(p.restitution, tuple) else p.restitution[0][0]
    return maxwellian_cooling(collisions - collisions[0], temperatures[0], p.dim, p.masses[0] if p.masses else 1.0,
                              p.restitution_law, restitution, p.law_speed, p.law_exponent, system.elastic_below)


def _cooling_rows(result: dict, pm) -> list[tuple[str, str, str]]:
    """A cooling gas's rate per collision, -d ln T / dC (C: collisions per particle), beside the theory's."""
    if "cooling_rate" not in result:
        return []
    theory = result.get("cooling_rate_theory")
    where = "Haff, (1 - e^2)/d" if "species_counts" not in result else "homogeneous cooling, Garzo-Dufty"
    if result.get("restitution_law", "constant") != "constant":
        sigmas = result.get("cooling_rate_deviation_sigmas")
        off = "" if sigmas is None or not math.isfinite(sigmas) else f"; measured {sigmas:+.1f} sigma"
        where = f"Maxwellian, {result['restitution_law']} law, blocks' mean{off}"
    if result.get("tangential_restitution") is not None:
        where = "rough spheres, Maxwellian, blocks' mean"
    shown = "" if theory is None or not math.isfinite(theory) else f"{theory:.5g} ({where})"
    return [("cooling rate per collision -d ln T/dC", pm("cooling_rate"), shown), *_homogeneity_rows(result)]


def _homogeneity_rows(result: dict) -> list[tuple[str, str, str]]:
    """Did the cooling gas stay homogeneous? The box-scale shear flows' energy over a homogeneous gas's share."""
    if "shear_mode_energy_max" not in result:
        return []
    lost, expected = result["homogeneity_lost_after"], result["shear_mode_energy_expected"]
    verdict = (f"homogeneous: below {result['shear_mode_energy_threshold']:.3g}" if lost is None else
               f"not homogeneous from C = {lost:.3g} (threshold {result['shear_mode_energy_threshold']:.3g})")
    if expected > 1.0:  # a stable box: its cooling state's enhanced flows
        verdict += f"; cooling state {expected:.3g}"
    if "shear_instability_length" in result:  # the dilute theory's critical box
        verdict += f"; box {result['box_length'] / result['shear_instability_length']:.2g} L_c"
    return [("shear flows / homogeneous share (max)", f"{result['shear_mode_energy_max']:.3g}", verdict)]


def _rotation_rows(result: dict, pm) -> list[tuple[str, str, str]]:
    """Rough spheres: the rotational kT and T_r / T, beside equipartition or the rough cooling state's ratio."""
    if result.get("tangential_restitution") is None:
        return []
    theory = result.get("temperature_ratio_theory")
    shown = "" if theory is None else (f"{theory:.5g} (" + ("equipartition" if result["elastic"] else
                                                            "Maxwellian, blocks' mean") + ")")
    return [("rotational temperature kT_r (final)", f"{result['rotational_temperature']:.6g}", ""),
            ("T_r / T (blocks' mean)", pm("temperature_ratio"), shown)]


def _a2_rows(result: dict, pm) -> list[tuple[str, str, str]]:
    """The velocity distribution's fourth cumulant a2, beside Maxwell's 0 or the cooling state's."""
    if "sonine_a2" not in result:
        return []
    theory = result.get("sonine_a2_theory")
    shown = "" if theory is None else ("0 (Maxwell)" if result["elastic"] else f"{theory:.4g} (van Noije-Ernst)")
    return [("velocity cumulant a2 = d<v^4>/((d+2)<v^2>^2) - 1", pm("sonine_a2"), shown)]


def _partial_contact_rows(result: dict) -> list[tuple[str, str, str]]:
    """A mixture's g_ab at contact, for each pair of species a <= b, with the equation of state's."""
    if "contact_values" not in result:
        return []
    from ..trajectory import type_names

    values, errors = result["contact_values"], result["contact_values_error"]
    theory = result.get("contact_values_theory")
    names = type_names(list(range(len(values))))
    def beside(a, b):
        if not _finite(values[a][b]):
            return "too few pairs near contact"
        return "" if theory is None else f"{theory[a][b]:.5g} ({result['theory'].split()[0]})"

    return [(f"g_{names[a]}{names[b]} at contact", _pm_or_dash(values[a][b], errors[a][b]), beside(a, b))
            for a in range(len(values)) for b in range(a, len(values))]


def _pm_or_dash(value, error) -> str:
    """value ± error, or "-" if either is missing (JSON's null) or not finite."""
    return f"{value:.5g} ± {error:.2g}" if _finite(value) and _finite(error) else "-"


def _finite(value) -> bool:
    return value is not None and math.isfinite(value)


def _species_rows(result: dict) -> list[tuple[str, str, str]]:
    """The row of a mixture (--fractions): the particles of each species, their diameters and masses."""
    if "species_counts" not in result:
        return []
    p = result["parameters"]
    count = len(p["fractions"])
    diameters, masses = p["diameters"] or [1.0] * count, p["masses"] or [1.0] * count
    kinds = ", ".join(f"{n} x (d {d:g}, m {m:g})" for n, d, m in zip(result["species_counts"], diameters, masses))
    rows = [("species: particles x (diameter, mass)", kinds, f"{count} species")]
    from ..trajectory import type_names

    names = type_names(list(range(count)))

    def each(key):
        return ", ".join(f"{names[k]} {_pm_or_dash(value, error)}" for k, (value, error) in
                         enumerate(zip(result[key], result[key + "_error"])))

    if "temperature_species" in result:
        theory = result.get("temperature_species_theory")
        where = "equipartition" if result["elastic"] else "homogeneous cooling, Garzo-Dufty"
        rows.append(("temperature per species T_a/T (block ends)", each("temperature_species"),
                     "" if theory is None else ", ".join(f"{names[k]} {value:.4g}" for k, value in enumerate(theory))
                     + f": {where}"))
    if "self_diffusion_species" in result:
        rows.append(("diffusion coefficient per species", each("self_diffusion_species"), "from the MSD of each"))
    return rows


def _number_or_table(value) -> str:
    """A well's width or depth or the restitution as printed: a number, or a matrix over the species row by row
    (``1.5 1.4 / 1.4 1``)."""
    if isinstance(value, (list, tuple)):
        return " / ".join(" ".join(f"{item:g}" for item in row) for row in value)
    return f"{value:g}"


def _well_rows(result: dict, pm) -> list[tuple[str, str, str]]:
    """The rows of a square-well run (--well-width): potential energy, mean kT, T*, the events at the wells' edges."""
    if not result.get("well_width"):
        return []
    return [
        ("potential energy per particle U/N", pm("potential_energy"),
         f"-epsilon per pair inside (lambda {_number_or_table(result['well_width'])}, epsilon "
         f"{_number_or_table(result['well_depth'])})"),
        ("temperature kT (time mean)", pm("temperature_mean"), f"T* = kT/epsilon = {result['reduced_temperature']:.5g}"),
        ("well events: captures / escapes / bounces",
         f"{result['well_captures']} / {result['well_escapes']} / {result['well_bounces']}", "since the start"),
    ]


def _shear_rows(result: dict, pm) -> list[tuple[str, str, str]]:
    """The rows of a sheared run (--shear-rate): the shear stress and the viscosity from it."""
    if "shear_rate" not in result:
        return []
    enskog = result.get("shear_viscosity_enskog")
    budget = " / ".join(f"{result[key]:.5g}" for key in
                        ("energy_lost_collisions_total", "thermostat_energy_total", "viscous_heating_total"))
    return [
        ("shear viscosity -P_xy/G", pm("shear_viscosity"),
         f"{enskog:.4g} (Enskog, G -> 0, at the mean kT)" if enskog is not None
         else f"shear rate G = {result['shear_rate']:g}"),
        ("shear stress P_xy (collisional part)", f"{pm('shear_stress')} ({pm('collisional_shear_stress')})",
         f"shear rate G = {result['shear_rate']:g}"),
        ("temperature kT (time average)", pm("temperature_mean"), "what the stress was measured at"),
        ("energy: collisions / thermostat / heating", budget, "total = collisions + thermostat - heating"),
    ]


def _transport_rows(result: dict, pm) -> list[tuple[str, str, str]]:
    """The rows of the transport coefficients (with --transport), Enskog's values in the theory column."""
    if "transport_fit_window" not in result:
        return []

    def enskog(key):
        return f"{result[key + '_enskog']:.4g} (Enskog)" if key + "_enskog" in result else ""

    low, high = result["transport_fit_window"]
    free_low, free_high = result["transport_fit_window_free_times"]
    rows = [
        ("shear viscosity", pm("shear_viscosity"), enskog("shear_viscosity")),
        ("bulk viscosity", pm("bulk_viscosity"), enskog("bulk_viscosity")),
        ("thermal conductivity", pm("thermal_conductivity"), enskog("thermal_conductivity")),
        ("self-diffusion", pm("self_diffusion"), enskog("self_diffusion")),
    ]
    if "self_diffusion_infinite" in result:
        rows.append(("self-diffusion, N = infinity", pm("self_diffusion_infinite"),
                     f"Yeh-Hummer: + {result['yeh_hummer_correction']:.3g}"))
    if "interdiffusion" in result:
        rows.append(("interdiffusion D12 (/ thermodynamic factor)", pm("interdiffusion"), ""))
    rows.append(("shear viscosity, Green-Kubo", pm("green_kubo_shear_viscosity"), "the stress series, cross-check"))
    rows.append(("transport fit window", f"{low:.4g} to {high:.4g}",
                 f"{free_low:.3g} to {free_high:.3g} mean free times"))
    return rows


def _speed_distribution(run, measurement, plotting, masses):
    """The speeds against Maxwell's distribution; a cooling gas's each scaled by its block's thermal speed (the
    shape of its distribution, at kT = 1), since pooled they span every kT it passed."""
    if not math.isfinite(measurement.cooling_rate):
        return plotting.plot_speed_distribution(measurement.speeds, measurement.temperature, run.system.dim, **masses)
    scaled = np.concatenate([speeds / math.sqrt(kT) for speeds, kT in zip(run.sampler.speeds,
                                                                            measurement.block_temperature)])
    ax = plotting.plot_speed_distribution(scaled, 1.0, run.system.dim, **masses)
    ax.set_title("a cooling gas: each block's speeds over its thermal speed")
    return ax


def _plots(run, measurement, out: Path, deliveries: Deliveries) -> None:
    """Draw the plots into ``out``, each written through ``deliveries`` (a failed one is reported at the end)."""
    import matplotlib

    matplotlib.use("Agg")
    from .. import plotting

    system, p = run.system, run.parameters
    figures = []
    composition = [count / p.particles for count in p.species_counts]  # as run: the fractions rounded to particles
    mixture = None if p.fractions is None else (composition, p.diameters or (1.0,) * len(composition))
    masses = {"mass": p.masses or 1.0, "fractions": composition if p.masses else None}
    if p.elastic:
        m = measurement
        point = [(m.packing_fraction, m.compressibility_factor, m.compressibility_factor_error)]
        figures.append(("equation_of_state.png", lambda: plotting.plot_equation_of_state(point, system.dim,
                                                                                       mixture=mixture)))
    figures.append(("speed_distribution.png", lambda: _speed_distribution(run, measurement, plotting, masses)))
    figures.append(("snapshot.png", lambda: plotting.plot_snapshot(
        system.positions(), system.radius, system.box[: system.dim], species=system.species if mixture else None)))
    figures.append(("radial_distribution.png", lambda: plotting.plot_radial_distribution(
        measurement.rdf_r, measurement.rdf, partial=measurement.partial_rdf)))
    if measurement.transport is not None:
        figures.append(("helfand_moments.png", lambda: plotting.plot_helfand_moments(measurement.transport)[0]))
    if math.isfinite(measurement.cooling_rate):
        collisions = 2.0 * run.sampler.per_block * np.arange(1, run.sampler.done + 1) / system.count
        summary = run.summary()
        rate = summary.get("cooling_rate_theory")  # (NaN: no theory, rough spheres of a mixture or with a law)
        rough = _rough_cooling(p, system, collisions, measurement)
        theory, rotation, theory_rotation = rough if rough is not None else (
            _law_cooling(p, system, collisions, measurement.block_temperature), None, None)
        figures.append(("cooling.png", lambda: plotting.plot_cooling(
            collisions, measurement.block_temperature, rate if rate is not None and math.isfinite(rate) else None,
            measurement.block_species_temperatures, species_theory=summary.get("temperature_species_theory"),
            theory_temperatures=theory, rotation=rotation, theory_rotation=theory_rotation,
            homogeneity_lost_after=summary.get("homogeneity_lost_after"))))

    def folder():
        out.mkdir(parents=True, exist_ok=True)

    deliveries.write(f"the plot folder {out}", folder)
    for name, draw in figures:
        deliveries.write(f"the plot {out / name}", lambda name=name, draw=draw: plotting.save(draw(), out / name))
    from .._io import write_csv

    deliveries.write(f"the block table {out / 'blocks.csv'}",
                     lambda: write_csv(out / "blocks.csv", measurement.block_table()))
    drawn = {name for name, _ in figures}
    for name in PLOTS:  # an earlier run's plot that this run does not draw (replaced with --overwrite) goes
        if name not in drawn:
            (out / name).unlink(missing_ok=True)


def report(run, options, extra: dict) -> None:
    """Print the table and the notes, write the files and the summary (rescued if writing fails: exit 1)."""
    measurement = run.measurement()
    deliveries = Deliveries("edmd")
    if options.xyz is not None:
        deliveries.write(f"--xyz {options.xyz}", lambda: run.write_xyz(options.xyz))
    if options.trajectory is not None:
        deliveries.files.append(options.trajectory)
    if options.plots:
        _plots(run, measurement, options.out, deliveries)
    result = run.summary(deliveries.files) | extra
    p = run.parameters
    kind = ("spheres" if p.dim == 3 else "discs") + ("" if p.fractions is None else f" of {len(p.fractions)} species")
    law = "" if p.restitution_law == "constant" else (
        f" ({p.restitution_law} law, u_c = {p.law_speed:g}" + (f", p = {p.law_exponent:g})" if p.restitution_law ==
                                                               "bridges" else ")"))
    if p.tangential_restitution is not None:
        law += f", rough: beta = {p.tangential_restitution:g}, kappa = {run.system.inertia_factor:g}"
        law += "" if p.friction is None else f", mu = {p.friction:g}"
    title = (f"EDMD: {p.particles} hard {kind}, eta = {p.packing_fraction:g}, e = {_number_or_table(p.restitution)}"
             f"{law}, seed {p.seed}")
    print_table(title, ("quantity", "measured", "theory"), rows(result))
    note = run.cooling_note()
    if note is not None:
        warn(note)
    for path in deliveries.files:
        say(f"wrote {path}")
    deliveries.finish(options.summary, result)
