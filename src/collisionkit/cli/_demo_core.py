"""Demo section: the exact two-body collision core."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

import collisionkit as ck
from collisionkit import scattering

from ._demo_section import SectionResult


def _random_pairs(count: int, rng: np.random.Generator):
    m1 = rng.uniform(0.1, 10.0, count)
    m2 = rng.uniform(0.1, 10.0, count)
    v1 = rng.normal(size=(count, 3))
    v2 = rng.normal(size=(count, 3))
    normal = rng.normal(size=(count, 3))
    return m1, v1, m2, v2, normal


def _conservation(count: int, rng: np.random.Generator):
    """Worst momentum/energy errors over random 3D contacts, elastic and inelastic."""
    m1, v1, m2, v2, normal = _random_pairs(count, rng)
    e = rng.uniform(0.0, 1.0, count)
    p_before = m1[:, None] * v1 + m2[:, None] * v2
    k_before = ck.kinetic_energy(m1, v1) + ck.kinetic_energy(m2, v2)
    scale_p = np.linalg.norm(np.abs(m1[:, None] * v1) + np.abs(m2[:, None] * v2), axis=1)

    a1, a2 = ck.resolve_contact(m1, v1, m2, v2, normal)
    momentum_error = np.max(np.linalg.norm(m1[:, None] * a1 + m2[:, None] * a2 - p_before, axis=1) / scale_p)
    energy_error = np.max(np.abs(ck.kinetic_energy(m1, a1) + ck.kinetic_energy(m2, a2) - k_before) / k_before)

    b1, b2 = ck.resolve_contact(m1, v1, m2, v2, normal, restitution=e)
    unit = normal / np.linalg.norm(normal, axis=1, keepdims=True)
    approach = np.maximum(np.einsum("ij,ij->i", v1 - v2, unit), 0.0)
    mu = ck.reduced_mass(m1, m2)
    loss = k_before - ck.kinetic_energy(m1, b1) - ck.kinetic_energy(m2, b2)
    expected = 0.5 * mu * (1.0 - e**2) * approach**2
    loss_error = np.max(np.abs(loss - expected) / k_before)
    return momentum_error, energy_error, loss_error, (approach, loss, mu, e)


def _throughput(count: int, rng: np.random.Generator) -> float:
    m1, v1, m2, v2, normal = _random_pairs(count, rng)
    ck.resolve_contact(m1[:10], v1[:10], m2[:10], v2[:10], normal[:10])  # compile / load cache
    best = np.inf
    for _ in range(3):
        start = time.perf_counter()
        ck.resolve_contact(m1, v1, m2, v2, normal)
        best = min(best, time.perf_counter() - start)
    return count / best


def run(pairs: int, seed: int, out: Path, plotting) -> SectionResult:
    """Conservation checks, the irfpy scan, scattering laws and throughput."""
    rng = np.random.default_rng(seed)
    momentum_error, energy_error, loss_error, loss_data = _conservation(pairs, rng)

    far = float(ck.time_to_contact([0.0, 0.0, 0.0], [1.0, 0, 0], [1e8, 0, 0], [0.0, 0, 0], 1.0))
    V1, W1, V2, W2 = ck.compat.irfpy.binary_collision_stationary(1.0, 1.0, 1.0, 0.5, 1.0)
    chi_hs = float(np.degrees(scattering.hard_sphere_deflection(0.5, 1.0)))
    chi_ru = float(np.degrees(scattering.rutherford_deflection(1.0, 1.0, 1.0, 1.0)))
    rate = _throughput(pairs, rng)

    files = []
    if plotting is not None:
        files.append(plotting.save(plotting.plot_stationary_scan(mass_ratio=1.0), out / "irfpy_stationary_scan.png"))
        files.append(plotting.save(plotting.plot_deflection_laws(), out / "deflection_laws.png"))
        sample = slice(0, min(pairs, 2000))
        approach, loss, mu, e = (np.asarray(x)[sample] for x in loss_data)
        files.append(plotting.save(plotting.plot_energy_loss(approach, loss, mu, e), out / "inelastic_energy_loss.png"))

    rows = [
        ("momentum conservation, worst relative error", f"{momentum_error:.2e}", "round-off (< 1e-13)"),
        ("energy conservation (e = 1), worst relative error", f"{energy_error:.2e}", "round-off (< 1e-13)"),
        ("inelastic loss vs mu(1-e^2)u_n^2/2, worst error", f"{loss_error:.2e}", "round-off (< 1e-13)"),
        ("time to contact, head-on from 1e8 away", f"{far:.17g}", "99999999 (to round-off)"),
        ("irfpy stationary d = 0.5: V1, W1, V2, W2", f"{V1:.4f}, {W1:.4f}, {V2:.4f}, {W2:.4f}", "0.25, 0.433, 0.75, -0.433"),
        ("hard-sphere deflection at b = sigma/2 (deg)", f"{chi_hs:.6f}", "120"),
        ("Rutherford deflection at b = k/(mu v^2) (deg)", f"{chi_ru:.6f}", "90"),
        ("resolve_contact throughput, 3D pairs/s", f"{rate:.3g}", "memory bound"),
    ]
    summary = {
        "pairs": pairs,
        "momentum_relative_error": momentum_error,
        "energy_relative_error": energy_error,
        "inelastic_loss_error": loss_error,
        "time_to_contact_far": far,
        "irfpy_stationary_d0.5": [float(V1), float(W1), float(V2), float(W2)],
        "resolve_contact_pairs_per_second": rate,
    }
    return SectionResult("collision core", rows, summary, files)
