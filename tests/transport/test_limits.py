"""The swarm's allowed ranges (collisionkit.transport._validation): absurd fields and gas temperatures are refused
by the library before any work, naming the argument, instead of running into overflow or a runaway; and the
runaway message names the field as well as the cross sections."""

import warnings

import numpy as np
import pytest
from scipy import constants

from collisionkit._kernels import transport as kernels
from collisionkit.transport import SwarmParameters, reid_ramp, simulate_swarm
from collisionkit.transport import _swarm_run, _validation
from collisionkit.transport._tables import build_tables
from collisionkit.transport._waveform import waveform_knots

FLAT_1E300 = [(0.0, 1e300), (1.0, 1e300)]  # a user's waveform file: "0 1e300" and "1 1e300"


@pytest.mark.parametrize("arguments, words", [
    ({"reduced_field": 1e30}, r"reduced_field \(E/N, Td\) must be in \[0, 1e\+06\]; got 1e\+30"),
    ({"reduced_field": [12.0, -5.0]}, r"reduced_field \(E/N, Td\) must be in \[0, 1e\+06\]; got -5"),
    ({"gas_temperature": 1e12}, r"gas_temperature \(K\) must be in \[0, 100000\]; got 1e\+12"),
    ({"reduced_magnetic_field": 1e300}, r"reduced_magnetic_field \(B/N, Hx\) must be in \[0, 1e\+06\]"),
    ({"reduced_frequency": 1e300}, r"reduced_frequency \(omega/N, rad m\^3/s\) must be 0 \(a static field\) or in "
                                   r"\[1e-20, 1e-08\]; got 1e\+300"),
    ({"reduced_frequency": 1e-300}, r"reduced_frequency .* or in \[1e-20, 1e-08\]; got 1e-300"),
    ({"reduced_frequency": 2e-14, "waveform": FLAT_1E300}, r"waveform E/E0 values must lie in \[-1e\+06, 1e\+06\]"),
    ({"reduced_frequency": 2e-14, "reduced_field": 100.0, "waveform": [(0.0, 1.0), (0.5, 2e4)]},
     r"the waveform's peak E/N \(the amplitude 100 Td times the largest \|E/E0\|, 20000\) is 2e\+06 Td; it must be "
     r"<= 1e\+06 Td"),
])
def test_the_parameters_refuse_absurd_fields_naming_the_argument(arguments, words):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no numpy overflow on the way (RuntimeWarning)
        with pytest.raises(ValueError, match=words):
            SwarmParameters(model="reid", **arguments)


def test_the_ends_of_the_ranges_are_allowed():
    p = SwarmParameters(model="reid", reduced_field=[0.0, 1e6], reduced_magnetic_field=1e6, gas_temperature=1e5,
                        reduced_frequency=1e-8, waveform=[(0.0, 1.0), (0.5, -1.0)])
    assert p.reduced_field == (0.0, 1e6) and p.reduced_frequency == 1e-8
    assert SwarmParameters(model="reid", reduced_frequency=1e-20).reduced_frequency == 1e-20
    assert SwarmParameters(model="reid", reduced_frequency=0.0).reduced_frequency == 0.0
    assert waveform_knots([(0.0, 1e6), (1.0, -1e6)])[1].max() == 1e6


@pytest.mark.parametrize("arguments, words", [
    ({"reduced_field": 1e30}, r"reduced_field \(E/N, Td\) must lie in \[0.0, 1000000.0\]"),
    ({"gas_temperature": 1e12}, r"gas_temperature \(K\) must lie in \[0.0, 100000.0\]"),
    ({"reduced_magnetic_field": 1e300}, r"reduced_magnetic_field \(B/N, Hx\) must lie in"),
    ({"reduced_frequency": 1e-300}, r"reduced_frequency .* must be 0 \(a static field\) or in \[1e-20, 1e-08\]"),
    ({"reduced_frequency": 2e-14, "waveform": FLAT_1E300}, r"waveform E/E0 values must lie in"),
    ({"reduced_frequency": 2e-14, "waveform": [(0.0, 1.0), (0.5, 1e5)]}, r"the waveform's peak E/N"),
])
def test_simulate_swarm_refuses_them_too_before_any_work(arguments, words):
    arguments = {"reduced_field": 12.0} | arguments
    field = arguments.pop("reduced_field")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=words):
            simulate_swarm(reid_ramp(), field, particles=128, threads=1, **arguments)


def test_the_ranges_are_finite_and_hold_the_practical_ones():
    low, high = _validation.REDUCED_FREQUENCY_RANGE
    assert 0 < low < 2 * np.pi * 13.56e6 / 2.45e25 < high  # 13.56 MHz at 1 atm
    electron_cyclotron_per_hx = constants.e / constants.m_e * 1e-27  # omega_c/N per Hx
    assert high > 10 * electron_cyclotron_per_hx * _validation.MAX_REDUCED_MAGNETIC_FIELD
    assert _validation.MAX_REDUCED_FIELD == 1e6 and _validation.MAX_GAS_TEMPERATURE == 1e5


def _stepper():
    tables = build_tables(reid_ramp(), constants.m_e, 0.0)
    return _swarm_run.Stepper(tables, kernels.derived_field(np.zeros(3), np.zeros(3)), constants.m_e, 1e24, 0, 1)


def _speed(energy_ev):
    return np.sqrt(2.0 * energy_ev * constants.e / constants.m_e)


def test_the_runaway_message_names_the_field_as_well_as_the_cross_sections():
    """A particle far above the top of the tables (E/N = 1e30 reached 3e27 eV): the field may drive the swarm
    beyond the energies the cross sections cover; the message blamed the cross sections (a units slip) alone."""
    stepper = _stepper()
    try:
        above = stepper._runaway_message(_speed(3e27), 1e-12)
        below = stepper._runaway_message(_speed(0.3), 4e275)
    finally:
        stepper.close()
    assert "ran away in the field" in above and "E/N" in above and "beyond the energies the cross sections cover" \
        in above and "lower it" in above and "units slip" in above
    # within the tables, a step far longer than its collisions: an oscillating field's period too long
    assert "raise omega/N" in below and "units slip" in below and "ran away" not in below


def test_whole_float_counts_are_taken_as_integers_and_fractions_refused():
    # particles=1e5 was a TypeError in simulate_slab and simulate_swarm (a float), though 1e5 is how users write it
    assert _validation.integer_in_range(1e5, "particles", 64) == 100_000
    assert type(_validation.integer_in_range(64.0, "particles", 64)) is int
    with pytest.raises(TypeError, match="particles must be an integer"):
        _validation.integer_in_range(64.5, "particles", 64)
    with pytest.raises(TypeError, match="particles must be an integer"):
        _validation.integer_in_range(True, "particles", 0)
