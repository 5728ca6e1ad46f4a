"""Restitution laws: the coefficient of normal restitution as a function of the impact speed.

The constant law takes the pair's coefficient. The others give the smaller
of that and their own ``e(u_n)``, ``u_n`` the speed of approach along the
line of centres:

- Bridges, Hatzes & Lin, Nature 309, 333 (1984), ice at low temperature
  (planetary rings): ``e = (u_n / u_c)^-exponent`` above ``u_c``, 1 below.
- Viscoelastic spheres (Brilliantov, Spahn, Hertzsch & Poeschel, Phys. Rev.
  E 53, 5382 (1996)): the Hertz contact with a dissipative force
  ``(3/2) A rho xi^(1/2) xi'``. ``e`` depends on the speed through one
  variable, ``q = (u_n / u_c)^(1/5)``, scaled so that ``1 - e = q + O(q^2)``:
  ``u_c = ((3/2) C1 A (rho / m_eff)^(2/5))^-5`` with Ramirez et al.'s
  ``C1 = 1.15345`` (Phys. Rev. E 60, 4465 (1999); the contact
  ``xi'' + (rho / m_eff)(xi^(3/2) + (3/2) A xi^(1/2) xi') = 0``). The contact
  ends when its force vanishes, before the surfaces separate (Schwager &
  Poeschel, Phys. Rev. E 78, 051304 (2008)).

``e(q)`` of the viscoelastic law is a Chebyshev series of ``ln e`` in
``t = ln(1 + sqrt q) / ln(1 + sqrt q_max)``, fitted at 49 Chebyshev nodes to
the contact equation solved directly (``tests/edmd/viscoelastic_contact.py``,
``chebyshev_fit(48)``; the tests check it against fresh solutions to 1e-9).
``e`` has a ``q^(5/2)`` term, hence the square root. Above ``q_max`` = 10^4
(``e`` = 3.6e-7) it follows its asymptote ``e ~ q^(-5/3)`` (within 1e-5);
below ``q`` = 10^-5 its expansion ``1 - q + (3/5) q^2`` (Ramirez et al.'s
``C2 / C1^2``; the ``q^(5/2)`` term, ``0.18 q^(5/2)``, is below 1e-8 of
``1 - e`` there), so that the loss ``1 - e`` of nearly elastic contacts keeps
its relative accuracy (the series' 1e-10 in ``e`` would be all of it).
"""

from __future__ import annotations

import math

import numpy as np

from ..._jit import borrowing_inline_kernel as inline_kernel

VISCOELASTIC_Q_MAX = 1e4
VISCOELASTIC_Q_SERIES = 1e-5  # below: e = 1 - q + (3/5) q^2
_LOG_SPAN = math.log1p(math.sqrt(VISCOELASTIC_Q_MAX))
_TAIL_EXPONENT = -5.0 / 3.0
# Chebyshev coefficients of ln e(q) on t in [0, 1] mapped to [-1, 1]
VISCOELASTIC_LOG_COEFFICIENTS = np.array((
    -6.918092268153338, -7.843351211699327, -0.29245137109547265, 0.37251450865159813, -0.22914352022982235,
    0.07640969786010222, 0.004115185122745274, -0.02380299943922835, 0.016540421189318016, -0.005532287174948472,
    -0.0007588023852959697, 0.00233278166553328, -0.0016251520846164475, 0.0005543827955426975,
    8.812979118262936e-05, -0.00026200161079978156, 0.00018912609201129042, -6.787329946787252e-05,
    -9.425788647861294e-06, 3.2417002770586005e-05, -2.444241564082682e-05, 9.247853390899166e-06,
    9.906158597042758e-07, -4.291276714642601e-06, 3.3722838284190866e-06, -1.3378906260210911e-06,
    -9.972401015526724e-08, 5.948979418563862e-07, -4.858278068227833e-07, 2.0112370617255492e-07,
    8.71889562074606e-09, -8.518554277367194e-08, 7.216690400320782e-08, -3.106193624651028e-08,
    -4.291494589637122e-10, 1.2489763606320147e-08, -1.0967144879652068e-08, 4.892965972217808e-09,
    -7.034587730826928e-11, -1.865432437204429e-09, 1.6951637892042244e-09, -7.821849656353505e-10,
    3.154985258432337e-11, 2.839217690434862e-10, -2.6489212329397934e-10, 1.2354436589555435e-10,
    -1.6008826825642572e-12, -4.973766371716485e-11, 4.0312703256794516e-11,
))


@inline_kernel
def viscoelastic_restitution(q):
    """e of viscoelastic spheres at ``q = (u_n / u_c)^(1/5)`` (see the module docstring); 1 at q = 0."""
    if q < VISCOELASTIC_Q_SERIES:
        return 1.0 - q + 0.6 * q * q
    tail = 1.0
    if q > VISCOELASTIC_Q_MAX:
        tail = (q / VISCOELASTIC_Q_MAX) ** _TAIL_EXPONENT
        q = VISCOELASTIC_Q_MAX
    x = 2.0 * math.log1p(math.sqrt(q)) / _LOG_SPAN - 1.0
    # Clenshaw's recurrence
    later = 0.0
    latest = 0.0
    for k in range(VISCOELASTIC_LOG_COEFFICIENTS.size - 1, 0, -1):
        later, latest = latest, 2.0 * x * latest - later + VISCOELASTIC_LOG_COEFFICIENTS[k]
    return math.exp(x * latest - later + VISCOELASTIC_LOG_COEFFICIENTS[0]) * tail
