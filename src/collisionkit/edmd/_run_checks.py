"""The checks of an EDMD run (:mod:`.run`): its parameters when they are made, its measurement when it is resumed.

:func:`checked_parameters` is :class:`~collisionkit.edmd.EdmdParameters`'
validation: every value in its range (a ``ValueError`` or ``TypeError``
naming the parameter and what it allows) and the rules between them, so a
run that cannot go is refused before any work. :func:`check_saved_run`
refuses a checkpoint whose measurement or engine does not fit its
parameters.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from .._params import check_choice, check_integer, check_real, check_seed
from ._cell_crossings import ENGINE_NAMES
from ._wells import MAX_WELL_WIDTH
from ._msd import MSD_GROUPS
from ._pair_distribution import PARTIAL_RDF_SPECIES
from ._rotation import UNIFORM_INERTIA
from ._system_setup import RESTITUTION_LAWS
from .initial import LATTICE_DIM, lattice_cells
from .mixture_theory import FRACTION_SUM_TOLERANCE
from .theory import MAX_PACKING_FRACTION

INITIAL_STATES = ("random", *LATTICE_DIM)
ENGINES = ("auto", *ENGINE_NAMES)
# the largest speed threshold (elastic_below, in thermal speeds sqrt(kT/m)): 1000 makes every contact elastic
MAX_SPEED = 1e3
# the largest shear rate, in sqrt(kT/m) / sigma: a box of 10 diameters then slides at 10^4 thermal speeds, where an
# inelastic gas is heated 10^6-fold; typical granular and rheology runs use 0.01 to 5
MAX_SHEAR_RATE = 1e3
# the deepest well, in units of the kT = 1 a run equilibrates at (T* = 1e-3: far below any phase transition)
MAX_WELL_DEPTH = 1e3
# the most pair collisions of a run's equilibration or measurement: about 3 years at 10^6 a second
MAX_COLLISIONS = 10**14
# a mixture's smallest diameter, relative to the largest (the unit): the neighbour lists are rebuilt from cells of
# the largest diameter, so a small particle's rebuild scans ~ratio^-d times its own neighbours
MIN_DIAMETER = 0.1
MASS_RANGE = (1e-3, 1e3)
# a restitution law's speed u_c, in thermal speeds: the viscoelastic law's 1 - e ~ (u_n / u_c)^(1/5) is still 1e-6 at
# u_c = 1e30 (a nearly elastic material); the Bridges law's exponent (0.234 for ice)
MAX_LAW_SPEED = 1e30
MAX_LAW_EXPONENT = 10.0
# the largest initial rotational kT of rough spheres, in units of the translational kT = 1
MAX_ROTATIONAL_TEMPERATURE = 100.0
# the largest friction coefficient of rough contacts (beyond a few, every contact sticks)
MAX_FRICTION = 100.0
MAX_SPECIES = 26


def checked_parameters(p) -> dict[str, Any]:
    """The values of the parameters ``p`` checked and normalised (ints, floats), by name; raises if one is refused.

    Examples
    --------
    >>> from collisionkit.edmd import EdmdParameters
    >>> EdmdParameters(engine="cells", shear_rate=0.1)
    Traceback (most recent call last):
    ...
    ValueError: engine cells cannot be combined with shear_rate: the cell-crossing engine runs straight flights only (use engine lists or auto)
    >>> EdmdParameters(engine="grid")
    Traceback (most recent call last):
    ...
    ValueError: engine must be one of auto, lists, cells; got 'grid'
    """
    values: dict[str, Any] = {}
    check_choice("dim", p.dim, (2, 3))
    values["particles"] = check_integer("particles", p.particles, 2, 100_000_000)
    limit = MAX_PACKING_FRACTION[p.dim]
    eta = check_real("packing_fraction", p.packing_fraction, 0.0, low_open=True)
    if eta > limit:
        raise ValueError(f"packing_fraction must lie in (0, {limit}] for dim={p.dim}; got {eta:g}")
    values["packing_fraction"] = eta
    if p.elastic_below is not None:
        values["elastic_below"] = check_real("elastic_below", p.elastic_below, 0.0, MAX_SPEED)
    blocks = values["blocks"] = check_integer("blocks", p.blocks, 2, 100_000)
    if p.equilibration is not None:
        values["equilibration"] = check_integer("equilibration", p.equilibration, 0, MAX_COLLISIONS)
    if p.collisions is not None:
        collisions = values["collisions"] = check_integer("collisions", p.collisions, 2, MAX_COLLISIONS)
        if collisions < blocks:
            raise ValueError(f"collisions must be >= blocks ({blocks}); got {collisions}")
    if p.seed is not None:
        values["seed"] = check_seed("seed", p.seed)
    check_choice("initial", p.initial, INITIAL_STATES)
    if p.initial != "random":
        lattice_cells(p.initial, p.dim, values["particles"])
    shear_rate = values["shear_rate"] = check_real("shear_rate", p.shear_rate, 0.0, MAX_SHEAR_RATE)
    for name in ("transport", "yeh_hummer", "thermostat", "elastic_equilibration"):
        if not isinstance(getattr(p, name), bool):
            raise ValueError(f"{name} must be true or false; got {getattr(p, name)!r}")
    check_choice("engine", p.engine, ENGINES)
    if p.elastic_equilibration and shear_rate != 0.0 and not p.thermostat:
        raise ValueError("elastic_equilibration with a shear_rate needs the thermostat: elastic contacts leave the "
                         "flow's heat nowhere to go, and the gas would heat up before the measurement")
    if p.thermostat and shear_rate == 0.0:
        raise ValueError("thermostat needs a shear_rate > 0 (it holds a sheared system at kT = 1)")
    if p.transport and shear_rate != 0.0:
        raise ValueError("transport cannot be combined with shear_rate (the Einstein-Helfand relations hold in "
                         "equilibrium); a sheared run reports shear_viscosity from its stress")
    if p.yeh_hummer and not (p.transport and p.dim == 3):
        raise ValueError("yeh_hummer needs transport (the correction uses the measured shear viscosity) and dim 3 "
                         "(its constant is the cubic lattice's)")
    values |= _checked_species(p, values["particles"])
    kinds = None if p.fractions is None else len(values["fractions"])
    values["restitution"] = _number_or_matrix("restitution", p.restitution, kinds, 0.0, 1.0, False)
    values |= _checked_law(p)
    values |= _checked_roughness(p, values["particles"])
    inelastic = bool(np.any(np.asarray(values["restitution"]) != 1.0)) or p.restitution_law != "constant"
    if inelastic and p.transport:
        given = (f"restitution {_shown(values['restitution'])}" if p.restitution_law == "constant" else
                 f"restitution_law {p.restitution_law}")
        raise ValueError(f"transport needs restitution 1 and restitution_law constant (the Einstein-Helfand "
                         f"relations hold in equilibrium, which an inelastic gas never reaches); got {given}")
    if p.well_width is not None:
        values["well_width"] = _number_or_matrix("well_width", p.well_width, kinds, 1.0, MAX_WELL_WIDTH, True)
        clashes = ((shear_rate != 0.0, "shear_rate", "wells run in a fluid at rest"),
                    (p.engine == "cells", "engine cells", "the cell-crossing engine has no wells: use lists or auto"),
                   (inelastic, "restitution below 1 or a restitution_law", "wells keep the energy of elastic pairs"))
        for clash, name, why in clashes:
            if clash:
                raise ValueError(f"well_width cannot be combined with {name} ({why})")
    depth = values["well_depth"] = _number_or_matrix("well_depth", p.well_depth, kinds, 0.0, MAX_WELL_DEPTH, True)
    if isinstance(depth, tuple) and not max(map(max, depth)) > 0.0:
        raise ValueError("well_depth: some pair of species needs a well (depth > 0); 0 is a pair without one")
    if p.engine == "cells" and shear_rate != 0.0:  # what HardSphereSystem refuses, said before any work
        raise ValueError("engine cells cannot be combined with shear_rate: the cell-crossing engine runs straight "
                         "flights only (use engine lists or auto)")
    return values


def _checked_roughness(p, particles: int) -> dict[str, Any]:
    """Rough spheres: beta in [-1, 1] and kappa in (0, 1]; an inertia factor needs beta, and rough spheres refuse
    transport, shear and wells (their collisional fluxes have no spin terms)."""
    temperature = check_real("initial_rotational_temperature", p.initial_rotational_temperature, 0.0,
                             MAX_ROTATIONAL_TEMPERATURE)
    if p.tangential_restitution is None:
        for name, unused in (("inertia_factor", p.inertia_factor is not None), ("friction", p.friction is not None),
                             ("initial_rotational_temperature", temperature != 1.0)):
            if unused:
                raise ValueError(f"{name} needs rough spheres: give a tangential restitution in [-1, 1]")
        return {"initial_rotational_temperature": temperature}
    values = {"tangential_restitution": check_real("tangential_restitution", p.tangential_restitution, -1.0, 1.0),
              "initial_rotational_temperature": temperature}
    if p.inertia_factor is not None:
        values["inertia_factor"] = check_real("inertia_factor", p.inertia_factor, 0.0, 1.0, low_open=True)
    if p.friction is not None:
        values["friction"] = check_real("friction", p.friction, 0.0, MAX_FRICTION, low_open=True)
    clashes = ((p.transport, "transport", "the Einstein-Helfand moments have no spin terms"),
               (p.shear_rate != 0.0, "a shear rate", "the sheared engine keeps no spins"),
               (p.well_width is not None, "square wells", "wells are smooth"))
    for clash, name, why in clashes:
        if clash:
            raise ValueError(f"tangential_restitution (rough spheres) cannot be combined with {name} ({why})")
    return values


def _checked_law(p) -> dict[str, Any]:
    """The restitution law and its parameters; a parameter the law does not use is refused unless left at its
    default (a law_speed given with the constant law would be silently ignored)."""
    check_choice("restitution_law", p.restitution_law, tuple(RESTITUTION_LAWS))
    values = {"law_speed": check_real("law_speed", p.law_speed, 0.0, MAX_LAW_SPEED, low_open=True),
              "law_exponent": check_real("law_exponent", p.law_exponent, 0.0, MAX_LAW_EXPONENT, low_open=True)}
    defaults = {field.name: field.default for field in dataclasses.fields(p)}
    used = {"constant": (), "bridges": ("law_speed", "law_exponent"), "viscoelastic": ("law_speed",)}
    for name in ("law_speed", "law_exponent"):
        if name not in used[p.restitution_law] and values[name] != defaults[name]:
            laws = " or ".join(law for law, names in used.items() if name in names)
            raise ValueError(f"{name} needs restitution_law {laws} (restitution_law {p.restitution_law} has no "
                             f"{name}); got {name} {values[name]:g}")
    return values


def _shown(value) -> str:
    """A number or a matrix as a message shows it."""
    return f"{value:g}" if not isinstance(value, tuple) else _listed(value)


def _listed(value) -> str:
    """Nested sequences as a config file writes them: [[0.9, 0.8], [0.8, 0.7]], not tuples."""
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_listed(item) for item in value) + "]"
    return repr(value)


def _reals(name: str, value, count: int | None, low: float, high: float, low_open=False) -> tuple[float, ...]:
    """``value`` as a tuple of floats in [low, high], one per species (``count`` of them if given)."""
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__"):
        raise ValueError(f"{name} must be a sequence of numbers, one per species; got {value!r}")
    if count is not None and len(value) != count:
        raise ValueError(f"{name} must give one value per species ({count}, as fractions does); got {len(value)}")
    return tuple(check_real(f"{name}[{index}]", item, low, high, low_open=low_open) for index, item in enumerate(value))


def _number_or_matrix(name: str, value, kinds: int | None, low: float, high: float, low_open: bool):
    """A number in its range, or (a mixture's) symmetric matrix over the species as a tuple of tuples; in a matrix
    a depth may be 0 (that pair has no well). Used for the wells and the restitution."""
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if not isinstance(value, (list, tuple)):
        return check_real(name, value, low, high, low_open=low_open)
    if kinds is None:
        raise ValueError(f"{name} as a matrix (one per species pair) needs fractions (the species)")
    if len(value) != kinds or any(not isinstance(row, (list, tuple)) or len(row) != kinds for row in value):
        raise ValueError(f"{name} must be a number or a {kinds} x {kinds} matrix (one per pair of the {kinds} "
                         f"species of fractions); got {_listed(value)}")
    entry_low_open = low_open and name != "well_depth"
    matrix = tuple(tuple(check_real(f"{name}[{a}][{b}]", item, low, high, low_open=entry_low_open)
                         for b, item in enumerate(row)) for a, row in enumerate(value))
    if any(matrix[a][b] != matrix[b][a] for a in range(kinds) for b in range(kinds)):
        raise ValueError(f"{name} must be a symmetric matrix (pair a, b is pair b, a); got {_listed(value)}")
    return matrix


def _checked_species(p, particles: int) -> dict[str, Any]:
    """A mixture's fractions, diameters and masses checked (tuples of floats), with the rules between them."""
    if p.fractions is None:
        for name in ("diameters", "masses"):
            if getattr(p, name) is not None:
                raise ValueError(f"{name} needs fractions (the species' number fractions, which {name} follows)")
        return {}
    fractions = _reals("fractions", p.fractions, None, 0.0, 1.0, low_open=True)
    if not 1 <= len(fractions) <= MAX_SPECIES:
        raise ValueError(f"fractions must give 1 to {MAX_SPECIES} species; got {len(fractions)}")
    if abs(sum(fractions) - 1.0) > FRACTION_SUM_TOLERANCE:
        raise ValueError(f"fractions must sum to 1; got {list(fractions)} (sum {sum(fractions):.9g})")
    values: dict[str, Any] = {"fractions": fractions}
    counts = species_counts(particles, fractions)
    if min(counts) < 1:
        raise ValueError(f"fractions {list(fractions)} leave a species without particles among {particles} "
                         f"(counts {list(counts)}): raise particles or a fraction")
    if p.diameters is not None:
        diameters = values["diameters"] = _reals("diameters", p.diameters, len(fractions), MIN_DIAMETER, 1.0)
        if max(diameters) != 1.0:
            raise ValueError(f"diameters are relative to the largest species (the unit of length): the largest must "
                             f"be 1; got {list(diameters)}")
    if p.masses is not None:
        values["masses"] = _reals("masses", p.masses, len(fractions), *MASS_RANGE)
    if p.initial != "random":
        raise ValueError(f"fractions (a mixture) needs initial random (a lattice holds one species); got initial "
                         f"{p.initial}")
    return values


def species_counts(particles: int, fractions) -> tuple[int, ...]:
    """``particles`` split by the number ``fractions``: floor(N x_i), the rest one each to the largest remainders.

    Ties go to the earlier species; no fractions: one species of all.

    Examples
    --------
    >>> species_counts(10, (0.25, 0.75)), species_counts(7, (1 / 3, 1 / 3, 1 / 3)), species_counts(5, None)
    ((3, 7), (3, 2, 2), (5,))
    """
    if fractions is None:
        return (particles,)
    shares = [particles * fraction / sum(fractions) for fraction in fractions]
    counts = [int(share) for share in shares]
    by_remainder = sorted(range(len(shares)), key=lambda index: (counts[index] - shares[index], index))
    for index in by_remainder[: particles - sum(counts)]:
        counts[index] += 1
    return tuple(counts)


def _species_fit(parameters, system) -> bool:
    """True if the system's particles are the parameters' species: their counts, diameters and masses."""
    counts = parameters.species_counts
    species = np.asarray(system.species)
    if system.count != parameters.particles or species.min() < 0 or species.max() >= len(counts):
        return False
    if tuple(np.bincount(species, minlength=len(counts))) != counts:
        return False
    diameters = np.asarray(parameters.diameters or (1.0,) * len(counts))[species]
    masses = np.asarray(parameters.masses or (1.0,) * len(counts))[species]
    return bool(np.array_equal(2.0 * np.asarray(system.radius), diameters) and np.array_equal(system.mass, masses))


def _species_temperatures_fit(row, parameters) -> bool:
    """A block's T_a / T: one per species, each finite and >= 0 with sum_a x_a T_a / T = 1, or all NaN (a block
    saved before they were recorded)."""
    counts = np.asarray(parameters.species_counts, dtype=float)
    row = np.asarray(row, dtype=float)
    if row.shape != counts.shape:
        return False
    if np.all(np.isnan(row)):
        return True
    return bool(np.all(np.isfinite(row) & (row >= 0.0)) and abs(np.dot(counts / counts.sum(), row) - 1.0) < 1e-9)


def check_saved_run(saved, sampler, parameters, system) -> None:
    """CheckpointError if the saved measurement does not fit the run (blocks, block length, records, positions),
    or the saved system runs another engine than ``parameters.engine`` asks for."""
    if parameters.engine != "auto" and system.engine != parameters.engine:
        raise saved.damaged(f"its system runs the {system.engine} engine, its parameters ask for engine "
                            f"{parameters.engine}")
    if not _species_fit(parameters, system):
        raise saved.damaged("its particles' species, diameters or masses are not those its parameters give")
    rough = (system.tangential_restitution, system.inertia_factor, system.friction)
    kappa = parameters.inertia_factor if parameters.inertia_factor is not None else UNIFORM_INERTIA[parameters.dim]
    if rough != ((None, None, None) if parameters.tangential_restitution is None else (
            parameters.tangential_restitution, kappa, parameters.friction)):
        raise saved.damaged("its system's roughness (tangential restitution, inertia factor, friction) is not the "
                            "one its parameters give")
    if sampler is None:
        return
    lengths = {len(values) for values in sampler.records.values()} | {len(sampler.speeds)}
    fits = (sampler.blocks, sampler.per_block) == (parameters.blocks, parameters.collisions // parameters.blocks)
    fits &= len(lengths) == 1 and lengths.pop() <= sampler.blocks and sampler.histogram.ndim == 1
    fits &= sampler.start_positions.shape == (system.count, system.dim) and math.isfinite(sampler.r_max)
    partial = sampler.partial_histograms
    kinds = len(parameters.species_counts)
    fits &= partial is None or (partial.shape == (kinds, kinds, sampler.histogram.size)
                                and bool(np.all(np.isfinite(partial) & (partial >= 0))))
    lag = sampler.lag_msd
    if lag is not None and lag.species_all is not None:
        fits &= lag.species_all.shape == (lag.lags, kinds) and lag.species_groups.shape == (lag.lags, kinds,
                                                                                             MSD_GROUPS)
        fits &= bool(np.all(np.isfinite(lag.species_all)))
    fits &= all(_species_temperatures_fit(row, parameters) for row in sampler.records.get("species_temperature", ()))
    shear_modes = np.asarray(sampler.records.get("shear_mode_energy", ()), dtype=float)  # >= 0, or NaN: unknown
    fits &= shear_modes.ndim == 1 and not np.any(np.isinf(shear_modes) | (shear_modes < 0))
    # a mixture of a few species records its partial histograms from its first block (a file without them is damaged)
    fits &= partial is not None or not 1 < kinds <= PARTIAL_RDF_SPECIES
    fits &= (sampler.transport is not None) == parameters.transport
    fits &= sampler.transport is None or len(sampler.transport.edge_times) == sampler.done + 1
    if not fits:
        raise saved.damaged("its measurement arrays (sampler_*) do not fit its parameters and particles")
