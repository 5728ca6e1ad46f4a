"""What every plotting module shares: a default Axes and the unit labels of EDMD figures."""

from __future__ import annotations

import matplotlib.pyplot as plt

SIGMA_X, SIGMA_Y = r"$x\,/\,\sigma$", r"$y\,/\,\sigma$"  # EDMD lengths: the largest diameter sigma
THERMAL_SPEED = r"$\sqrt{kT/m}$"  # EDMD speeds


def _axes(ax):
    if ax is None:
        _, ax = plt.subplots(figsize=(6, 4), layout="constrained")
    return ax
