r"""Kinetic theory of rough inelastic spheres and discs: translational and rotational temperatures through collisions.

Rough spheres (:class:`~collisionkit.edmd.HardSphereSystem` with a
tangential restitution beta) trade energy between translation and rotation
at every contact. With molecular chaos and Maxwell distributions of the
velocities (temperature T) and angular velocities (T_r), a pair collision
changes on average (mass 1 per particle, :math:`\eta = \kappa (1 + \beta) /
(2 (1 + \kappa))`, :math:`\kappa = I / (m a^2)`)

.. math::

    \langle \Delta E_{tr} \rangle &= -(1 - e^2) T
        - 2 (d - 1) [\eta (1 - \eta) T - (\eta^2 / \kappa) T_r], \\
    \langle \Delta E_{rot} \rangle &= 2 (d - 1) [(\eta^2 / \kappa) T
        - (\eta / \kappa) (1 - \eta / \kappa) T_r],

because a collision comes with :math:`\langle u_n^2 \rangle = 4 T / m`
(weighted by the approach speed) and :math:`\langle g_t^2 \rangle = 2 (d -
1) (T + T_r / \kappa)` for the tangential velocity of the touching surfaces.
With d translational and f rotational degrees of freedom per particle (f =
3 for spheres, 1 for discs) and c collisions per particle (two particles per
collision), :math:`dT/dc = \langle \Delta E_{tr} \rangle / d` and
:math:`dT_r/dc = \langle \Delta E_{rot} \rangle / f`: linear in (T, T_r),
so the temperatures through the collisions are a matrix exponential. In 3D
this is Huthmann & Zippelius, Phys. Rev. E 56, R6275 (1997) and Luding,
Huthmann, McNamara & Zippelius, Phys. Rev. E 58, 3416 (1998), eq. (7):
:math:`dT/dc \propto -A T + B T_r`, :math:`dT_r/dc \propto B T - C T_r` with
:math:`A = (1 - e^2)/4 + \eta (1 - \eta)`, :math:`B = \eta^2 / \kappa`,
:math:`C = (\eta / \kappa)(1 - \eta / \kappa)`.
Counting collisions, not time, takes the collision frequency (the density,
g(sigma) and :math:`\sqrt T`) out: the law holds at any density as long as
the gas stays homogeneous and the distributions Maxwellian (the cumulant
corrections of rough spheres are of a few per cent: Santos, Kremer & Garzo,
Prog. Theor. Phys. Suppl. 184, 31 (2010)).
"""

from __future__ import annotations

import numpy as np

from . import _checks
from ._rotation import UNIFORM_INERTIA, rotational_degrees

__all__ = ["rough_cooling", "rough_cooling_matrix", "rough_cooling_state"]


def _inputs(restitution, tangential_restitution, inertia_factor, dim):
    dim = _checks.dimension(dim)
    e = _checks.bounded(restitution, "restitution", 0.0, 1.0, closed=(True, True))
    beta = _checks.bounded(tangential_restitution, "tangential_restitution", -1.0, 1.0, closed=(True, True))
    kappa = UNIFORM_INERTIA[dim] if inertia_factor is None else _checks.bounded(
        inertia_factor, "inertia_factor", 0.0, 1.0, closed=(False, True))
    return e, beta, kappa, dim


