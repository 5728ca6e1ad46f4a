"""
Hard-disc equation of state
===========================

The pressure of a hard-disc fluid comes entirely from collisions: the virial
theorem turns the momentum exchanged per unit time into the compressibility
factor :math:`Z = PV/(NkT)`. Event-driven dynamics measures it directly
(:func:`collisionkit.edmd.measure`), and Henderson's equation of state
(Mol. Phys. 30, 971 (1975)),

.. math:: Z = \\frac{1 + \\eta^2/8}{(1 - \\eta)^2},

predicts it from the packing fraction :math:`\\eta`. This small run (200
discs, a few thousand collisions per point) takes a few seconds; the test
suite and the validation page use larger ones.
"""

import matplotlib.pyplot as plt

from collisionkit import edmd, plotting

points = []
for eta in (0.1, 0.3, 0.5):
    system = edmd.random_fluid(2, 200, eta, seed=7)
    system.run(collisions=10 * system.count)  # equilibrate
    m = edmd.measure(system, collisions=60 * system.count, blocks=5)
    points.append(m)
    print(f"eta = {eta}: Z = {m.compressibility_factor:.3f} +- {m.compressibility_factor_error:.3f}, "
          f"Henderson {float(edmd.henderson(eta)):.3f}")

ax = plotting.plot_equation_of_state(points, dim=2)

# %%
# The last system, drawn to scale.

fig, ax = plt.subplots(figsize=(4.5, 4.5), layout="constrained")
plotting.plot_snapshot(system.positions(), system.radius, system.box[:2], ax=ax)
