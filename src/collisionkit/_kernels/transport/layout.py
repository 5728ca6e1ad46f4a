"""Codes and column layout shared by the transport kernels and :mod:`collisionkit.transport`."""

from __future__ import annotations

# process kinds
ELASTIC = 0
EXCITATION = 1
IONIZATION = 2
ATTACHMENT = 3
SUPERELASTIC = 4  # the inverse of a reversible excitation: its (negative) threshold is the energy gained

# angular models (collisionkit.transport.angular)
ISOTROPIC = 0
SCREENED_COULOMB = 1
OKHRIMOVSKYY = 2
VAHEDI_SURENDRA = 3
FORWARD = 4

ELECTRONVOLT = 1.602176634e-19  # J
HARTREE = 27.211386245988 * ELECTRONVOLT  # J, the energy scale of the Okhrimovskyy law

# energy sharing in ionization
SHARE_EQUAL = 0
SHARE_UNIFORM = 1

# columns of the per-particle tallies: one per process, then these
NULL_COLUMN_OFFSET = 0  # tallies[i, P]: null collisions
TIME_COLUMN_OFFSET = 1  # tallies[i, P + 1]: particle time alive in the step
BOUND_COLUMN_OFFSET = 2  # tallies[i, P + 2]: trials where the true rate exceeded the bound (checked runs)
DISPLACEMENT_COLUMN_OFFSET = 3  # tallies[i, P + 3 .. P + 5]: the integral of the velocity over the step (m)
EXTRA_COLUMNS = 6
