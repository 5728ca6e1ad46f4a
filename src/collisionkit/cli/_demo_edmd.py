"""Demo section: event-driven molecular dynamics of hard spheres and discs."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from collisionkit import edmd

from ._demo_section import SectionResult

SPHERES, SPHERE_ETA = 500, 0.3
DISC_CELLS, DISC_ETA = 12, 0.3  # hexagonal lattice: 2 * 12^2 = 288 discs


def _spheres(seed: int):
    """500 spheres grown to eta = 0.3 by Lubachevsky-Stillinger compression, then measured."""
    system = edmd.random_fluid(3, SPHERES, SPHERE_ETA, seed=seed)
    system.run(collisions=10 * SPHERES)
    return system, edmd.measure(system, collisions=100 * SPHERES, blocks=10)


def _discs(seed: int):
    """288 discs melted from a hexagonal lattice at eta = 0.3, then measured."""
    positions, box = edmd.lattice("hexagonal", DISC_CELLS, DISC_ETA)
    velocities = edmd.maxwell_boltzmann(np.ones(len(positions)), 2, seed=seed)
    system = edmd.HardSphereSystem(positions, velocities, 0.5, box)
    system.run(collisions=20 * len(positions))
    return system, edmd.measure(system, collisions=100 * len(positions), blocks=10)


def _rows(label: str, m, theory_name: str, theory: float):
    omega_from_z = float(edmd.enskog_collision_frequency(m.compressibility_factor, m.dim, kT=m.temperature))
    z = f"{m.compressibility_factor:.4f} ± {m.compressibility_factor_error:.4f}"
    omega = f"{m.collision_frequency:.4f} ± {m.collision_frequency_error:.4f}"
    return [
        (f"{label}: Z = PV/NkT", z, f"{theory:.4f} ({theory_name})"),
        (f"{label}: collision frequency per particle", omega, f"{omega_from_z:.4f} (Enskog, from Z)"),
    ]


def _summary(m, theory: float, gap: float):
    return m.summary() | {"compressibility_factor_theory": theory, "smallest_gap": gap}


def run(pairs: int, seed: int, out: Path, plotting) -> SectionResult:
    """Z and the collision frequency of small hard-sphere and hard-disc fluids against theory.

    The sizes are fixed (a few seconds in all); ``pairs`` is not used here.
    """
    spheres, m3 = _spheres(seed)
    discs, m2 = _discs(seed)
    z3, z2 = float(edmd.hansen_goos(SPHERE_ETA)), float(edmd.henderson(DISC_ETA))
    gap = min(spheres.check(), discs.check())

    files = []
    if plotting is not None:
        files.append(plotting.save(plotting.plot_equation_of_state([m3], dim=3), out / "edmd_equation_of_state.png"))
        speeds = plotting.plot_speed_distribution(m3.speeds, m3.temperature, dim=3)
        files.append(plotting.save(speeds, out / "edmd_speed_distribution.png"))
        snapshot = plotting.plot_snapshot(discs.positions(), discs.radius, discs.box[:2])
        files.append(plotting.save(snapshot, out / "edmd_snapshot.png"))

    rows = [
        *_rows(f"{SPHERES} spheres, eta {SPHERE_ETA}", m3, "Hansen-Goos", z3),
        *_rows(f"{discs.count} discs, eta {DISC_ETA}", m2, "Henderson", z2),
        ("smallest surface gap after the runs", f"{gap:.2e}", ">= 0 up to round-off (no overlaps)"),
        ("3D pair collisions per second (wall clock)", f"{m3.collisions_per_second:.3g}", "numba event loop"),
    ]
    summary = {"spheres": _summary(m3, z3, spheres.check()), "discs": _summary(m2, z2, discs.check())}
    return SectionResult("event-driven MD", rows, summary, files)
