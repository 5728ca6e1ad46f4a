r"""Classical scattering laws: hard spheres and the Coulomb (Rutherford) force.

The deflection angle chi is the centre-of-mass scattering angle of the
relative motion. For a central potential it is (Landau & Lifshitz, Mechanics,
eq. 18.1)

.. math:: \chi = \pi - 2\int_{r_{min}}^\infty \frac{b\,dr}{r^2\sqrt{1 - b^2/r^2 - V(r)/E}},

which the test suite evaluates numerically as an independent check of the
closed forms here. Coulomb strength ``k``: ``V(r) = k / r`` with
``k = q1 q2 / (4 pi eps0)`` (> 0 repulsive, < 0 attractive; ``-G m1 m2``
for gravity). The collision energy is that of the relative motion,
``E = mu v^2 / 2``.
"""

from __future__ import annotations

import numpy as np
import scipy.constants as const

from . import _arrays

__all__ = [
    "hard_sphere_impact_parameter",
    "hard_sphere_deflection",
    "hard_sphere_cross_section",
    "hard_sphere_differential_cross_section",
    "coulomb_strength",
    "rutherford_deflection",
    "rutherford_impact_parameter",
    "rutherford_differential_cross_section",
    "rutherford_cross_section_above",
    "coulomb_closest_approach",
]


def _nonnegative(value, name):
    array = _arrays.as_float_array(value, name)
    _arrays.require_finite(array, name)
    _arrays.require_in_range(array, name, 0.0, np.inf, inclusive=(True, False))
    return array


def _positive(value, name):
    array = _arrays.as_float_array(value, name)
    _arrays.require_finite(array, name)
    _arrays.require_in_range(array, name, 0.0, np.inf, inclusive=(False, False))
    return array


def _angle(value, name="chi"):
    array = _arrays.as_float_array(value, name)
    _arrays.require_in_range(array, name, 0.0, np.pi)
    return array


def hard_sphere_impact_parameter(chi, sigma):
    r"""Impact parameter giving the CM deflection chi off a hard sphere: :math:`b = \sigma\cos(\chi/2)`.

    Examples
    --------
    >>> from collisionkit.scattering import hard_sphere_impact_parameter
    >>> float(hard_sphere_impact_parameter(0.0, 2.0))
    2.0
    """
    return _positive(sigma, "sigma") * np.cos(0.5 * _angle(chi))


def hard_sphere_deflection(impact_parameter, sigma):
    r"""CM deflection off a hard sphere: :math:`\chi = 2\arccos(b/\sigma)` for b < sigma, else 0.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.scattering import hard_sphere_deflection
    >>> np.degrees(hard_sphere_deflection([0.0, 0.5, 2.0], 1.0)).round(9)
    array([180., 120.,   0.])
    """
    b = _nonnegative(impact_parameter, "impact_parameter")
    sigma = _positive(sigma, "sigma")
    return np.where(b < sigma, 2.0 * np.arccos(np.minimum(b / sigma, 1.0)), 0.0)


def hard_sphere_cross_section(sigma, dimension=3):
    """Total cross section of hard bodies with contact distance sigma.

    pi sigma^2 in 3D (area of the collision disc), 2 sigma in 2D (width of
    the collision segment).

    Examples
    --------
    >>> from collisionkit.scattering import hard_sphere_cross_section
    >>> float(hard_sphere_cross_section(1.0, dimension=2))
    2.0
    """
    sigma = _positive(sigma, "sigma")
    if dimension == 3:
        return np.pi * sigma**2
    if dimension == 2:
        return 2.0 * sigma
    raise ValueError(f"dimension must be 2 or 3; got {dimension!r}")


def hard_sphere_differential_cross_section(chi, sigma):
    r"""3D CM differential cross section of hard spheres: isotropic, :math:`\sigma^2/4`.

    From :math:`d\sigma/d\Omega = b/\sin\chi\,|db/d\chi|` with
    :math:`b = \sigma\cos(\chi/2)`; it integrates to :math:`\pi\sigma^2`.

    Examples
    --------
    >>> from collisionkit.scattering import hard_sphere_differential_cross_section
    >>> float(hard_sphere_differential_cross_section(1.0, 2.0))
    1.0
    """
    chi = _angle(chi)
    return np.broadcast_to(0.25 * _positive(sigma, "sigma") ** 2, np.broadcast_shapes(chi.shape, np.shape(sigma))).copy()


