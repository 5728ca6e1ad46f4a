"""Where a swarm's transient ends: the MSER truncation rule on its sampled series.

A swarm starts far from its steady state (all particles at the origin,
Maxwellian at a guessed energy) and relaxes, sometimes slowly (elastic energy
loss in a heavy gas takes ~M/(2m) collisions). Averages must leave the
transient out, and a run must not stop measuring before it has ended.

The marginal standard error rule (MSER; White, Simulation 69, 323 (1997);
Franklin & White, Proc. Winter Simulation Conf. 2008; "MSER-5" with batches of
five samples) truncates a series x_0 .. x_{n-1} of batch means at the d that
minimises

    MSER(d) = sum_{j >= d} (x_j - xbar_d)^2 / (n - d)^2,

the squared standard error of the mean of what is kept, as if its samples
were independent: cutting more of a trend lowers the spread faster than the
shorter series raises it, cutting into the steady part does not. The rule
has no tolerance to tune, and applied again to a longer series it moves the
cut later whenever the longer series resolves a slow tail the shorter one
could not. Cuts are sought in the first half of the series only (the rule's
validity condition; the last few batches of a steady series can scatter
little by chance and would fake a minimum there), and the steady state
counts as found when the minimum lies inside that half, not at its end
(a series still relaxing keeps gaining from every further cut).
"""

from __future__ import annotations

import numpy as np

BATCH = 5  # samples per batch mean (MSER-5)


def mser_truncation(series, batch: int = BATCH) -> int | None:
    """Index of the first steady sample of ``series`` (one value per sample), or None while still transient.

    Parameters
    ----------
    series : array_like
        One or more series sampled together, shape ``(n,)`` or ``(n, k)``;
        each column is truncated on its own and the latest cut is returned.
    batch : int
        Samples per batch mean.

    Returns
    -------
    int or None
        The truncation index (a multiple of ``batch`` counted from the end,
        so the leftover ``n % batch`` first samples are always cut), or None
        if some column's MSER minimum over the first half of its batches
        lies at the end of that half (or there are fewer than 4 batches).

    Examples
    --------
    A relaxation followed by noise is cut where the decay has sunk below it:

    >>> import numpy as np
    >>> rng = np.random.default_rng(1)
    >>> t = np.arange(400)
    >>> cut = mser_truncation(np.exp(-t / 20.0) + 0.01 * rng.standard_normal(400))
    >>> 50 <= cut <= 150
    True
    >>> mser_truncation(np.exp(-t / 400.0)) is None  # still decaying: no steady state yet
    True
    """
    values = np.asarray(series, dtype=float)
    if values.ndim == 1:
        values = values[:, None]
    n = values.shape[0]
    batches = n // batch
    if batches < 4:
        return None
    offset = n - batches * batch
    means = values[offset:].reshape(batches, batch, -1).mean(axis=1)
    latest = 0
    for column in means.T:
        # suffix sums give every candidate's mean and spread in one pass
        count = np.arange(batches, 0, -1, dtype=float)
        total = np.cumsum(column[::-1])[::-1]
        squares = np.cumsum((column[::-1] - column.mean()) ** 2)[::-1]
        shifted_mean = total / count - column.mean()
        spread = squares - count * shifted_mean**2
        half = batches // 2  # cuts beyond the middle are not candidates: the last few batches can
        mser = spread[: half + 1] / count[: half + 1] ** 2  # scatter little by chance and fake a minimum there
        cut = int(np.argmin(mser))
        if cut == half:
            return None
        latest = max(latest, cut)
    return offset + latest * batch
