r"""The relative orbit r = x2 - x1 of two bodies: a conic's shape, orientation and timing.

The separation obeys Kepler's problem :math:`\ddot{\mathbf r} = -\mu_K\,\mathbf r / r^3`,
whose solution depends on the masses only through :math:`\mu_K`. Kepler's
equation is solved in the universal anomaly with Stumpff functions, measured
from periastron (Danby, *Fundamentals of Celestial Mechanics*, sec. 6.9), see
:mod:`collisionkit._kernels.encounters`. Times are always measured from a
periastron passage: negative before it, positive after.
"""

from __future__ import annotations

import copy
import math

import numpy as np

from .. import _arrays
from .._kernels import encounters as _k
from ._elements import perifocal_basis
from ._validation import state_vector

__all__ = ["ON_ORBIT_TOLERANCE", "RelativeOrbit"]

#: Relative mismatch of energy or angular momentum up to which a state counts as lying on an orbit.
ON_ORBIT_TOLERANCE = 1e-9


class RelativeOrbit:
    r"""The conic traced by the separation of two bodies under an inverse-square force.

    Shape (periastron, eccentricity, axes), orientation (:attr:`basis`) and
    timing (the relative state at a time, the time at a separation or of a
    state, the asymptotes) of the relative motion
    :math:`\ddot{\mathbf r} = -\mu_K\,\mathbf r / r^3`. It is not built on its
    own: :class:`~collisionkit.encounters.orbit.TwoBodyOrbit` and
    :class:`~collisionkit.encounters.orbit.Hyperbolic` are the relative
    orbits of two given bodies, and add their masses, energies and states.

    The conic is held as :math:`(\mu_K, r_p, \beta, q, h)` and the perifocal
    basis, with :math:`\beta = 2\mu_K/r_p - v_p^2`, :math:`q = |\mu_K| e` and
    :math:`h = r_p v_p`.

    Examples
    --------
    >>> from collisionkit.encounters import TwoBodyOrbit
    >>> from collisionkit.encounters.relative_orbit import RelativeOrbit
    >>> circle = TwoBodyOrbit(1.0, 1.0, periastron=1.0, eccentricity=0.0)
    >>> isinstance(circle, RelativeOrbit), circle.apoastron, circle.periastron_speed  # sqrt(G M / r)
    (True, 1.0, 1.4142135623730951)
    """

    def _set_elements(self, mu_k, rp, beta, basis, h=None) -> None:
        """Store the conic; ``h`` = |r x v| when the caller knows it better than r_p (mu_K + q) does.

        For a repulsive force mu_K + q = |mu_K| (e - 1) cancels as e -> 1 (a
        near head-on encounter): there h = b v_inf or |r x v| keeps all its digits.
        """
        self._mu_k, self._rp, self._beta = mu_k, rp, beta
        self._q = max(mu_k - beta * rp, 0.0)  # |mu_K| e, >= 0 (round-off of a circular state)
        self._h = math.sqrt(max(rp * (mu_k + self._q), 0.0)) if h is None else float(h)
        self._basis = np.array(basis, dtype=float)

    def _oriented_through(self, separation: float, r_hat, theta_hat) -> RelativeOrbit:
        """A copy of this orbit turned so that its inbound point at ``separation`` lies along
        ``r_hat``, moving towards ``theta_hat`` (unit vectors, perpendicular)."""
        s = _k.anomaly_at_separation(separation, self._rp, self._beta, self._q)
        x_p, x_q = _k.perifocal_position(-s, self._mu_k, self._rp, self._beta, self._q, self._h)
        turned = copy.copy(self)
        turned._basis = perifocal_basis(r_hat, theta_hat, x_p, x_q)
        return turned

    # -- shape --------------------------------------------------------------------

    @property
    def kepler_parameter(self) -> float:
        """mu_K = G (m1 + m2) - k / mu in r'' = -mu_K r / r^3 (< 0: repulsive)."""
        return self._mu_k

    @property
    def attractive(self) -> bool:
        """Whether the net force pulls the bodies together."""
        return self._mu_k > 0

    @property
    def kind(self) -> str:
        """'elliptic', 'parabolic' or 'hyperbolic' (sign of the energy)."""
        return "elliptic" if self._beta > 0 else "parabolic" if self._beta == 0 else "hyperbolic"

    @property
    def periastron(self) -> float:
        """Distance of closest approach r_p."""
        return self._rp

    @property
    def periastron_speed(self) -> float:
        """Relative speed at periastron, v_p = sqrt(v_inf^2 + 2 mu_K / r_p) (eq. 36)."""
        return self._h / self._rp

    @property
    def apoastron(self) -> float:
        """Largest separation, r_p (1 + e) / (1 - e) (elliptic); inf otherwise."""
        return 2.0 * self._mu_k / self._beta - self._rp if self._beta > 0 else math.inf

    @property
    def eccentricity(self) -> float:
        """e = q / |mu_K| = 1 + r_p v_inf^2 / mu_K (attractive) or 1 + r_p v_p^2 / |mu_K| (repulsive)."""
        return self._q / abs(self._mu_k)

    @property
    def semi_major_axis(self) -> float:
        """a = mu_K / beta = -mu_K / v_inf^2 when unbound (inf for a parabola)."""
        return self._mu_k / self._beta if self._beta != 0 else math.inf

    @property
    def semi_latus_rectum(self) -> float:
        """p = h^2 / |mu_K|."""
        return self._h**2 / abs(self._mu_k)

    @property
    def specific_energy(self) -> float:
        """Energy of the relative motion per unit reduced mass, v^2/2 - mu_K/r = -beta/2."""
        return -0.5 * self._beta

    @property
    def specific_angular_momentum(self) -> float:
        """h = |r x v| = r_p v_p."""
        return self._h

    @property
    def basis(self) -> np.ndarray:
        """Rows P (towards periastron), Q (velocity at periastron), W = P x Q."""
        return self._basis.copy()

    @property
    def v_inf(self) -> float:
        """Relative speed at infinity sqrt(-beta); 0 for a parabola, NaN when bound."""
        if self._beta > 0:
            return math.nan
        return math.sqrt(-self._beta) if self._beta < 0 else 0.0

    @property
    def impact_parameter(self) -> float:
        """b = J_T / (mu v_inf) = sqrt(r_p^2 + 2 mu_K r_p / v_inf^2) (eq. 38); inf parabolic, NaN bound."""
        if self._beta > 0:
            return math.nan
        return self._h / self.v_inf if self._beta < 0 else math.inf

    @property
    def period(self) -> float:
        """Orbital period 2 pi sqrt(a^3 / mu_K) (elliptic); inf otherwise."""
        return 2.0 * math.pi * self._mu_k / self._beta**1.5 if self._beta > 0 else math.inf

    # -- propagation ------------------------------------------------------------

    def _perifocal(self, times: np.ndarray) -> np.ndarray:
        out = np.empty((times.size, 4))
        _k.perifocal_states(
            np.ascontiguousarray(times.ravel()), self._mu_k, self._rp, self._beta, self._q, self._h, out
        )
        return out

    def relative_state_at_time(self, t):
        r"""Separation x2 - x1 and relative velocity v2 - v1 at time t from periastron.

        Solves Kepler's equation :math:`t = r_p s + q G_3(s)` for the
        universal anomaly (safeguarded Newton from a rigorous upper bound, an
        asinh bound for large hyperbolic times) and evaluates
        :math:`\mathbf r = (r_p - \mu_K G_2)\hat P + h G_1 \hat Q`,
        :math:`\mathbf v = (-\mu_K G_1\hat P + h G_0\hat Q)/r`.

        Parameters
        ----------
        t : float or array_like
            Times from periastron (negative: before).

        Returns
        -------
        separation, relative_velocity : ndarray, shape t.shape + (3,)

        Examples
        --------
        >>> from collisionkit.encounters import Hyperbolic
        >>> r, v = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0).relative_state_at_time(0.0)
        >>> r, v  # v_p = sqrt(1 + 2 * 2 / 1)
        (array([1., 0., 0.]), array([0.        , 2.23606798, 0.        ]))
        """
        times = _arrays.as_float_array(t, "t")
        _arrays.require_finite(times, "t")
        perifocal = self._perifocal(times)
        plane = self._basis[:2]
        separation = perifocal[:, :2] @ plane
        velocity = perifocal[:, 2:] @ plane
        shape = times.shape + (3,)
        return separation.reshape(shape), velocity.reshape(shape)

    def time_at_separation(self, r, branch: str = "inbound"):
        r"""Time from periastron at which the separation equals r.

        Inverts :math:`r = r_p + q G_2(s)` in closed form (an asinh for
        hyperbolae, an asin for ellipses) and returns
        :math:`t = \pm(r_p s + q G_3(s))`: negative on the way in
        (``branch="inbound"``, the default), positive on the way out
        (``branch="outbound"``); the orbit is symmetric about periastron, so
        the two differ only in sign. For an ellipse the time is that within the
        current orbit, in [-P/2, P/2].

        Parameters
        ----------
        r : float or array_like
            Separations, r_p <= r (<= apoastron for a bound orbit).
        branch : {"inbound", "outbound"}

        Examples
        --------
        >>> from collisionkit.encounters import Hyperbolic
        >>> orbit = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0)
        >>> t_in = orbit.time_at_separation(10.0)
        >>> t_out = orbit.time_at_separation(10.0, branch="outbound")
        >>> t_in < 0 < t_out == -t_in
        True
        """
        if branch not in ("inbound", "outbound"):
            raise ValueError(f"branch must be 'inbound' or 'outbound'; got {branch!r}")
        separations = _arrays.as_float_array(r, "r")
        _arrays.require_finite(separations, "r")
        _arrays.require_in_range(separations, "r", self._rp, self.apoastron)
        flat = np.ascontiguousarray(separations.ravel())
        out = np.empty(flat.size)
        _k.times_at_separations(flat, self._rp, self._beta, self._q, out)
        sign = -1.0 if branch == "inbound" else 1.0
        result = (sign * out).reshape(separations.shape)
        return float(result) if result.ndim == 0 else result

    def time_since_periastron(self, separation, relative_velocity) -> float:
        r"""Time from periastron of a relative state lying on this orbit.

        Uses :math:`G_1(s) = \mathbf r\cdot\mathbf v / q` (and, for ellipses,
        :math:`G_0 = 1 - \beta (r - r_p)/q` to pick the half-orbit), which is
        accurate right at periastron where inverting r(t) is not. A state
        whose energy or angular momentum differs from the orbit's by more
        than ``ON_ORBIT_TOLERANCE`` (relative) is refused: it has no time on
        this orbit.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.encounters import Hyperbolic
        >>> orbit = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0)
        >>> r, v = orbit.relative_state_at_time(-3.0)
        >>> round(orbit.time_since_periastron(r, v), 12)
        -3.0
        """
        r_vec = state_vector(separation, "separation")
        v_vec = state_vector(relative_velocity, "relative_velocity")
        r = float(np.linalg.norm(r_vec))
        self._require_on_orbit(r_vec, v_vec, r)
        s = _k.anomaly_of_state(max(r, self._rp), float(r_vec @ v_vec), self._rp, self._beta, self._q)
        return math.copysign(_k.time_of_anomaly(abs(s), self._rp, self._beta, self._q), s)

    def _require_on_orbit(self, r_vec, v_vec, r) -> None:
        """ValueError unless the state has this orbit's energy and angular momentum (to ON_ORBIT_TOLERANCE)."""
        if r == 0.0:
            raise ValueError("separation must be a non-zero vector")
        v2 = float(v_vec @ v_vec)
        energy_off = abs(0.5 * v2 - self._mu_k / r + 0.5 * self._beta) / (0.5 * v2 + abs(self._mu_k) / r)
        h = float(np.linalg.norm(np.cross(r_vec, v_vec)))
        momentum_off = abs(h - self._h) / max(r * math.sqrt(v2), self._h, 1e-300)
        if energy_off > ON_ORBIT_TOLERANCE or momentum_off > ON_ORBIT_TOLERANCE or r < self._rp * (1 - ON_ORBIT_TOLERANCE):
            raise ValueError(
                f"the state is not on this orbit: energy off by {energy_off:.2g}, angular momentum by "
                f"{momentum_off:.2g} (relative), separation {r:.6g} against periastron {self._rp:.6g}"
            )

    # -- asymptotes -------------------------------------------------------------

    def _require_unbound(self, what: str) -> None:
        """ValueError naming ``what`` unless the orbit is hyperbolic."""
        if self._beta >= 0:
            raise ValueError(f"{what} needs a hyperbolic orbit (v_inf > 0); this one is {self.kind}")

    def asymptotes(self):
        r"""Directions of the incoming and outgoing relative velocity, and the centre of the hyperbola.

        With :math:`w = v_\infty` the velocity far away is
        :math:`(\mu_K \hat P \pm h w \hat Q)/q` (in: +; out: the mirror
        :math:`(-\mu_K, h w)/q`); both asymptotes pass through the centre
        :math:`(r_p + \mu_K/v_\infty^2)\hat P` (for gravity: :math:`a e` from
        the focus, towards periastron). The angle between the two directions is
        the deflection angle (:attr:`~collisionkit.encounters.orbit.TwoBodyOrbit.deflection_angle`).

        Returns
        -------
        incoming, outgoing : ndarray, shape (3,)
            Unit vectors of the relative velocity before and after.
        centre : ndarray, shape (3,)
            Where the two asymptotes of the separation cross.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.encounters import Hyperbolic
        >>> orbit = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0)
        >>> v_in, v_out, centre = orbit.asymptotes()
        >>> bool(np.isclose(np.arccos(v_in @ v_out), orbit.deflection_angle))
        True
        """
        self._require_unbound("asymptotes")
        w = self.v_inf
        p_hat, q_hat = self._basis[0], self._basis[1]
        incoming = (self._mu_k * p_hat + self._h * w * q_hat) / self._q
        outgoing = (-self._mu_k * p_hat + self._h * w * q_hat) / self._q
        centre = (self._rp + self._mu_k / w**2) * p_hat
        return incoming, outgoing, centre
