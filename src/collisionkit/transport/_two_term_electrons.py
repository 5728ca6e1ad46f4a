r"""Electron-electron collisions in the two-term Boltzmann equation (Coulomb collisions among the electrons).

In a gas ionized to a degree :math:`n_e/N` the electrons also collide with
each other. For the isotropic part of the distribution the Fokker-Planck
(Rosenbluth) operator of like particles is a flux in energy, which adds a
drift and a diffusion to the equation's (Hagelaar & Pitchford, Plasma
Sources Sci. Technol. 14, 722 (2005), eqs. (22)-(25); Rockwood, Phys. Rev. A
8, 2348 (1973)):

.. math::

    \tilde G_{ee} = \tilde W_{ee}F_0 - \tilde D_{ee}\,\partial_\epsilon F_0,
    \qquad \tilde W_{ee} = -3a\frac{n_e}{N}A_1,
    \qquad \tilde D_{ee} = 2a\frac{n_e}{N}\bigl(A_2 + \epsilon^{3/2}A_3\bigr),

.. math::

    A_1 = \int_0^\epsilon u^{1/2}F_0\,du,\quad
    A_2 = \int_0^\epsilon u^{3/2}F_0\,du,\quad
    A_3 = \int_\epsilon^\infty F_0\,du,\quad
    a = \frac{e^2\gamma\ln\Lambda}{24\pi\varepsilon_0^2},

with :math:`\ln\Lambda = \ln[12\pi(\varepsilon_0 kT_e/e^2)^{3/2} n_e^{-1/2}]`
and :math:`kT_e = \frac23\bar\epsilon`. Derived here from the velocity form
:math:`\partial_t f = (\Gamma/v^2)\partial_v[4\pi M_0 f + \frac{4\pi}{3}(M_4/v +
v^2 N_1)\partial_v f]` (:math:`M_k = \int_0^v f u^k du`, :math:`N_1 = \int_v^\infty
f u\,du`, :math:`\Gamma = 4\pi n_e (e^2/4\pi\varepsilon_0 m)^2\ln\Lambda`) with
:math:`f = F_0/(2\pi\gamma^3)`: the coefficients make a Maxwellian at any
temperature a zero flux, conserve the electrons and their energy
(:math:`\int\tilde G_{ee}\,d\epsilon = 0` for every :math:`F_0`), and give an
electron far above the others the classical energy loss to free electrons,
:math:`d\epsilon/dt = -e^4 n_e\ln\Lambda/(4\pi\varepsilon_0^2 m v)` (the tests
check all three). The operator depends on :math:`F_0` itself: the equation is
solved again with the coefficients of the last solution until :math:`F_0`
settles (:func:`collisionkit.transport.two_term_boltzmann`).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import constants

from ._two_term_growth import MAX_GROWTH_ITERATIONS
from ._two_term_operators import GAMMA, central_flux_matrix

__all__ = ["ElectronCollisions", "coulomb_logarithm", "with_electron_collisions"]

# a / ln(Lambda) (eV^3/2 m^3/s with energies in eV): e^2 gamma / (24 pi eps0^2)
COULOMB_FACTOR = constants.e**2 * GAMMA / (24.0 * math.pi * constants.epsilon_0**2)
MAX_EE_ITERATIONS = 200
EE_ENERGY_TOLERANCE = 1e-10  # net energy the electrons exchange among themselves, relative to what they move
EE_TOLERANCE = 1e-7  # largest change of F0 between electron-electron rounds, relative to its peak
MIN_COULOMB_LOGARITHM = 2.0  # below it the plasma is not weakly coupled: the Fokker-Planck operator fails


def coulomb_logarithm(mean_energy, electron_density):
    r""":math:`\ln\Lambda = \ln[12\pi(\varepsilon_0 kT_e/e^2)^{3/2}n_e^{-1/2}]` with :math:`kT_e = \frac23\bar\epsilon`.

    Twelve pi electrons in a Debye sphere, :math:`\Lambda = 12\pi n_e\lambda_D^3`
    (Hagelaar & Pitchford 2005, eq. (25)).

    Parameters
    ----------
    mean_energy : float
        Mean electron energy (eV).
    electron_density : float
        m^-3.

    Examples
    --------
    A plasma of 1e18 electrons per m^3 at kT_e = 2 eV:

    >>> round(coulomb_logarithm(3.0, 1e18), 3)
    10.688
    """
    temperature = 2.0 / 3.0 * mean_energy  # kT_e in eV, so eps0 kT_e / e^2 = eps0 T_e[V] / e
    return math.log(12.0 * math.pi * (constants.epsilon_0 * temperature / constants.e) ** 1.5
                    / math.sqrt(electron_density))


class ElectronCollisions:
    r"""The electron-electron drift and diffusion at the inner cell edges of a grid, from a distribution on it.

    Parameters
    ----------
    ionization_degree : float
        :math:`n_e/N`.
    electron_density : float
        :math:`n_e` (m^-3), for the Coulomb logarithm only.
    edges : ndarray
        Cell edges (eV), equal cells; :math:`F_0` is constant in each, so
        the integrals :math:`A_1, A_2, A_3` are exact sums over whole cells.

    Examples
    --------
    A Maxwellian gets no net flux from the collisions among its electrons:

    >>> edges = np.linspace(0.0, 40.0, 2001)
    >>> middle = 0.5 * (edges[1:] + edges[:-1])
    >>> eedf = np.exp(-middle / 2.0)
    >>> ee = ElectronCollisions(1e-4, 1e18, edges)
    >>> drift, diffusion = ee.coefficients(eedf / (eedf @ ee.density))
    >>> flux = drift * 0.5 * (eedf[1:] + eedf[:-1]) - diffusion * np.diff(eedf) / (edges[1] - edges[0])
    >>> bool(np.max(np.abs(flux)) < 1e-4 * np.max(np.abs(drift * eedf[1:])))
    True
    """

    def __init__(self, ionization_degree, electron_density, edges):
        self.ionization_degree = ionization_degree
        self.electron_density = electron_density
        self.edges = edges
        low, high = edges[:-1], edges[1:]
        self.width = edges[1] - edges[0]
        self.density = (high**1.5 - low**1.5) / 1.5  # integral of eps^1/2 over each cell
        self.energy_density = (high**2.5 - low**2.5) / 2.5  # of eps^3/2: the mean energy
        # A2's weights: eps_k^3/2 h + (3h/4) (the cell's eps^1/2 integral), the integral of eps^3/2 over the cell
        # to O(h^3), chosen so that the central flux conserves energy exactly (see coefficients)
        self.a2_weight = low**1.5 * self.width + 0.75 * self.width * self.density
        self.coulomb_logarithm = math.nan

    def coefficients(self, eedf):
        r"""(:math:`\tilde W_{ee}`, :math:`\tilde D_{ee}`) at the inner edges for the normalised ``eedf``; sets
        :attr:`coulomb_logarithm` at its mean energy.

        :math:`A_1` sums the cells' exact :math:`\int\epsilon^{1/2}d\epsilon`
        below the edge, :math:`A_3` their widths above it, and :math:`A_2`
        the weights :math:`h\epsilon_k^{3/2} + \frac34 h\int_k\epsilon^{1/2}d\epsilon`:
        with these the energy the central flux
        (:func:`._two_term_operators.central_flux_matrix`) carries,
        :math:`\sum_j h\tilde G_j`, is a quadratic form in :math:`F` whose
        terms cancel pair by pair (derived here, the discrete analogue of
        swapping the two energies of the double integral), so the electrons
        exchange energy without creating any, whatever :math:`F_0` (but for
        the top cell, where :math:`F_0` has fallen 10-18 decades).
        """
        mean_energy = float(eedf @ self.energy_density)
        self.coulomb_logarithm = coulomb_logarithm(mean_energy, self.electron_density)
        strength = COULOMB_FACTOR * self.coulomb_logarithm * self.ionization_degree
        a1 = np.cumsum(eedf * self.density)[:-1]
        a2 = np.cumsum(eedf * self.a2_weight)[:-1]
        a3 = np.cumsum((eedf * self.width)[::-1])[::-1][1:]
        inner = self.edges[1:-1]
        return -3.0 * strength * a1, 2.0 * strength * (a2 + inner**1.5 * a3)

    def matrix(self, eedf):
        """The flux divergence of the electron-electron collisions, with the coefficients of ``eedf``."""
        return central_flux_matrix(*self.coefficients(eedf), self.width)

    def exchanged_fraction(self, drift, diffusion, eedf):
        """The net energy the central flux of these coefficients moves in ``eedf``, relative to what its drift
        alone moves: :math:`\\sum_j G_j / \\sum_j |\\tilde W_j| \\bar F_j` (0 for coefficients of the same F0)."""
        mean = 0.5 * (eedf[:-1] + eedf[1:])
        flux = drift * mean - diffusion * np.diff(eedf) / self.width
        return float(np.sum(flux)) / float(np.sum(np.abs(drift) * mean))

    def power(self, eedf):
        r"""The net power the electron-electron flux carries out of the distribution per electron and N,
        :math:`-\sum_j h\tilde G_j` (eV m^3/s): zero but for round-off and the top cell."""
        drift, diffusion = self.coefficients(eedf)
        flux = drift * 0.5 * (eedf[:-1] + eedf[1:]) - diffusion * np.diff(eedf) / self.width
        return float(-np.sum(flux) * self.width)


def with_electron_collisions(coulomb, among_electrons, settled, eedf, growth):
    """Solve again with the electron-electron coefficients of the last F0 until F0 settles (its largest change
    below ``EE_TOLERANCE`` of its peak); returns (eedf, effective cross section, growth, solves).

    Coefficients from the last F0 act on the next as a heat bath at the last F0's temperature, so the plain
    iteration crawls where the electrons collide with each other far more than with the gas (the gas moves
    their temperature a little each round). So each round scales the diffusion of the electron-electron
    operator by the factor that makes it exchange no net energy with the F0 it gives (secant iteration,
    to 1e-4 of the last round's change): the temperature is then set by the field and the gas at
    once, and the rounds only settle the shape. The factor is 1 at the solution, where the operator
    conserves energy exactly.
    """
    solves, change, scale, slope = 0, math.inf, 1.0, None
    for _ in range(MAX_EE_ITERATIONS):
        drift, diffusion = coulomb.coefficients(eedf)
        if coulomb.coulomb_logarithm < MIN_COULOMB_LOGARITHM:
            raise ValueError(f"electron_density: the Coulomb logarithm is {coulomb.coulomb_logarithm:.3g} (< "
                             f"{MIN_COULOMB_LOGARITHM:g}) at n_e = {coulomb.electron_density:.3g} m^-3 and this "
                             "mean energy: too dense for the weakly coupled (Fokker-Planck) electron collisions")

        def exchanged(scale):
            among_electrons[0] = central_flux_matrix(drift, scale * diffusion, coulomb.width)
            solution = settled(growth)
            return solution, coulomb.exchanged_fraction(drift, scale * diffusion, solution[0])

        tolerance = max(EE_ENERGY_TOLERANCE, 1e-4 * min(change, 0.1))
        solution, used, scale, slope = _energy_neutral(exchanged, scale, slope, tolerance)
        solves += used
        change = float(np.max(np.abs(solution[0] - eedf)) / np.max(eedf))
        eedf, effective, growth = solution[0], solution[1], solution[2]
        if change <= EE_TOLERANCE:
            return eedf, effective, growth, solves
    raise RuntimeError(f"the electron-electron iteration did not settle in {MAX_EE_ITERATIONS} rounds (last "
                       f"change {change:.2g} of the peak)")


def _energy_neutral(exchanged, start, slope, tolerance):
    """The solution at the diffusion scale where ``exchanged(scale)`` (the energy the electrons exchange among
    themselves, relative to what they move) is below ``tolerance``, by the secant method from ``start`` (with the
    last round's ``slope`` if known); returns (solution, solves, scale, slope)."""
    scale, (solution, residual) = start, exchanged(start)
    solves = solution[3]
    for _ in range(MAX_GROWTH_ITERATIONS):
        if abs(residual) <= tolerance:
            return solution, solves, scale, slope
        following = scale - residual / slope if slope else scale * (1.0 + 1e-3)
        solution, next_residual = exchanged(following)
        solves += solution[3]
        if next_residual == residual:  # round-off: nothing left to gain
            break
        slope = (next_residual - residual) / (following - scale)
        scale, residual = following, next_residual
    if abs(residual) <= 10.0 * tolerance:
        return solution, solves, scale, slope
    raise RuntimeError(f"the electron-electron energy balance did not settle (last imbalance {residual:.2g})")
