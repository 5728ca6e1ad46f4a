"""Memory layout of the EDMD engine's arrays: record columns, geometry rows, parameter and accumulator slots.

The public module :mod:`collisionkit.edmd` fills these arrays and reads them
back through the names below; the kernels index them the same way.
"""

from __future__ import annotations

from ..._jit import borrowing_kernel as kernel

# columns of the particle records p (float64, N x 8)
X = 0  # position x, y, z (z = 0 in 2D)
V = 3  # velocity
T = 6  # the particle's own time
R = 7  # radius at scale 1

# columns of the bookkeeping records b (float64, N x 8: one 64-byte cache line a particle, so an
# event reads and writes one line besides p; integers are stored as floats, exact below 2^53)
TARGET = 0  # the particle's next event: a collision with partner TARGET (>= 0), else LIST_TARGET or wall_target(face)
PREDICTED_AT = 1  # number of the event at which that event was predicted
CHANGED_AT = 2  # number of the event that last changed the velocity
ANCHOR = 3  # anchor x, y, z: the position where the neighbour list was last built
MASS = 6
SPECIES = 7

LIST_TARGET = -1  # next event: the particle moved shell / 2 from its anchor, rebuild its list

# particles per block of the event queue: their event times fill one 64-byte cache line
QUEUE_BLOCK = 8

# rows of the geometry array (float64, 4 x 3)
G_BOX = 0
G_CELL = 1
G_GRAVITY = 2
G_PERIODIC = 3  # 1.0 periodic, 0.0 walls

# entries of the parameter array (float64)
P_SCALE0 = 0  # radius scale at time 0
P_GROWTH = 1  # d scale / dt (compression)
P_LAW = 2
P_LAW_SPEED = 3
P_LAW_EXPONENT = 4
P_ELASTIC_BELOW = 5
P_WALL_RESTITUTION = 6
P_SHELL = 7  # neighbour-list shell (skin) width
P_LIST_SCALE = 8  # largest radius scale the lists are valid for
# Lees-Edwards shear (x the flow, y the gradient): the image boxes at y +- L_y slide along x at +- G L_y
P_SHEAR_RATE = 9  # the shear rate G (0: no shear)
P_SHEAR_OFFSET = 10  # x offset of the image box above at clock time 0, in [0, L_x) (G L_y t mod L_x)
# under shear the anchors move with the flow at their height, u_x = G (y - L_y / 2), and the cells hold them in the
# co-moving (Lagrangian) frame: xi = x - G (y - L_y / 2) (t - t_f), their x at the frame time t_f (see .neighbour_lists)
P_SHEAR_SWEEP = 11  # clock time of the next sweep: the frame time moves there and the anchors are re-binned
# R, the largest list radius (2 r_max list_scale + shell + slack): a list's shell budget shrinks by |G| R / 4 per unit
# of its age
P_SHEAR_REACH = 12
P_THERMOSTAT = 13  # kT the peculiar velocities are rescaled to under shear (0: no thermostat)
P_SHEAR_FRAME = 14  # the frame time t_f: clock time at which the co-moving frame coincides with the lab frame
# square wells (.wells): a pair of species a and b attracts with depth epsilon_ab between contact and lambda_ab
# times contact; the table of (lambda_ab, epsilon_ab) follows the parameters (well_slot), S x S pairs of entries
P_WELL_WIDTH = 15  # the widest lambda > 1 in the table (the lists' reach; 0: hard spheres, no well)
P_WELL_DEPTH = 16  # the deepest epsilon > 0 in the table
P_WELL_SPECIES = 17  # S, the species the table covers (0: no table)
# rough spheres (.contacts.rough_impulse): beta, the tangential restitution, and kappa, the moment of inertia in units
# of m a^2; a system is rough when kappa > 0 (beta = -1 then spins without change; smooth systems hold 0 in both)
P_TANGENTIAL_RESTITUTION = 18
P_INERTIA_FACTOR = 19
# Walton's Coulomb limit of rough contacts: the friction coefficient mu (0: none), |J_t| <= mu |J_n|
P_FRICTION = 20
P_SIZE = 21
# the parameter array's size before the shear entries (checkpoints of engine formats 2 and 3), before the frame time
# (format 5)
P_SIZE_WITHOUT_SHEAR = 9
P_SIZE_WITHOUT_FRAME = 14
P_SIZE_WITHOUT_WELL = 15
P_SIZE_WITHOUT_WELL_TABLE = 17  # format 8: one width and depth for every pair
P_SIZE_WITHOUT_ROUGHNESS = 18  # format 9: smooth spheres (the well table follows at 18)
P_SIZE_WITHOUT_FRICTION = 20  # format 10: rough spheres without a Coulomb limit
# the strain G (t - t_f) at which the frame time moves on (a sweep): the cells are scanned (1 + strain) list radii
# along x around a particle's anchor
SHEAR_SWEEP_STRAIN = 0.25
# how far (in box lengths) a sheared particle's x may stray outside [0, L_x) before it rebuilds its list (and is
# wrapped): its anchor moves with the flow, so the list alone would not bound it, and the Lees-Edwards minimum image
# needs it
SHEAR_X_EXCURSION = 0.25

