r"""Polytropic stars: the Lane-Emden equation and unrelaxed SPH particle models of its solutions.

A polytrope :math:`P = K\rho^{1+1/n}` in hydrostatic equilibrium has
:math:`\rho = \rho_c\theta^n(\xi)`, :math:`r = \alpha\xi`, where
:math:`\theta` solves the Lane-Emden equation (S. Chandrasekhar, *An
Introduction to the Study of Stellar Structure*, 1939, ch. IV; R.
Kippenhahn, A. Weigert and A. Weiss, *Stellar Structure and Evolution*,
2nd ed., sec. 19)

.. math:: \frac{1}{\xi^2}\frac{d}{d\xi}\Big(\xi^2\frac{d\theta}{d\xi}\Big) = -\theta^n,
          \qquad \theta(0) = 1,\quad \theta'(0) = 0,

solved here numerically (:func:`lane_emden`: scipy's ``solve_ivp``, DOP853,
started at :math:`\xi_0 = 10^{-3}` from the series
:math:`\theta = 1 - \xi^2/6 + n\xi^4/120 - n(8n-5)\xi^6/15120`). The surface
is the first zero :math:`\xi_1` (finite for n < 5). For a star of mass M and
radius R: :math:`\alpha = R/\xi_1`, the mass inside :math:`\xi` is
:math:`M\,\xi^2\theta'(\xi)/(\xi_1^2\theta'(\xi_1))`, and

.. math:: \frac{P}{\rho} = \frac{4\pi G\alpha^2\rho_c}{n+1}\theta
          = \frac{GM}{R}\,\frac{\xi_1\,\theta}{(n+1)\,\omega_n},\qquad
          \omega_n = -\xi_1^2\theta'(\xi_1).

The potential energy of the star is :math:`W = -\frac{3}{5-n}\frac{GM^2}{R}`
(Chandrasekhar, ch. IV, eq. 90).

:func:`polytrope_star` samples one as SPH particles: equal masses M/K,
radii from the inverse of the enclosed-mass fraction (the radius at which a
uniform random number is reached, found by bisection on the Lane-Emden
solution), isotropic directions, zero velocities, smoothing lengths from a
fixed neighbour number (:func:`~collisionkit.encounters.star_model.neighbour_smoothing_lengths`)
and internal energy per unit mass :math:`u = P/((\gamma - 1)\rho)`, with
:math:`\gamma = 1 + 1/n` (the polytropic relation itself) unless another
adiabatic index is given. The model is **unrelaxed**: random positions carry
Poisson noise in the density, so it is the input to the SPH code's own
relaxation (damped evolution of the isolated star), not a star to collide
as it is.
"""

from __future__ import annotations

import dataclasses
import math
import sys
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from .._params import Parameters, check_choice, check_integer, check_real, check_seed
from .star_model import StarModel, neighbour_smoothing_lengths
from .units import UNIT_SYSTEMS, unit_system

__all__ = ["LaneEmden", "PolytropeParameters", "lane_emden", "polytrope_star", "polytrope_summary"]

XI_START = 1e-3
_RTOL, _ATOL = 1e-12, 1e-14
MAX_PARTICLES = 10_000_000


def _series(n: float, xi):
    """theta and dtheta/dxi from the series about the centre (error O(xi^8))."""
    xi = np.asarray(xi, dtype=float)
    theta = 1.0 - xi**2 / 6.0 + n * xi**4 / 120.0 - n * (8.0 * n - 5.0) * xi**6 / 15120.0
    slope = -xi / 3.0 + n * xi**3 / 30.0 - n * (8.0 * n - 5.0) * xi**5 / 2520.0
    return theta, slope


