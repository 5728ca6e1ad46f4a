"""Demo section: Monte Carlo transport (a Reid's ramp swarm and the rod-model slab)."""

from __future__ import annotations

from pathlib import Path

from ._demo_section import SectionResult


def run(pairs: int, seed: int, out: Path, plotting) -> SectionResult:
    """A small Reid's ramp swarm at 12 Td, the slab rod model, and plots."""
    from ..transport import reid_ramp, simulate_slab, simulate_swarm
    from ..transport.swarm import trace_trajectories

    particles = max(640, min(pairs // 100, 4000))
    # Reid's ramp is a benchmark at 0 K (the default gas temperature is 300 K)
    swarm = simulate_swarm(reid_ramp(), 12.0, gas_temperature=0.0, particles=particles, seed=seed,
                           tolerances={"mean_energy": 0.01}, collision_budget=2e7)
    slab = simulate_slab(2.0, model="rod", particles=max(6400, min(pairs, 200_000)), seed=seed)
    files = []
    if plotting is not None:
        files.append(plotting.save(plotting.plot_energy_distribution([swarm]), out / "transport_eedf.png"))
        _, positions = trace_trajectories(reid_ramp(), 12.0, particles=4, points=800, seed=seed, gas_temperature=0.0)
        files.append(plotting.save(plotting.plot_trajectories(positions), out / "transport_trajectories.png"))
    rows = [
        ("Reid 12 Td mean energy (eV)", f"{swarm.mean_energy:.4f} ± {swarm.mean_energy_error:.1g}", "0.2691 (LoKI-MC)"),
        ("Reid 12 Td |bulk W| (m/s)", f"{abs(swarm.drift_velocity_bulk[2]):.4g} ± {swarm.drift_velocity_bulk_error[2]:.1g}",
         "6.838e4 (LoKI-MC)"),
        # a demo-size swarm (hundreds to thousands of particles) does few collisions a step, so the fixed cost of
        # a step weighs more than in a full run: benchmarks/bench_transport.py measures the speed
        ("real collisions per second", f"{swarm.collisions_per_second:.3g}",
         "demo size; speed: benchmarks/bench_transport.py"),
        ("rod slab d = 2: transmission", f"{slab.transmission:.4f} ± {slab.transmission_error:.1g}", "0.5 = 1/(1 + d/2)"),
    ]
    summary = {"reid_12Td": {"mean_energy": swarm.mean_energy, "mean_energy_error": swarm.mean_energy_error,
                             "drift_velocity_bulk": swarm.drift_velocity_bulk.tolist(),
                             "collisions_per_second": swarm.collisions_per_second},
               "rod_slab": {"transmission": slab.transmission, "transmission_error": slab.transmission_error}}
    return SectionResult("Monte Carlo transport", rows, summary, files)
