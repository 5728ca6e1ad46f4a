"""Hard-sphere and hard-disc theory: equations of state, Enskog's collision rate and transport, packing fractions
(the square-well fluid's: :mod:`~collisionkit.edmd.square_well_theory`).

The references an EDMD run is checked against, and the packing-fraction
limits of the engine's random fluids (:data:`MAX_PACKING_FRACTION`).
"""

from __future__ import annotations

import math

import numpy as np

from . import _checks

# the square-well theory moved to .square_well_theory (not documented here twice: not in __all__); kept importable
from .square_well_theory import (  # noqa: F401
    square_well_low_density,
    square_well_second_virial,
    square_well_third_virial,
)

__all__ = [
    "MAX_PACKING_FRACTION",
    "YEH_HUMMER_XI",
    "carnahan_starling",
    "chapman_enskog_transport",
    "cooling_state_a2",
    "enskog_collision_frequency",
    "enskog_transport",
    "granular_shear_flow",
    "hansen_goos",
    "henderson",
    "packing_fraction",
    "yeh_hummer_correction",
]

#: Densest packing fraction supported per dimension (discs 2, spheres 3): a random fluid is
#: compressed up to it (denser runs risk jamming before the target, and crystallise).
MAX_PACKING_FRACTION = {2: 0.7, 3: 0.5}


def _packing(eta):
    """Packing fraction(s) for an equation of state: finite, in [0, 1)."""
    return _checks.bounded(eta, "eta", 0.0, 1.0, scalar=False)


def carnahan_starling(eta):
    r"""Carnahan-Starling compressibility factor of hard spheres.

    :math:`Z = (1 + \eta + \eta^2 - \eta^3)/(1 - \eta)^3`
    (J. Chem. Phys. 51, 635 (1969)).

    Parameters
    ----------
    eta : float or array_like
        Packing fraction(s), in [0, 1).

    Returns
    -------
    float or ndarray
        Z, shaped like ``eta``.

    Examples
    --------
    >>> from collisionkit.edmd import carnahan_starling
    >>> round(float(carnahan_starling(0.4)), 6)
    6.925926
    """
    eta = _packing(eta)
    return (1 + eta + eta**2 - eta**3) / (1 - eta) ** 3


_HANSEN_GOOS_B = (9.0, -19.0, 47.0 / 3.0, -2.635232, -1.265575, 0.041212, 0.248245, -0.096495)


def hansen_goos(eta):
    r"""Hansen-Goos compressibility factor of the hard-sphere fluid.

    :math:`Z = 8\ln(1-\eta)/\eta + \sum_{i=0}^7 b_i\eta^i/(1-\eta)^3`
    (J. Chem. Phys. 144, 164506 (2016)); more accurate than Carnahan-Starling
    near freezing.

    Parameters
    ----------
    eta : float or array_like
        Packing fraction(s), in [0, 1); Z = 1 at eta = 0.

    Returns
    -------
    float or ndarray
        Z, shaped like ``eta``.

    Examples
    --------
    >>> from collisionkit.edmd import hansen_goos
    >>> round(float(hansen_goos(0.4)), 4)
    6.945
    >>> float(hansen_goos(0.0))
    1.0
    """
    eta = _packing(eta)
    series = sum(b * eta**i for i, b in enumerate(_HANSEN_GOOS_B))
    # ln(1 - eta) / eta tends to -1 at eta = 0
    log_ratio = np.divide(np.log1p(-eta), eta, out=np.full_like(eta, -1.0), where=eta != 0)
    return 8.0 * log_ratio + series / (1 - eta) ** 3


