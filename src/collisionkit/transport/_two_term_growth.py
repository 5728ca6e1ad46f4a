r"""How a swarm that ionizes or attaches grows, in the two-term equation of :mod:`collisionkit.transport.two_term`.

Temporal growth (a pulsed swarm) adds :math:`(\bar\nu/N)/(\gamma\epsilon^{1/2})`
to the momentum-transfer cross section (:func:`effective_cross_section`);
spatial growth (steady-state Townsend conditions) adds a drift and a source
(:class:`SpatialGrowth`). Either way the growth must be the one the solution
itself produces: :func:`settled_growth` finds it (Hagelaar & Pitchford,
Plasma Sources Sci. Technol. 14, 722 (2005), sec. 2.3).
"""

from __future__ import annotations

import numpy as np
from scipy import sparse

from ._two_term_operators import GAMMA, cell_integral

MAX_GROWTH_ITERATIONS = 200
GROWTH_TOLERANCE = 1e-10  # relative change of nu/N between iterations at convergence


class SpatialGrowth:
    r"""The terms of steady-state Townsend growth, :math:`n \propto e^{\alpha z}` along the drift.

    With :math:`F_1 = (E\,\partial_\epsilon F_0 + \alpha F_0)/(N\sigma_m)` the
    equation gains a drift :math:`-\frac{\gamma}{3}\frac{E}{N}\frac{\alpha}{N}\frac{\epsilon}{\sigma_m}`
    and a source :math:`\frac{\alpha}{N}\frac{\gamma}{3}\frac{\epsilon}{\sigma_m}
    (\frac{E}{N}\partial_\epsilon F_0 + \frac{\alpha}{N}F_0)` (Hagelaar & Pitchford 2005,
    sec. 2.3), whose integral makes the growth consistent only if
    :math:`\alpha W - \alpha^2 D = \bar\nu` (W and D the flux values): :meth:`alpha` solves it for the
    smaller root. The source's derivative is the mean of the two edges' differences of a cell, so that
    its sum over the cells is the discrete mobility's.
    """

    def __init__(self, edges, inner, sigma_m, collisions, field_si):
        self.field = field_si
        self.edge_weight = inner / sigma_m  # eps / sigma_m at the inner edges
        self.cell_weight = cell_integral(lambda e: e / sum(x * s(e) for x, s in collisions.momentum), edges)
        n = edges.size - 1
        half = 0.5 * self.edge_weight
        # row i: (1/2)[w_up (F_{i+1} - F_i) + w_down (F_i - F_{i-1})]
        diagonal = np.zeros(n)
        diagonal[:-1] -= half
        diagonal[1:] += half
        self.derivative = sparse.diags([diagonal, half, -half], [0, 1, -1], shape=(n, n), format="csr")

    def drift(self, alpha):
        return -GAMMA / 3.0 * self.field * alpha * self.edge_weight

    def source(self, alpha):
        """Minus the source (it moves to the left-hand side of the system)."""
        return -alpha * GAMMA / 3.0 * (self.field * self.derivative + alpha * sparse.diags(self.cell_weight))

    def alpha(self, eedf, production):
        """alpha/N from alpha W - alpha^2 D = nu with the flux W, N D and nu/N of ``eedf`` (the smaller root; at
        the vertex W / 2D, the largest growth the relation allows, where it has none: see :meth:`check`)."""
        drift, diffusion, net = self._moments(eedf, production)
        discriminant = drift * drift - 4.0 * diffusion * net
        if discriminant < 0.0:
            return drift / (2.0 * diffusion)
        return 2.0 * net / (drift + np.sqrt(discriminant))  # the smaller root, without cancellation

    def check(self, eedf, production):
        """A RuntimeError if the relation has no root for the settled F0: no steady-state Townsend growth."""
        drift, diffusion, net = self._moments(eedf, production)
        if drift * drift < 4.0 * diffusion * net * (1.0 - 1e-9):
            raise RuntimeError(f"no steady-state Townsend growth: alpha W - alpha^2 D = nu has no root (W = "
                               f"{drift:.3g} m/s, N D = {diffusion:.3g} /m/s, nu/N = {net:.3g} m^3/s, so 4 D nu / W^2 "
                               f"= {4.0 * diffusion * net / drift**2:.3g} > 1): ionization outruns the drift, beyond "
                               "the two-term SST model; use growth='temporal' or simulate_sst")

    def _moments(self, eedf, production):
        drift = -GAMMA / 3.0 * self.field * float(self.edge_weight @ np.diff(eedf))
        return drift, GAMMA / 3.0 * float(self.cell_weight @ eedf), float(production @ eedf)


