"""
Newton's cradle
===============

Five equal steel balls hang in a row, almost touching. One ball swings in:
one ball swings out at the far end, and the ones in between stay put. Two in:
two out. The collision core explains why: a head-on elastic collision of equal
masses exchanges the velocities (:func:`collisionkit.resolve_contact`), so the
momentum is handed along the row one contact at a time.

Here the row is one-dimensional (the balls' bottom arcs are nearly straight)
with a small gap between neighbours, and a tiny event loop asks
:func:`collisionkit.time_to_contact` which neighbouring pair touches next.
"""

import matplotlib.pyplot as plt
import numpy as np

import collisionkit as ck

diameter, gap = 1.0, 0.02
balls = 5


def cradle(moving, t_end=12.0, restitution=1.0):
    """Worldlines of the balls after ``moving`` of them enter from the left at speed 1."""
    x = np.arange(balls) * (diameter + gap)
    v = np.zeros(balls)
    v[:moving] = 1.0
    x[:moving] -= 3.0  # they start a little way off
    t, times, positions = 0.0, [0.0], [x.copy()]
    while True:
        # contact times of every neighbouring pair (np.inf if they never touch)
        dt = ck.time_to_contact(x[:-1, None], v[:-1, None], x[1:, None], v[1:, None], diameter)
        pair = int(np.argmin(dt))
        if t + dt[pair] > t_end:
            break
        t += dt[pair]
        x += v * dt[pair]
        v1, v2 = ck.resolve_contact(1.0, [v[pair]], 1.0, [v[pair + 1]], [1.0], restitution=restitution)
        v[pair], v[pair + 1] = v1[0], v2[0]
        times.append(t)
        positions.append(x.copy())
    times.append(t_end)
    positions.append(x + v * (t_end - t))
    return np.array(times), np.array(positions), v


fig, axes = plt.subplots(1, 2, figsize=(9, 4), sharey=True, layout="constrained")
for ax, moving in zip(axes, (1, 2)):
    times, positions, v = cradle(moving)
    for ball in range(balls):
        ax.plot(positions[:, ball], times, color=f"C{ball}")
    ax.set_xlabel("position")
    ax.set_title(f"{moving} in, {np.count_nonzero(v > 0.5)} out")
    print(f"{moving} ball(s) in: final velocities {np.round(v, 12)}, momentum {v.sum():.12f}, "
          f"kinetic energy {0.5 * (v**2).sum():.12f}")
axes[0].set_ylabel("time")
fig.suptitle("Newton's cradle: worldlines of five equal balls")

# %%
# With a coefficient of restitution below one the hand-over is imperfect:
# every contact leaves a little velocity behind, and the row creeps along.

times, positions, v = cradle(1, restitution=0.9)
print("e = 0.9: final velocities", np.round(v, 4))