def henderson(eta):
    r"""Henderson's hard-disc equation of state :math:`Z = (1 + \eta^2/8)/(1 - \eta)^2`.

    Mol. Phys. 30, 971 (1975).

    Parameters
    ----------
    eta : float or array_like
        Packing fraction(s) of the discs, in [0, 1).

    Returns
    -------
    float or ndarray
        Z, shaped like ``eta``.

    Examples
    --------
    >>> from collisionkit.edmd import henderson
    >>> round(float(henderson(0.3)), 6)
    2.063776
    """
    eta = _packing(eta)
    return (1 + eta**2 / 8) / (1 - eta) ** 2


def enskog_collision_frequency(compressibility, dim, diameter=1.0, kT=1.0, mass=1.0):
    r"""Collision frequency per particle from the pressure: :math:`\omega = (2d/\sigma)(Z-1)\sqrt{kT/(\pi m)}`.

    Each pair collision counts for both particles.

    Parameters
    ----------
    compressibility : float or array_like
        Compressibility factor Z = PV/(NkT), finite and >= 1 (the hard-core
        pressure is never below the ideal gas's).
    dim : {2, 3}
    diameter, kT, mass : float or array_like, optional
        Finite and > 0.

    Returns
    -------
    float or ndarray
        Collisions per particle per unit time.

    Examples
    --------
    >>> from collisionkit.edmd import enskog_collision_frequency
    >>> round(float(enskog_collision_frequency(2.0, 3)), 6)
    3.385138
    """
    compressibility = _checks.bounded(compressibility, "compressibility", 1.0, scalar=False)
    dim = _checks.dimension(dim)
    diameter, kT, mass = (
        _checks.positive(diameter, "diameter", scalar=False),
        _checks.positive(kT, "kT", scalar=False),
        _checks.positive(mass, "mass", scalar=False),
    )
    return (2.0 * dim / diameter) * (compressibility - 1.0) * np.sqrt(kT / (np.pi * mass))


def _ball_volume(radius, dim):
    """Area of a disc (dim 2) or volume of a sphere (dim 3) of the given radius."""
    return np.pi * radius**2 if dim == 2 else 4.0 / 3.0 * np.pi * radius**3


def packing_fraction(radii, box):
    """Fraction of the box volume covered by the particles.

    Parameters
    ----------
    radii : float or array_like
        Radii of the discs or spheres, finite and > 0.
    box : array_like, shape (2,) or (3,)
        Box lengths, finite and > 0; the length gives the dimension.

    Returns
    -------
    float

    Examples
    --------
    >>> from collisionkit.edmd import packing_fraction
    >>> round(packing_fraction([0.5], [1.0, 1.0]), 6)
    0.785398
    """
    radii = _checks.positive(radii, "radii", scalar=False)
    box = _checks.positive(box, "box", scalar=False)
    if box.shape not in ((2,), (3,)):
        raise ValueError(f"box must have shape (2,) or (3,) (the dimension); got {box.shape}")
    return float(np.sum(_ball_volume(radii, box.size)) / np.prod(box))


# The dilute gas's first Sonine approximations times the factors of the higher orders (viscosity,
# conductivity): spheres, Chapman & Cowling, The Mathematical Theory of Non-uniform Gases, 3rd ed., sec.
# 10.21 and 16.5; discs, Gass, J. Chem. Phys. 54, 1898 (1971).
_SONINE_FACTORS = {3: (1.016, 1.025), 2: (1.022, 1.029)}

#: Largest packing fraction Enskog's formulas are evaluated at, per dimension (beyond freezing, as users
#: compare glassy or metastable fluids with them; the contact values diverge at 1).
_ENSKOG_PACKING_LIMIT = {2: 0.8, 3: 0.6}


