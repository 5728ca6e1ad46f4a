"""The time-averaged temperature of a sheared run and its energy budget (collisionkit.edmd._shear.run_sheared).

Between the thermostat's rescalings the flow's work heats the fluid; the stress is measured over that cycle, so
its temperature is the time average of kT. The reference here samples the same trajectory every 0.01 time
units (some 300 samples between two rescalings) and integrates them with the trapezoid.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from collisionkit import edmd
from collisionkit.edmd._shear import quadratic_area, run_sheared


def _discs(rate=0.5, thermostat=1.0, eta=0.3, cells=8, seed=1):
    positions, box = edmd.lattice("square", cells, eta)
    velocities = edmd.maxwell_boltzmann(np.ones(len(positions)), 2, seed=seed)
    return edmd.HardSphereSystem(positions, velocities, 0.5, box, shear_rate=rate, thermostat=thermostat)


class FineSampling:
    """Replaces ``system.run``: the same pair collisions in stretches of at most ``dt``, E sampled after each.

    Every stop of the caller is a stop here too, and a rescaling always ends a stretch (where E just before it is
    E after plus what the thermostat removed), so the caller sees the trajectory it samples, sampled finely.
    """

    def __init__(self, system, dt):
        self.system, self.dt, self.run = system, dt, system.run
        self.pieces = [[(system.elapsed, system.kinetic_energy())]]
        system.run = self

    def __call__(self, collisions, progress=None):
        system, done = self.system, 0
        while done < collisions:
            left = collisions - done
            if system.thermostat is not None:
                left = min(left, system._thermostat_due_in())
            removed = system.thermostat_energy
            made = self.run(collisions=left, time=self.dt)
            done += made
            energy = system.kinetic_energy()
            removed = system.thermostat_energy - removed
            self.pieces[-1].append((system.elapsed, energy + removed))
            if removed != 0.0:
                self.pieces.append([(system.elapsed, energy)])
        return done

    def mean_energy(self, since=None):
        """Time average of E from ``since`` (a sample's time) on: the fine trapezoid, and that of the pieces' ends."""
        fine = ends = duration = 0.0
        for piece in self.pieces:
            t, e = np.array(piece).T
            kept = t >= (since if since is not None else -math.inf)
            t, e = t[kept], e[kept]
            if len(t) > 1:
                fine += np.trapezoid(e, t)
                ends += 0.5 * (e[0] + e[-1]) * (t[-1] - t[0])
                duration += t[-1] - t[0]
        return fine / duration, ends / duration


def test_quadratic_area_is_exact_for_parabolas_and_converges_as_h4():
    t = np.array([0.0, 0.4, 0.5, 1.3, 2.0, 2.2])  # uneven steps, an odd number of them
    assert quadratic_area(t, 3 - 2 * t + 0.7 * t**2) == pytest.approx(3 * 2.2 - 2.2**2 + 0.7 * 2.2**3 / 3, rel=1e-13)
    assert quadratic_area(t[:3], t[:3] ** 2) == pytest.approx(0.5**3 / 3, rel=1e-13)  # one pair of steps
    assert quadratic_area(t[:2], t[:2]) == pytest.approx(0.08, rel=1e-13)  # one step: the trapezoid
    assert quadratic_area([1.0], [5.0]) == 0.0
    errors = [abs(quadratic_area(np.linspace(0, 1, n + 1), np.exp(np.linspace(0, 1, n + 1))) - (math.e - 1))
              for n in (8, 16)]
    assert 12 < errors[0] / errors[1] < 20  # fourth order: 16


def test_mean_temperature_of_a_strongly_heated_thermostatted_run_matches_fine_sampling():
    """Discs at eta = 0.3, G = 0.5: kT climbs from 1 to about 2 between rescalings (4 N pair collisions).

    The measurement's ``temperature_mean`` (samples every half interval, quadratics) against the fine trapezoid of
    the same trajectory: within 0.5 % (measured 0.08-0.26 % for seeds 1-3: the quadratics' error; the fine
    trapezoid's is some (0.01 / 1.4)^2 of the coarse one's). The trapezoid of the values just after and just
    before each rescaling is 3.7-3.8 % off: the test tells them apart. The rise per interval is checked to be large.
    """
    system = _discs()
    system.run(collisions=40 * system.count)
    sampling = FineSampling(system, dt=0.01)
    m = edmd.measure(system, collisions=20_000, blocks=10)  # 2000 a block: blocks end between rescalings
    fine, ends = (2 * e / (2 * system.count) for e in sampling.mean_energy())
    rises = [piece[-1][1] / piece[0][1] for piece in sampling.pieces[1:-1]]
    assert np.mean(rises) > 1.7
    assert m.temperature_mean == pytest.approx(fine, rel=0.005)
    assert abs(ends / fine - 1) > 0.02
    assert m.temperature == pytest.approx(1.0, rel=0.5) and m.temperature_mean > 1.3
    # each block's mean is its own stretch's: the blocks' means, weighted by their durations, give the whole
    durations = np.diff(np.concatenate([[0.0], m.msd_time[1:]]))
    assert np.sum(m.block_temperature_mean * durations) / np.sum(durations) == pytest.approx(m.temperature_mean,
                                                                                              rel=1e-12)


def _standard_error_of_time_average(t, e):
    """Standard error of the time average of a sampled E(t): fluctuations about a quadratic trend, 2 tau / T."""
    deviation = e - np.polyval(np.polyfit(t, e, 2), t)
    correlation = np.correlate(deviation, deviation, "full")[len(deviation) - 1 :]
    correlation /= correlation[0] * np.arange(len(deviation), 0, -1) / len(deviation)
    cut = int(np.argmax(correlation < 0)) or len(correlation)
    tau = (t[1] - t[0]) * (0.5 + correlation[1:cut].sum())
    return deviation.std() * math.sqrt(2.0 * tau / (t[-1] - t[0]))


def test_mean_temperature_without_a_thermostat_follows_the_heating():
    """Elastic discs sheared without a thermostat heat up steadily: the mean kT of run_sheared against fine sampling
    of the same trajectory. E(t) of 64 discs fluctuates by some 5 % about its trend; the samples every 2 N collisions
    miss those wiggles (0.03-0.2 % for seeds 1-4), which must stay below a quarter of the time average's own
    statistical error (0.9-2.5 % here: then it adds at most 3 % to the error), while the trapezoid of the ends is
    14-28 % off."""
    system = _discs(rate=0.3, thermostat=None)
    sampling = FineSampling(system, dt=0.01)
    start = system.elapsed
    area = run_sheared(system, 6000)
    fine, ends = sampling.mean_energy()
    t, e = np.array(sampling.pieces[0]).T
    tolerance = 0.25 * _standard_error_of_time_average(t, e) / fine
    assert tolerance < 0.01
    assert area / (system.elapsed - start) == pytest.approx(fine, rel=tolerance)
    assert abs(ends / fine - 1) > 0.1
    assert system.temperature() > 1.2


def test_energy_budget_of_a_sheared_run_closes():
    """The summary's budget since the start, and the measurement's, close to round-off.

    energy_lost_total = loss in collisions + thermostat - viscous heating; over the measurement the heating from
    the blocks' stresses, -G V sum P_xy t, equals the change of E plus the loss plus what the thermostat removed
    (taken here from the system's own sums at the measurement's start and end).
    """
    parameters = edmd.EdmdParameters(dim=2, particles=64, initial="square", restitution=0.95, shear_rate=0.4,
                                     thermostat=True, equilibration=2000, collisions=6000, blocks=4, seed=2)
    run = edmd.EdmdRun(parameters)
    run.run()
    summary, system = run.summary(), run.system
    scale = abs(summary["viscous_heating_total"])
    closing = (summary["energy_lost_collisions_total"] + summary["thermostat_energy_total"]
               - summary["viscous_heating_total"] - summary["energy_lost_total"])
    assert abs(closing) < 1e-12 * scale
    assert summary["energy_lost_total"] == pytest.approx(run.initial_energy - system.kinetic_energy(), abs=1e-9)
    assert summary["energy_lost_collisions_total"] == system.energy_lost > 0
    assert summary["thermostat_energy_total"] == system.thermostat_energy
    assert summary["viscous_heating_total"] > summary["viscous_heating"] > 0

    # the measurement's window: the same run again, stopped where the measurement starts
    start = edmd.EdmdRun(parameters).system
    start.run(collisions=parameters.equilibration)  # one chunk, as the run's equilibration
    change = system.kinetic_energy() - start.kinetic_energy()
    lost = system.energy_lost - start.energy_lost
    removed = system.thermostat_energy - start.thermostat_energy
    assert summary["thermostat_energy"] == pytest.approx(removed, rel=1e-12)
    assert summary["energy_lost"] == pytest.approx(lost, rel=1e-12)
    assert summary["viscous_heating"] == pytest.approx(change + lost + removed, rel=1e-10)


def test_a_sampler_saved_before_the_mean_temperature_was_recorded_resumes_without_it():
    """A checkpoint without the records of the mean kT and the thermostat's energy (written by an earlier
    version): the blocks done before have them unknown (NaN, so the totals are NaN), the blocks after record
    them."""
    system = _discs()
    sampler = edmd.Sampler(system, collisions=4000, blocks=4)
    for _ in range(2):
        sampler.run_block()
    state = sampler.state_dict()
    del state["sampler_temperature_mean"], state["sampler_thermostat_energy"]
    resumed = edmd.Sampler.from_state_dict(edmd.HardSphereSystem.from_state_dict(system.state_dict()), state)
    while not resumed.finished:
        resumed.run_block()
    m = resumed.result()
    assert math.isnan(m.temperature_mean) and math.isnan(m.thermostat_energy)
    assert np.all(np.isnan(m.block_temperature_mean[:2])) and np.all(m.block_temperature_mean[2:] > 1.0)
    assert math.isfinite(m.shear_viscosity) and math.isfinite(m.viscous_heating)
