"""Exact two-body collisions of spheres and discs in 1, 2 and 3 dimensions.

The collision rule follows the pair-collision notes: the velocity change is
along the line of centres, its size fixed by conservation of momentum and by
energy (elastic) or a restitution law (inelastic). Contact times solve the
quadratic ``|r + u t| = sigma``. Everything works on whole arrays of pairs:
inputs broadcast over leading axes and the last axis is the dimension.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _arrays
from ._kernels import collisions as _k

RESTITUTION_MODELS = {"normal": _k.MODEL_NORMAL, "cm": _k.MODEL_CM}

# kernel status code -> (the argument at fault, or None, and what it must be)
_KERNEL_ERRORS = {
    _k.BAD_M1: ("m1", "must lie in (0, inf] (np.inf for a fixed body)"),
    _k.BAD_M2: ("m2", "must lie in (0, inf] (np.inf for a fixed body)"),
    _k.BOTH_MASSES_INFINITE: (None, "m1 and m2 cannot both be infinite"),
    _k.BAD_V1: ("v1", "must be finite (no NaN or inf)"),
    _k.BAD_V2: ("v2", "must be finite (no NaN or inf)"),
    _k.BAD_NORMAL: ("normal", "must be finite (no NaN or inf)"),
    _k.ZERO_NORMAL: ("normal", "must be a non-zero vector (the line of centres)"),
    _k.BAD_RESTITUTION: ("restitution", "must lie in [0, 1]"),
    _k.BAD_X1: ("x1", "must be finite (no NaN or inf)"),
    _k.BAD_X2: ("x2", "must be finite (no NaN or inf)"),
    _k.BAD_CONTACT_DISTANCE: ("contact_distance", "must be finite and >= 0"),
    _k.SEPARATION_OVERFLOW: (None, "x2 - x1 and v2 - v1 must be finite: the bodies are more than 1.8e308 apart"),
}


def _raise_on_kernel_error(status, pairs) -> None:
    """A ValueError naming the argument, its rule, the value given and (for arrays) the pair's index."""
    code, index = status
    if code == _k.OK:
        return
    name, rule = _KERNEL_ERRORS[code]
    message = rule
    if name is not None:
        given = pairs.scalars[name] if name in pairs.scalars else pairs.vectors[name]
        message = f"{name} {rule}; got {given[index].tolist()!r}"
    if pairs.leading_shape:
        message += f" (pair index {tuple(int(j) for j in np.unravel_index(index, pairs.leading_shape))})"
    raise ValueError(message)


def _model_code(restitution_model: str) -> int:
    if restitution_model not in RESTITUTION_MODELS:
        allowed = ", ".join(repr(name) for name in RESTITUTION_MODELS)
        raise ValueError(f"restitution_model must be one of {allowed}; got {restitution_model!r}")
    return RESTITUTION_MODELS[restitution_model]