def _first_sonine(dim, diameter, mass, kT):
    r"""Dilute shear viscosity, thermal conductivity and n D of d-dimensional hard spheres, first Sonine order.

    :math:`\eta_0 = \frac{d+2}{8}\frac{\Gamma(d/2)}{\pi^{(d-1)/2}}\frac{\sqrt{mkT}}{\sigma^{d-1}}`,
    :math:`\lambda_0 = \frac{d(d+2)}{2(d-1)}\frac{\eta_0}{m}` (k = 1),
    :math:`nD_0 = \frac{d\,\Gamma(d/2)}{4\pi^{(d-1)/2}}\frac{1}{\sigma^{d-1}}\sqrt{kT/m}` (Garzó & Dufty,
    Phys. Rev. E 59, 5895 (1999) at e = 1; 5/16, 75/64 and 3/8 over sqrt(pi) for spheres).
    """
    geometric = math.gamma(dim / 2) / (math.pi ** ((dim - 1) / 2) * diameter ** (dim - 1))
    viscosity = (dim + 2) / 8 * geometric * np.sqrt(mass * kT)
    conductivity = dim * (dim + 2) / (2 * (dim - 1)) * viscosity / mass
    return viscosity, conductivity, dim / 4 * geometric * np.sqrt(kT / mass)


def _as_given(values: dict) -> dict:
    """Each value as a float if the inputs were scalars (a 0-d result), else as an array."""
    return {key: float(value) if np.ndim(value) == 0 else np.asarray(value) for key, value in values.items()}


def _broadcast(*values):
    """The inputs broadcast against each other (a ValueError naming the shapes if they cannot be)."""
    try:
        return np.broadcast_arrays(*values)
    except ValueError:
        raise ValueError(f"the inputs' shapes {[np.shape(value) for value in values]} do not broadcast") from None


def chapman_enskog_transport(density, diameter=1.0, mass=1.0, kT=1.0, dim=3):
    r"""Transport coefficients of the dilute gas of hard spheres or discs (Chapman-Enskog), as a dict.

    Spheres: shear viscosity :math:`\eta_0 = 1.016\,\frac{5}{16\sigma^2}\sqrt{mkT/\pi}`,
    thermal conductivity :math:`\lambda_0 = 1.025\,\frac{75}{64\sigma^2}\sqrt{kT/(\pi m)}`
    (k = 1), self-diffusion :math:`D_0 = \frac{3}{8 n\sigma^2}\sqrt{kT/(\pi m)}`:
    the first Sonine approximations, the first two times the factors of
    the higher orders (Chapman & Cowling, The Mathematical Theory of
    Non-uniform Gases, 3rd ed., sec. 10.21 and 16.5); D0 in the first
    approximation, as Alder, Gass & Wainwright (J. Chem. Phys. 53, 3813
    (1970)) normalise it. Discs: :math:`\eta_0 = 1.022\,\frac{1}{2\sigma}\sqrt{mkT/\pi}`,
    :math:`\lambda_0 = 1.029\,\frac{2}{\sigma}\sqrt{kT/(\pi m)}`,
    :math:`D_0 = \frac{1}{2n\sigma}\sqrt{kT/(\pi m)}` (Gass, J. Chem. Phys.
    54, 1898 (1971)). The bulk viscosity of the dilute gas is 0.

    Parameters
    ----------
    density : float or array_like
        Number density n (per volume, or per area for discs), finite and > 0.
    diameter, mass, kT : float or array_like, optional
        Finite and > 0; every input broadcasts against the others.
    dim : {3, 2}, optional
        Spheres (3) or discs (2).

    Returns
    -------
    dict
        ``shear_viscosity``, ``bulk_viscosity``, ``thermal_conductivity``, ``self_diffusion``: floats for
        scalar inputs, else arrays of the broadcast shape.

    Examples
    --------
    >>> from collisionkit.edmd import chapman_enskog_transport
    >>> {key: round(value, 5) for key, value in chapman_enskog_transport(0.1).items()}
    {'shear_viscosity': 0.17913, 'bulk_viscosity': 0.0, 'thermal_conductivity': 0.67769, 'self_diffusion': 2.11571}
    >>> round(chapman_enskog_transport(0.1, dim=2)["shear_viscosity"], 5)  # 1.022 / (2 sqrt(pi))
    0.2883
    >>> chapman_enskog_transport([0.1, 0.2])["self_diffusion"].round(4)  # D0 falls as 1/n
    array([2.1157, 1.0579])
    """
    density = _checks.positive(density, "density", scalar=False)
    diameter, mass, kT = (_checks.positive(value, name, scalar=False) for value, name in
                          ((diameter, "diameter"), (mass, "mass"), (kT, "kT")))
    dim = _checks.dimension(dim)
    density, diameter, mass, kT = _broadcast(density, diameter, mass, kT)
    viscosity, conductivity, density_diffusion = _first_sonine(dim, diameter, mass, kT)
    viscosity_factor, conductivity_factor = _SONINE_FACTORS[dim]
    return _as_given({
        "shear_viscosity": viscosity_factor * viscosity,
        "bulk_viscosity": np.zeros_like(viscosity),
        "thermal_conductivity": conductivity_factor * conductivity,
        "self_diffusion": density_diffusion / density,
    })


