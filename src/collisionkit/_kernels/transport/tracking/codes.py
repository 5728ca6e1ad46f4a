"""Codes and column layouts shared by the tracking kernels and :mod:`collisionkit.transport.tracking`."""

from __future__ import annotations

# electric field kinds (parameters in a float64 array, see fields.py)
E_NONE = 0
E_UNIFORM = 1  # Ex, Ey, Ez (V/m)
E_PLATES = 2  # gap d, voltage V of the plane z = d (the plane z = 0 at 0 V)
E_COAXIAL = 3  # axis x, axis y, wire radius a, cathode radius b, voltage V of the wire (cathode 0 V), ln(b/a)
E_POINT = 4  # x, y, z of the charge, k = Q / (4 pi eps0) (V m), smallest radius
E_MAP = 5  # the grid (meta, values)
E_USER = 6  # a compiled function; parameter 0: an upper bound of |E| (V/m), 0 if unknown

# magnetic field kinds
B_NONE = 0
B_UNIFORM = 1  # Bx, By, Bz (T)
B_DIPOLE = 2  # x, y, z of the dipole, moment mx, my, mz (A m^2), smallest radius
B_MIRROR = 3  # x, y, z of the centre, B0 (T), L (m): Bz = B0 (1 + (z/L)^2), Br = -(r/2) dBz/dz
B_MAP = 4
B_USER = 5

FIELD_PARAMETERS = 8  # length of a field's parameter array

# a field map's meta array: origin (3), spacing (3), points per axis (3), dimensions (2 or 3), largest |value|,
# levels of its local bounds (see fields.electric_bound), 1 / spacing (3: a multiplication costs less than a division)
MAP_META = 15

# collision methods
NULL_COLLISION = 0  # trial collisions at a piecewise-constant bound of the rate (Skullerud)
PATH_LENGTH = 1  # the optical depth integrated along the trajectory until it reaches -ln(xi) (Krasov 5.5)

# surfaces: kind, action, then parameters (see geometry.py)
PLANE = 0  # point (3), unit normal into the volume (3)
CYLINDER = 1  # point on the axis (3), unit axis (3), radius, side (+1: the volume is inside, -1: outside)
SPHERE = 2  # centre (3), radius, side
SURFACE_COLUMNS = 12

ABSORB = 0  # an electrode: the particle ends there
REFLECT = 1  # a mirror: specular reflection
TRANSPARENT = 2  # the particle leaves the volume through it (recorded, not followed further)

# how a particle ended (the status column of an end record)
ENDED_SURFACE = 0  # absorbed at, or left through, the surface of the record's surface column
ENDED_ATTACHED = 1
ENDED_TIME = 2  # reached the time limit
ENDED_OUTSIDE_FIELD = 3  # left the box of a field map
ENDED_STEPS = 4  # used up its integration steps (a stalled or runaway particle)

# end records: one row per particle that ended
RECORD_PRIMARY, RECORD_STATUS, RECORD_SURFACE, RECORD_TIME = 0, 1, 2, 3
RECORD_X, RECORD_Y, RECORD_Z, RECORD_VX, RECORD_VY, RECORD_VZ = 4, 5, 6, 7, 8, 9
RECORD_BIRTH = 10  # time the particle was born
RECORD_COLUMNS = 11

# ion births: primary, time, x, y, z
BIRTH_COLUMNS = 5

# per-primary tallies: the collisions of each process, then these columns
TALLY_NULL = 0  # null collisions
TALLY_STEPS = 1  # accepted integration steps
TALLY_REJECTED = 2  # rejected integration steps
TALLY_ELECTRONS = 3  # particles followed (the primary and its secondaries)
TALLY_INDUCED = 4  # integral of the induced current q E_w . v dt (C)
TALLY_WEIGHTING = 5  # -q (phi_w(end) - phi_w(start)) summed over the particles' paths (C)
TALLY_TIME = 6  # particle time (s)
TALLY_COLUMNS = 7

# per-sample moments: count, r (3), r^2 (3), v (3), kinetic energy (J), r_k v_k (3)
MOMENT_COLUMNS = 14

# weighting field kinds (the readout electrode at unit potential, the others at 0)
W_NONE = 0
W_PLATES = 1  # gap d: phi_w = z / d (the plane z = d reads out)
W_COAXIAL = 2  # axis x, y, a, b, ln(b/a): phi_w = ln(b / r) / ln(b / a) (the wire reads out)

# profile coordinates
PROFILE_Z = 0
PROFILE_RADIUS = 1  # distance from the z axis through (x0, y0)

# kernel call outcomes
DONE = 0
SUSPENDED = 1  # a buffer is full or the collision budget of the call is used: call again (with larger buffers)
