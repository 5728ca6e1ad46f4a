"""Tests of swarms that cannot be advanced (collisionkit.transport._swarm_run): cross sections zero or tiny.

A swarm in a field whose cross sections are zero (an ELASTIC block of zeros) or tiny (a units slip) runs away:
the particles gain energy without end and a step never ended, ignoring the collision budget, inside one kernel
call where Ctrl-C cannot land. The kernel is compiled before each deadline (a cold numba cache takes tens of
seconds), so the deadline times only the run.
"""

import warnings

import numpy as np
import pytest
from scipy import constants

from collisionkit._kernels import transport as kernels
from collisionkit.transport import Gas, Process, Species, reid_ramp, simulate_swarm
from collisionkit.transport import _swarm_run
from collisionkit.transport._tables import build_tables
from collisionkit.transport.swarm import trace_trajectories
from tests.sweep.helpers import deadline


def _flat_gas(cross_section):
    """Helium-like targets with a constant elastic cross section (m^2) from 0 to 100 eV."""
    return Gas((Species("flat", 6.6e-26, (Process("elastic", [0.0, 100.0], [cross_section, cross_section]),)),))


@pytest.fixture(scope="module")
def compiled():
    trace_trajectories(reid_ramp(), 12.0, particles=1, points=2)


def test_a_gas_with_no_collision_at_all_is_refused_before_the_run():
    gas = _flat_gas(0.0)
    with deadline(10.0):
        with pytest.raises(ValueError, match="every cross section and rate coefficient of the gas is zero"):
            simulate_swarm(gas, 10.0, particles=128, threads=1)
        with pytest.raises(ValueError, match="no particle can ever collide"):
            trace_trajectories(gas, 10.0, particles=2, points=10)


@pytest.mark.parametrize("threads", [1, 2])
def test_a_swarm_that_runs_away_stops_with_the_likely_cause(compiled, threads):
    # 1e-40 m^2 (1e-20 in cm^2 read as m^2 would be 1e-24): the probe step, planned at the starting energy,
    # accelerates the particles to 1e22 eV, colliding ever more often on the way
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the default diffusion tolerances are out of reach of 128 particles
        with deadline(30.0), pytest.raises(RuntimeError, match=r"ran away in the field. Either the field .* or the "
                                                               r"cross sections are zero or tiny .* units slip"):
            simulate_swarm(_flat_gas(1e-40), 10.0, particles=128, threads=threads, collision_budget=1e4)
    with deadline(30.0), pytest.raises(RuntimeError, match=r"reached [0-9.e+]+ eV \([0-9.e+]+ times the top"):
        trace_trajectories(_flat_gas(1e-40), 10.0, particles=2, points=50)


def test_a_large_swarm_is_advanced_in_calls_of_a_bounded_number_of_particles(monkeypatch):
    # one call per thread's share of a million particles took seconds, where Ctrl-C cannot land
    ranges = []

    def record(lo, hi, *args):
        ranges.append((lo, hi))
        return -1, 0.0

    monkeypatch.setattr(kernels, "advance_swarm", record)
    tables = build_tables(reid_ramp(), constants.m_e, 0.0)
    stepper = _swarm_run.Stepper(tables, kernels.derived_field(np.zeros(3), np.zeros(3)), constants.m_e, 1e24, 0, 1)
    n = 3 * _swarm_run.PARTICLES_PER_CALL + 1
    swarm = _swarm_run.initial_swarm(n, 16, 1, constants.m_e, 1.0)
    stepper.step(swarm, 0.0, 1e-12, 16)
    assert len(ranges) == 8 and ranges[0][0] == 0 and ranges[-1][1] == n  # 8 a thread: enough
    ranges.clear()
    big = _swarm_run.initial_swarm(20 * _swarm_run.PARTICLES_PER_CALL, 16, 1, constants.m_e, 1.0)
    stepper.step(big, 0.0, 1e-12, 16)
    assert len(ranges) == 20 and max(hi - lo for lo, hi in ranges) <= _swarm_run.PARTICLES_PER_CALL