def enskog_transport(eta, diameter=1.0, mass=1.0, kT=1.0, dim=3):
    r"""Transport coefficients of hard spheres or discs in Enskog's dense-gas theory, as a dict.

    Enskog's solution in d dimensions (Garzó & Dufty, Phys. Rev. E 59,
    5895 (1999), at restitution 1), with the contact value :math:`\chi`,
    the first-Sonine dilute values :math:`\eta_0^{(1)}, \lambda_0^{(1)}`
    and the higher-order factors :math:`s_\eta, s_\lambda` applied to the
    kinetic parts (as Chapman & Cowling do)::

        eta_E    = s_eta eta0 / chi (1 + 2^d/(d+2) eta chi)^2 + d/(d+2) zeta_E
        zeta_E   = 2^(2d+2)/(pi (d+2)) eta^2 chi eta0                (exact)
        lambda_E = s_lambda lambda0 / chi (1 + 3 2^(d-1)/(d+2) eta chi)^2
                   + 2^(2d+2) (d-1)/(pi (d+2)^2) eta^2 chi lambda0
        D_E      = D0 / chi

    With :math:`y = bn` (4 eta for spheres, 2 eta for discs) these are
    Chapman & Cowling's :math:`\eta_E/\eta_0 = 1/\chi + 0.8y + 0.761y^2\chi`,
    :math:`\zeta_E = 1.002\eta_0 y^2\chi`, :math:`\lambda_E/\lambda_0 = 1/\chi
    + 1.2y + 0.757y^2\chi` (sec. 16.5) and Gass's hard-disc
    :math:`\eta_E/\eta_0 = 1/\chi + y + 0.8729y^2\chi`, :math:`\lambda_E/\lambda_0
    = 1/\chi + 1.5y + 0.8718y^2\chi` (J. Chem. Phys. 54, 1898 (1971)). The
    contact values are Carnahan-Starling's :math:`\chi = (1 - \eta/2)/(1 -
    \eta)^3` and Henderson's :math:`\chi = (1 - 7\eta/16)/(1 - \eta)^2`.
    Enskog's theory neglects correlated collisions: molecular dynamics of
    spheres finds D up to about 1.3 D_E and the viscosity within a few per
    cent of eta_E up to n sigma^3 = 0.5, then above it (Alder, Gass &
    Wainwright, J. Chem. Phys. 53, 3813 (1970); Sigurgeirsson & Heyes, Mol.
    Phys. 101, 469 (2003); Pieprzyk et al., Phys. Chem. Chem. Phys. 21, 6886
    (2019)); in two dimensions the long-time tails make the coefficients grow
    slowly with the observation time and the system size.

    Parameters
    ----------
    eta : float or array_like
        Packing fraction, in (0, 0.6) for spheres and (0, 0.8) for discs.
    diameter, mass, kT : float or array_like, optional
        Finite and > 0; every input broadcasts against the others.
    dim : {3, 2}, optional
        Spheres (3) or discs (2).

    Returns
    -------
    dict
        ``shear_viscosity``, ``bulk_viscosity``, ``thermal_conductivity``, ``self_diffusion``, and the
        contact value ``contact_value``: floats for scalar inputs, else arrays of the broadcast shape.

    Examples
    --------
    >>> import math
    >>> from collisionkit.edmd import enskog_transport
    >>> enskog = enskog_transport(math.pi / 12)  # n sigma^3 = 0.5
    >>> {key: round(value, 4) for key, value in enskog.items()}  # doctest: +NORMALIZE_WHITESPACE
    {'shear_viscosity': 0.5562, 'bulk_viscosity': 0.4255, 'thermal_conductivity': 2.3815,
     'self_diffusion': 0.1959, 'contact_value': 2.1605}
    >>> round(enskog_transport(0.3, dim=2)["shear_viscosity"], 4)
    0.4962
    >>> enskog_transport([0.1, 0.3, 0.5])["contact_value"].round(3)  # a curve in one call
    array([1.303, 2.478, 6.   ])
    """
    dim = _checks.dimension(dim)
    eta = _checks.bounded(eta, "eta", 0.0, _ENSKOG_PACKING_LIMIT[dim], closed=(False, False), scalar=False)
    diameter, mass, kT = (_checks.positive(value, name, scalar=False) for value, name in
                          ((diameter, "diameter"), (mass, "mass"), (kT, "kT")))
    eta, diameter, mass, kT = _broadcast(eta, diameter, mass, kT)
    viscosity, conductivity, density_diffusion = _first_sonine(dim, diameter, mass, kT)
    viscosity_factor, conductivity_factor = _SONINE_FACTORS[dim]
    chi = (1.0 - 0.5 * eta) / (1.0 - eta) ** 3 if dim == 3 else (1.0 - 7.0 * eta / 16.0) / (1.0 - eta) ** 2
    transfer = 2.0**dim / (dim + 2) * eta * chi
    collisional = 2.0 ** (2 * dim + 2) / (math.pi * (dim + 2)) * eta * eta * chi
    bulk = collisional * viscosity
    ball = math.pi ** (dim / 2) / math.gamma(dim / 2 + 1) * (diameter / 2) ** dim
    return _as_given({
        "shear_viscosity": viscosity_factor * viscosity / chi * (1.0 + transfer) ** 2 + dim / (dim + 2) * bulk,
        "bulk_viscosity": bulk,
        "thermal_conductivity": conductivity_factor * conductivity / chi * (1.0 + 1.5 * transfer) ** 2
        + (dim - 1) / (dim + 2) * collisional * conductivity,
        "self_diffusion": density_diffusion * ball / (eta * chi),
        "contact_value": chi,
    })