@dataclasses.dataclass(frozen=True, repr=False, eq=False)
class LaneEmden:
    r"""A numerical solution of the Lane-Emden equation of index n (made by :func:`lane_emden`).

    Attributes
    ----------
    n : float
    xi1 : float
        The first zero of theta (the surface); ``inf`` if theta has none
        below ``xi_max``.
    slope1 : float
        dtheta/dxi at xi1 (NaN without a surface).
    xi_max : float
        The end of the solution.

    Examples
    --------
    >>> import math
    >>> from collisionkit.encounters import lane_emden
    >>> solution = lane_emden(1.0)
    >>> round(solution.xi1, 10) == round(math.pi, 10), round(float(solution.theta(1.0)), 12) == round(math.sin(1.0), 12)
    (True, True)
    """

    n: float
    xi1: float
    slope1: float
    xi_max: float
    _solution: Any = dataclasses.field(repr=False)

    def _state(self, xi):
        xi = np.asarray(xi, dtype=float)
        flat = xi.reshape(-1)
        if np.any(~(flat >= 0)):
            raise ValueError("xi must be >= 0")
        if not math.isfinite(self.xi1) and np.any(flat > self.xi_max):
            raise ValueError(f"xi must be <= xi_max = {self.xi_max:g} (the end of the solution)")
        theta, slope = _series(self.n, np.minimum(flat, XI_START))
        far = flat > XI_START
        if np.any(far):
            theta[far], slope[far] = self._solution(np.minimum(flat[far], self.xi_max))
        outside = flat >= self.xi1
        theta[outside], slope[outside] = 0.0, self.slope1
        return theta.reshape(xi.shape), slope.reshape(xi.shape)

    def theta(self, xi):
        """theta(xi) (0 outside the surface).

        Examples
        --------
        >>> from collisionkit.encounters import lane_emden
        >>> round(float(lane_emden(0.0).theta(1.5)), 12)  # 1 - xi^2 / 6
        0.625
        """
        return self._state(xi)[0]

    def slope(self, xi):
        """dtheta/dxi at xi (its surface value outside the surface).

        Examples
        --------
        >>> from collisionkit.encounters import lane_emden
        >>> round(float(lane_emden(0.0).slope(1.5)), 12)  # -xi / 3
        -0.5
        """
        return self._state(xi)[1]

    @property
    def omega(self) -> float:
        """omega_n = -xi1^2 theta'(xi1): the star's mass is 4 pi alpha^3 rho_c omega_n."""
        return -self.xi1**2 * self.slope1

    def mass_fraction(self, xi):
        """The fraction of the mass inside xi: xi^2 theta'(xi) / (xi1^2 theta'(xi1)) (n < 5).

        Examples
        --------
        >>> from collisionkit.encounters import lane_emden
        >>> solution = lane_emden(0.0)  # uniform density: (xi / xi1)^3
        >>> round(float(solution.mass_fraction(0.5 * solution.xi1)), 12)
        0.125
        """
        if not math.isfinite(self.xi1):
            raise ValueError(f"n = {self.n:g} has no surface below xi_max: the mass fraction is undefined")
        xi = np.asarray(xi, dtype=float)
        return np.minimum(-(xi**2) * self.slope(xi) / self.omega, 1.0) + 0.0  # + 0.0: no -0.0 at the centre

    def radius_of_mass_fraction(self, fraction, *, table: int = 4096, iterations: int = 100):
        """The xi inside which ``fraction`` of the mass lies (the inverse of :meth:`mass_fraction`), to round-off.

        Each value is bracketed in a table of ``table`` intervals, then
        found by Newton's method on the mass fraction (its derivative is
        xi^2 theta^n / omega_n), bisecting whenever a step would leave the
        bracket, until each value's mass fraction is within 2 ulp of its
        target or its step is below 4 ulp of it.

        Examples
        --------
        >>> from collisionkit.encounters import lane_emden
        >>> solution = lane_emden(0.0)
        >>> round(float(solution.radius_of_mass_fraction(0.125) / solution.xi1), 12)
        0.5
        """
        shape = np.shape(fraction)
        fraction = np.asarray(fraction, dtype=float).reshape(-1)
        if np.any(~((fraction >= 0) & (fraction <= 1))):
            raise ValueError("fraction must be in [0, 1]")
        grid = self.xi1 * np.linspace(0.0, 1.0, table + 1)
        values = self.mass_fraction(grid)
        values[-1] = 1.0
        where = np.clip(np.searchsorted(values, fraction, side="right") - 1, 0, table - 1)
        low, high = grid[where], grid[where + 1]
        width = values[where + 1] - values[where]
        xi = low + np.divide(fraction - values[where], width, out=np.zeros_like(width), where=width > 0) * (high - low)
        eps = np.finfo(float).eps
        active = np.ones(xi.shape, dtype=bool)
        for _ in range(iterations):
            x, lo, hi, target = xi[active], low[active], high[active], fraction[active]
            theta, slope = self._state(x)
            error = np.minimum(-(x**2) * slope / self.omega, 1.0) - target
            lo, hi = np.where(error < 0, x, lo), np.where(error > 0, x, hi)
            derivative = x**2 * np.maximum(theta, 0.0) ** self.n / self.omega
            with np.errstate(divide="ignore", invalid="ignore"):
                newton = x - error / derivative
            step = np.where((newton > lo) & (newton < hi), newton, 0.5 * (lo + hi))
            finished = (np.abs(error) <= 2 * eps * target) | (np.abs(step - x) <= 4 * eps * x)
            xi[active] = np.where(finished, x, step)
            low[active], high[active] = lo, hi
            active[active] = ~finished
            if not np.any(active):
                break
        return xi.reshape(shape)

    def __repr__(self) -> str:
        return f"LaneEmden(n={self.n:g}, xi1={self.xi1:.10g})"


