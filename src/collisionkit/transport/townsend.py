r"""Townsend ionization and attachment coefficients of steady-state Townsend (SST) conditions from bulk coefficients.

In an SST experiment electrons leave a cathode into a uniform field and the
current grows as :math:`e^{\alpha_{eff} z}`. To first order in the density
gradient (the hydrodynamic regime) the density of a swarm
:math:`n \propto e^{\alpha_{eff} z}` whose bulk drift velocity is :math:`W`,
longitudinal diffusion coefficient :math:`D_L` and effective ionization
frequency :math:`\nu_{eff} = \nu_i - \nu_a` is stationary when
:math:`\nu_{eff} = \alpha_{eff} W - \alpha_{eff}^2 D_L`, whose physical root is

.. math::

    \alpha_{eff} = \frac{W}{2 D_L}\Bigl[1 - \sqrt{1 - \frac{4 D_L \nu_{eff}}{W^2}}\Bigr]
                 = \frac{2\nu_{eff}}{W (1 + \sqrt{1 - 4 D_L \nu_{eff}/W^2})}

(Blevin & Fletcher, Aust. J. Phys. 37, 593 (1984); Robson, Aust. J. Phys. 44,
685 (1991); Dujko, White, Petrović & Robson, Phys. Rev. E 81, 046403 (2010);
the form the LoKI-MC benchmarks use). The electron flux there is
:math:`\Gamma = n(W - \alpha_{eff} D_L)`, so each reaction's events per unit
length and flux are its frequency over :math:`W - \alpha_{eff} D_L =
\tfrac{W}{2}(1 + \sqrt{\cdot})`: the ionization and attachment coefficients
split :math:`\alpha_{eff}` in proportion to the frequencies,

.. math::

    \alpha = \frac{2\nu_i}{W (1 + \sqrt{1 - 4 D_L \nu_{eff}/W^2})}, \qquad
    \eta = \frac{2\nu_a}{W (1 + \sqrt{1 - 4 D_L \nu_{eff}/W^2})},

(no division by :math:`\nu_{eff}`, which may vanish). Every quantity scales
with the gas density: with :math:`N D_L` and the rate coefficients
:math:`k = \nu/N` the formulas give :math:`\alpha/N` and :math:`\eta/N` in
m^2. Without a real root (:math:`4 D_L \nu_{eff} > W^2`) or a drift
(:math:`W \le 0` with reactions) there is no SST growth of this form: NaN.
"""

from __future__ import annotations

import numpy as np

__all__ = ["townsend_coefficients"]


def townsend_coefficients(drift_velocity, diffusion_L_N, ionization_frequency_N, attachment_frequency_N):
    r"""SST Townsend coefficients :math:`(\alpha/N, \eta/N)` (m^2) from bulk W, N D_L and k_i, k_a.

    W in m/s (along the field), N D_L in 1/(m s), the ionization and
    attachment rate coefficients k_i, k_a in m^3/s.

    See the module docstring for the formulas and their sources. Arrays
    broadcast; a gas without ionization or attachment gives (0, 0).

    Examples
    --------
    Lucas-Saelee, F = 0.5, 10 Td (LoKI-MC benchmark: W = 8.50e4 m/s, N D_L = 2.85e25 /m/s,
    nu_eff/N = 1.31e-17 m^3/s, no attachment):

    >>> from collisionkit.transport import townsend_coefficients
    >>> alpha, eta = townsend_coefficients(8.50e4, 2.85e25, 1.31e-17, 0.0)
    >>> round(float(alpha) * 1e22, 3), float(eta)
    (1.63, 0.0)
    """
    w = np.asarray(drift_velocity, dtype=float)
    d = np.asarray(diffusion_L_N, dtype=float)
    ki = np.asarray(ionization_frequency_N, dtype=float)
    ka = np.asarray(attachment_frequency_N, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = 4.0 * d * (ki - ka) / (w * w)
        root = np.sqrt(np.where(x <= 1.0, 1.0 - x, np.nan))
        root = np.where(w > 0.0, root, np.nan)
        denominator = 0.5 * w * (1.0 + root)
        alpha = ki / denominator  # both NaN where the relation has no root
        eta = ka / denominator
    none = (ki == 0.0) & (ka == 0.0)
    return np.where(none, 0.0, alpha)[()], np.where(none, 0.0, eta)[()]