#: Yeh & Hummer's constant of the cubic periodic lattice (J. Phys. Chem. B 108, 15873 (2004)).
YEH_HUMMER_XI = 2.837297


def yeh_hummer_correction(viscosity, box_length, kT=1.0):
    r"""The finite-size correction of the self-diffusion coefficient in a cubic periodic box: :math:`\xi kT/(6\pi\eta L)`.

    A particle's periodic images drag it through the hydrodynamic flow
    they make, so D measured in a box of side L falls short of the
    infinite system's: :math:`D_\infty = D_L + \xi kT / (6\pi\eta L)`,
    :math:`\xi = 2.837297` (Dünweg & Kremer, J. Chem. Phys. 99, 6983
    (1993); Yeh & Hummer, J. Phys. Chem. B 108, 15873 (2004)). Add it to a
    measured D with the measured shear viscosity.

    Parameters
    ----------
    viscosity : float or array_like
        Shear viscosity eta, finite and > 0.
    box_length : float or array_like
        Side L of the cubic box, finite and > 0.
    kT : float, optional
        Finite and > 0.

    Returns
    -------
    float or ndarray

    Examples
    --------
    >>> from collisionkit.edmd import yeh_hummer_correction
    >>> round(float(yeh_hummer_correction(0.6, 14.0)), 5)
    0.01792
    """
    viscosity = _checks.positive(viscosity, "viscosity", scalar=False)
    box_length = _checks.positive(box_length, "box_length", scalar=False)
    kT = _checks.positive(kT, "kT", scalar=False)
    return YEH_HUMMER_XI * kT / (6.0 * np.pi * viscosity * box_length)


