"""Monte Carlo transport of particles with collisions: swarms in fields and slabs.

Following Krasov (sec. 5.5): a particle moves under a force field, a free
path is drawn at random (``s = -lambda ln xi``), the trajectory is followed
until the path is used up, the particle collides and scatters, and a new
free path is drawn. Extended with energy-dependent cross sections (null
collisions), real gases (LXCat files) and transport coefficients.

* :func:`simulate_swarm` - drift, diffusion, rates and mean energy of a
  swarm in E (and B) fields; :class:`SwarmResult`; :func:`trace_trajectories`
  for plots; :func:`diffusion_error_floor`;
* :class:`SwarmScan` - the ``swarm`` command's E/N scan (:class:`SwarmParameters`),
  with checkpoint and resume;
* :func:`two_term_boltzmann` - the two-term Boltzmann equation (as BOLSIG+
  and LoKI-B solve it): the energy distribution, mobility, diffusion and
  rates in milliseconds to a second; :class:`TwoTermResult`; :class:`TwoTermScan`, the
  ``boltzmann`` command's E/N scan and its tables;
* :func:`bolsig_tables` - a scan's coefficients as BOLSIG+'s output tables
  (:func:`write_bolsig_tables`, :func:`read_bolsig_section`), which plasma
  fluid codes read;
* :func:`simulate_slab` - transmission and reflection of a beam by a slab
  (:class:`SlabRun`: the same, checkpointed);
* gases: :class:`Gas`, :class:`Species`, :class:`Process`, model gases
  (:func:`maxwell_model`, :func:`hard_sphere_gas`, :func:`reid_ramp`,
  :func:`lucas_saelee`) and :func:`read_lxcat`;
* real gases by name: :func:`catalogue_gas` (``"Ar"``, ``"Ar:0.9,N2:0.1"``),
  the :data:`CATALOGUE` of LXCat sets (shipped, or placed in :func:`data_folder`);
* angular scattering laws (:mod:`~collisionkit.transport.angular`:
  :func:`mean_scattering_cosine`, :func:`momentum_transfer_ratio`),
  superelastic collisions (:mod:`~collisionkit.transport.superelastic`:
  :func:`superelastic_cross_section`, :func:`level_populations`) and SST
  Townsend coefficients (:func:`townsend_coefficients`), also measured by
  a spatially resolved SST run (:func:`simulate_sst`);
* particles in any field and in devices (:mod:`collisionkit.transport.tracking`):
  fields, surfaces, :class:`Device`, :func:`track` (avalanches, gain, spectra,
  induced currents), :class:`TrackParameters` and :class:`TrackRun` (the
  ``track`` command).
"""

from .angular import SCATTERING_LAWS, mean_scattering_cosine, momentum_transfer_ratio
from .bolsig_tables import BOLSIG_SECTIONS, bolsig_tables, missing_rows, read_bolsig_section, write_bolsig_tables
from .detector_units import TORR, detector_coefficients, gas_number_density, reduced_fields
from .gases import (
    MODEL_GASES,
    SCATTERING_KINDS,
    Gas,
    Process,
    Species,
    hard_sphere_gas,
    lucas_saelee,
    maxwell_model,
    model_gas,
    reid_ramp,
    screened_coulomb_momentum_ratio,
)
from .lxcat import LXCatError, LXCatWarning, parse_lxcat, read_lxcat
from .catalogue import (
    CATALOGUE,
    GasSet,
    catalogue,
    catalogue_entry,
    catalogue_files,
    catalogue_gas,
    data_folder,
    parse_gas_spec,
)
from .scan import SwarmParameters, SwarmScan, swarm_summary
from .slab import SlabResult, simulate_slab
from .superelastic import level_populations, superelastic_cross_section
from .slab_parameters import SlabParameters, run_slab, slab_summary
from .slab_run import SlabRun
from .sst import SSTResult, simulate_sst
from .swarm import (
    DEFAULT_TOLERANCES,
    HUXLEY,
    TOWNSEND,
    SwarmResult,
    diffusion_error_floor,
    simulate_swarm,
    trace_trajectories,
)
from .townsend import townsend_coefficients

__all__ = [
    "TORR",
    "detector_coefficients",
    "gas_number_density",
    "reduced_fields",
    "BOLSIG_SECTIONS",
    "CATALOGUE",
    "DEFAULT_TOLERANCES",
    "HUXLEY",
    "MODEL_GASES",
    "SCATTERING_KINDS",
    "SCATTERING_LAWS",
    "TOWNSEND",
    "Gas",
    "GasSet",
    "LXCatError",
    "LXCatWarning",
    "Process",
    "Species",
    "SlabParameters",
    "SlabResult",
    "SSTResult",
    "SwarmParameters",
    "SwarmScan",
    "SwarmResult",
    "bolsig_tables",
    "catalogue",
    "catalogue_entry",
    "catalogue_files",
    "catalogue_gas",
    "data_folder",
    "diffusion_error_floor",
    "hard_sphere_gas",
    "level_populations",
    "lucas_saelee",
    "maxwell_model",
    "mean_scattering_cosine",
    "missing_rows",
    "model_gas",
    "parse_gas_spec",
    "momentum_transfer_ratio",
    "parse_lxcat",
    "read_bolsig_section",
    "read_lxcat",
    "reid_ramp",
    "run_slab",
    "screened_coulomb_momentum_ratio",
    "simulate_slab",
    "simulate_sst",
    "simulate_swarm",
    "slab_summary",
    "SlabRun",
    "superelastic_cross_section",
    "swarm_summary",
    "townsend_coefficients",
    "trace_trajectories",
    "write_bolsig_tables",
]

# particle tracking in devices (issue 18)
from . import tracking  # noqa: E402
from .tracking import (  # noqa: E402
    CoaxialField, Cylinder, Device, DipoleMagneticField, FieldMap, Geometry, IonDrift, MagneticMirror,
    ParallelPlateField, Plane, PointChargeField, Sphere, TrackingResult, TrackParameters, TrackRun, UniformField,
    UniformMagneticField, UserField, WeightingField, coaxial_geometry, gas_density, parallel_plate_geometry,
    read_field_map, track, track_summary,
)

__all__ += [
    "CoaxialField", "Cylinder", "Device", "DipoleMagneticField", "FieldMap", "Geometry", "IonDrift", "MagneticMirror",
    "ParallelPlateField", "Plane", "PointChargeField", "Sphere", "TrackingResult", "TrackParameters", "TrackRun",
    "UniformField", "UniformMagneticField", "UserField", "WeightingField", "coaxial_geometry", "gas_density",
    "parallel_plate_geometry", "read_field_map", "track", "track_summary",
]

# a periodic field of any shape given as samples (issue 20)
from ._waveform import read_waveform  # noqa: E402

__all__ += ["read_waveform"]

# the two-term Boltzmann equation (the approximation of BOLSIG+ and LoKI-B): the swarm's fast companion
from .two_term import TwoTermResult, TwoTermWarning, two_term_boltzmann  # noqa: E402

__all__ += ["TwoTermResult", "TwoTermWarning", "two_term_boltzmann"]
from .two_term_scan import TwoTermParameters, TwoTermScan, run_two_term, two_term_summary  # noqa: E402

__all__ += ["TwoTermParameters", "TwoTermScan", "run_two_term", "two_term_summary"]
