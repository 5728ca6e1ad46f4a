r"""Elements of a relative orbit, and its perifocal basis, from a state or a direction.

An orbit is held as :math:`(\mu_K, r_p, \beta, q, h)` (see
:mod:`collisionkit._kernels.encounters`) and the rows P, Q, W of its
perifocal basis: P towards periastron, Q along the velocity there, W = P x Q
along the angular momentum.
"""

from __future__ import annotations

import math

import numpy as np

from .._kernels import encounters as _k


def unit_vector(vector: np.ndarray) -> np.ndarray:
    """``vector`` divided by its length."""
    return vector / np.linalg.norm(vector)


def perpendicular_unit(vector: np.ndarray) -> np.ndarray:
    """Some unit vector perpendicular to ``vector``."""
    axis = np.zeros(3)
    axis[int(np.argmin(np.abs(vector)))] = 1.0
    return unit_vector(np.cross(vector, axis))


def perifocal_basis(r_hat, theta_hat, x_p, x_q) -> np.ndarray:
    """Rows P, Q, W of the perifocal basis, given the state's direction r_hat,
    the in-plane normal theta_hat (towards the motion) and the perifocal position."""
    length = math.hypot(x_p, x_q)
    p = (x_p * r_hat - x_q * theta_hat) / length
    q = (x_q * r_hat + x_p * theta_hat) / length
    return np.array([p, q, np.cross(p, q)])


def elements_from_state(mu_k: float, r_vec: np.ndarray, v_vec: np.ndarray):
    r"""(r_p, beta, basis, h) of the orbit through the relative state (r_vec, v_vec).

    Energy and angular momentum fix :math:`\beta = 2\mu_K/r - v^2` and
    :math:`h = |\mathbf r\times\mathbf v|`; the periastron comes from the
    Laplace-Runge-Lenz vector (attraction) or the root of the energy equation
    at periastron (repulsion), as described in
    :meth:`collisionkit.encounters.orbit.TwoBodyOrbit.from_state`.
    """
    r = float(np.linalg.norm(r_vec))
    if r == 0.0:
        raise ValueError("separation must be a non-zero vector")
    h_vec = np.cross(r_vec, v_vec)
    h = float(np.linalg.norm(h_vec))
    beta = 2.0 * mu_k / r - float(v_vec @ v_vec)
    energy = -0.5 * beta
    if mu_k > 0 and h <= 1e-15 * r * math.sqrt(2.0 * mu_k / r + float(v_vec @ v_vec)):
        raise ValueError("the state is on a radial orbit (zero angular momentum): the bodies collide head-on")
    if mu_k > 0:
        # e from the Laplace-Runge-Lenz vector (good to round-off even for a circle,
        # where sqrt(mu^2 + 2 eps h^2) = mu e would only give e to sqrt(round-off))
        e = float(np.linalg.norm(np.cross(v_vec, h_vec) / mu_k - r_vec / r))
        rp = h * h / (mu_k * (1.0 + e))
    else:
        rp = (math.sqrt(mu_k * mu_k + 2.0 * energy * h * h) - mu_k) / (2.0 * energy)
    rp = min(rp, r)
    q = max(mu_k - beta * rp, 0.0)  # as RelativeOrbit stores it, so the anomaly and the orbit agree
    sigma = float(r_vec @ v_vec)
    s = _k.anomaly_of_state(r, sigma, rp, beta, q)
    x_p, x_q = _k.perifocal_position(s, mu_k, rp, beta, q, h)
    r_hat = r_vec / r
    if h > 0.0:
        theta_hat = np.cross(h_vec / h, r_hat)
    else:
        theta_hat = perpendicular_unit(r_hat)
    return rp, beta, perifocal_basis(r_hat, theta_hat, x_p, x_q), h
