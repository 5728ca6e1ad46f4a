"""Transport coefficients from a swarm's per-step sums: per-group estimates and their standard errors."""

from __future__ import annotations

import math

import numpy as np
from scipy import constants

from .._kernels import transport as _k

EV = constants.e


def slope(t, y):
    """Least-squares slope of y(t) along axis 0."""
    tc = t - t.mean()
    return np.tensordot(tc, y - y.mean(axis=0), axes=(0, 0)) / np.dot(tc, tc)


def estimates(times, moments, tallies, kinds, density):
    """Per-group estimates (groups on the first axis) from the steady window."""
    n = moments[..., 0]
    mean = moments[..., 1:14] / n[..., None]
    centroid = mean[..., 0:3]
    variance = (mean[..., 3:6] - centroid**2) * (n / np.maximum(n - 1, 1))[..., None]
    velocity = mean[..., 6:9]
    energy = mean[..., 9] / EV
    cross = mean[..., 10:13] - centroid * velocity
    rates_time = tallies.sum(axis=0)
    n_proc = len(kinds)
    particle_time = rates_time[:, n_proc + _k.TIME_COLUMN_OFFSET]
    counts = rates_time[:, :n_proc]
    est = {
        "mean_energy": energy.mean(axis=0),
        "drift_velocity_flux": velocity.mean(axis=0),
        "drift_velocity_bulk": slope(times, centroid),
        "diffusion_L_N_flux": density * cross[..., 2].mean(axis=0),
        "diffusion_T_N_flux": density * 0.5 * (cross[..., 0] + cross[..., 1]).mean(axis=0),
        "diffusion_L_N": density * 0.5 * slope(times, variance[..., 2]),
        "diffusion_T_N": density * 0.25 * slope(times, variance[..., 0] + variance[..., 1]),
        "rates": counts / (particle_time[:, None] * density),
    }
    ionization = np.array([kind == "ionization" for kind in kinds])
    attachment = np.array([kind == "attachment" for kind in kinds])
    est["ionization_frequency_N"] = counts[:, ionization].sum(axis=1) / (particle_time * density)
    est["attachment_frequency_N"] = counts[:, attachment].sum(axis=1) / (particle_time * density)
    return est


def mean_and_error(values):
    """Mean over the groups (axis 0) and its standard error."""
    values = np.asarray(values, dtype=float)
    return values.mean(axis=0), values.std(axis=0, ddof=1) / math.sqrt(values.shape[0])