def coulomb_strength(q1, q2):
    """Coulomb constant ``k = q1 q2 / (4 pi eps0)`` in J m for charges in coulombs.

    Examples
    --------
    >>> from collisionkit.scattering import coulomb_strength
    >>> e = 1.602176634e-19
    >>> round(float(coulomb_strength(e, e)) / e * 1e9, 6)  # 1.44 eV nm
    1.439965
    """
    q1 = _arrays.as_float_array(q1, "q1")
    q2 = _arrays.as_float_array(q2, "q2")
    _arrays.require_finite(q1, "q1")
    _arrays.require_finite(q2, "q2")
    return q1 * q2 / (4.0 * np.pi * const.epsilon_0)


def _coulomb_length(k, reduced_mass, relative_speed):
    """k / (mu v^2): half the head-on distance of closest approach (signed)."""
    k = _arrays.as_float_array(k, "k")
    _arrays.require_finite(k, "k")
    mu = _positive(reduced_mass, "reduced_mass")
    v = _positive(relative_speed, "relative_speed")
    return k / (mu * v**2)


def rutherford_deflection(impact_parameter, k, reduced_mass, relative_speed):
    r"""CM deflection in a Coulomb field: :math:`\tan(\chi/2) = k / (\mu v^2 b)`.

    Signed: positive for repulsion (k > 0, away from the centre), negative
    for attraction (k < 0, towards it); the magnitude is the same for both.
    b = 0 gives +-pi (head-on).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.scattering import rutherford_deflection
    >>> float(np.degrees(rutherford_deflection(1.0, 1.0, 1.0, 1.0)))
    90.0
    """
    a = _coulomb_length(k, reduced_mass, relative_speed)
    b = _nonnegative(impact_parameter, "impact_parameter")
    return 2.0 * np.arctan2(a, b)


def rutherford_impact_parameter(chi, k, reduced_mass, relative_speed):
    r"""Impact parameter for CM deflection |chi|: :math:`b = |k|/(\mu v^2)\cot(\chi/2)`.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.scattering import rutherford_impact_parameter
    >>> round(float(rutherford_impact_parameter(np.pi / 2, -1.0, 1.0, 1.0)), 12)
    1.0
    """
    chi = _arrays.as_float_array(chi, "chi")
    _arrays.require_in_range(np.abs(chi), "|chi|", 0.0, np.pi, inclusive=(False, True))
    a = np.abs(_coulomb_length(k, reduced_mass, relative_speed))
    half = 0.5 * np.abs(chi)
    return a * np.cos(half) / np.sin(half)


def rutherford_differential_cross_section(chi, k, reduced_mass, relative_speed):
    r"""Rutherford's CM cross section :math:`(k / (2\mu v^2))^2 / \sin^4(\chi/2)`.

    Same for attraction and repulsion; chi in (0, pi].

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.scattering import rutherford_differential_cross_section
    >>> float(rutherford_differential_cross_section(np.pi, 2.0, 1.0, 1.0))
    1.0
    """
    chi = _arrays.as_float_array(chi, "chi")
    _arrays.require_in_range(np.abs(chi), "|chi|", 0.0, np.pi, inclusive=(False, True))
    a = _coulomb_length(k, reduced_mass, relative_speed)
    return (0.5 * a) ** 2 / np.sin(0.5 * chi) ** 4


def rutherford_cross_section_above(chi_min, k, reduced_mass, relative_speed):
    r"""Cross section for deflections larger than chi_min: :math:`\pi (k/(\mu v^2))^2\cot^2(\chi_{min}/2)`.

    The disc of impact parameters below :math:`b(\chi_{min})`; it diverges
    as chi_min -> 0 (the long range of the Coulomb force).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.scattering import rutherford_cross_section_above
    >>> round(float(rutherford_cross_section_above(np.pi / 2, 1.0, 1.0, 1.0) / np.pi), 12)
    1.0
    """
    b = rutherford_impact_parameter(chi_min, k, reduced_mass, relative_speed)
    return np.pi * b**2


def coulomb_closest_approach(impact_parameter, k, reduced_mass, relative_speed):
    r"""Periapsis distance of Coulomb scattering: :math:`r_{min} = a + \sqrt{a^2 + b^2}`, :math:`a = k/(\mu v^2)`.

    From energy and angular momentum conservation; a < 0 (attraction) gives
    the closer approach of a hyperbolic fly-by. Head-on repulsion stops at 2a.

    Examples
    --------
    >>> from collisionkit.scattering import coulomb_closest_approach
    >>> float(coulomb_closest_approach(0.0, 1.0, 1.0, 1.0))
    2.0
    """
    a = _coulomb_length(k, reduced_mass, relative_speed)
    b = _nonnegative(impact_parameter, "impact_parameter")
    # a + sqrt(a^2 + b^2) cancels for a < 0; b^2 / (sqrt(a^2 + b^2) - a) does not
    root = np.hypot(a, b)
    with np.errstate(invalid="ignore", divide="ignore"):
        attractive = b**2 / (root - a)
    return np.where(a >= 0, a + root, attractive)