def effective_cross_section(sigma_m, growth, inner):
    """sigma_m + (nu/N) / (gamma eps^1/2) at the inner edges; a RuntimeError if it is not positive."""
    effective = sigma_m + growth / (GAMMA * np.sqrt(inner))
    if np.any(effective <= 0.0):
        raise RuntimeError("the growth term made the effective momentum-transfer cross section negative at low "
                           f"energies (net production nu/N = {growth:.3g} m^3/s, attachment dominated): the "
                           "two-term temporal-growth model fails here; use simulate_swarm")
    return effective


def settled_growth(eedf_at, produced, production, guess=0.0, ceiling=None):
    """The growth x (nu/N or alpha/N) that the F0 it gives produces again, ``produced(eedf_at(x)) == x``, by
    secant iterations from ``guess``; and the solves made. No ionization or attachment: no growth.

    Below the solution the equation gains more electrons than it loses and has no positive steady state: the
    solve returns a distribution with negative cells, useless for the next step. So an invalid start is
    replaced by ``ceiling``, a growth no distribution can exceed (from above the equation loses electrons and
    F0 stays positive), and a step that lands on an invalid distribution goes back halfway to the last valid
    one (temporal growth, with a ``ceiling``).
    """
    if not np.any(production):
        return 0.0, 0
    solves, strict = 1, ceiling is not None
    previous, previous_residual = guess, _residual(eedf_at, produced, guess, strict)
    if previous_residual is None and ceiling is not None and ceiling > guess:
        previous, previous_residual = ceiling, _residual(eedf_at, produced, ceiling, strict)
        solves += 1
    if previous_residual is None:
        raise RuntimeError(f"no positive distribution at the growth's first guess ({previous:.3g}): the two-term "
                           "model fails here (a grid top far above the distribution, or attachment far above "
                           "ionization); use simulate_swarm")
    if guess != 0.0 and previous == guess and abs(previous_residual) <= GROWTH_TOLERANCE * abs(guess):
        return guess, solves  # (the guess is the last grid's or round's growth: often settled already)
    growth = previous + previous_residual  # a first fixed-point step
    while solves < MAX_GROWTH_ITERATIONS:
        residual = _residual(eedf_at, produced, growth, strict)
        solves += 1
        if residual is None:  # overshot into the region without a steady state
            growth = 0.5 * (growth + previous)
            continue
        if abs(residual) <= GROWTH_TOLERANCE * max(abs(growth), 1e-300):
            return growth, solves
        slope = (residual - previous_residual) / (growth - previous) if growth != previous else -1.0
        previous, previous_residual = growth, residual
        growth = growth - residual / slope if slope < 0.0 else growth + residual  # (slope is about -1 + dP/dx)
    raise RuntimeError(f"the growth iteration did not settle in {MAX_GROWTH_ITERATIONS} solves (growth = "
                       f"{growth:.3g})")


def _residual(eedf_at, produced, growth, strict):
    """produced(F0) - growth for the F0 of ``growth``; if ``strict``, None where that F0 is not a distribution
    (negative cells beyond round-off, or a growth term that makes the effective cross section negative).
    Spatial growth is not strict: its secant steps through such F0 to the solution."""
    if not strict:
        return produced(eedf_at(growth)[0]) - growth
    try:
        eedf = eedf_at(growth)[0]
    except RuntimeError:
        return None
    if np.min(eedf) < -1e-8 * np.max(eedf):
        return None
    return produced(eedf) - growth
