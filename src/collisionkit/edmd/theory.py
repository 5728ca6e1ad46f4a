"""Hard-sphere and hard-disc theory: equations of state, Enskog's collision rate, packing fractions.

The references an EDMD run is checked against, and the packing-fraction
limits of the engine's random fluids (:data:`MAX_PACKING_FRACTION`).
"""

from __future__ import annotations

import numpy as np

from . import _checks

__all__ = [
    "MAX_PACKING_FRACTION",
    "carnahan_starling",
    "enskog_collision_frequency",
    "hansen_goos",
    "henderson",
    "packing_fraction",
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
