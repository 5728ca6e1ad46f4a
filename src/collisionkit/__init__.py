"""collisionkit: exact binary-collision physics.

The collision core is available at the top level::

    import collisionkit as ck
    v1_after, v2_after = ck.resolve_contact(m1, v1, m2, v2, normal)

Modules: :mod:`collisionkit.collisions` (contact resolution and detection),
:mod:`collisionkit.kinematics` (geometry and frames),
:mod:`collisionkit.scattering` (hard-sphere and Rutherford laws),
:mod:`collisionkit.compat.irfpy` (irfpy's collision API); the domains
:mod:`collisionkit.edmd` (event-driven dynamics), :mod:`collisionkit.transport`
(Monte Carlo transport), :mod:`collisionkit.encounters` (two-body
encounters); :mod:`collisionkit.sweep` (parameter studies),
:mod:`collisionkit.trajectory` (GSD and XYZ files) and
:mod:`collisionkit.plotting` (needs matplotlib).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # the names below, imported on first use (PEP 562)
    from . import compat, edmd, encounters, kinematics, scattering, sweep, trajectory, transport
    from .collisions import RESTITUTION_MODELS, Contact, collide, resolve_contact, time_to_contact
    from .kinematics import (
        centre_of_mass_velocity, energy_transfer_fraction, from_centre_of_mass_frame, impact_angle_2d,
        impact_angles_3d, impact_parameter, kinetic_energy, lab_scattering_angle, normal_from_impact_angles,
        recoil_angle, reduced_mass, resolve_impact_angles, sample_impact, scattering_angle_cm, to_centre_of_mass_frame,
    )

# `import collisionkit` imports nothing heavy (numpy, numba, scipy take a second or two): the submodules and the
# names below load on first use, so the `collisionkit` script starts at once and answers a Ctrl-C during its
# imports with one line instead of a traceback (collisionkit._command)
# (python -X importtime: the eager imports took 1.06 s and 161 MB, so a run of one domain also paid for the others)
_SUBMODULES = ("compat", "edmd", "encounters", "kinematics", "plotting", "scattering", "sweep", "trajectory",
               "transport")
_NAMES = dict.fromkeys(("RESTITUTION_MODELS", "Contact", "collide", "resolve_contact", "time_to_contact"),
                       "collisions") | dict.fromkeys((
    "centre_of_mass_velocity", "energy_transfer_fraction", "from_centre_of_mass_frame", "impact_angle_2d",
    "impact_angles_3d", "impact_parameter", "kinetic_energy", "lab_scattering_angle", "normal_from_impact_angles",
    "recoil_angle", "reduced_mass", "resolve_impact_angles", "sample_impact", "scattering_angle_cm",
    "to_centre_of_mass_frame"), "kinematics")


def __getattr__(name: str):
    """A submodule or a name of the collision core, imported the first time it is asked for."""
    if name in _SUBMODULES:
        return importlib.import_module(f"{__name__}.{name}")
    if name in _NAMES:
        value = getattr(importlib.import_module(f"{__name__}.{_NAMES[name]}"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


__version__ = "0.1.0"

__all__ = [
    "Contact",
    "RESTITUTION_MODELS",
    "centre_of_mass_velocity",
    "collide",
    "compat",
    "edmd",
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
    "trajectory",
    "transport",
]  # not plotting: `from collisionkit import *` would need matplotlib, an extra