def lane_emden(n: float, xi_max: float | None = None) -> LaneEmden:
    """Solve the Lane-Emden equation of index ``n`` from the centre to the surface (or to ``xi_max``).

    Parameters
    ----------
    n : float
        Polytropic index, >= 0. Below 5 the solution stops at its first zero
        (the surface); from 5 on (no surface) ``xi_max`` is required.
    xi_max : float, optional
        The farthest xi to solve to (default: 1e7, beyond the surface of
        every n < 4.999).

    Returns
    -------
    LaneEmden

    Examples
    --------
    >>> from collisionkit.encounters import lane_emden
    >>> solution = lane_emden(1.5)  # Chandrasekhar, table 4: xi1 = 3.65375, omega = 2.71406
    >>> round(solution.xi1, 5), round(solution.omega, 5)
    (3.65375, 2.71406)
    >>> solution = lane_emden(5.0, xi_max=10.0)  # theta = (1 + xi^2 / 3)^(-1/2)
    >>> round(float(solution.theta(3.0)), 12)
    0.5
    """
    n = check_real("n", n, 0.0)
    if xi_max is None:
        if n >= 5.0:
            raise ValueError(f"n = {n:g} >= 5 has no surface: give xi_max")
        xi_max = 1e7
    xi_max = check_real("xi_max", xi_max, XI_START, low_open=True)

    def rhs(xi, y):
        return [y[1], -max(y[0], 0.0) ** n - 2.0 * y[1] / xi]

    def surface(xi, y):
        return y[0]

    surface.terminal, surface.direction = True, -1.0
    start = [float(value) for value in _series(n, XI_START)]
    result = solve_ivp(rhs, (XI_START, xi_max), start, method="DOP853", rtol=_RTOL, atol=_ATOL,
                       events=surface, dense_output=True)
    if result.status == -1:
        raise RuntimeError(f"the Lane-Emden integration failed for n = {n:g}: {result.message}")
    if result.t_events[0].size:
        xi1, slope1, end = float(result.t_events[0][0]), float(result.y_events[0][0][1]), float(result.t_events[0][0])
    else:
        xi1, slope1, end = math.inf, math.nan, float(result.t[-1])
    return LaneEmden(n=n, xi1=xi1, slope1=slope1, xi_max=end, _solution=result.sol)


def _gamma(n: float, gamma: float | None) -> float:
    if gamma is None:
        if n == 0.0:
            raise ValueError("n = 0 (uniform density) has no polytropic gamma (1 + 1/n is infinite): give gamma")
        return 1.0 + 1.0 / n
    return check_real("gamma", gamma, 1.0, low_open=True)


def _checked_star(n, particles, mass, radius, neighbours, gamma) -> dict:
    """The numbers of a polytropic star, checked (a ValueError or TypeError naming the first bad one)."""
    n = check_real("polytrope", n, 0.0, 5.0, high_open=True)
    neighbours = check_integer("neighbours", neighbours, 1)
    checked = {
        "polytrope": n,
        "particles": check_integer("particles", particles, neighbours + 1, MAX_PARTICLES),
        "mass": check_real("mass", mass, 0.0, low_open=True),
        "radius": check_real("radius", radius, 0.0, low_open=True),
        "neighbours": neighbours,
        "gamma": None if gamma is None else _gamma(n, gamma),
    }
    _gamma(n, checked["gamma"])
    return checked


