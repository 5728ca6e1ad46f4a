"""Contact geometry and reference frames of a two-body collision.

Impact parameter, Smid's impact angle (2D) and the two impact angles of the
3D case, centre-of-mass frame conversions, scattering angles in the centre
of mass and the laboratory, energy transfer, and random impacts for an
unknown geometry. Sources: R. Smid, "Elastic and inelastic collision in two
dimensions" (impact angle, eqs. 7-9, 14-16); Landau & Lifshitz, Mechanics,
sections 16-17 (frames, lab angles, energy transfer).
"""

from __future__ import annotations

import numpy as np

from . import _arrays
from .collisions import resolve_contact

__all__ = [
    "reduced_mass",
    "centre_of_mass_velocity",
    "to_centre_of_mass_frame",
    "from_centre_of_mass_frame",
    "kinetic_energy",
    "impact_parameter",
    "impact_angle_2d",
    "impact_angles_3d",
    "normal_from_impact_angles",
    "resolve_impact_angles",
    "scattering_angle_cm",
    "impact_angle_from_scattering_angle",
    "scattering_angle_from_impact_angle",
    "lab_scattering_angle",
    "recoil_angle",
    "energy_transfer_fraction",
    "sample_impact",
]


def _masses(m, name):
    array = _arrays.as_float_array(m, name)
    _arrays.require_positive_masses(array, name)
    return array


def _finite_vectors(**named):
    """The named arguments as finite float vector arrays that broadcast together; errors name them."""
    arrays = {}
    for name, value in named.items():
        arrays[name] = _arrays.as_vector_array(value, name)
        _arrays.require_finite(arrays[name], name)
    try:
        np.broadcast_shapes(*(array.shape for array in arrays.values()))
    except ValueError:
        shapes = ", ".join(f"{name} {array.shape}" for name, array in arrays.items())
        raise ValueError(f"{', '.join(arrays)} must broadcast together (one dimension); got shapes {shapes}") from None
    return tuple(arrays.values())


def reduced_mass(m1, m2):
    """Reduced mass ``m1 m2 / (m1 + m2)``; an infinite mass gives the other.

    Examples
    --------
    >>> from collisionkit.kinematics import reduced_mass
    >>> float(reduced_mass(2.0, 2.0)), float(reduced_mass(3.0, float("inf")))
    (1.0, 3.0)
    """
    m1, m2 = _masses(m1, "m1"), _masses(m2, "m2")
    with np.errstate(invalid="ignore"):
        return np.where(np.isinf(m1), m2, np.where(np.isinf(m2), m1, m1 * m2 / (m1 + m2)))


def centre_of_mass_velocity(m1, v1, m2, v2):
    """Velocity of the centre of mass ``(m1 v1 + m2 v2) / (m1 + m2)`` (Smid eqs. 22-23).

    Evaluated as ``v_heavy + m_light / (m1 + m2) (v_light - v_heavy)``: the
    share of the lighter body is at most 1/2, so nothing cancels, also for a
    light projectile on a heavy target at rest (an electron on argon), where
    ``v1 + m2 / (m1 + m2) (v2 - v1)`` would lose digits to ``m2 / (m1 + m2)``
    rounding near 1. An infinite mass carries the centre of mass with it.

    Examples
    --------
    >>> from collisionkit.kinematics import centre_of_mass_velocity
    >>> centre_of_mass_velocity(1.0, [2.0, 0.0], 3.0, [-2.0, 0.0])
    array([-1.,  0.])
    """
    m1, m2 = _masses(m1, "m1")[..., None], _masses(m2, "m2")[..., None]
    if np.any(np.isinf(m1) & np.isinf(m2)):
        raise ValueError("m1 and m2 cannot both be infinite")
    v1, v2 = _finite_vectors(v1=v1, v2=v2)
    first_heavier = m1 >= m2
    heavy_v, light_v = np.where(first_heavier, v1, v2), np.where(first_heavier, v2, v1)
    light_share = np.where(first_heavier, m2, m1) / (m1 + m2)  # 0 when the other mass is infinite
    return heavy_v + light_share * (light_v - heavy_v)


