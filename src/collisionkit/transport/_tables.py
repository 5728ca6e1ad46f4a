"""Turn a :class:`~collisionkit.transport.gases.Gas` into the kernel's arrays.

The gas becomes channels (:mod:`._channels`: its processes, converted for
anisotropic laws, and the superelastic inverses). All are evaluated on the
union of their energy nodes: exact for piecewise-linear tables (with an extra
node just below a table that starts with a jump); a curved cross section
(momentum-transfer conversion, detailed balance) adds nodes until linear
interpolation is within ``CURVE_RTOL`` of it. The trial-frequency bound per
species is, on uniform speed bins, the running maximum of
``max(sigma_tot) * v_high + k_tot`` (the maximum of a piecewise-linear
function on a bin is at its ends or at a node inside); ``sigma_total`` holds
each species' summed cross section at the nodes, for the kernel's early
rejection of null trials.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import constants

from .._kernels import transport as _k
from ._channels import gas_channels, refined_nodes
from .gases import Gas

EV = constants.e
ACCELERATOR_CELLS = 4096  # cells of the node lookup's uniform grid at the least ...
MAX_ACCELERATOR_CELLS = 1 << 20  # ... doubled up to this many while a cell holds more than CELL_NODES nodes
CELL_NODES = 8
CURVE_RTOL = 1e-4  # linear interpolation of a curved cross section between nodes, relative
CURVE_TOP = 1000.0  # eV: curved cross sections are tabulated at least this far (then held constant, as tables are)
BOUND_BINS = 4096
GAS_SPEED_SIGMAS = 8.0  # P(|V| > 8 sigma) ~ 1e-14 for a 3D Maxwellian

KIND_CODES = {"elastic": _k.ELASTIC, "excitation": _k.EXCITATION, "ionization": _k.IONIZATION,
              "attachment": _k.ATTACHMENT, "superelastic": _k.SUPERELASTIC}
ANGULAR_CODES = {"isotropic": _k.ISOTROPIC, "screened_coulomb": _k.SCREENED_COULOMB, "okhrimovskyy": _k.OKHRIMOVSKYY,
                 "vahedi-surendra": _k.VAHEDI_SURENDRA, "forward": _k.FORWARD}
SHARING_CODES = {"equal": _k.SHARE_EQUAL, "uniform": _k.SHARE_UNIFORM}  # energy sharing after ionization


@dataclass(frozen=True)
class KernelTables:
    """Arrays handed to :func:`collisionkit._kernels.transport.advance_swarm`."""

    labels: tuple[str, ...]
    kinds: tuple[str, ...]
    gas: np.ndarray
    kind: np.ndarray
    species_of: np.ndarray
    threshold: np.ndarray
    const_rate: np.ndarray
    angular: np.ndarray
    screening: np.ndarray
    nodes: np.ndarray
    sigma: np.ndarray
    accelerator: np.ndarray
    accelerator_step: float
    bound: np.ndarray
    bound_step: float
    sigma_max: np.ndarray
    const_max: np.ndarray
    sigma_total: np.ndarray

    def arrays(self):
        """The table arguments of ``advance_swarm`` after ``density``, in order."""
        return (self.gas, self.kind, self.species_of, self.threshold, self.const_rate, self.angular,
                self.screening)

    def lookup(self):
        return (self.nodes, self.sigma, self.accelerator, self.accelerator_step, self.bound, self.bound_step,
                self.sigma_max, self.const_max, self.sigma_total)


def _nodes(channels, mass: float) -> np.ndarray:
    """The union of the channels' breakpoints, refined where a channel is curved (eV; projectile of ``mass``)."""
    union = np.unique(np.concatenate([np.zeros(1)] + [c.breakpoints for c in channels]))
    top = float(union[-1]) if union.size > 1 else 1.0
    if any(c.curved for c in channels):
        top = max(top, CURVE_TOP)
    extra = [refined_nodes(c.column, c.breakpoints, top, CURVE_RTOL, c.const_rate, mass) for c in channels if c.curved]
    union = np.unique(np.concatenate([union, *extra]))
    return union if union.size > 1 else np.array([0.0, 1.0])