def _check_scales(mass: float, radius: float, particles: int, G: float) -> None:
    """ValueError unless the star's scales are normal floats (~2.2e-308 to ~1.8e308).

    The potential energy G M^2 / R, the density M / R^3, the specific
    energy G M / R, the particle mass M / K and the squared spacing
    (R / K^(1/3))^2 (the smoothing lengths come from squared distances):
    beyond these the star's numbers overflow or vanish in double precision.
    """
    spacing = radius / particles ** (1.0 / 3.0)
    scales = {
        "G M^2 / R": G * mass * (mass / radius),
        "M / R^3": mass / radius / radius / radius,
        "G M / R": G * (mass / radius),
        "M / particles": mass / particles,
        "(R / particles^(1/3))^2": spacing * spacing,
        "R^2": radius * radius,
    }
    for name, value in scales.items():
        if not sys.float_info.min <= value < math.inf:
            raise ValueError(f"the mass and radius give {name} = {value:.3g}, outside the floating-point range "
                             f"({sys.float_info.min:.3g} to {sys.float_info.max:.3g}): choose units in which they "
                             "are nearer 1")


@dataclasses.dataclass(frozen=True)
class PolytropeParameters(Parameters):
    """A polytropic star to sample as SPH particles (``collisionkit star``), checked when made.

    Parameters
    ----------
    polytrope : float
        The polytropic index n, in [0, 5).
    particles : int
        Number of particles K, > ``neighbours`` (at most 1e7).
    mass, radius : float
        M and R (> 0) in the mass and length units of ``units``.
    units : str
        ``nbody`` (G = 1), ``si``, ``cgs``, ``solar`` or ``stellar``.
    neighbours : int
        Neighbour number of the smoothing lengths (>= 1).
    gamma : float, optional
        Adiabatic index of the gas (> 1) for u = P/((gamma - 1) rho);
        default 1 + 1/n (required for n = 0).
    seed : int
        Random seed (>= 0).

    Examples
    --------
    >>> from collisionkit.encounters import PolytropeParameters
    >>> round(PolytropeParameters(polytrope=1.5, particles=1000).gamma_used, 12)  # 1 + 1/n
    1.666666666667
    """

    polytrope: float = 1.5
    particles: int = 10_000
    mass: float = 1.0
    radius: float = 1.0
    units: str = "nbody"
    neighbours: int = 50
    gamma: float | None = None
    seed: int = 2026

    def __post_init__(self):
        check_choice("units", self.units, UNIT_SYSTEMS)
        object.__setattr__(self, "seed", check_seed("seed", self.seed))
        for name, value in _checked_star(self.polytrope, self.particles, self.mass, self.radius, self.neighbours,
                                         self.gamma).items():
            object.__setattr__(self, name, value)
        _check_scales(self.mass, self.radius, self.particles, unit_system(self.units).G)

    @property
    def gamma_used(self) -> float:
        """The adiabatic index of the internal energies: ``gamma``, or 1 + 1/n."""
        return _gamma(self.polytrope, self.gamma)


