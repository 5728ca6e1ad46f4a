"""Reid's ramp in an AC field against static-field runs in the low- and high-frequency limits.

White, Robson & Ness (Aust. J. Phys. 48, 925 (1995)) give the AC Reid ramp (10 Td r.m.s.) as figures only (the
LoKI-MC paper, Dias et al., PSST 32, 095003 (2023), compares with them in its figure 15, again without a table; its
curves, read off the figure, are tests/data/white1995_ac_reid.txt, which tests/transport/test_periodic_white.py
checks at the three higher frequencies), so the cosine field is also checked here against two limits derived
independently of the AC code, each from static runs:

* low frequency (omega far below the energy and momentum relaxation frequencies, omega/N = 1.777e-17 rad m^3/s,
  White's lowest): the swarm follows the field quasi-statically, <e>(omega t) = <e>_DC(E0 |cos omega t|) and
  W(omega t) = sign(cos omega t) W_DC(E0 |cos omega t|). It fails only near the zeros of the field, where the
  energy relaxes through elastic collisions alone (2 m/M nu_m, far below omega): the phases with |cos| >= 0.38
  (E >= 5.4 Td) are compared;
* high frequency at cyclotron resonance (omega = Omega = e B/m, E perpendicular to B, omega >> nu_m): the
  co-rotating half of E0 cos(omega t) is static in the gyrating frame and the counter-rotating half averages
  out, so <e> tends to <e>_DC at E0/2 with no B (Dias et al. 2023, sec. 3.2, their horizontal lines), with a
  deviation that falls as nu_m / omega: two frequencies show the trend.

0 K, 16 phases. Writes benchmarks/results/ac_limits.md and ac_limits.json.

    NUMBA_CACHE_DIR=.numba_cache .venv/bin/python benchmarks/bench_ac_limits.py
"""

from __future__ import annotations

import math
import os
import time
from pathlib import Path

import numpy as np
from scipy import constants

from collisionkit._io import atomic_write_json, atomic_write_text
from collisionkit.transport import reid_ramp, simulate_swarm
from collisionkit.transport.swarm import HUXLEY

RESULTS = Path(__file__).parent / "results"
E_RMS = 10.0  # Td
E0 = E_RMS * math.sqrt(2.0)
LOW = 1.777e-17  # omega/N, rad m^3/s
HIGH = (7.10e-14, 14.2e-14)  # Dias et al. 2023, table 1: f = 400 and 800 MHz at N = 3.54e22 m^-3
PARTICLES = 4000


def _static(reduced_field, seed, cache={}):
    key = round(reduced_field, 9)
    if key not in cache:
        r = simulate_swarm(reid_ramp(), reduced_field, gas_temperature=0.0, particles=PARTICLES, seed=seed, threads=2,
                           tolerances={"mean_energy": 1e-3, "drift_velocity_bulk": 1e-3})
        cache[key] = r.mean_energy, r.mean_energy_error, -r.drift_velocity_flux[2], r.drift_velocity_flux_error[2]
    return cache[key]


def _agreement(value, error, reference, reference_error):
    return (value - reference) / math.hypot(error, reference_error)


def low_frequency() -> dict:
    r = simulate_swarm(reid_ramp(), E0, reduced_frequency=LOW, gas_temperature=0.0, particles=PARTICLES, seed=1,
                       threads=2, tolerances={"mean_energy": 1e-3}, collision_budget=4e9)
    rows = []
    for k, phase in enumerate(r.phases):
        amplitude = abs(math.cos(phase))
        if amplitude < 0.38:
            continue
        energy, energy_error, drift, drift_error = _static(E0 * amplitude, 10 + k)
        sign = math.copysign(1.0, math.cos(phase))
        w, w_error = -r.drift_velocity_flux_by_phase[k, 2], r.drift_velocity_flux_by_phase_error[k, 2]
        rows.append({"phase": float(phase), "E_over_N": E0 * amplitude,
                     "mean_energy": float(r.mean_energy_by_phase[k]),
                     "mean_energy_error": float(r.mean_energy_by_phase_error[k]),
                     "static_mean_energy": energy, "static_mean_energy_error": energy_error,
                     "drift": float(w), "drift_error": float(w_error), "static_drift": sign * drift,
                     "static_drift_error": drift_error})
    return {"omega_N": LOW, "converged": r.converged, "collisions": r.collisions, "rows": rows}