def resolve_contact(m1, v1, m2, v2, normal, restitution=1.0, restitution_model="normal"):
    r"""Velocities of two bodies after they touch along ``normal``.

    Normal-restitution model (the granular-dynamics standard), with the unit
    normal :math:`\hat n` and approach speed :math:`u_n = (v_1 - v_2)\cdot\hat n`:

    .. math::
        v_1' = v_1 - (1+e)\frac{m_2}{m_1+m_2} u_n \hat n, \qquad
        v_2' = v_2 + (1+e)\frac{m_1}{m_1+m_2} u_n \hat n

    For ``e = 1`` this is the elastic rule of the pair-collision notes; the
    kinetic energy lost is :math:`\tfrac12 \mu (1-e^2) u_n^2`.
    Centre-of-mass model (Smid, "Elastic and inelastic collision in two
    dimensions", eqs. 22-27): the elastic velocities relative to the centre
    of mass are scaled by ``R``, so all of the relative velocity, tangential
    part included, shrinks by ``R`` and the loss is
    :math:`\tfrac12 \mu (1-R^2) |v_1 - v_2|^2`.

    Parameters
    ----------
    m1, m2 : array_like
        Masses, > 0; either may be ``np.inf`` (a wall or fixed target), not both.
    v1, v2 : array_like, shape (..., d)
        Velocities before contact, d = 1, 2 or 3.
    normal : array_like, shape (..., d)
        Line of centres pointing from body 1 to body 2, any non-zero length.
    restitution : array_like, optional
        Coefficient in [0, 1] per pair (1 elastic, 0 perfectly inelastic).
    restitution_model : {"normal", "cm"}
        Which law ``restitution`` belongs to (see above).

    Returns
    -------
    v1_after, v2_after : ndarray, shape (..., d)
        Only approaching pairs (:math:`u_n > 0`) change; others are copies.

    Examples
    --------
    Equal masses head-on exchange their velocities:

    >>> import collisionkit as ck
    >>> ck.resolve_contact(1.0, [1.0, 0.0], 1.0, [0.0, 0.0], normal=[1.0, 0.0])
    (array([0., 0.]), array([1., 0.]))
    """
    model = _model_code(restitution_model)
    pairs = _arrays.flatten_pairs(
        {"m1": m1, "m2": m2, "restitution": restitution},
        {"v1": v1, "v2": v2, "normal": normal},
    )
    out1 = np.empty((pairs.count, pairs.dimension))
    out2 = np.empty((pairs.count, pairs.dimension))
    s, v = pairs.scalars, pairs.vectors
    status = _k.resolve_contacts(
        s["m1"], v["v1"], s["m2"], v["v2"], v["normal"], s["restitution"], model, out1, out2
    )
    _raise_on_kernel_error(status, pairs)
    shape = pairs.leading_shape + (pairs.dimension,)
    return out1.reshape(shape), out2.reshape(shape)


def time_to_contact(x1, v1, x2, v2, contact_distance):
    r"""First time at which two bodies in straight-line motion touch.

    Solves :math:`|r + u t| = \sigma` with :math:`r = x_2 - x_1`,
    :math:`u = v_2 - v_1` (pair-collision notes, "Collision times"). The
    quadratic's discriminant is taken as :math:`|u|^2\sigma^2 - |r\times u|^2`
    and its smaller root as :math:`c/(-r\cdot u + \sqrt{D})` with
    :math:`c = |r|^2 - \sigma^2`, so no step subtracts nearly equal large
    numbers: a head-on pair 10^8 diameters apart still gets its time exactly.

    Parameters
    ----------
    x1, v1, x2, v2 : array_like, shape (..., d)
        Positions and velocities of the centres.
    contact_distance : array_like
        Centre distance at contact, sigma = r1 + r2 >= 0.

    Returns
    -------
    ndarray, shape (...)
        Time >= 0; ``np.inf`` where the pair never touches (separating, at
        rest relative to each other, or passing by). A pair already touching
        or overlapping gets 0 if approaching, inf if not. A grazing pair
        (impact parameter exactly sigma) touches once, at the tangency time.

    Examples
    --------
    >>> import collisionkit as ck
    >>> float(ck.time_to_contact([0.0, 0.0], [1.0, 0.0], [5.0, 0.0], [0.0, 0.0], 1.0))
    4.0
    """
    pairs = _arrays.flatten_pairs(
        {"contact_distance": contact_distance},
        {"x1": x1, "v1": v1, "x2": x2, "v2": v2},
    )
    out = np.empty(pairs.count)
    s, v = pairs.scalars, pairs.vectors
    status = _k.contact_times(v["x1"], v["v1"], v["x2"], v["v2"], s["contact_distance"], out)
    _raise_on_kernel_error(status, pairs)
    return out.reshape(pairs.leading_shape)