def dilute_granular_rates(alpha: float, dim: int) -> tuple[float, float]:
    r"""The dilute granular gas's reduced cooling rate and momentum-flux collision rate, Maxwellian first Sonine.

    :math:`\zeta^* = (d+2)(1-\alpha^2)/(4d)` and :math:`\nu_\eta^* = (1+\alpha)(3 - 3\alpha + 2d)/(4d)`, in units
    of :math:`\nu_0 = n kT / \eta_0` (:math:`\eta_0` the elastic gas's first-Sonine viscosity; Garzó & Dufty,
    Phys. Rev. E 59, 5895 (1999), their dilute limit with a2 = 0). The Navier-Stokes shear viscosity is
    :math:`\eta_0 / (\nu_\eta^* - \zeta^*/2)` (Brey, Dufty, Kim & Santos, Phys. Rev. E 58, 4638 (1998)).

    Examples
    --------
    >>> dilute_granular_rates(1.0, 3)
    (0.0, 1.0)
    """
    return (dim + 2) * (1 - alpha**2) / (4 * dim), (1 + alpha) * (3 - 3 * alpha + 2 * dim) / (4 * dim)


def granular_shear_flow(restitution, shear_rate, density, dim=3, diameter=1.0, mass=1.0):
    r"""Steady uniform shear flow of a dilute granular gas (inelastic hard spheres or discs), Grad's solution.

    Viscous heating balances collisional cooling at a temperature set by
    the restitution alpha and the shear rate a. In Grad's (first Sonine)
    approximation the collisional moments of the pressure tensor are
    :math:`-\nu_\eta (P_{ij} - p\delta_{ij}) - \zeta p\,\delta_{ij}`, with
    :math:`\nu_\eta^* = (1+\alpha)(3 - 3\alpha + 2d)/(4d)` and the cooling
    rate :math:`\zeta^* = (d+2)(1-\alpha^2)/(4d)` in units of
    :math:`\nu_0 = p/\eta_0` (:math:`\eta_0` the elastic gas's first-Sonine
    viscosity, :math:`(d+2)\Gamma(d/2)/(8\pi^{(d-1)/2})\sqrt{mT}/\sigma^{d-1}`;
    V. Garzó and J. W. Dufty, Phys. Rev. E 59, 5895 (1999), their dilute
    limit). The steady balances of :math:`P_{yy}`, :math:`P_{xy}` and the
    energy, :math:`P_{yy}/p = 1 - \zeta/\nu_\eta`,
    :math:`P_{xy} = -a P_{yy}/\nu_\eta` and :math:`-2aP_{xy}/(dp) = \zeta`,
    give the reduced shear rate

    .. math:: a^{*2} = \left(\frac{a}{\nu_0}\right)^2 = \frac{d\,\zeta^*\nu_\eta^{*2}}{2(\nu_\eta^* - \zeta^*)}

    (A. Santos, V. Garzó and J. W. Dufty, Phys. Rev. E 69, 061303 (2004),
    dilute limit; V. Garzó, Granular Gaseous Flows, Springer 2019, ch. 6),
    and with :math:`\nu_0 \propto \sqrt{T}` the temperature. The theory
    agrees with simulations of the Boltzmann equation to a few per cent
    in T for alpha >= 0.7 (Santos et al. 2004, their Fig. 2; Brey,
    Ruiz-Montero & Moreno, Phys. Rev. E 55, 2846 (1997)).

    Parameters
    ----------
    restitution : float
        alpha in (0, 1).
    shear_rate : float
        a > 0.
    density : float
        Number density n > 0 (dilute: n sigma^d << 1).
    dim : {2, 3}
    diameter, mass : float
        > 0.

    Returns
    -------
    dict
        ``reduced_shear_rate`` a*, ``temperature`` kT,
        ``viscosity`` -P_xy / a and ``normal_stress_yy`` P_yy / p.

    Examples
    --------
    >>> flow = granular_shear_flow(0.9, 0.1, 0.01)
    >>> round(flow["reduced_shear_rate"], 4), round(flow["normal_stress_yy"], 4)
    (0.3587, 0.9206)
    """
    alpha = _checks.bounded(restitution, "restitution", 0.0, 1.0, closed=(False, False))
    rate = _checks.positive(shear_rate, "shear_rate")
    density = _checks.positive(density, "density")
    dim = _checks.dimension(dim)
    diameter = _checks.positive(diameter, "diameter")
    mass = _checks.positive(mass, "mass")
    cooling, momentum = dilute_granular_rates(alpha, dim)
    reduced = math.sqrt(dim * cooling * momentum**2 / (2 * (momentum - cooling)))
    # nu_0 = n T / eta_0 = n sigma^(d-1) sqrt(T / m) / C
    constant = (dim + 2) * math.gamma(dim / 2) / (8 * math.pi ** ((dim - 1) / 2))
    per_root_temperature = density * diameter ** (dim - 1) / (constant * math.sqrt(mass))
    kT = (rate / (reduced * per_root_temperature)) ** 2
    normal = 1 - cooling / momentum
    viscosity = density * kT * normal / (momentum * per_root_temperature * math.sqrt(kT))
    return {"reduced_shear_rate": reduced, "temperature": kT, "viscosity": viscosity, "normal_stress_yy": normal}


