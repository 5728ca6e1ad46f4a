"""Demo section: two-body encounters (StarCrash set-up, exact Kepler propagation)."""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

from collisionkit import encounters

from ._demo_section import SectionResult


def _relative_ode(_, y, mu):
    r = y[:3]
    return np.concatenate([y[3:], -mu * r / math.sqrt(r @ r) ** 3])


def _dop853_disagreement(orbit, duration: float, samples: int = 200) -> float:
    """Largest relative position/velocity difference from DOP853 (rtol 1e-13), from periastron."""
    worst = 0.0
    r0, v0 = orbit.relative_state_at_time(0.0)
    for end in (duration, -duration):
        times = np.linspace(0.0, end, samples)
        solution = solve_ivp(
            _relative_ode, (0.0, end), np.concatenate([r0, v0]), method="DOP853",
            rtol=1e-13, atol=1e-20, t_eval=times, args=(orbit.kepler_parameter,),
        )  # fmt: skip
        r, v = orbit.relative_state_at_time(times)
        for exact, numeric in ((r, solution.y[:3].T), (v, solution.y[3:].T)):
            error = np.linalg.norm(numeric - exact, axis=1) / np.linalg.norm(exact, axis=1)
            worst = max(worst, float(error.max()))
    return worst


def _throughput(orbit, count: int, rng: np.random.Generator) -> float:
    times = rng.uniform(-1e4, 1e4, count)
    orbit.state_at_time(times[:10])  # compile / load cache
    start = time.perf_counter()
    orbit.state_at_time(times)
    return count / (time.perf_counter() - start)


def run(pairs: int, seed: int, out: Path, plotting) -> SectionResult:
    """A StarCrash set-up, deflection against the closed form, DOP853 check, Kepler throughput."""
    rng = np.random.default_rng(seed)
    ic = encounters.starcrash_initial_conditions(1.0, 1.0, rp=1.0, v_inf=0.5, sep0=10.0)
    stellar = encounters.unit_system("stellar")
    sun_pair = encounters.starcrash_initial_conditions(1.0, 1.0, rp=1.0, v_inf=100.0, sep0=20.0, G=stellar.G)
    orbit = ic.orbit
    closed_form = 2.0 * math.asin(1.0 / orbit.eccentricity)
    deflection_error = abs(orbit.deflection_angle - closed_form)
    hyperbolic_error = _dop853_disagreement(encounters.Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=0.5), 1e3)
    elliptic = encounters.TwoBodyOrbit(1.0, 1.0, periastron=1.0, eccentricity=0.5)
    elliptic_error = _dop853_disagreement(elliptic, 3.0 * elliptic.period)
    rate = _throughput(orbit, min(pairs, 1_000_000), rng)

    files = []
    if plotting is not None:
        files.append(plotting.save(plotting.plot_encounter(ic), out / "encounter_trajectories.png"))

    rows = [
        ("StarCrash rp=1, vinf=0.5, sep0=10 (G=M=1): b, vt/v0", f"{ic.impact_parameter:.6f}, {ic.speed_ratio:.4f}", "sqrt(17) = 4.123106, < 0.5774"),
        ("two Suns, rp = 1 Rsun, vinf = 100 km/s: v0, e", f"{sun_pair.v0:.2f} km/s, {sun_pair.orbit.eccentricity:.5f}", "v0^2 = vinf^2 + 2GM/r0"),
        ("deflection vs 2 asin(1/e), difference (rad)", f"{deflection_error:.1e}", "round-off"),
        ("DOP853 vs exact, hyperbolic to t = +-1e3", f"{hyperbolic_error:.1e}", "< 1e-9"),
        ("DOP853 vs exact, e = 0.5 over 3 periods", f"{elliptic_error:.1e}", "< 1e-9"),
        ("state_at_time throughput, times/s", f"{rate:.3g}", "Kepler solves"),
    ]
    summary = {
        "starcrash": ic.to_dict(),
        "deflection_error": deflection_error,
        "dop853_hyperbolic": hyperbolic_error,
        "dop853_elliptic": elliptic_error,
        "state_at_time_per_second": rate,
    }
    return SectionResult("two-body encounters", rows, summary, files)
