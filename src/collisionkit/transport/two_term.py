r"""The two-term Boltzmann equation of electrons in a gas: the steady energy distribution in milliseconds to a second.

:func:`two_term_boltzmann` solves the classical two-term approximation of the
electron Boltzmann equation in a uniform DC field, as BOLSIG+ and LoKI-B do
(Hagelaar & Pitchford, Plasma Sources Sci. Technol. 14, 722 (2005), eqs.
(15)-(20) and (41)-(62); the temporal-growth model of their sec. 2.3):

.. math::

    \frac{\partial}{\partial\epsilon}\Bigl(\tilde W F_0 - \tilde D\,
    \frac{\partial F_0}{\partial\epsilon}\Bigr) = \tilde S
    - \frac{\bar\nu}{N}\,\epsilon^{1/2} F_0,
    \qquad \tilde W = -\gamma\epsilon^2\sigma_\epsilon,
    \qquad \tilde D = \frac{\gamma}{3}\Bigl(\frac{E}{N}\Bigr)^2
    \frac{\epsilon}{\tilde\sigma_m} + \frac{\gamma k T}{e}\epsilon^2\sigma_\epsilon,

with :math:`\gamma = (2e/m)^{1/2}`, :math:`\sigma_\epsilon = \sum 2(m/M)\,x\,\sigma_{el}`,
:math:`\tilde\sigma_m = \sum x\sigma + \bar\nu/(N\gamma\epsilon^{1/2})` (the
momentum-transfer cross section of every process, plus the growth term),
:math:`\tilde S` the inelastic, superelastic, ionizing and attaching
collisions, and :math:`\bar\nu/N` the net production of electrons, found by
iteration. :math:`F_0` is normalised to :math:`\int\epsilon^{1/2}F_0\,d\epsilon = 1`.
In an ionized gas the electrons' collisions with each other add a drift and
a diffusion that depend on :math:`F_0` itself (:mod:`._two_term_electrons`),
solved in rounds.

It is exact for the drift velocity and the energy of a gas of constant
collision frequency, up to terms in m/M (the tests check the Maxwell and
Druyvesteyn distributions), and an approximation when the distribution is
far from isotropic (large inelastic cross sections: Reid's ramp at 12 and
24 Td is 2-3 % above the Monte Carlo swarm in mean energy and drift). It is what fluid models
tabulate rate coefficients with; :func:`~collisionkit.transport.simulate_swarm`
is the exact (Monte Carlo) check, and measures the longitudinal diffusion and
the bulk coefficients the two-term equation does not give.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import sparse
from scipy.sparse.linalg import spsolve

from .._repr import dataclass_repr
from ._two_term_collisions import collision_operator, gas_collisions
from ._two_term_electrons import ElectronCollisions, with_electron_collisions
from ._two_term_moments import field_diffusion, moments
from ._two_term_growth import SpatialGrowth, effective_cross_section, settled_growth
from ._two_term_operators import GAMMA, drift_diffusion_matrix
from ._validation import MAX_GAS_TEMPERATURE, MAX_REDUCED_FIELD, check_reduced_frequency
from .gases import Gas
from .superelastic import BOLTZMANN_EV
from .swarm import TOWNSEND

__all__ = ["TwoTermResult", "TwoTermWarning", "two_term_boltzmann"]

SHARING = ("equal", "uniform")
GROWTH_MODELS = ("temporal", "spatial")
DECADES = (10.0, 18.0)  # F0 falls by this many decades from its peak to the grid's top energy
MAX_GRID_ADJUSTMENTS = 60
# n_e/N up to which the electron-electron collisions are solved and tested; beyond it electron-ion collisions
# (not in the model) matter as much
MAX_IONIZATION_DEGREE = 0.01
ROW_FIELDS = ("mean_energy", "mobility_N", "drift_velocity", "diffusion_N", "characteristic_energy",
              "energy_mobility_N", "energy_diffusion_N", "momentum_frequency_N", "ionization_frequency_N", "attachment_frequency_N", "alpha_N", "eta_N", "power_balance", "max_energy",
              "cells", "ionization_degree", "electron_density", "coulomb_logarithm", "omega_N")


# the units of TwoTermResult's fields and of the columns of its rows (rate_coefficient[...] in m^3/s)
UNITS = {"E_N": "Td", "reduced_field": "Td", "gas_temperature": "K", "energy": "eV", "eedf": "eV^-3/2",
         "mean_energy": "eV", "mobility_N": "1/(V m s)", "drift_velocity": "m/s", "diffusion_N": "1/(m s)",
         "characteristic_energy": "eV", "energy_mobility_N": "1/(V m s)", "energy_diffusion_N": "1/(m s)",
         "momentum_frequency_N": "m^3/s", "rate_coefficients": "m^3/s", "rate_coefficient[...]": "m^3/s",
         "ionization_frequency_N": "m^3/s", "attachment_frequency_N": "m^3/s", "alpha_N": "m^2", "eta_N": "m^2",
         "power_balance": "1", "power_fractions": "1", "power_fraction[...]": "1", "max_energy": "eV", "cells": "1", "iterations": "1", "ionization_degree": "1",
         "electron_density": "m^-3", "coulomb_logarithm": "1", "omega_N": "rad m^3/s"}

# a solution is reported doubtful when its power balance is off by more than this (1000 cells: 1e-5 - 1e-4), or
# when more than BEYOND_TABLES of its electrons lie above the highest energy of the gas's cross-section tables
MIN_GAS_TEMPERATURE = 1e-6  # K, if not 0 (at E = 0, 1e-300 K made the grid's matrix singular)
POWER_BALANCE_WARNING = 1e-2
BEYOND_TABLES = 1e-3


class TwoTermWarning(UserWarning):
    """A two-term solution to read with care: its power does not balance (a coarse grid or a top that cuts the
    distribution) or its electrons reach beyond the cross sections' tables.

    Examples
    --------
    >>> import warnings
    >>> from collisionkit.transport import catalogue_gas, two_term_boltzmann
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     result = two_term_boltzmann(catalogue_gas("Ar"), 1e4)
    >>> "above 1000 eV" in str(caught[0].message)
    True
    """


@dataclass(frozen=True, repr=False)
class TwoTermResult:
    r"""The two-term solution at one E/N.

    Attributes
    ----------
    reduced_field : float
        E/N (Td).
    gas_temperature : float
        K.
    energy : ndarray
        Cell centres (eV).
    eedf : ndarray
        :math:`F_0` (eV^-3/2) at those energies, :math:`\int\epsilon^{1/2}F_0\,d\epsilon = 1`.
    mean_energy : float
        :math:`\int\epsilon^{3/2}F_0\,d\epsilon` (eV).
    mobility_N : float
        :math:`\mu N = -\frac{\gamma}{3}\int\frac{\epsilon}{\tilde\sigma_m}\frac{\partial F_0}{\partial\epsilon}d\epsilon`
        (1/(V m s)).
    drift_velocity : float
        :math:`\mu N \cdot E/N` (m/s, the flux drift along -E).
    diffusion_N : float
        :math:`DN = \frac{\gamma}{3}\int\frac{\epsilon}{\tilde\sigma_m}F_0\,d\epsilon`
        (1/(m s); the flux diffusion, the same in every direction at this order).
    characteristic_energy : float
        D / mu (eV).
    energy_mobility_N, energy_diffusion_N : float
        The energy transport coefficients of fluid models,
        :math:`\mu_\epsilon N = -\frac{\gamma}{3\bar\epsilon}\int\frac{\epsilon^2}{\tilde\sigma_m}\frac{\partial F_0}{\partial\epsilon}d\epsilon`
        and :math:`D_\epsilon N = \frac{\gamma}{3\bar\epsilon}\int\frac{\epsilon^2}{\tilde\sigma_m}F_0\,d\epsilon`
        (Hagelaar & Pitchford eqs. (61)-(62); 5/3 of mu N and D N for a Maxwellian of constant collision frequency).
    momentum_frequency_N : float
        :math:`\gamma\int\epsilon\,\sigma_m F_0\,d\epsilon` (m^3/s), every process's momentum transfer.
    rate_coefficients : dict
        :math:`x k` with :math:`k = \gamma\int\epsilon\sigma F_0\,d\epsilon` and x the
        process's share of the gas (the species' fraction, times its level's population for a
        reversible excitation and its inverse), per ``"species:label"`` (m^3/s), as
        :attr:`SwarmResult.rate_coefficients <collisionkit.transport.SwarmResult.rate_coefficients>`;
        superelastic ones as ``"species:label (superelastic)"``.
    ionization_frequency_N, attachment_frequency_N : float
        Sums of the ionizing and attaching rate coefficients (m^3/s).
    alpha_N, eta_N : float
        Townsend coefficients of ionization and attachment (m^2): k / W with temporal growth, as BOLSIG+
        gives them; with spatial growth the self-consistent net :math:`\alpha_{eff}/N` split as the rates are.
    power_balance : float
        (power from the field - power lost in collisions and carried by the growth) / power from the
        field: zero but for the discretisation (a check of the solution).
    power_fractions : dict
        Where the field's power goes, as fractions of it (BOLSIG+'s and LoKI-B's power balance):
        ``"elastic"`` (recoil, net of the gas's thermal motion), every inelastic process by its label
        (negative for a superelastic one, which gives energy back), ``"growth"`` (carried by the growth
        terms) and ``"electron-electron"`` (zero but for the discretisation); they sum to 1 - power_balance.
    growth : str
        The growth model, ``"temporal"`` or ``"spatial"``.
    max_energy : float
        Top of the energy grid (eV).
    cells : int
    iterations : int
        Linear solves made (the grid's adjustment, the growth's and the electron-electron iterations).
    ionization_degree, electron_density : float
        :math:`n_e/N` and :math:`n_e` (m^-3) of the electron-electron collisions (0 without them).
    coulomb_logarithm : float
        Their :math:`\ln\Lambda` at the solution's mean energy (0 without them).
    omega_N : float
        :math:`\omega/N` of a high-frequency field (rad m^3/s; 0 for a DC field).

    Examples
    --------
    >>> from collisionkit.transport import reid_ramp, two_term_boltzmann
    >>> result = two_term_boltzmann(reid_ramp(), 1.0, gas_temperature=0.0)
    >>> result  # doctest: +ELLIPSIS
    TwoTermResult(reduced_field=1, gas_temperature=0, energy=<array (1000,) float64>, ..., mean_energy=0.101561, ...)
    """

    reduced_field: float
    gas_temperature: float
    energy: np.ndarray
    eedf: np.ndarray
    mean_energy: float
    mobility_N: float
    drift_velocity: float
    diffusion_N: float
    characteristic_energy: float
    energy_mobility_N: float = 0.0
    energy_diffusion_N: float = 0.0
    momentum_frequency_N: float = 0.0
    rate_coefficients: dict = field(default_factory=dict)
    ionization_frequency_N: float = 0.0
    attachment_frequency_N: float = 0.0
    alpha_N: float = 0.0
    eta_N: float = 0.0
    power_balance: float = 0.0
    power_fractions: dict = field(default_factory=dict)
    growth: str = "temporal"
    max_energy: float = 0.0
    cells: int = 0
    iterations: int = 0
    # shown in the repr only when set (electron-electron collisions, a high-frequency field)
    ionization_degree: float = field(default=0.0, metadata={"optional": True})
    electron_density: float = field(default=0.0, metadata={"optional": True})
    coulomb_logarithm: float = field(default=0.0, metadata={"optional": True})
    omega_N: float = field(default=0.0, metadata={"optional": True})

    __repr__ = dataclass_repr

    def to_dict(self) -> dict:
        """The result as plain numbers and lists (JSON-ready).

        Examples
        --------
        >>> from collisionkit.transport import maxwell_model, two_term_boltzmann
        >>> sorted(two_term_boltzmann(maxwell_model(), 10.0).to_dict())[:3]
        ['alpha_N', 'attachment_frequency_N', 'cells']
        """
        return {name: (value.tolist() if isinstance(value, np.ndarray) else value)
                for name, value in self.__dict__.items()}

    def to_row(self) -> dict:
        """The scalars as one flat row (a CSV line): ``E_N``, the moments, then ``rate_coefficient[<label>]`` per
        process (named as in :meth:`SwarmResult.to_row <collisionkit.transport.SwarmResult.to_row>`), then
        ``power_fraction[<name>]`` per entry of :attr:`power_fractions`.

        Examples
        --------
        >>> from collisionkit.transport import reid_ramp, two_term_boltzmann
        >>> row = two_term_boltzmann(reid_ramp(), 12.0, 0.0).to_row()
        >>> list(row)[:3], [key for key in row if key.startswith("rate_coefficient")]
        (['E_N', 'gas_temperature', 'mean_energy'], ['rate_coefficient[reid:excitation]'])
        """
        row = {"E_N": self.reduced_field, "gas_temperature": self.gas_temperature}
        row |= {name: getattr(self, name) for name in ROW_FIELDS}
        row |= {f"rate_coefficient[{label}]": rate for label, rate in self.rate_coefficients.items()}
        row |= {f"power_fraction[{name}]": share for name, share in self.power_fractions.items()}
        return row


def two_term_boltzmann(gas: Gas, reduced_field: float, gas_temperature: float = 300.0, *, cells: int = 1000,
                       max_energy: float | None = None, sharing: str = "equal", growth: str = "temporal",
                       ionization_degree: float = 0.0, electron_density: float | None = None,
                       omega_N: float = 0.0) -> TwoTermResult:
    r"""Solve the two-term Boltzmann equation of electrons in ``gas`` at ``reduced_field``.

    Parameters
    ----------
    gas : Gas
        The gas (model gases, LXCat sets, mixtures). Elastic processes may
        scatter by any law (their momentum-transfer cross section enters);
        the others must be isotropic, as the two-term equation assumes.
    reduced_field : float
        E/N in Td, in [0, 1e6].
    gas_temperature : float, optional
        K, in [0, 1e5]; the levels of reversible excitations are populated
        at it (Boltzmann) unless set by hand, as in the swarm.
    cells : int, optional
        Cells of the energy grid, 50 to 100 000. The scheme is second order:
        at 1000 cells the moments are within 1e-5 of the exact solution for
        elastic collisions (the Maxwell and Druyvesteyn cases), 1e-3 with
        thresholds of a few cells (F0 is constant across a cell).
    max_energy : float, optional
        Top of the grid (eV). By default it is found: the grid is widened or
        narrowed until :math:`F_0` falls by 10 to 18 decades across it.
    sharing : {"equal", "uniform"}, optional
        How an ionization shares the energy left between the two electrons
        (as the swarm's ``sharing``).
    growth : {"temporal", "spatial"}, optional
        How a swarm that ionizes or attaches grows, as in BOLSIG+: in time
        (a pulsed swarm; ``alpha_N = k_i / W``) or in space (steady-state
        Townsend conditions, :math:`n \propto e^{\alpha z}`: ``alpha_N`` and
        ``eta_N`` split the self-consistent :math:`\alpha_{eff}/N` as the
        rates are). The same for a gas that does neither.
    ionization_degree : float, optional
        :math:`n_e/N`, in [0, 0.01]: above 0 the electrons also collide with
        each other (Coulomb collisions, the Fokker-Planck operator of
        :mod:`~collisionkit.transport._two_term_electrons`, as BOLSIG+ and
        LoKI-B), which pulls the distribution towards a Maxwellian (argon
        at 50 Td: the mean energy 0.06 % lower at 1e-6, 4 % at 1e-4, 15 % at
        1e-3). Beyond 0.01 collisions with the ions, not in the model,
        matter as much.
    electron_density : float, optional
        :math:`n_e` (m^-3, in (0, 1e32]) for the Coulomb logarithm; needed
        with ``ionization_degree`` > 0 and only then.
    omega_N : float, optional
        :math:`\omega/N` (rad m^3/s; 0, or 1e-20 to 1e-8 as the swarm's) of
        a high-frequency field :math:`E_0\cos\omega t`, ``reduced_field``
        its amplitude :math:`E_0/N` (as the swarm's ``reduced_frequency``;
        BOLSIG+ takes the RMS value :math:`E_0/\sqrt2 N`). The distribution is
        the steady one of a field much faster than the electrons' energy
        relaxation: the field heats as
        :math:`\tilde D = \frac{\gamma}{3}\frac{E_0^2}{2N^2}\frac{\epsilon\tilde\sigma_m}{\tilde\sigma_m^2
        + q^2/\epsilon}`, :math:`q = \omega/(N\gamma)` (Hagelaar & Pitchford 2005,
        eq. (16)). The mobility, diffusion and drift are then those a DC field
        would give this distribution (as BOLSIG+ reports them); temporal growth only.

    Returns
    -------
    TwoTermResult

    Raises
    ------
    TypeError, ValueError
        At the first argument of the wrong kind or out of range (named).
    RuntimeError
        If the growth iteration does not settle (a gas that attaches far
        faster than it ionizes may drive :math:`\tilde\sigma_m` negative),
        or the electron-electron iteration does not.

    Warns
    -----
    TwoTermWarning
        If the power balance is off by more than 1 % of the field's power
        (``POWER_BALANCE_WARNING``: refine ``cells``), if a ``max_energy``
        given cuts the distribution (F0 falls fewer than ``DECADES[0]`` = 10
        decades across the grid), or if more than 0.1 % of the electrons lie above the
        highest energy of the gas's tables (``BEYOND_TABLES``). The result is
        returned all the same.

    Examples
    --------
    Reid's ramp at 12 Td, 0 K: the two-term equation is 2-3 % above the
    exact (Monte Carlo, multi-term) 0.2691 eV and 6.84e4 m/s (Dias et al.
    2023), as the ramp's large inelastic cross section makes the
    distribution anisotropic:

    >>> from collisionkit.transport import reid_ramp, two_term_boltzmann
    >>> result = two_term_boltzmann(reid_ramp(), 12.0, gas_temperature=0.0)
    >>> round(result.mean_energy, 4), round(result.drift_velocity / 1e4, 3)
    (0.2736, 7.028)
    """
    reduced_field, gas_temperature, cells, max_energy, sharing, growth_model = _checked(
        gas, reduced_field, gas_temperature, cells, max_energy, sharing, growth)
    electrons = _checked_electrons(ionization_degree, electron_density)
    omega_N = check_reduced_frequency(omega_N, "omega_N (omega/N, rad m^3/s)")
    if omega_N and growth_model == "spatial":
        raise ValueError("growth='spatial' (steady-state Townsend) is for a DC field; a high-frequency field "
                         "(omega_N > 0) takes growth='temporal'")
    field_si = reduced_field * TOWNSEND
    kT = BOLTZMANN_EV * gas_temperature
    top = max_energy if max_energy is not None else _first_top(gas, kT)
    iterations, growth = 0, 0.0  # (the growth found on one grid is the next grid's first guess)
    # the electrons collide with each other only once the grid holds the distribution (their energy exchange
    # is exact only where F0 has fallen far at the top), then the grid is checked again with them
    colliding, solution = max_energy is not None, {"coulomb": None}
    for _ in range(MAX_GRID_ADJUSTMENTS):
        start = (solution["energy"], solution["eedf"]) if colliding and solution["coulomb"] is not None else None
        solution, used = _solve_on_grid(gas, (field_si, omega_N), kT, cells, top, sharing, growth_model, growth,
                                        electrons if colliding else None, start)
        growth = solution["growth"]  # the next grid's iteration starts from it
        iterations += used
        if max_energy is not None:
            break
        decades = _decades(solution["eedf"])
        if DECADES[0] <= decades <= DECADES[1]:
            if colliding or electrons is None:
                break
            colliding = True
            continue
        top = _adjusted_top(solution, top, decades)
    result = TwoTermResult(reduced_field=reduced_field, gas_temperature=gas_temperature, max_energy=float(top),
                           cells=cells, iterations=iterations, **moments(solution, field_si))
    _warn_if_doubtful(result, gas, solution, max_energy is not None)
    return result


def _warn_if_doubtful(result, gas, solution, top_given):
    """A :class:`TwoTermWarning` for a solution whose power does not balance, whose top cuts the distribution, or
    whose electrons reach beyond the cross-section tables."""
    import warnings

    if abs(result.power_balance) > POWER_BALANCE_WARNING:
        warnings.warn(f"E/N = {result.reduced_field:g} Td: the power balance is off by "
                      f"{abs(result.power_balance):.2g} of the field's power: refine the grid (cells = "
                      f"{result.cells}) or fit its top to the distribution (max_energy = {result.max_energy:.4g} eV; "
                      "left out, it is found)", TwoTermWarning,
                      stacklevel=3)
    decades = _decades(result.eedf)
    if top_given and decades < DECADES[0]:
        warnings.warn(f"E/N = {result.reduced_field:g} Td: F0 falls only {decades:.3g} decades across the grid "
                      f"(max_energy = {result.max_energy:.4g} eV): the top cuts the distribution; leave max_energy "
                      "out to have it found", TwoTermWarning, stacklevel=3)
    tops = [float(process.energy[-1]) for _, process in gas.processes if len(process.energy)]
    if tops:
        edges = solution["edges"]
        above = float(np.sum(solution["eedf"] * np.diff(np.maximum(edges, max(tops)) ** 1.5 / 1.5)))
        if above > BEYOND_TABLES:
            warnings.warn(f"E/N = {result.reduced_field:g} Td: {100 * above:.2g} % of the electrons lie above "
                          f"{max(tops):g} eV, the highest energy of the gas's cross-section tables (continued as "
                          "constants beyond it)", TwoTermWarning, stacklevel=3)


def _checked_electrons(ionization_degree, electron_density):
    """(ionization degree, electron density) if the electrons collide with each other, else None."""
    from .._params import check_real

    ionization_degree = check_real("ionization_degree (n_e/N)", ionization_degree, 0.0, MAX_IONIZATION_DEGREE)
    if ionization_degree == 0.0:
        if electron_density is not None:
            raise ValueError("electron_density is used only with ionization_degree > 0 (electron-electron "
                             "collisions); give both or neither")
        return None
    if electron_density is None:
        raise ValueError("ionization_degree > 0 needs electron_density (m^-3, in (0, 1e32]) for the Coulomb "
                         "logarithm")
    return ionization_degree, check_real("electron_density (m^-3)", electron_density, 0.0, 1e32, low_open=True)


def _checked(gas, reduced_field, gas_temperature, cells, max_energy, sharing, growth):
    from .._params import check_choice, check_integer, check_real

    if not isinstance(gas, Gas):
        raise TypeError(f"gas must be a Gas; got {type(gas).__name__}")
    for species in gas.species:
        for process in species.processes:
            if process.kind != "elastic" and process.scattering != "isotropic":
                raise ValueError(f"{process.label}: the two-term equation takes inelastic collisions as isotropic; "
                                 f"got scattering {process.scattering!r} (use simulate_swarm)")
            if process.reversible and process.superelastic_scattering != "isotropic":
                raise ValueError(f"{process.label}: the two-term equation takes superelastic collisions as "
                                 f"isotropic; got {process.superelastic_scattering!r} (use simulate_swarm)")
    reduced_field = check_real("reduced_field (E/N, Td)", reduced_field, 0.0, MAX_REDUCED_FIELD)
    gas_temperature = check_real("gas_temperature (K)", gas_temperature, 0.0, MAX_GAS_TEMPERATURE)
    if 0.0 < gas_temperature < MIN_GAS_TEMPERATURE:
        raise ValueError(f"gas_temperature (K) must be 0 or from {MIN_GAS_TEMPERATURE:g} to {MAX_GAS_TEMPERATURE:g}; "
                         f"got {gas_temperature:g} (a Maxwellian this cold does not fit a grid of double precision)")
    if reduced_field == 0.0 and gas_temperature == 0.0:
        raise ValueError("E/N = 0 in a gas at 0 K has no steady state: give gas_temperature > 0 or E/N > 0")
    cells = check_integer("cells", cells, 50, 100_000)
    if max_energy is not None:
        max_energy = check_real("max_energy (eV)", max_energy, 0.0, 1e7, low_open=True)
    check_choice("sharing", sharing, SHARING)
    check_choice("growth", growth, GROWTH_MODELS)
    return reduced_field, gas_temperature, cells, max_energy, sharing, growth


def _first_top(gas, kT):
    """A first guess of the grid's top: above every threshold, and well above the gas temperature."""
    thresholds = [p.threshold for _, p in gas.processes]
    return max(1.0, 30.0 * kT, 1.5 * max(thresholds, default=0.0))


def _decades(eedf):
    """Decades F0 falls from its peak to the top cell (inf if it reaches zero)."""
    peak, last = float(np.max(eedf)), float(eedf[-1])
    return math.inf if last <= 0.0 else math.log10(peak / last)


def _adjusted_top(solution, top, decades):
    """A wider grid if F0 has not fallen far enough at the top, else one ending where it has fallen 14 decades (from
    its peak)."""
    if decades < DECADES[0]:  # log F0 falls about linearly in eps in the tail: aim at 14 decades
        return top * min(max(14.0 / max(decades, 0.5), 1.2), 4.0)
    eedf, energy = solution["eedf"], solution["energy"]
    peak = np.argmax(eedf)
    below = np.nonzero((eedf[peak:] < eedf[peak] * 1e-14))[0]
    end = energy[peak + below[0]] if below.size else top
    return max(min(end * 1.05, 0.9 * top), 2.0 * energy[1])


def _solve_on_grid(gas, field, kT, cells, top, sharing, growth_model, guess=0.0, electrons=None, start=None):
    """F0 on a grid of ``cells`` up to ``top`` in ``field`` (E in V m^2, omega/N), with the growth (nu/N in time, or alpha/N in space) that the
    solution itself produces, found by the secant method, and with the electron-electron collisions of
    ``electrons`` (ionization degree, electron density) by iteration from ``start`` (energies and F0 of another
    grid's solution) if given; returns (solution, linear solves)."""
    field_si, omega_N = field
    edges = np.linspace(0.0, top, cells + 1)
    inner = edges[1:-1]
    collisions = gas_collisions(gas, kT)
    sigma_eps = sum(x * ratio * sigma(inner) for x, ratio, sigma in collisions.mass_ratios)
    sigma_m = sum(x * sigma(inner) for x, sigma in collisions.momentum)
    collision_matrix, production = collision_operator(collisions, edges, sharing)
    density = (edges[1:] ** 1.5 - edges[:-1] ** 1.5) / 1.5  # integral of eps^1/2 over each cell
    normalisation = sparse.csr_matrix(density[None, :])
    spatial = SpatialGrowth(edges, inner, sigma_m, collisions, field_si) if growth_model == "spatial" else None
    among_electrons = [0.0]  # the electron-electron collisions' flux divergence (a matrix once they collide)

    def eedf_at(growth):
        effective = sigma_m if spatial else effective_cross_section(sigma_m, growth, inner)
        drift = -GAMMA * inner**2 * sigma_eps
        heating = field_diffusion(field_si, omega_N, inner, effective)
        diffusion = heating + GAMMA * kT * inner**2 * sigma_eps
        if spatial:
            drift = drift + spatial.drift(growth)
            extra = spatial.source(growth)
        else:
            extra = sparse.diags(growth * density)
        system = (drift_diffusion_matrix(drift, diffusion, edges[1] - edges[0]) - collision_matrix + extra
                  + among_electrons[0]).tocsr()
        # the balances sum to zero (the system is singular): the normalisation replaces the bottom cell's
        rhs = np.zeros(cells)
        rhs[0] = 1.0
        return spsolve(sparse.vstack([normalisation, system[1:]], format="csc"), rhs), (effective, heating)

    def produced(eedf):
        return spatial.alpha(eedf, production) if spatial else float(production @ eedf)

    # nu/N <= max over cells of the production per electron in the cell (F0 constant in it, sum density F0 = 1)
    ceiling = None if spatial else float(np.max(production / density))

    def settled(growth):
        last = {}  # the iteration's last solve: the settled growth's F0, not solved again

        def remembered(value):
            last.clear()
            last[value] = eedf_at(value)
            return last[value]

        growth, used = settled_growth(remembered, produced, production, growth, ceiling)
        if growth not in last:
            remembered(growth)
            used += 1
        eedf, effective = last[growth]
        return np.maximum(eedf, 0.0), effective, growth, used

    coulomb = ElectronCollisions(*electrons, edges) if electrons else None
    if coulomb is not None and start is not None:  # the last grid's F0 with the collisions, on this grid
        eedf, growth, solves = np.interp(0.5 * (edges[:-1] + edges[1:]), *start, right=0.0), guess, 0
        eedf /= float(eedf @ density)
    else:
        eedf, effective, growth, solves = settled(guess)
    if coulomb is not None:
        eedf, effective, growth, used = with_electron_collisions(coulomb, among_electrons, settled, eedf, growth)
        solves += used
    if spatial:
        spatial.check(eedf, production)
    return {"eedf": eedf, "energy": 0.5 * (edges[:-1] + edges[1:]), "edges": edges,
            "growth": growth, "growth_model": growth_model, "effective": effective[0],
            "field_diffusion": effective[1], "omega_N": omega_N, "collisions": collisions,
            "inner": inner, "sigma_eps": sigma_eps, "kT": kT, "production": float(production @ eedf),
            "coulomb": coulomb}, solves
