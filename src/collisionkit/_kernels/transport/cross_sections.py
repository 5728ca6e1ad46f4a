"""Cross-section tables: the node interval of an energy and the trial-frequency bound per species."""

from __future__ import annotations

from ..._jit import kernel


@kernel
def node_index(energy, nodes, accelerator, inverse_cell):
    """Index i of the node interval [nodes[i], nodes[i+1]) holding ``energy``.

    -1 below the first node, len(nodes) - 1 at or above the last one. The
    search starts at ``accelerator[cell]``, the first interval of the
    energy's cell of a uniform grid; ``inverse_cell`` is 1/accelerator_step
    rounded down by 1e-12, so the cell is never above
    int(energy / accelerator_step) and the search upwards stays exact.
    """
    if energy < nodes[0]:
        return -1
    x = energy * inverse_cell
    last = nodes.shape[0] - 1
    if x >= accelerator.shape[0]:
        return last
    i = accelerator[int(x)]
    while i < last and nodes[i + 1] <= energy:
        i += 1
    return i


@kernel
def rate_bound(species, speed, bound, inverse_step, sigma_max, const_rate):
    """Upper bound of sum_j sigma_j g + k_j of a species for relative speeds <= ``speed``.

    ``bound`` holds a running maximum over uniform speed bins; beyond the
    table, the largest cross section times the speed plus the constant
    rates. ``inverse_step`` is 1/bound_step rounded up by 1e-12: the bin
    index is then never below int(speed / bound_step), and a higher bin of
    the running maximum is a larger, still valid bound.
    """
    x = speed * inverse_step
    if x < bound.shape[1]:
        return bound[species, int(x)]
    return max(bound[species, bound.shape[1] - 1], sigma_max[species] * speed + const_rate[species])


@kernel
def trial_frequencies(speed, density, gas, bound, inverse_step, sigma_max, const_max, nu_s):
    """Trial frequency per species (in ``nu_s``) and their sum for projectile speeds <= ``speed``."""
    total = 0.0
    for s in range(gas.shape[0]):
        nu = density * rate_bound(s, speed + gas[s, 2], bound, inverse_step, sigma_max, const_max)
        nu_s[s] = nu
        total += nu
    return total
