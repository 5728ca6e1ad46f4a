"""Event-driven molecular dynamics of hard spheres (3D) and hard discs (2D).

Particles fly ballistically (parabolas under uniform gravity) between exact
pair collisions, processed one event at a time in time order; collision
times come from the contact quadratic and the collision rule acts along the
line of centres (the pair-collision notes). Boxes may be periodic or closed by
hard walls on each axis; radii and masses may differ (mixtures); collisions
may be inelastic with a coefficient of normal restitution per species pair,
optionally velocity dependent.

The numeric work runs in :mod:`collisionkit._kernels.edmd` (neighbour lists
with a shell, rebuilt from cell lists; an array-backed tournament tree over
blocks of event times; lazily updated particles).

Modules: :mod:`~collisionkit.edmd.theory` (equations of state, Enskog's
collision rate, packing fractions and their limits),
:mod:`~collisionkit.edmd.mixture_theory` (the same for mixtures),
:mod:`~collisionkit.edmd.restitution_laws` (velocity-dependent restitution
and the cooling of a granular gas),
:mod:`~collisionkit.edmd.initial` (velocities, lattices, compressed random
fluids), :mod:`~collisionkit.edmd.system` (the system and its event loop),
:mod:`~collisionkit.edmd.measurement` (block-averaged observables; with
``transport=True`` also the transport coefficients from the Einstein-Helfand
moments, sampled on a time grid and fitted in ``_helfand``),
:mod:`~collisionkit.edmd.run` (:class:`EdmdRun`: the ``edmd`` command's run,
with checkpoint and bit-for-bit resume). Every
public name is importable from here.

Units: any consistent set; the CLI uses diameter 1 (largest species), mass 1
and initial kT = 1.
"""

from ._helfand import FIT_END, FIT_NOISE, FIT_START, EinsteinFit, green_kubo_viscosity
from ._msd import MSD_FIT_FROM, MSD_GROUPS, MSD_MAX_LAGS
from ._neighbour_lists import LIST_SCALE_MARGIN
from .initial import LATTICE_BASIS, LATTICE_DIM, lattice, lattice_cells, maxwell_boltzmann, random_fluid
from ._transport import TransportMeasurement, TransportSampler
from .measurement import RECORDS, Measurement, Sampler, measure
from .run import EdmdParameters, EdmdRun
from ._shear import THERMOSTAT_INTERVAL
from .system import (
    DEFAULT_SHELL, DENSE_PACKING, DENSE_SHELL, DILUTE_PACKING, LIST_NEIGHBOURS, RESTITUTION_LAWS, SORT_INTERVAL,
    HardSphereSystem, OverlapError, default_shell, well_shell,
)
from .mixture_theory import (
    MIXTURE_EQUATION_OF_STATE, homogeneous_cooling_rate, homogeneous_cooling_temperatures, mixture_collision_frequency,
    mixture_compressibility, mixture_contact_values, mixture_cooling_rates,
)
from ._rotation import random_spins
from .rough_theory import rough_cooling, rough_cooling_matrix, rough_cooling_state
from .homogeneity import homogeneity_threshold, shear_instability_length, shear_mode_energy, shear_mode_growth
from .restitution_laws import maxwellian_cooling, maxwellian_cooling_rate, restitution_coefficient
from .square_well_theory import (
    square_well_collision_integral,
    square_well_deflection,
    square_well_dilute_transport,
    square_well_low_density,
    square_well_mixture_second_virial,
    square_well_second_virial,
    square_well_third_virial,
)
from .theory import (
    MAX_PACKING_FRACTION,
    YEH_HUMMER_XI,
    carnahan_starling,
    chapman_enskog_transport,
    cooling_state_a2,
    enskog_collision_frequency,
    enskog_transport,
    granular_shear_flow,
    hansen_goos,
    henderson,
    packing_fraction,
    yeh_hummer_correction,
)

__all__ = [
    "EdmdParameters",
    "EdmdRun",
    "DEFAULT_SHELL",
    "DENSE_PACKING",
    "DENSE_SHELL",
    "DILUTE_PACKING",
    "EinsteinFit",
    "FIT_END",
    "FIT_NOISE",
    "FIT_START",
    "LATTICE_BASIS",
    "LATTICE_DIM",
    "LIST_NEIGHBOURS",
    "LIST_SCALE_MARGIN",
    "MAX_PACKING_FRACTION",
    "MIXTURE_EQUATION_OF_STATE",
    "MSD_FIT_FROM",
    "MSD_GROUPS",
    "MSD_MAX_LAGS",
    "RECORDS",
    "RESTITUTION_LAWS",
    "SORT_INTERVAL",
    "THERMOSTAT_INTERVAL",
    "TransportMeasurement",
    "TransportSampler",
    "YEH_HUMMER_XI",
    "HardSphereSystem",
    "Measurement",
    "OverlapError",
    "Sampler",
    "carnahan_starling",
    "chapman_enskog_transport",
    "cooling_state_a2",
    "default_shell",
    "well_shell",
    "enskog_collision_frequency",
    "enskog_transport",
    "granular_shear_flow",
    "green_kubo_viscosity",
    "hansen_goos",
    "maxwellian_cooling",
    "maxwellian_cooling_rate",
    "restitution_coefficient",
    "henderson",
    "lattice",
    "lattice_cells",
    "maxwell_boltzmann",
    "measure",
    "homogeneity_threshold",
    "homogeneous_cooling_rate",
    "homogeneous_cooling_temperatures",
    "mixture_collision_frequency",
    "mixture_compressibility",
    "mixture_contact_values",
    "mixture_cooling_rates",
    "packing_fraction",
    "random_fluid",
    "random_spins",
    "rough_cooling",
    "rough_cooling_matrix",
    "rough_cooling_state",
    "shear_instability_length",
    "shear_mode_energy",
    "shear_mode_growth",
    "square_well_collision_integral",
    "square_well_deflection",
    "square_well_dilute_transport",
    "square_well_low_density",
    "square_well_mixture_second_virial",
    "square_well_second_virial",
    "square_well_third_virial",
    "yeh_hummer_correction",
]