def cooling_state_a2(restitution, dim=3):
    r"""The fourth cumulant a2 of the velocity distribution of a homogeneously cooling gas (first Sonine order).

    With :math:`c = v / \sqrt{2kT/m}`, :math:`a_2 = \frac{d}{d+2} \frac{\langle v^4 \rangle}{\langle v^2
    \rangle^2} - 1` (0 for a Maxwellian), and in the homogeneous cooling state

    .. math:: a_2 = \frac{16 (1 - \alpha) (1 - 2 \alpha^2)}{9 + 24 d - \alpha (41 - 8 d) + 30 \alpha^2 (1 - \alpha)}

    (T. P. C. van Noije and M. H. Ernst, Granular Matter 1, 57 (1998); for
    spheres :math:`16(1-\alpha)(1-2\alpha^2)/(81 - 17\alpha + 30\alpha^2(1-\alpha))`, Brilliantov & Poschel,
    Kinetic Theory of Granular Gases (2004)). It vanishes for elastic spheres and at
    :math:`\alpha = 1/\sqrt2`, and is small (|a2| < 0.02) for alpha above 0.6, where it describes the
    simulated distribution well.

    Parameters
    ----------
    restitution : float or array_like
        alpha in [0, 1].
    dim : {2, 3}

    Returns
    -------
    float or ndarray

    Examples
    --------
    >>> from collisionkit.edmd import cooling_state_a2
    >>> round(float(cooling_state_a2(0.9)), 5), abs(float(cooling_state_a2(1.0)))
    (-0.01456, 0.0)
    """
    alpha = _checks.bounded(restitution, "restitution", 0.0, 1.0, closed=(True, True), scalar=False)
    d = _checks.dimension(dim)
    return 16.0 * (1.0 - alpha) * (1.0 - 2.0 * alpha**2) / (
        9.0 + 24.0 * d - alpha * (41.0 - 8.0 * d) + 30.0 * alpha**2 * (1.0 - alpha))
