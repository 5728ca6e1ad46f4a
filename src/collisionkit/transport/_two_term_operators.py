"""The discretised two-term Boltzmann operator of :mod:`collisionkit.transport.two_term`.

The energy axis is cut into ``n`` equal cells; the distribution ``F0`` is
constant in each. :class:`CrossSectionIntegral` gives the exact integrals
:math:`\\int_a^b \\epsilon\\,\\sigma(\\epsilon)\\,d\\epsilon` of a process
(its table is linear between breakpoints, plus ``k / (gamma sqrt(eps))`` for
a rate coefficient); :func:`transfer_matrix` turns a collision that moves
electrons from energy ``eps'`` into an interval of energies into the
matrix of cell-to-cell transfers; :func:`drift_diffusion_matrix` is the
exponential (Scharfetter-Gummel) scheme of the flux in energy space.
Every transfer takes from the source cell exactly what it gives, so the
discrete operator conserves electrons to round-off (Hagelaar & Pitchford,
Plasma Sources Sci. Technol. 14, 722 (2005), sec. 3.2).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import constants, sparse

GAMMA = math.sqrt(2.0 * constants.e / constants.m_e)  # v = GAMMA sqrt(eps), eps in eV


class CrossSectionIntegral:
    """Exact :math:`\\int_a^b \\epsilon\\,\\sigma(\\epsilon)\\,d\\epsilon` (eV m^2 eV) of one process.

    Parameters
    ----------
    sigma : callable
        The tabulated cross section (m^2) against energy (eV), linear
        between ``breakpoints`` (and constant beyond the last).
    breakpoints : array_like
        Energies (eV) where ``sigma`` may change slope or jump.
    rate_coefficient : float
        k (m^3/s): adds :math:`k/(\\gamma\\sqrt\\epsilon)` to the cross section.

    Examples
    --------
    >>> integral = CrossSectionIntegral(lambda e: np.full_like(e, 2.0), [0.0], 0.0)
    >>> float(integral(np.array([1.0]), np.array([3.0]))[0])  # 2 (9 - 1) / 2
    8.0
    """

    def __init__(self, sigma, breakpoints, rate_coefficient):
        points = np.unique(np.asarray(breakpoints, float))
        self.points = points
        width = np.diff(points)
        # two interior samples per piece fix its line (jumps sit on the breakpoints)
        inner_left = sigma(points[:-1] + 0.25 * width) if width.size else np.zeros(0)
        inner_right = sigma(points[:-1] + 0.75 * width) if width.size else np.zeros(0)
        self.slope = (inner_right - inner_left) / np.where(width > 0, 0.5 * width, 1.0)
        self.start = inner_left - 0.25 * width * self.slope  # sigma at each piece's left end
        self.last = float(sigma(np.array([points[-1] + 1.0]))[0])  # constant beyond the last breakpoint
        self.before = float(sigma(np.array([0.5 * points[0]]))[0]) if points[0] > 0 else 0.0
        self.rate_coefficient = float(rate_coefficient)
        self.cumulative = np.concatenate([[self._piece(0, points[0], self.before, 0.0)],
                                          self._piece(points[:-1], points[1:], self.start, self.slope)])
        self.cumulative = np.cumsum(self.cumulative)

    @staticmethod
    def _piece(a, b, start, slope):
        """Integral of eps (start + slope (eps - a)) from a to b."""
        return start * (b * b - a * a) / 2.0 + slope * ((b**3 - a**3) / 3.0 - a * (b * b - a * a) / 2.0)

    def cumulative_at(self, x):
        """:math:`\\int_0^x \\epsilon\\,\\sigma\\,d\\epsilon` for each x >= 0."""
        x = np.asarray(x, float)
        points = self.points
        piece = np.clip(np.searchsorted(points, x, side="right") - 1, -1, points.size - 1)
        below = piece < 0
        inside = (piece >= 0) & (piece < points.size - 1)
        index = np.clip(piece, 0, max(points.size - 2, 0))
        total = np.where(below, self._piece(0.0, x, self.before, 0.0), 0.0)
        if points.size > 1:
            base = self.cumulative[index]
            total = np.where(inside, base + self._piece(points[index], x, self.start[index], self.slope[index]),
                             total)
        beyond = piece == points.size - 1
        total = np.where(beyond, self.cumulative[-1] + self._piece(points[-1], x, self.last, 0.0), total)
        if self.rate_coefficient:
            total = total + self.rate_coefficient / GAMMA * (2.0 / 3.0) * np.maximum(x, 0.0) ** 1.5
        return total

    def __call__(self, a, b):
        """:math:`\\int_a^b \\epsilon\\,\\sigma\\,d\\epsilon` for arrays a <= b."""
        return self.cumulative_at(b) - self.cumulative_at(a)

    def integrand(self, x):
        """:math:`\\epsilon\\,\\sigma(\\epsilon)` at each x > 0 (the piecewise line, plus the rate coefficient's term)."""
        x = np.asarray(x, float)
        points = self.points
        piece = np.clip(np.searchsorted(points, x, side="right") - 1, -1, points.size - 1)
        index = np.clip(piece, 0, max(points.size - 2, 0))
        sigma = np.where(piece < 0, self.before, self.last)
        if points.size > 1:
            inside = (piece >= 0) & (piece < points.size - 1)
            sigma = np.where(inside, self.start[index] + self.slope[index] * (x - points[index]), sigma)
        if self.rate_coefficient:
            sigma = sigma + self.rate_coefficient / (GAMMA * np.sqrt(x))
        return x * sigma


class ShiftedIntegral:
    """The integral of a :class:`CrossSectionIntegral` over intervals shifted up by ``shift``: a superelastic
    collision at eps has the rate of the excitation at eps + u (over g_k / g_0).

    Examples
    --------
    >>> flat = CrossSectionIntegral(lambda e: np.ones_like(e), [0.0], 0.0)
    >>> float(ShiftedIntegral(flat, 1.0)(np.array([0.0]), np.array([1.0]))[0])  # (4 - 1) / 2
    1.5
    """

    def __init__(self, base: CrossSectionIntegral, shift: float):
        self.base, self.shift = base, float(shift)

    def __call__(self, a, b):
        return self.base(np.asarray(a) + self.shift, np.asarray(b) + self.shift)


def transfer_matrix(integral: CrossSectionIntegral, edges, low, high, scale, weight=1.0):
    """Cell-to-cell transfers of a collision that moves the electrons of source energies [low, high] into each cell.

    Electrons collide at source energies :math:`\\epsilon'` at the rate
    :math:`\\gamma\\,\\epsilon'\\sigma(\\epsilon')F_0(\\epsilon')`; those in
    ``[low[i], high[i]]`` land in cell ``i`` (``weight`` of them per
    collision, as counted in that cell's energies: 2 for the equal sharing
    of an ionization, whose interval is twice a cell wide). Entry (i, j) is
    ``scale * weight * integral`` over the part of source cell j inside
    ``[low[i], high[i]]``: the gain of cell i per unit ``F0`` of cell j.

    Parameters
    ----------
    integral : CrossSectionIntegral
    edges : ndarray, shape (n + 1,)
        The cell edges (eV), equally spaced from 0.
    low, high : ndarray, shape (n,)
        The source energies feeding each cell.
    scale, weight : float

    Returns
    -------
    scipy.sparse.coo_matrix, shape (n, n)

    Examples
    --------
    >>> edges = np.linspace(0.0, 4.0, 5)
    >>> flat = CrossSectionIntegral(lambda e: np.ones_like(e), [0.0], 0.0)
    >>> transfer_matrix(flat, edges, edges[:-1] + 1.0, edges[1:] + 1.0, 1.0).toarray()[0]  # cell 0 from cell 1
    array([0. , 1.5, 0. , 0. ])
    """
    n = edges.size - 1
    width = edges[1] - edges[0]
    rows, cols, values = [], [], []
    first = np.floor(low / width + 1e-12).astype(np.int64)
    span = int(np.max(np.ceil((high - low) / width))) + 1 if n else 0
    for offset in range(span + 1):
        source = first + offset
        valid = (source >= 0) & (source < n)
        i = np.nonzero(valid)[0]
        j = source[valid]
        a = np.maximum(low[i], edges[j])
        b = np.minimum(high[i], edges[j + 1])
        keep = b > a
        rows.append(i[keep])
        cols.append(j[keep])
        values.append(scale * weight * integral(a[keep], b[keep]))
    return sparse.coo_matrix((np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n))


def bernoulli(z):
    """:math:`B(z) = z / (e^z - 1)`, B(0) = 1, without overflow or cancellation.

    Examples
    --------
    >>> [round(float(v), 6) for v in bernoulli(np.array([0.0, 1e-9, -800.0, 800.0]))]
    [1.0, 1.0, 800.0, 0.0]
    """
    z = np.asarray(z, float)
    small = np.abs(z) < 1e-8
    safe = np.where(small, 1.0, z)
    with np.errstate(over="ignore"):
        value = safe / np.expm1(safe)
    return np.where(small, 1.0 - 0.5 * z, value)


def drift_diffusion_matrix(drift, diffusion, width):
    """The flux divergence :math:`\\partial_\\epsilon(\\tilde W F_0 - \\tilde D\\,\\partial_\\epsilon F_0)` per cell.

    ``drift`` and ``diffusion`` are :math:`\\tilde W, \\tilde D` at the
    ``n - 1`` inner cell edges; the flux through the edge between cells
    j - 1 and j is :math:`(\\tilde D/\\Delta)[B(-z)F_{j-1} - B(z)F_j]` with
    :math:`z = \\tilde W\\Delta/\\tilde D` (the exponential scheme), and zero
    through the two outer edges.

    Returns
    -------
    scipy.sparse.csr_matrix, shape (n, n)
        Row i: flux out of the top of cell i minus flux into its bottom.

    Examples
    --------
    >>> m = drift_diffusion_matrix(np.zeros(2), np.ones(2), 1.0).toarray()
    >>> m  # pure diffusion: the discrete -d2/de2 with closed ends
    array([[ 1., -1.,  0.],
           [-1.,  2., -1.],
           [ 0., -1.,  1.]])
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(diffusion > 0, drift * width / np.where(diffusion > 0, diffusion, 1.0), 0.0)
    coefficient = diffusion / width
    # flux through edge j per unit F_{j-1} and per unit F_j
    return flux_divergence(coefficient * bernoulli(-z), -coefficient * bernoulli(z))


def central_flux_matrix(drift, diffusion, width):
    r"""The flux divergence of :func:`drift_diffusion_matrix` with the central flux
    :math:`\tilde W (F_{j-1} + F_j)/2 - \tilde D (F_j - F_{j-1})/\Delta` through each inner edge.

    Stable while :math:`|\tilde W|\Delta < 2\tilde D`; the electron-electron
    operator uses it, since its energy conservation holds for this flux
    exactly (:mod:`._two_term_electrons`).

    Examples
    --------
    >>> central_flux_matrix(np.array([2.0]), np.array([1.0]), 1.0).toarray()  # W = 2, D = 1: flux 2 F_0 + 0 F_1
    array([[ 2.,  0.],
           [-2.,  0.]])
    """
    return flux_divergence(0.5 * drift + diffusion / width, 0.5 * drift - diffusion / width)


def flux_divergence(lower, upper):
    """The matrix of the balance of each cell (flux out of its top minus flux into its bottom) for fluxes through
    the inner edges ``lower F_{j-1} + upper F_j`` (none through the two outer edges).

    Examples
    --------
    >>> flux_divergence(np.array([1.0]), np.array([-1.0])).toarray()
    array([[ 1., -1.],
           [-1.,  1.]])
    """
    n = lower.size + 1
    # row j-1 gains +flux(j) (flux out of its top), row j gains -flux(j)
    diagonal = np.zeros(n)
    diagonal[:-1] += lower
    diagonal[1:] -= upper
    return sparse.diags([diagonal, upper, -lower], [0, 1, -1], shape=(n, n), format="csr")


def cell_integral(function, edges, order=4):
    """Gauss-Legendre integral of ``function`` over each cell.

    Examples
    --------
    >>> np.round(cell_integral(lambda e: e**3, np.array([0.0, 1.0, 2.0])), 12).tolist()  # exact up to degree 7
    [0.25, 3.75]
    """
    nodes, weights = np.polynomial.legendre.leggauss(order)
    half = 0.5 * (edges[1:] - edges[:-1])
    middle = 0.5 * (edges[1:] + edges[:-1])
    points = middle[:, None] + half[:, None] * nodes[None, :]
    return (function(points) * weights[None, :]).sum(axis=1) * half