def to_centre_of_mass_frame(m1, v1, m2, v2):
    """Split lab velocities into the centre-of-mass velocity and CM-frame velocities.

    Returns
    -------
    v_cm, w1, w2 : ndarray
        ``w_i = v_i - v_cm``; for finite masses ``m1 w1 + m2 w2 = 0``.

    Examples
    --------
    >>> from collisionkit.kinematics import to_centre_of_mass_frame
    >>> to_centre_of_mass_frame(1.0, [2.0], 1.0, [0.0])
    (array([1.]), array([1.]), array([-1.]))
    """
    v_cm = centre_of_mass_velocity(m1, v1, m2, v2)
    return v_cm, np.asarray(v1, float) - v_cm, np.asarray(v2, float) - v_cm


def from_centre_of_mass_frame(v_cm, w1, w2):
    """Lab velocities ``(w1 + v_cm, w2 + v_cm)`` from CM-frame velocities.

    Examples
    --------
    >>> from collisionkit.kinematics import from_centre_of_mass_frame
    >>> from_centre_of_mass_frame([1.0], [1.0], [-1.0])
    (array([2.]), array([0.]))
    """
    v_cm, w1, w2 = _finite_vectors(v_cm=v_cm, w1=w1, w2=w2)
    return w1 + v_cm, w2 + v_cm


def kinetic_energy(m, v):
    """Kinetic energy ``m |v|^2 / 2`` over the last axis.

    Examples
    --------
    >>> from collisionkit.kinematics import kinetic_energy
    >>> float(kinetic_energy(2.0, [3.0, 4.0]))
    25.0
    """
    m = _arrays.as_float_array(m, "m")
    _arrays.require_finite(m, "m")
    _arrays.require_in_range(m, "m", 0.0, np.inf, inclusive=(True, False))
    (v,) = _finite_vectors(v=v)
    return 0.5 * m * np.einsum("...i,...i->...", v, v)


def _relative_state(x1, v1, x2, v2):
    x1, v1, x2, v2 = _finite_vectors(x1=x1, v1=v1, x2=x2, v2=v2)
    return x2 - x1, v1 - v2


def _cross_norm2(a, b):
    """|a x b|^2 in any dimension 1-3, as sum over i<j of (a_i b_j - a_j b_i)^2."""
    d = a.shape[-1]
    total = np.zeros(np.broadcast_shapes(a.shape, b.shape)[:-1])
    for i in range(d):
        for j in range(i + 1, d):
            total = total + (a[..., i] * b[..., j] - a[..., j] * b[..., i]) ** 2
    return total


def impact_parameter(x1, v1, x2, v2):
    r"""Impact parameter: the distance of the relative velocity's line from the other centre.

    :math:`b = |r \times u| / |u|` with :math:`r = x_2 - x_1`,
    :math:`u = v_1 - v_2`; a pair at relative rest keeps :math:`b = |r|`.
    For an approaching pair (:math:`r \cdot u > 0`) it is the distance of
    closest approach in straight-line motion; a receding pair has passed its
    closest approach, and b is that of the whole straight line.

    Examples
    --------
    >>> from collisionkit.kinematics import impact_parameter
    >>> float(impact_parameter([0.0, 0.5], [1.0, 0.0], [3.0, 0.0], [0.0, 0.0]))
    0.5
    """
    r, u = _relative_state(x1, v1, x2, v2)
    uu = np.einsum("...i,...i->...", u, u)
    rr = np.einsum("...i,...i->...", r, r)
    with np.errstate(invalid="ignore", divide="ignore"):
        b = np.sqrt(_cross_norm2(r, u) / uu)
    return np.where(uu > 0, b, np.sqrt(rr))


