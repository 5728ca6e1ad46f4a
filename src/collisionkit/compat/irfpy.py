r"""The collision API of ``irfpy.util.collision``, on collisionkit's core.

Same names, arguments and return conventions as irfpy's module, for users
porting code; all three also accept arrays of collisions (leading axes).

irfpy's theory (stationary target 2 at the origin, particle 1 coming along
+x at height d, contact distance r1 + r2), with
:math:`\mu = m_2/m_1`, :math:`\delta = d/\sqrt{(r_1+r_2)^2 - d^2}` and
:math:`\alpha = (\mu+1)(1+\delta^2)`:

.. math::
    V_1 = v_1(1 - 2\mu/\alpha),\; W_1 = 2 v_1 \mu\delta/\alpha,\;
    V_2 = 2 v_1/\alpha,\; W_2 = -2 v_1\delta/\alpha .

irfpy's docs leave the fourth equation (the recoil direction
:math:`W_2 = -\delta V_2`) to be checked in the centre-of-mass system; the
test suite does so (``tests/compat/test_irfpy.py``). The forms used below are
algebraically identical but use :math:`1/(1+\delta^2) = 1 - (d/\sigma)^2`,
which stays finite for a grazing hit (d = r1 + r2) and for an infinite m2.
"""

from __future__ import annotations

import re
from contextlib import contextmanager

import numpy as np

from .. import _arrays
from ..collisions import collide

__all__ = ["binary_collision", "binary_collision_stationary_vector1", "binary_collision_stationary"]

# collide's argument names and irfpy's for the same inputs
_IRFPY_NAMES = {"m1": "mass1", "m2": "mass2", "x1": "pos1", "x2": "pos2", "v1": "vel1", "v2": "vel2",
                "contact_distance": "collision_length"}
_CORE_NAME = re.compile(r"\b(" + "|".join(_IRFPY_NAMES) + r")\b")


@contextmanager
def _irfpy_names():
    """Re-raise the core's input errors with irfpy's argument names (pos1 for x1, ...)."""
    try:
        yield
    except (ValueError, TypeError) as error:
        message = _CORE_NAME.sub(lambda match: _IRFPY_NAMES[match.group(1)], str(error))
        raise type(error)(message) from None


def binary_collision(mass1, pos1, vel1, mass2, pos2, vel2, collision_length):
    """Velocities after the collision of two moving particles (irfpy API).

    The particles move in straight lines from ``pos1``, ``pos2``; if they
    come within ``collision_length`` (r1 + r2) they collide elastically at
    that moment. Particles that move apart or pass by keep their velocities.

    Returns
    -------
    vel1, vel2 : ndarray
        Velocities after the collision (unchanged where none happens).

    Examples
    --------
    >>> from collisionkit.compat.irfpy import binary_collision
    >>> binary_collision(1.0, [0, 0, 0], [1, 0, 0], 1.0, [3, 0, 0], [0, 0, 0], 1.0)
    (array([0., 0., 0.]), array([1., 0., 0.]))
    """
    with _irfpy_names():
        contact = collide(mass1, pos1, vel1, mass2, pos2, vel2, collision_length)
    return contact.v1, contact.v2


def binary_collision_stationary_vector1(mass1, pos1, vel1, mass2, collision_length):
    """Velocities after particle 1 hits particle 2 resting at the origin (irfpy API).

    If the particles separate as time goes on (negative relative velocity),
    or 1 passes by, no collision happens and the velocities are returned
    unchanged (particle 2 keeps zero velocity).

    Examples
    --------
    >>> from collisionkit.compat.irfpy import binary_collision_stationary_vector1
    >>> binary_collision_stationary_vector1(1.0, [-3.0, 0.0], [1.0, 0.0], 1.0, 1.0)
    (array([0., 0.]), array([1., 0.]))
    """
    pos1 = _arrays.as_vector_array(pos1, "pos1")
    zero = np.zeros(pos1.shape[-1])
    with _irfpy_names():
        contact = collide(mass1, pos1, vel1, mass2, zero, zero, collision_length)
    return contact.v1, contact.v2


def binary_collision_stationary(mass1, speed1, mass2, impact_parameter, collision_length):
    """(V1, W1, V2, W2) after particle 1 (speed v1 along +x, height d) hits 2 at rest.

    irfpy's closed form (module docstring). Where ``impact_parameter`` is not
    below ``collision_length`` there is no collision: (v1, 0, 0, 0).

    Parameters
    ----------
    mass1, mass2 : array_like
        Masses > 0; ``mass2`` may be ``np.inf`` (a fixed scatterer).
    speed1 : array_like
        Speed of particle 1, > 0.
    impact_parameter : array_like
        d >= 0.
    collision_length : array_like
        r1 + r2 > 0.

    Returns
    -------
    V1, W1, V2, W2 : ndarray
        x and y velocity components of particles 1 and 2 after the collision.

    Examples
    --------
    >>> from collisionkit.compat.irfpy import binary_collision_stationary
    >>> [round(float(c), 12) for c in binary_collision_stationary(1.0, 1.0, 1.0, 0.5, 1.0)]
    [0.25, 0.433012701892, 0.75, -0.433012701892]
    """
    m1 = _arrays.as_float_array(mass1, "mass1")
    m2 = _arrays.as_float_array(mass2, "mass2")
    if not np.all(np.isfinite(m1) & (m1 > 0)):
        raise ValueError("mass1 must be finite and > 0")
    _arrays.require_positive_masses(m2, "mass2")
    v1 = _arrays.as_finite_in_range(speed1, "speed1", 0.0, inclusive=(False, False))
    d = _arrays.as_finite_in_range(impact_parameter, "impact_parameter", 0.0)
    sigma = _arrays.as_finite_in_range(collision_length, "collision_length", 0.0, inclusive=(False, False))

    hit = d < sigma
    ratio = np.where(hit, d / sigma, 0.0)
    cos2 = 1.0 - ratio**2  # 1 / (1 + delta^2)
    sin_cos = ratio * np.sqrt(cos2)  # delta / (1 + delta^2)
    share1 = 1.0 / (1.0 + m1 / m2)  # mu / (mu + 1), exact 1 for m2 = inf
    share2 = 1.0 / (1.0 + m2 / m1)  # 1 / (mu + 1), exact 0 for m2 = inf
    V2 = np.where(hit, 2.0 * v1 * share2 * cos2, 0.0)
    W2 = np.where(hit, -2.0 * v1 * share2 * sin_cos, 0.0)
    V1 = np.where(hit, v1 * (1.0 - 2.0 * share1 * cos2), v1)
    W1 = np.where(hit, 2.0 * v1 * share1 * sin_cos, 0.0)
    return V1, W1, V2, W2