def _accelerator(nodes_joule):
    """The first node interval of each cell of a uniform energy grid: 4096 cells, more where nodes crowd."""
    cells = ACCELERATOR_CELLS
    while cells < MAX_ACCELERATOR_CELLS:
        per_cell = np.bincount(np.minimum((nodes_joule / (nodes_joule[-1] / cells)).astype(np.int64), cells - 1))
        if per_cell.max() <= CELL_NODES:
            break
        cells *= 2
    step = nodes_joule[-1] / cells
    starts = np.arange(cells) * step
    index = np.clip(np.searchsorted(nodes_joule, starts, side="right") - 1, 0, nodes_joule.size - 1)
    return index.astype(np.int64), float(step)


def _species_bound(total_sigma, const_total, nodes_joule, mass):
    """Running maximum over speed bins of the largest sigma_tot * v + k."""
    v_top = math.sqrt(2.0 * nodes_joule[-1] / mass)
    step = v_top / BOUND_BINS
    edges = np.arange(BOUND_BINS + 1) * step
    edge_energy = 0.5 * mass * edges**2
    at_edges = np.interp(edge_energy, nodes_joule, total_sigma)
    bin_max = np.maximum(at_edges[:-1], at_edges[1:])
    node_bins = np.minimum((np.sqrt(2.0 * nodes_joule / mass) / step).astype(np.int64), BOUND_BINS - 1)
    np.maximum.at(bin_max, node_bins, total_sigma)
    bound = np.maximum.accumulate(bin_max * edges[1:] + const_total)
    return bound * (1.0 + 1e-12), step


def _unique(labels) -> tuple[str, ...]:
    """The labels with repeats numbered (``"Ar:excitation"``, ``"Ar:excitation #2"``), so that results keyed by
    label keep every process: an LXCat file may give two processes the same reaction text.

    Examples
    --------
    >>> _unique(["Ar:elastic", "Ar:excitation", "Ar:excitation"])
    ('Ar:elastic', 'Ar:excitation', 'Ar:excitation #2')
    """
    seen: dict[str, int] = {}
    unique = []
    for label in labels:
        seen[label] = seen.get(label, 0) + 1
        unique.append(label if seen[label] == 1 else f"{label} #{seen[label]}")
    return tuple(unique)


def build_tables(gas: Gas, mass: float, gas_temperature: float) -> KernelTables:
    """Kernel arrays for a projectile of ``mass`` (kg) in ``gas`` at ``gas_temperature`` (K)."""
    channels = gas_channels(gas, mass, gas_temperature)
    nodes = _nodes(channels, mass)
    nodes_joule = nodes * EV
    sigma = np.column_stack([c.column(nodes) for c in channels])
    n_species = len(gas.species)
    species_of = np.array([c.species for c in channels], dtype=np.int64)
    const_rate = np.array([c.const_rate for c in channels])
    bounds, sigma_max, const_max, step = [], np.zeros(n_species), np.zeros(n_species), 1.0
    sigma_total = np.zeros((nodes.size, n_species))
    for s in range(n_species):
        mine = species_of == s
        total = sigma[:, mine].sum(axis=1)
        sigma_total[:, s] = total
        const_max[s] = const_rate[mine].sum()
        sigma_max[s] = total.max() * (1.0 + 1e-12)
        bound, step = _species_bound(total, const_max[s], nodes_joule, mass)
        bounds.append(bound)
    gas_rows = []
    for member in gas.species:
        thermal = math.sqrt(constants.k * gas_temperature / member.mass)
        gas_rows.append((member.mass, thermal, GAS_SPEED_SIGMAS * thermal))
    accelerator, accelerator_step = _accelerator(nodes_joule)
    return KernelTables(
        labels=_unique(c.label for c in channels),
        kinds=tuple(c.kind for c in channels),
        gas=np.array(gas_rows, dtype=float),
        kind=np.array([KIND_CODES[c.kind] for c in channels], dtype=np.int64),
        species_of=species_of,
        threshold=np.array([c.threshold for c in channels]) * EV,
        const_rate=const_rate,
        angular=np.array([ANGULAR_CODES[c.angular] for c in channels], dtype=np.int64),
        screening=np.array([c.screening for c in channels]) * EV,
        nodes=np.ascontiguousarray(nodes_joule),
        sigma=np.ascontiguousarray(sigma),
        accelerator=accelerator,
        accelerator_step=accelerator_step,
        bound=np.ascontiguousarray(np.array(bounds)),
        bound_step=step,
        sigma_max=sigma_max,
        const_max=const_max,
        sigma_total=np.ascontiguousarray(sigma_total),
    )