@dataclass(frozen=True, repr=False)
class Contact:
    """Outcome of :func:`collide` for each pair.

    Attributes
    ----------
    hit : ndarray of bool, shape (...)
        Whether the pair touches at some time >= 0.
    time : ndarray, shape (...)
        Time of contact; ``np.inf`` where there is no hit.
    x1, x2 : ndarray, shape (..., d)
        Positions at contact (the initial positions where there is no hit).
    v1, v2 : ndarray, shape (..., d)
        Velocities after the contact (the initial velocities where no hit).
    normal : ndarray, shape (..., d)
        Unit line of centres at contact, from 1 to 2 (NaN where no hit).

    Examples
    --------
    >>> import collisionkit as ck
    >>> contact = ck.collide(1.0, [[0.0, 0.0], [0.0, 5.0]], [1.0, 0.0], 1.0, [3.0, 0.0], [0.0, 0.0], 1.0)
    >>> contact.hit, contact.time
    (array([ True, False]), array([ 2., inf]))
    >>> contact
    Contact(pairs=2, hits=1, dimension=2)
    """

    hit: np.ndarray
    time: np.ndarray
    x1: np.ndarray
    x2: np.ndarray
    v1: np.ndarray
    v2: np.ndarray
    normal: np.ndarray

    def __repr__(self) -> str:
        hits = int(np.count_nonzero(self.hit))
        return f"Contact(pairs={self.hit.size}, hits={hits}, dimension={self.x1.shape[-1]})"

    def _repr_html_(self) -> str:
        from ._repr import contact_rows, html_table

        return html_table("Contact", contact_rows(self))


def collide(m1, x1, v1, m2, x2, v2, contact_distance, restitution=1.0, restitution_model="normal"):
    """Find when two moving bodies touch and resolve the collision there.

    Remote detection (Smid, eqs. 14-21): both centres move in straight lines
    to the contact time of :func:`time_to_contact`, then :func:`resolve_contact`
    acts along the line of centres at that moment.

    Parameters
    ----------
    m1, m2 : array_like
        Masses, > 0 (``np.inf`` for a fixed body).
    x1, v1, x2, v2 : array_like, shape (..., d)
        Positions and velocities now.
    contact_distance : array_like
        r1 + r2, >= 0.
    restitution, restitution_model
        As in :func:`resolve_contact`.

    Returns
    -------
    Contact
        ``hit``, ``time``, positions at contact ``x1``, ``x2``, velocities
        after ``v1``, ``v2`` and the unit ``normal``. Pairs that never touch
        keep their state, with time inf.

    Examples
    --------
    >>> import collisionkit as ck
    >>> c = ck.collide(1.0, [0.0], [1.0], 1.0, [3.0], [-1.0], contact_distance=1.0)
    >>> bool(c.hit), float(c.time), c.v1, c.v2
    (True, 1.0, array([-1.]), array([1.]))
    """
    time = time_to_contact(x1, v1, x2, v2, contact_distance)
    x1 = _arrays.as_vector_array(x1, "x1")
    x2 = _arrays.as_vector_array(x2, "x2")
    v1 = _arrays.as_vector_array(v1, "v1")
    v2 = _arrays.as_vector_array(v2, "v2")
    hit = np.isfinite(time)
    t = np.where(hit, time, 0.0)[..., np.newaxis]
    x1_contact = x1 + v1 * t
    x2_contact = x2 + v2 * t
    # The line of centres at contact is r + u t, computed from the relative
    # state (more accurate than differencing the two contact positions). For
    # point bodies (sigma = 0) it vanishes at contact; the head-on direction
    # of approach r then stands in for it. Non-hit pairs get any non-zero
    # normal: their result is masked below.
    initial = x2 - x1
    separation = initial + (v2 - v1) * t
    degenerate = np.linalg.norm(separation, axis=-1, keepdims=True) == 0.0
    separation = np.where(degenerate, initial, separation)
    safe_normal = np.where(hit[..., np.newaxis], separation, 1.0)
    v1_after, v2_after = resolve_contact(m1, v1, m2, v2, safe_normal, restitution, restitution_model)
    mask = hit[..., np.newaxis]
    v1_after = np.where(mask, v1_after, np.broadcast_to(v1, v1_after.shape))
    v2_after = np.where(mask, v2_after, np.broadcast_to(v2, v2_after.shape))
    length = np.linalg.norm(separation, axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        unit_normal = np.where(mask, separation / length, np.nan)
    shape = v1_after.shape
    return Contact(
        hit=hit,
        time=time,
        x1=np.broadcast_to(x1_contact, shape).copy(),
        x2=np.broadcast_to(x2_contact, shape).copy(),
        v1=v1_after,
        v2=v2_after,
        normal=unit_normal if unit_normal.shape == shape else np.broadcast_to(unit_normal, shape).copy(),
    )