# accumulator slots (acc array)
ACC_VIRIAL = 0  # sum over pair collisions of impulse * contact distance
ACC_PAIR_COLLISIONS = 1
ACC_WALL_COLLISIONS = 2
ACC_LIST_REBUILDS = 3  # neighbour-list rebuilds; under the cell-crossing engine its cell crossings (.crossings)
ACC_STALE_EVENTS = 4
ACC_ENERGY_LOST = 5
ACC_WALL_IMPULSE = 6  # sum of |momentum| transferred to walls
ACC_LIST_OVERFLOW = 7  # > 0: a neighbour list outgrew its row; the run stopped to grow the rows
ACC_EVENTS = 8  # events processed (pair, stale, list, wall): numbers them for stale detection
ACC_CELL_OVERFLOW = 9  # > 0: a cell outgrew its slots; the run stopped to grow them
# the transport sums (see .contacts): with dp_j the impulse on j, dE_j its energy change and r = x_j - x_i the
# minimum-image separation at contact, each pair collision adds
ACC_STRESS = 10  # 6 slots xx, yy, zz, xy, xz, yz: the collisional stress sum dp_j,a r_b (STRESS_PAIRS order)
ACC_HEAT = 16  # 3 slots: the collisional energy transfer sum dE_j r_a
# Erpenbeck's image corrections of the Helfand moments of the stored positions x (wrapped lazily):
# sum m v_a x_b jumps by dp_j,a (x_j - x_i)_b at a collision, by -m v_a L_b at a wrap of x_b; the moment of the
# stress integral jumps by dp_j,a r_b and never at a wrap. The slots hold the difference of the two
ACC_MOMENTUM_IMAGE = 19  # 9 slots, 3 a + b: sum dp_j,a (r - (x_j - x_i))_b over collisions - sum m v_a dx_b over wraps
ACC_ENERGY_IMAGE = 28  # 3 slots: sum dE_j (r - (x_j - x_i))_a over collisions - sum (m v^2 / 2) dx_a over wraps
ACC_THERMOSTAT = 31  # kinetic energy the thermostat of a sheared system removed (negative: added)
# square wells: the pairs inside their wells now, the time integral of that number up to ACC_WELL_SINCE (the clock
# time of its last change), and the well events by outcome
ACC_WELL_PAIRS = 32
ACC_WELL_PAIR_TIME = 33
ACC_WELL_SINCE = 34
ACC_CAPTURES = 35  # a pair entered its well
ACC_ESCAPES = 36  # a pair left its well
ACC_BOUNCES = 37  # a pair too slow to leave was turned back at the well's edge
ACC_WELL_ENERGY = 38  # the depths of the pairs inside summed (minus the potential energy)
ACC_WELL_ENERGY_TIME = 39  # its time integral up to ACC_WELL_SINCE
ACC_SIZE = 40
# the accumulator's size before the wells' energy slots (checkpoints of engine format 8)
ACC_SIZE_WITHOUT_WELL_ENERGY = 38
# the accumulator's size before the square-well slots (checkpoints of engine formats 4 to 7)
ACC_SIZE_WITHOUT_WELL = 32
# the accumulator's size before the thermostat slot (checkpoints of engine format 3)
ACC_SIZE_WITHOUT_THERMOSTAT = 31
# the accumulator's size before the transport sums (checkpoints of engine format 2)
ACC_SIZE_WITHOUT_TRANSPORT = 10
# the (a, b) axis pairs of the six ACC_STRESS slots
STRESS_PAIRS = ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))