def high_frequency() -> dict:
    energy, energy_error, _, _ = _static(E0 / 2.0, 30)
    rows = []
    for k, omega_n in enumerate(HIGH):
        b_n = omega_n * constants.m_e / constants.e / HUXLEY  # Omega = omega
        r = simulate_swarm(reid_ramp(), E0, reduced_frequency=omega_n, reduced_magnetic_field=b_n, field_angle=90.0,
                           gas_temperature=0.0, particles=PARTICLES, seed=40 + k, threads=2,
                           tolerances={"mean_energy": 1e-3}, collision_budget=4e9)
        rows.append({"omega_N": omega_n, "B_N": b_n, "mean_energy": r.mean_energy,
                     "mean_energy_error": r.mean_energy_error, "converged": r.converged, "collisions": r.collisions})
    return {"static_E_over_N": E0 / 2.0, "static_mean_energy": energy, "static_mean_energy_error": energy_error,
            "rows": rows}


def main() -> None:
    start = time.perf_counter()
    data = {"low": low_frequency(), "high": high_frequency(), "load_average_at_end": os.getloadavg(),
            "seconds": time.perf_counter() - start}
    atomic_write_json(RESULTS / "ac_limits.json", data)
    low, high = data["low"], data["high"]
    lines = ["# Reid's ramp in an AC field (10 Td r.m.s.) against static runs in the two limits", "",
             "benchmarks/bench_ac_limits.py (see its docstring for the derivations); 0 K, "
             f"{PARTICLES} particles, errors one standard error; z-score = difference / combined error.", "",
             f"## Low frequency, omega/N = {LOW:g} rad m^3/s: quasi-static", "",
             "| omega t (rad) | E0 cos / N (Td) | <e> AC (eV) | <e> DC (eV) | z | W AC (m/s) | W DC (m/s) | z |",
             "|---|---|---|---|---|---|---|---|"]
    for row in low["rows"]:
        lines.append(
            f"| {row['phase']:.3f} | {row['E_over_N']:.2f} | {row['mean_energy']:.4f} ± {row['mean_energy_error']:.4f} "
            f"| {row['static_mean_energy']:.4f} ± {row['static_mean_energy_error']:.4f} "
            f"| {_agreement(row['mean_energy'], row['mean_energy_error'], row['static_mean_energy'], row['static_mean_energy_error']):+.1f} "
            f"| {row['drift']:.4g} ± {row['drift_error']:.2g} | {row['static_drift']:.4g} ± {row['static_drift_error']:.2g} "
            f"| {_agreement(row['drift'], row['drift_error'], row['static_drift'], row['static_drift_error']):+.1f} |")
    lines += ["", f"({low['collisions']:.3g} collisions, converged: {low['converged']}; W is along -z, the electrons' "
              "drift when E points along +z.)", "",
              f"## High frequency at cyclotron resonance (E perpendicular to B) against DC at E0/2 = "
              f"{high['static_E_over_N']:.3f} Td without B: <e> = {high['static_mean_energy']:.4f} ± "
              f"{high['static_mean_energy_error']:.4f} eV", "",
              "| omega/N (rad m^3/s) | B/N (Hx) | <e> cycle average (eV) | relative deviation from DC at E0/2 |",
              "|---|---|---|---|"]
    for row in high["rows"]:
        deviation = row["mean_energy"] / high["static_mean_energy"] - 1.0
        lines.append(f"| {row['omega_N']:.3g} | {row['B_N']:.1f} | {row['mean_energy']:.4f} ± "
                     f"{row['mean_energy_error']:.4f} | {100 * deviation:+.2f} % |")
    lines += ["", f"Load average at the end {data['load_average_at_end'][0]:.1f}; {data['seconds']:.0f} s wall."]
    atomic_write_text(RESULTS / "ac_limits.md", "\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
