"""
Argon's electrons in an ionized gas and in a high-frequency field
=================================================================

The two-term Boltzmann equation (:func:`collisionkit.transport.two_term_boltzmann`)
for the shipped argon (IST-Lisbon) at 50 Td.

*Left:* as the ionization degree :math:`n_e/N` rises, the electrons' collisions
with each other share out their energy: the distribution turns towards a
Maxwellian (a straight line here), its tail above the 11.5 eV excitation
threshold fills, the excitations rise and the mean energy falls (Hagelaar &
Pitchford 2005 show the same).

*Right:* a field :math:`E_0\\cos\\omega t` of the same amplitude heats less as
:math:`\\omega/N` passes the momentum-transfer frequency per molecule: below it the
field acts as its RMS value, above it as :math:`E_0\\nu/(\\sqrt2\\,\\omega)`.
"""

import matplotlib.pyplot as plt

from collisionkit.transport import catalogue_gas, two_term_boltzmann

argon = catalogue_gas("Ar")
fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4), sharey=True)

for degree in (0.0, 1e-6, 1e-4, 1e-3):
    extra = {"ionization_degree": degree, "electron_density": 1e18} if degree else {}
    result = two_term_boltzmann(argon, 50.0, **extra)
    shown = result.eedf > 1e-12 * result.eedf.max()
    left.semilogy(result.energy[shown], result.eedf[shown],
                  label=f"n_e/N = {degree:g}: <e> = {result.mean_energy:.2f} eV")
left.set(xlabel="energy (eV)", ylabel="F0 (eV^-3/2)", title="50 Td, n_e = 1e18 m^-3", xlim=(0, 40))
left.legend(fontsize=8)

for omega_N in (0.0, 1e-14, 1e-13, 1e-12):
    result = two_term_boltzmann(argon, 50.0, omega_N=omega_N)
    shown = result.eedf > 1e-12 * result.eedf.max()
    label = "DC" if omega_N == 0 else f"omega/N = {omega_N:g} rad m^3/s"
    right.semilogy(result.energy[shown], result.eedf[shown], label=f"{label}: <e> = {result.mean_energy:.2f} eV")
right.set(xlabel="energy (eV)", title="amplitude 50 Td", xlim=(0, 40))
right.legend(fontsize=8)
fig.tight_layout()
plt.show()
