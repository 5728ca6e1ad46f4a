"""collisionkit: exact binary-collision physics.

The collision core is available at the top level::

    import collisionkit as ck
    v1_after, v2_after = ck.resolve_contact(m1, v1, m2, v2, normal)

Modules: :mod:`collisionkit.collisions` (contact resolution and detection),
:mod:`collisionkit.kinematics` (geometry and frames),
:mod:`collisionkit.scattering` (hard-sphere and Rutherford laws),
:mod:`collisionkit.compat.irfpy` (irfpy's collision API).
"""

import importlib

from . import kinematics
from .collisions import RESTITUTION_MODELS, Contact, collide, resolve_contact, time_to_contact
from .kinematics import (
    centre_of_mass_velocity,
    energy_transfer_fraction,
    from_centre_of_mass_frame,
    impact_angle_2d,
    impact_angles_3d,
    impact_parameter,
    kinetic_energy,
    lab_scattering_angle,
    normal_from_impact_angles,
    recoil_angle,
    reduced_mass,
    resolve_impact_angles,
    sample_impact,
    scattering_angle_cm,
    to_centre_of_mass_frame,
)

__version__ = "0.1.0"

# the domains and tools load on first use (``collisionkit.transport``, ``import collisionkit.edmd``): a run of one
# domain does not import the others (nor scipy's integrators through them): `import collisionkit` took 1.06 s and
# 161 MB, most of it the encounters, sweep and compat modules (python -X importtime; issue 21's memory point)
_SUBMODULES = ("compat", "edmd", "encounters", "plotting", "scattering", "sweep", "trajectory", "transport")


def __getattr__(name):
    """Import a domain or tool module the first time it is used (PEP 562)."""
    if name in _SUBMODULES:
        module = importlib.import_module(f".{name}", __name__)
        globals()[name] = module
        return module
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_SUBMODULES))

__all__ = [
    "Contact",
    "RESTITUTION_MODELS",
    "centre_of_mass_velocity",
    "collide",
    "compat",
    "encounters",
    "energy_transfer_fraction",
    "from_centre_of_mass_frame",
    "impact_angle_2d",
    "impact_angles_3d",
    "impact_parameter",
    "kinematics",
    "kinetic_energy",
    "lab_scattering_angle",
    "normal_from_impact_angles",
    "recoil_angle",
    "reduced_mass",
    "resolve_contact",
    "resolve_impact_angles",
    "sample_impact",
    "scattering",
    "scattering_angle_cm",
    "sweep",
    "time_to_contact",
    "to_centre_of_mass_frame",
    "transport",
]