def impact_angle_2d(x1, v1, x2, v2, contact_distance):
    r"""Smid's impact angle alpha of a 2D collision (eqs. 14-16), in radians.

    .. math:: \alpha = \arcsin\left[d \sin(\gamma_{xy} - \gamma_v)/(r_1 + r_2)\right]

    with :math:`\gamma_{xy}` the angle of :math:`x_2 - x_1` and
    :math:`\gamma_v` that of :math:`v_1 - v_2`. alpha lies in
    [-pi/2, pi/2] (0 head-on, +-pi/2 grazing) and the line of centres at
    contact points along :math:`\gamma_v + \alpha`. Pairs that will not
    collide (moving apart, or missing) get NaN. A pair that already
    overlaps (:math:`d < r_1 + r_2`) and approaches collides now, along its
    present line of centres (as :func:`collisionkit.collide` resolves it):
    alpha is then the angle of :math:`x_2 - x_1` from :math:`\gamma_v`
    (d in place of :math:`r_1 + r_2` above; the two agree at touching).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.kinematics import impact_angle_2d
    >>> round(float(np.degrees(impact_angle_2d([0, 0], [1, 0], [5, -0.5], [0, 0], 1.0))), 6)
    -30.0
    """
    r, u = _relative_state(x1, v1, x2, v2)
    if r.shape[-1] != 2:
        raise ValueError(f"impact_angle_2d needs 2D vectors; got dimension {r.shape[-1]}")
    sigma = _arrays.as_float_array(contact_distance, "contact_distance")
    _arrays.require_finite(sigma, "contact_distance")
    _arrays.require_in_range(sigma, "contact_distance", 0.0, np.inf, inclusive=(False, False))
    speed = np.hypot(u[..., 0], u[..., 1])
    # d sin(gamma_xy - gamma_v) is the signed offset (u_hat x r), no angles needed
    with np.errstate(invalid="ignore", divide="ignore"):
        offset = (u[..., 0] * r[..., 1] - u[..., 1] * r[..., 0]) / speed
        approaching = np.einsum("...i,...i->...", r, u) > 0
        ratio = offset / np.minimum(sigma, np.hypot(r[..., 0], r[..., 1]))  # |r| < sigma: overlapping, contact now
        return np.where(approaching & (np.abs(ratio) <= 1), np.arcsin(np.clip(ratio, -1, 1)), np.nan)


def _perpendicular_basis(unit):
    """Two unit vectors completing ``unit`` (shape (..., 3)) to a right-handed basis.

    The first is built from the coordinate axis least aligned with ``unit``,
    so the basis is well conditioned for every direction.
    """
    axis_index = np.argmin(np.abs(unit), axis=-1)
    axis = np.zeros_like(unit)
    np.put_along_axis(axis, axis_index[..., None], 1.0, axis=-1)
    e1 = axis - np.einsum("...i,...i->...", axis, unit)[..., None] * unit
    e1 /= np.linalg.norm(e1, axis=-1, keepdims=True)
    e2 = np.cross(unit, e1)
    return e1, e2