def rough_cooling_matrix(restitution, tangential_restitution, inertia_factor=None, dim=3):
    r"""The matrix M of :math:`d(T, T_r)/dc = M (T, T_r)`, c the collisions per particle (module docstring).

    Parameters
    ----------
    restitution : float
        Normal restitution e in [0, 1].
    tangential_restitution : float
        beta in [-1, 1].
    inertia_factor : float, optional
        kappa = I / (m a^2) in (0, 1]; default 2/5 (spheres) or 1/2 (discs).
    dim : {2, 3}

    Returns
    -------
    numpy.ndarray, shape (2, 2)

    Examples
    --------
    >>> from collisionkit.edmd import rough_cooling_matrix
    >>> rough_cooling_matrix(0.9, -1.0)  # smooth spheres: Haff's (1 - e^2)/d, no rotation change
    array([[-0.06333333,  0.        ],
           [ 0.        ,  0.        ]])
    >>> rough_cooling_matrix(1.0, 1.0).sum(axis=1) * [3, 3]  # perfectly rough, elastic: equipartition is kept
    array([0., 0.])
    """
    e, beta, kappa, dim = _inputs(restitution, tangential_restitution, inertia_factor, dim)
    eta = kappa * (1.0 + beta) / (2.0 * (1.0 + kappa))
    tangential = 2.0 * (dim - 1)
    translation = [-(1.0 - e * e) - tangential * eta * (1.0 - eta), tangential * eta * eta / kappa]
    rotation = [tangential * eta * eta / kappa, -tangential * (eta / kappa) * (1.0 - eta / kappa)]
    # (+ 0.0: no negative zeros where a term vanishes)
    return np.array([np.array(translation) / dim, np.array(rotation) / rotational_degrees(dim)]) + 0.0


def rough_cooling(kT, kT_rotation, collisions_per_particle, restitution, tangential_restitution, inertia_factor=None,
                  dim=3):
    r"""Translational and rotational kT after c collisions per particle: :math:`\exp(M c) (T_0, T_{r,0})`.

    Parameters
    ----------
    kT, kT_rotation : float
        Temperatures at c = 0, >= 0.
    collisions_per_particle : array_like
        c >= 0 (2 x pair collisions / N).
    restitution, tangential_restitution, inertia_factor, dim
        As :func:`rough_cooling_matrix`.

    Returns
    -------
    tuple of numpy.ndarray
        T(c) and T_r(c), each of the shape of ``collisions_per_particle``.

    Examples
    --------
    >>> from collisionkit.edmd import rough_cooling
    >>> T, Tr = rough_cooling(1.0, 0.0, [0.0, 50.0], 1.0, 1.0)  # elastic, perfectly rough: towards equipartition
    >>> [round(float(x), 6) for x in T], [round(float(x), 6) for x in Tr]
    ([1.0, 0.5], [0.0, 0.5])
    """
    start = np.array([_checks.bounded(kT, "kT", 0.0), _checks.bounded(kT_rotation, "kT_rotation", 0.0)])
    counts = _checks.bounded(collisions_per_particle, "collisions_per_particle", 0.0, scalar=False)
    rates, vectors = np.linalg.eig(rough_cooling_matrix(restitution, tangential_restitution, inertia_factor, dim))
    # M is real with real eigenvalues (its off-diagonal entries share a sign), so the decomposition stays real
    weights = np.linalg.solve(vectors.real, start)
    modes = np.exp(np.multiply.outer(counts, rates.real)) * weights
    temperatures = modes @ vectors.real.T
    return temperatures[..., 0], temperatures[..., 1]


def rough_cooling_state(restitution, tangential_restitution, inertia_factor=None, dim=3):
    r"""The homogeneous cooling state: T_r / T and the cooling rate per collision per particle it settles to.

    The slower mode of :func:`rough_cooling_matrix`: its eigenvector gives
    the ratio R = T_r / T that any start reaches, its eigenvalue
    :math:`-\gamma` the rate :math:`-d \ln T / dc = \gamma` (Luding et al.
    1998, eq. (9), for the ratio in 3D).

    Returns
    -------
    tuple of float
        (R, gamma). R is NaN for smooth spheres (beta = -1), whose rotation
        is decoupled.

    Examples
    --------
    >>> from collisionkit.edmd import rough_cooling_state
    >>> ratio, rate = rough_cooling_state(1.0, 1.0)  # elastic, perfectly rough: equipartition, no cooling
    >>> round(ratio, 12), abs(rate) < 1e-15
    (1.0, True)
    """
    matrix = rough_cooling_matrix(restitution, tangential_restitution, inertia_factor, dim)
    if matrix[0, 1] == 0.0:
        return float("nan"), float(-matrix[0, 0])
    rates, vectors = np.linalg.eig(matrix)
    slow = int(np.argmax(rates.real))
    vector = vectors[:, slow].real
    return float(vector[1] / vector[0]), float(-rates[slow].real) + 0.0
