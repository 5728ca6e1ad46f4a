"""Per-group sums of the swarm's particles: moments, tallies and the energy histogram."""

from __future__ import annotations

import numpy as np

from ..._jit import inline_kernel, kernel


@inline_kernel
def add_particle(row, mass, x, y, z, vx, vy, vz):
    """Add one particle to a row of sums of 1, r (3), r_k^2 (3), v (3), energy, r_k v_k (3): 14 columns."""
    row[0] += 1.0
    row[1] += x
    row[2] += y
    row[3] += z
    row[4] += x * x
    row[5] += y * y
    row[6] += z * z
    row[7] += vx
    row[8] += vy
    row[9] += vz
    row[10] += 0.5 * mass * (vx * vx + vy * vy + vz * vz)
    row[11] += x * vx
    row[12] += y * vy
    row[13] += z * vz


@kernel
def group_moments(pos, vel, alive, group, n_groups, mass, moments):
    """Add per-group sums of 1, r, r^2, v, energy, r_k v_k (14 columns, :func:`add_particle`) to ``moments``."""
    for i in range(pos.shape[0]):
        if alive[i]:
            add_particle(moments[group[i]], mass, pos[i, 0], pos[i, 1], pos[i, 2], vel[i, 0], vel[i, 1], vel[i, 2])


@kernel
def energy_histogram(vel, alive, mass, edges_step, counts):
    """Add the particles' kinetic energies (1/2 m v^2, J) to a uniform histogram of bin width ``edges_step`` (J).

    ``counts`` holds the bins and one slot more: energies beyond the last
    bin are counted there (an overflow count, not a bin of width
    ``edges_step``).
    """
    last = counts.shape[0] - 1
    for i in range(vel.shape[0]):
        if alive[i]:
            e = 0.5 * mass * (vel[i, 0] ** 2 + vel[i, 1] ** 2 + vel[i, 2] ** 2)
            counts[min(last, int(e / edges_step))] += 1.0


@kernel
def group_sums(values, group, n_groups):
    """Per-group column sums of a 2D array."""
    out = np.zeros((n_groups, values.shape[1]))
    for i in range(values.shape[0]):
        for k in range(values.shape[1]):
            out[group[i], k] += values[i, k]
    return out


@kernel
def group_tensor_moments(pos, vel, alive, group, moments):
    """Add per-group sums of r_i r_j (columns 3 i + j) and r_i v_j (columns 9 + 3 i + j) to ``moments`` (18 columns).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.moments import group_tensor_moments
    >>> moments = np.zeros((1, 18))
    >>> group_tensor_moments(np.array([[1.0, 2.0, 3.0]]), np.array([[0.0, 0.0, 5.0]]), np.array([True]),
    ...                      np.array([0]), moments)
    >>> moments[0, 5], moments[0, 9 + 3 * 1 + 2]  # y z and y v_z
    (np.float64(6.0), np.float64(10.0))
    """
    for i in range(pos.shape[0]):
        if not alive[i]:
            continue
        row = moments[group[i]]
        for a in range(3):
            for b in range(3):
                row[3 * a + b] += pos[i, a] * pos[i, b]
                row[9 + 3 * a + b] += pos[i, a] * vel[i, b]
