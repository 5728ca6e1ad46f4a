"""
Real argon: drift velocity against measurements
===============================================

An electron swarm in argon at 300 K, with the IST-Lisbon cross-section set
that ships with collisionkit (``collisionkit swarm --gas Ar``; Yanguas-Gil,
Cotrino and Alves, J. Phys. D 38, 1588 (2005)), compared with the drift
velocities measured by Nakamura and Kurachi (J. Phys. D 21, 718 (1988); 1 %
rms). The set itself predicts drift velocities 7-10 % above these
measurements at 20-50 Td, as the two-term solution of the same file shows
(:func:`~collisionkit.transport.two_term_boltzmann`, milliseconds per point,
drawn as a line): the difference is the cross-section set's, not the Monte
Carlo's (see the transport guide's table). Any other LXCat set can be compared the same way
(``read_lxcat`` or ``--cross-sections``).
"""

import warnings

import matplotlib.pyplot as plt
import numpy as np

from collisionkit import transport

with warnings.catch_warnings():
    warnings.simplefilter("ignore", transport.LXCatWarning)
    argon = transport.catalogue_gas("Ar")

fields = [30.0, 50.0]
results = [
    transport.simulate_swarm(argon, field, gas_temperature=300.0, particles=2000, groups=8, seed=3,
                             tolerances={"mean_energy": 0.01, "drift_velocity_bulk": 0.02})
    for field in fields
]
for result in results:
    print(f"E/N = {result.reduced_field:4.0f} Td: mean energy {result.mean_energy:.3f} eV, bulk W "
          f"{-result.drift_velocity_bulk[2]:.4g} +- {result.drift_velocity_bulk_error[2]:.2g} m/s")

# Nakamura & Kurachi (1988), 300 K: E/N (Td) and W (m/s)
measured_fields = np.array([10.0, 12.0, 14.0, 17.0, 20.0, 25.0, 30.0, 35.0, 40.0, 50.0])
measured_drift = np.array([9.56, 11.7, 13.4, 16.3, 18.8, 22.4, 27.1, 31.1, 34.4, 41.2]) * 1e3

two_term_fields = np.linspace(5.0, 55.0, 26)
two_term_drift = [transport.two_term_boltzmann(argon, field, gas_temperature=300.0).drift_velocity
                  for field in two_term_fields]

figure, axes = plt.subplots()
axes.plot(measured_fields, measured_drift, "o", mfc="none", label="measured (Nakamura & Kurachi 1988)")
axes.plot(two_term_fields, two_term_drift, "-", lw=1, label="two-term equation, same set (flux W)")
axes.errorbar(fields, [-r.drift_velocity_bulk[2] for r in results],
              yerr=[r.drift_velocity_bulk_error[2] for r in results], fmt="s", label="collisionkit, IST-Lisbon set")
axes.set_xlabel("E/N (Td)")
axes.set_ylabel("bulk drift velocity W (m/s)")
axes.set_title("Electrons in argon at 300 K")
axes.legend()
plt.show()