def polytrope_star(n: float, particles: int, mass: float = 1.0, radius: float = 1.0, *, units="nbody",
                   neighbours: int = 50, gamma: float | None = None, seed=None, progress=None) -> StarModel:
    """An unrelaxed polytrope of index n as SPH particles (see the module's description).

    Parameters
    ----------
    n : float
        Polytropic index in [0, 5).
    particles : int
        K > neighbours, all of mass M / K, with IDs 1 ... K.
    mass, radius : float
        M and R, in the units of ``units``.
    units : UnitSystem or str
        Sets G in u = P/((gamma - 1) rho).
    neighbours : int
        Each smoothing length holds this many neighbours.
    gamma : float, optional
        Adiabatic index for the internal energy; default 1 + 1/n.
    seed : int or numpy.random.Generator, optional
    progress : callable, optional
        Called with the fraction of the work done (the smoothing lengths,
        the longest part, in steps).

    Returns
    -------
    StarModel
        Centred on the model's centre (the sample's centre of mass is off it
        by the sampling noise, about R / sqrt(K)), at rest.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.encounters import polytrope_star
    >>> star = polytrope_star(1.5, 500, mass=2.0, radius=3.0, neighbours=20, seed=1)
    >>> len(star), round(star.mass, 12), bool(np.max(np.linalg.norm(star.positions, axis=1)) <= 3.0)
    (500, 2.0, True)
    >>> sorted(set(np.count_nonzero(np.linalg.norm(star.positions[:, None] - star.positions, axis=2)
    ...                             < star.smoothing_lengths[:, None] * (1 + 1e-12), axis=1).tolist()))
    [21]
    """
    star = _checked_star(n, particles, mass, radius, neighbours, gamma)
    n, count, mass, radius = star["polytrope"], star["particles"], star["mass"], star["radius"]
    system = unit_system(units) if isinstance(units, str) else units
    _check_scales(mass, radius, count, system.G)
    rng = np.random.default_rng(seed)
    solution = lane_emden(n)
    xi = solution.radius_of_mass_fraction(rng.random(count))
    cos_polar = rng.uniform(-1.0, 1.0, count)
    azimuth = rng.uniform(0.0, 2.0 * math.pi, count)
    sin_polar = np.sqrt(1.0 - cos_polar**2)
    r = radius * xi / solution.xi1
    positions = r[:, None] * np.c_[sin_polar * np.cos(azimuth), sin_polar * np.sin(azimuth), cos_polar]
    if progress is not None:
        progress(0.2)
    pressure_over_density = system.G * mass / radius * solution.xi1 * solution.theta(xi) / ((n + 1.0) * solution.omega)
    return StarModel(
        positions=positions,
        velocities=np.zeros((count, 3)),
        masses=np.full(count, mass / count),
        smoothing_lengths=neighbour_smoothing_lengths(
            positions, star["neighbours"], progress=None if progress is None else lambda done: progress(0.2 + 0.8 * done)),
        internal_energies=pressure_over_density / (_gamma(n, star["gamma"]) - 1.0),
        ids=np.arange(1, count + 1),
        units=system,
    )


def polytrope_summary(parameters: PolytropeParameters, progress=None) -> tuple[dict, StarModel]:
    """The ``star`` command as a library call: the sampled star and its summary.

    The summary holds the Lane-Emden surface (xi1, omega_n), the star's
    properties (:meth:`StarModel.summary`), the expected potential energy
    -3/(5-n) G M^2 / R and thermal energy, the seed and the ``parameters``;
    ``progress`` as in :func:`polytrope_star`.

    Examples
    --------
    >>> from collisionkit.encounters import PolytropeParameters, polytrope_summary
    >>> summary, star = polytrope_summary(PolytropeParameters(polytrope=1.0, particles=200, neighbours=10, seed=3))
    >>> round(summary["lane_emden"]["xi1"], 9), summary["star"]["particles"], summary["seed"]
    (3.141592654, 200, 3)
    """
    star = polytrope_star(parameters.polytrope, parameters.particles, parameters.mass, parameters.radius,
                          units=parameters.units, neighbours=parameters.neighbours, gamma=parameters.gamma,
                          seed=parameters.seed, progress=progress)
    solution = lane_emden(parameters.polytrope)
    n, G, M, R = parameters.polytrope, star.G, parameters.mass, parameters.radius
    potential = -3.0 / (5.0 - n) * G * M**2 / R
    summary = {
        "units": parameters.units,
        "G": G,
        "lane_emden": {"n": n, "xi1": solution.xi1, "omega": solution.omega},
        "gamma": parameters.gamma_used,
        "star": star.summary(),
        "potential_energy_expected": potential,
        "thermal_energy_expected": -potential / (3.0 * (parameters.gamma_used - 1.0)),
        "thermal_energy": float(star.masses @ star.internal_energies),
        "relaxed": False,
        "seed": parameters.seed,
        "parameters": parameters.to_dict(),
    }
    return summary, star