def impact_angles_3d(x1, v1, x2, v2, contact_distance):
    """The two impact angles of a 3D collision: polar alpha and azimuth phi.

    alpha in [0, pi/2] is the angle between the relative velocity
    ``v1 - v2`` and the line of centres at contact (0 head-on, pi/2 grazing),
    the 3D form of Smid's impact angle; phi in (-pi, pi] is the azimuth of
    the line of centres about the relative velocity, measured in the basis of
    :func:`normal_from_impact_angles`. Pairs that will not collide get NaN.
    A pair that already overlaps and approaches collides now, along its
    present line of centres (as :func:`collisionkit.collide` resolves it).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.kinematics import impact_angles_3d
    >>> alpha, phi = impact_angles_3d([0, 0, 0], [1, 0, 0], [5, 0, 0.5], [0, 0, 0], 1.0)
    >>> round(float(np.degrees(alpha)), 6)
    30.0
    """
    r, u = _relative_state(x1, v1, x2, v2)
    if r.shape[-1] != 3:
        raise ValueError(f"impact_angles_3d needs 3D vectors; got dimension {r.shape[-1]}")
    sigma = _arrays.as_float_array(contact_distance, "contact_distance")
    _arrays.require_finite(sigma, "contact_distance")
    _arrays.require_in_range(sigma, "contact_distance", 0.0, np.inf, inclusive=(False, False))
    speed = np.linalg.norm(u, axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        unit = u / speed
        e1, e2 = _perpendicular_basis(np.where(speed > 0, unit, [1.0, 0.0, 0.0]))
        # Position of 2 relative to 1 projected on the collision plane: offset vector
        along = np.einsum("...i,...i->...", r, unit)
        offset = r - along[..., None] * unit
        b = np.linalg.norm(offset, axis=-1)
        hits = (along > 0) & (b <= sigma) & (speed[..., 0] > 0)
        # an overlapping pair (|r| < sigma) collides now: its present line of centres, sin(alpha) = b / |r|
        alpha = np.arcsin(np.clip(b / np.minimum(sigma, np.linalg.norm(r, axis=-1)), 0.0, 1.0))
        phi = np.arctan2(np.einsum("...i,...i->...", offset, e2), np.einsum("...i,...i->...", offset, e1))
    return np.where(hits, alpha, np.nan), np.where(hits, phi, np.nan)


def normal_from_impact_angles(relative_velocity, alpha, phi=None):
    r"""Unit line of centres at contact from the impact angle(s).

    2D: the relative velocity ``v1 - v2`` rotated by the signed angle alpha
    (Smid: :math:`\theta = \gamma_v + \alpha`). 3D:
    :math:`\hat n = \cos\alpha\,\hat u + \sin\alpha(\cos\phi\,e_1 + \sin\phi\,e_2)`
    with :math:`(e_1, e_2, \hat u)` right-handed and :math:`e_1` built from the
    coordinate axis least aligned with :math:`\hat u`. 1D: :math:`\hat u`.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.kinematics import normal_from_impact_angles
    >>> np.round(normal_from_impact_angles([2.0, 0.0], np.pi / 2), 12)
    array([0., 1.])
    """
    u = _arrays.as_vector_array(relative_velocity, "relative_velocity")
    _arrays.require_finite(u, "relative_velocity")
    speed = np.linalg.norm(u, axis=-1, keepdims=True)
    if np.any(speed == 0):
        raise ValueError("relative_velocity must be non-zero: the impact angles are measured from it")
    unit = u / speed
    alpha = _arrays.as_float_array(alpha, "alpha")
    _arrays.require_finite(alpha, "alpha")
    d = u.shape[-1]
    if d == 1:
        return np.broadcast_to(unit, np.broadcast_shapes(unit.shape, alpha.shape + (1,))).copy()
    if d == 2:
        _arrays.require_in_range(alpha, "alpha", -np.pi / 2, np.pi / 2)
        c, s = np.cos(alpha), np.sin(alpha)
        return np.stack([c * unit[..., 0] - s * unit[..., 1], s * unit[..., 0] + c * unit[..., 1]], axis=-1)
    _arrays.require_in_range(alpha, "alpha", 0.0, np.pi / 2)
    phi = _arrays.as_float_array(0.0 if phi is None else phi, "phi")
    _arrays.require_finite(phi, "phi")
    e1, e2 = _perpendicular_basis(unit)
    alpha, phi = alpha[..., None], phi[..., None]
    return np.cos(alpha) * unit + np.sin(alpha) * (np.cos(phi) * e1 + np.sin(phi) * e2)


def resolve_impact_angles(m1, v1, m2, v2, alpha, phi=None, restitution=1.0, restitution_model="normal"):
    """Resolve a collision given by its impact angle(s) instead of positions.

    For an unknown geometry (Smid: "treat alpha as a free parameter"), e.g.
    with angles from :func:`sample_impact`. Equivalent to
    :func:`~collisionkit.resolve_contact` with the normal of
    :func:`normal_from_impact_angles`.

    Examples
    --------
    >>> from collisionkit.kinematics import resolve_impact_angles
    >>> resolve_impact_angles(1.0, [1.0, 0.0], 1.0, [0.0, 0.0], alpha=0.0)
    (array([0., 0.]), array([1., 0.]))
    """
    v1, v2 = _finite_vectors(v1=v1, v2=v2)  # named here: the angles are measured from v1 - v2
    if np.any(np.all(v1 == v2, axis=-1)):
        raise ValueError("v1 and v2 must differ: the impact angles are measured from the relative velocity v1 - v2")
    normal = normal_from_impact_angles(v1 - v2, alpha, phi)
    return resolve_contact(m1, v1, m2, v2, normal, restitution, restitution_model)


def _angle_between(a, b):
    """Angle between vectors on the last axis, accurate near 0 and pi (atan2 form)."""
    dot = np.einsum("...i,...i->...", a, b)
    return np.arctan2(np.sqrt(_cross_norm2(a, b)), dot)


def scattering_angle_cm(v1, v2, v1_after, v2_after):
    """Centre-of-mass scattering angle chi: the turn of the relative velocity.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.kinematics import scattering_angle_cm
    >>> float(np.degrees(scattering_angle_cm([1.0, 0.0], [0.0, 0.0], [0.0, 0.0], [1.0, 0.0])))
    180.0
    """
    v1, v2, v1_after, v2_after = _finite_vectors(v1=v1, v2=v2, v1_after=v1_after, v2_after=v2_after)
    return _angle_between(v1 - v2, v1_after - v2_after)


def impact_angle_from_scattering_angle(chi):
    """Smid's impact angle from the CM scattering angle: alpha = (pi - chi) / 2 (elastic).

    Examples
    --------
    >>> from collisionkit.kinematics import impact_angle_from_scattering_angle
    >>> float(impact_angle_from_scattering_angle(3.141592653589793))
    0.0
    """
    chi = _arrays.as_float_array(chi, "chi")
    _arrays.require_in_range(chi, "chi", 0.0, np.pi)
    return 0.5 * (np.pi - chi)


def scattering_angle_from_impact_angle(alpha):
    """CM scattering angle of an elastic collision: chi = pi - 2 |alpha|.

    Examples
    --------
    >>> from collisionkit.kinematics import scattering_angle_from_impact_angle
    >>> float(scattering_angle_from_impact_angle(0.0))
    3.141592653589793
    """
    alpha = _arrays.as_float_array(alpha, "alpha")
    _arrays.require_in_range(alpha, "alpha", -np.pi / 2, np.pi / 2)
    return np.pi - 2.0 * np.abs(alpha)


def _mass_ratio(m1, m2):
    m1, m2 = _masses(m1, "m1"), _masses(m2, "m2")
    if np.any(np.isinf(m1)):
        raise ValueError("m1 must be finite: the projectile cannot be a fixed body")
    return m1 / m2


def lab_scattering_angle(chi, m1, m2):
    r"""Lab deflection of the projectile off a target at rest (elastic).

    :math:`\tan\theta_1 = \sin\chi / (\cos\chi + m_1/m_2)` (Landau &
    Lifshitz, eq. 16.5), evaluated with atan2 so every mass ratio works.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.kinematics import lab_scattering_angle
    >>> float(np.degrees(lab_scattering_angle(np.pi / 2, 1.0, 1.0)))
    45.0
    """
    chi = _arrays.as_float_array(chi, "chi")
    _arrays.require_in_range(chi, "chi", 0.0, np.pi)
    ratio = _mass_ratio(m1, m2)
    return np.arctan2(np.sin(chi), np.cos(chi) + ratio)


def recoil_angle(chi):
    """Lab angle of the recoiling target (at rest before, elastic): (pi - chi) / 2.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.kinematics import recoil_angle
    >>> float(np.degrees(recoil_angle(np.pi / 2)))
    45.0
    """
    chi = _arrays.as_float_array(chi, "chi")
    _arrays.require_in_range(chi, "chi", 0.0, np.pi)
    return 0.5 * (np.pi - chi)


def energy_transfer_fraction(chi, m1, m2):
    r"""Fraction of the projectile's energy given to a target at rest (elastic).

    :math:`\Delta E / E = \frac{4 m_1 m_2}{(m_1+m_2)^2}\sin^2(\chi/2)`
    (Landau & Lifshitz, eq. 17.6); an infinite target takes nothing.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.kinematics import energy_transfer_fraction
    >>> float(energy_transfer_fraction(np.pi, 1.0, 1.0))
    1.0
    """
    chi = _arrays.as_float_array(chi, "chi")
    _arrays.require_in_range(chi, "chi", 0.0, np.pi)
    ratio = _mass_ratio(m1, m2)
    return 4.0 * ratio / (1.0 + ratio) ** 2 * np.sin(0.5 * chi) ** 2


def sample_impact(relative_velocity, contact_distance, size=None, seed=None):
    """Random impacts for an unknown geometry, uniform over the collision disc.

    A straight-line approach hits the target's disc of radius sigma = r1 + r2
    (3D) or its segment [-sigma, sigma] (2D) at a uniformly distributed point,
    so the impact parameter has density 2 b / sigma^2 (3D) or is uniform in
    |b| (2D). Returns the unit line of centres at contact, which feeds
    :func:`~collisionkit.resolve_contact` directly.

    Parameters
    ----------
    relative_velocity : array_like, shape (..., d)
        ``v1 - v2``, non-zero.
    contact_distance : float
        sigma > 0.
    size : int or tuple, optional
        Leading shape of the sample; default: the leading shape of
        ``relative_velocity``.
    seed : int, numpy.random.Generator or None, optional
        Seed or generator of the random numbers.

    Returns
    -------
    normal : ndarray, shape (..., d)
        Unit line of centres at contact, from body 1 to body 2.
    impact_parameter : ndarray, shape (...)
        b = sigma sin(alpha) >= 0.

    Examples
    --------
    >>> from collisionkit.kinematics import sample_impact
    >>> normal, b = sample_impact([1.0, 0.0, 0.0], 1.0, size=1000, seed=1)
    >>> normal.shape, bool((b <= 1).all())
    ((1000, 3), True)
    """
    u = _arrays.as_vector_array(relative_velocity, "relative_velocity")
    sigma = _arrays.as_float_array(contact_distance, "contact_distance")
    _arrays.require_finite(sigma, "contact_distance")
    _arrays.require_in_range(sigma, "contact_distance", 0.0, np.inf, inclusive=(False, False))
    generator = np.random.default_rng(seed)
    shape = u.shape[:-1] if size is None else tuple(np.atleast_1d(size))
    u = np.broadcast_to(u, shape + u.shape[-1:])
    d = u.shape[-1]
    if d == 1:
        return normal_from_impact_angles(u, np.zeros(shape)), np.zeros(shape)
    if d == 2:
        signed = generator.uniform(-1.0, 1.0, shape)
        return normal_from_impact_angles(u, np.arcsin(signed)), sigma * np.abs(signed)
    radius_fraction = np.sqrt(generator.uniform(0.0, 1.0, shape))
    phi = generator.uniform(-np.pi, np.pi, shape)
    return normal_from_impact_angles(u, np.arcsin(radius_fraction), phi), sigma * radius_fraction