# why run_events returned (its second result)
STOP_COLLISIONS = 0  # it made the pair collisions asked for
STOP_TIME = 1  # the next event comes after t_stop
STOP_NO_EVENT = 2  # nothing will ever happen (every particle at rest)
STOP_EVENTS = 3  # it processed the events allowed per call: call again (the caller can be interrupted in between)
STOP_OVERFLOW = 4  # a neighbour list or a cell outgrew its row (acc[ACC_LIST_OVERFLOW], acc[ACC_CELL_OVERFLOW])
STOP_STALLED = 5  # STALLED_EVENTS events in a row without the clock moving: a collapse (Zeno), never progress

# events in a row at one instant that make run_events give up (the clock of a collapse stops in floating point)
STALLED_EVENTS = 1 << 16

# float32 anchor-and-radius slots of a cell in one 64-byte cache line
CELL_SLOTS_PER_LINE = 4

# relative round-off bound of the float32 anchors in the cell lists (8 float32 ulps), times the box size
ANCHOR_ROUNDING = 2.0**-21

# lowest levels of a block's path up the event tree to prefetch (the upper ones stay cached)
TREE_LEVELS_PREFETCHED = 6

# particles from which the event loops prefetch: a smaller system's records stay in the core's cache, where the
# prefetches only cost instructions. In-process A/B (issue 21): the lists' loop 2 % slower with them at N = 864,
# 14 % faster at N = 4000, eta 0.26; the cells' loop 1.00 (0.96-1.08) at N = 4000, eta 0.1, 1.42 at N = 32000
PREFETCH_FROM = 2048
# the same for the cell engine's loop (.crossings), whose records and cells stay cached longer: on the Intel VM of
# 2026-11-28, in one process at eta 0.1 against the loop prefetching from 2048, no prefetches at all were 1.07x at
# N = 4000, 1.00 at 6912, 0.98 at 8788, 0.94 at 13500 and 0.87 at 32000 (on the AMD VM 1.00 (0.96-1.08) at 4000)
CELLS_PREFETCH_FROM = 6144
# particles from which the lists' loop also prefetches for the likely next event's list rebuild (its neighbours'
# lists, the cells around its anchor and their members): in-process A/B against the loop without it, eta 0.45:
# 1.16x at N = 10^6 (quartiles 1.10-1.28), 1.12x at 108000; none at 32000 and 3 % slower at N = 4000, eta 0.26
# (issue 21, benchmarks/results/edmd_ab_*_rebuild_prefetch.md)
PREFETCH_REBUILDS_FROM = 65536


# restitution laws
LAW_CONSTANT = 0
LAW_BRIDGES = 1  # e = min(1, (u_n / u_c)^-exponent), Bridges, Hatzes & Lin, Nature 309, 333 (1984)
LAW_VISCOELASTIC = 2  # viscoelastic spheres, 1 - e = (u_n / u_c)^(1/5) + ... (restitution_laws.py)


@kernel
def wall_target(face):
    """TARGET code of a collision with wall ``face`` (2 * axis + 1 upper, 2 * axis lower); its own inverse."""
    return -2 - face


# TARGET codes at and below this are well events (.wells): the edge of the well of i and partner well_target(code)
WELL_TARGET_BASE = -8


@kernel
def well_target(partner):
    """TARGET code of an event at the edge of the square well shared with ``partner``; its own inverse."""
    return WELL_TARGET_BASE - partner



@kernel
def well_slot(species, a, b):
    """Index in the parameters of lambda_ab (epsilon_ab follows) for a table of ``species`` species."""
    return P_SIZE + 2 * (a * species + b)
