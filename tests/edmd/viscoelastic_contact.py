"""The viscoelastic contact of two spheres solved directly, and the fit the kernels ship.

The contact's compression xi obeys (Brilliantov, Spahn, Hertzsch & Poeschel,
Phys. Rev. E 53, 5382 (1996))

    m_eff xi'' + rho xi^(3/2) + (3/2) A rho xi^(1/2) xi' = 0,  xi(0) = 0,  xi'(0) = v.

With xi in units of (v^2 m_eff / rho)^(2/5) and time in that over v it is

    x'' + x^(3/2) + P x^(1/2) x' = 0,  x(0) = 0,  x'(0) = 1,

one parameter P = (3/2) A (rho / m_eff)^(2/5) v^(1/5). The contact ends when
the force vanishes, x + P x' = 0 (the material does not pull: Schwager &
Poeschel, Phys. Rev. E 78, 051304 (2008)), or, in the older convention, when x
returns to 0 (Ramirez, Poeschel, Brilliantov & Schwager, Phys. Rev. E 60, 4465
(1999)); the coefficient of restitution is -x'(end).

:func:`chebyshev_fit` made ``VISCOELASTIC_LOG_COEFFICIENTS`` of
``collisionkit._kernels.edmd.restitution_laws`` (``chebyshev_fit(48)``).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.polynomial import chebyshev
from scipy.integrate import solve_ivp
from scipy.special import gamma

# 1 - e = C1 P + O(P^2) (Ramirez et al. 1999, eq. 27): the first-order loss over the elastic Hertz trajectory
C1 = math.sqrt(math.pi) * gamma(0.6) / (2**0.2 * 5**0.4 * gamma(2.1))


def restitution_of_damping(damping: float, end: str = "force") -> float:
    """e(P), P the dimensionless damping above; ``end`` "force" (force vanishes) or "zero" (x returns to 0)."""
    if damping == 0.0:
        return 1.0

    def motion(_time, state):
        root = math.sqrt(max(state[0], 0.0))
        return [state[1], -root**3 - damping * root * state[1]]

    def force_vanishes(_time, state):
        return state[0] + damping * state[1]

    def back_at_zero(time, state):
        return state[0] if time > 1e-6 else 1.0

    event = force_vanishes if end == "force" else back_at_zero
    event.terminal = True
    event.direction = -1
    solution = solve_ivp(motion, (0.0, 1e3), [0.0, 1.0], events=event, method="DOP853", rtol=1e-13, atol=1e-16)
    return -float(solution.y_events[0][0][1])


def restitution_of_q(q: float) -> float:
    """e at q = C1 P, the variable of the kernels' law (1 - e = q + O(q^2))."""
    return restitution_of_damping(q / C1)


def chebyshev_fit(degree: int, q_max: float = 1e4) -> np.ndarray:
    """Chebyshev coefficients of ln e(q) in t = ln(1 + sqrt q) / ln(1 + sqrt q_max), mapped to [-1, 1].

    e has a q^(5/2) term (the force criterion), so the series is in sqrt q.
    """
    nodes = np.cos(np.pi * (np.arange(degree + 1) + 0.5) / (degree + 1))
    t = (nodes + 1.0) / 2.0
    q = np.expm1(t * math.log1p(math.sqrt(q_max))) ** 2
    values = np.log([restitution_of_q(float(value)) for value in q])
    return chebyshev.chebfit(nodes, values, degree)
