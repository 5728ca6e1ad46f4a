"""The two-term solver's own checks: a robust start of the growth iteration, and warnings for solutions to read
with care (power not balanced, a top that cuts the distribution, electrons beyond the cross-section tables)."""

import warnings

import pytest

from collisionkit.transport import TwoTermWarning, catalogue_gas, reid_ramp, two_term_boltzmann


@pytest.fixture(scope="module")
def argon():
    return catalogue_gas("Ar")


def quietly(*args, **kwargs):
    """The result and the TwoTermWarnings it raised."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = two_term_boltzmann(*args, **kwargs)
    return result, [str(w.message) for w in caught if issubclass(w.category, TwoTermWarning)]


@pytest.mark.parametrize("top", [5000.0, 10000.0])
def test_the_growth_iteration_starts_from_above_when_zero_growth_has_no_steady_state(argon, top):
    """Argon at 1e4 Td on a grid set by hand up to 5-10 keV: at zero growth the ionizing equation has no positive
    solution (it failed with 'attachment dominated' in a gas that does not attach); started from the largest
    growth any F0 allows it settles on the found grid's value (within 0.1 %, the grids differ)."""
    found, _ = quietly(argon, 1e4)
    fixed, _ = quietly(argon, 1e4, max_energy=top)
    assert fixed.ionization_frequency_N == pytest.approx(found.ionization_frequency_N, rel=1e-3)
    assert fixed.mean_energy == pytest.approx(found.mean_energy, rel=1e-3)


def test_ordinary_solutions_raise_no_warning(argon):
    for gas, field, temperature in ((argon, 100.0, 300.0), (reid_ramp(), 12.0, 0.0), (argon, 0.0, 300.0)):
        assert quietly(gas, field, temperature)[1] == []


def test_electrons_beyond_the_tables_are_reported(argon):
    """At 1e4 Td 2 % of argon's electrons lie above 1000 eV, where its tables end (a new user got 229 eV
    silently)."""
    result, messages = quietly(argon, 1e4)
    assert any("% of the electrons lie above 1000 eV" in message for message in messages), messages
    assert quietly(argon, 1e3)[1] == []


@pytest.mark.parametrize(("kwargs", "words"), [
    ({"max_energy": 1000.0}, "the power balance is off by"),  # 1 eV cells against a 0.2 eV threshold
    ({"max_energy": 0.001}, "the top cuts the distribution"),  # F0 flat across the grid
])
def test_a_doubtful_grid_is_reported(kwargs, words):
    result, messages = quietly(reid_ramp(), 12.0, 0.0, **kwargs)
    assert any(words in message for message in messages), messages


def test_a_coarse_grid_is_reported(argon):
    result, messages = quietly(argon, 1e4, cells=50)
    assert abs(result.power_balance) > 0.1
    assert any("refine the grid (cells = 50)" in message for message in messages), messages


@pytest.mark.parametrize("temperature", [1e-300, 1e-7])
def test_a_gas_too_cold_for_the_grid_is_refused(temperature):
    with pytest.raises(ValueError, match="gas_temperature .K. must be 0 or from 1e-06"):
        two_term_boltzmann(reid_ramp(), 0.0, temperature)


def test_the_power_fractions_close_the_balance_and_name_every_process(argon):
    """The field's power split into elastic recoil, each process (its rate times its threshold; an attachment
    also takes the electron's energy), the growth and the electrons' exchange: they sum to 1 - power_balance, every
    process of the gas has its entry, and in argon at 100 Td the ionization takes the share its rate gives
    (k_i * 15.76 eV / (W E/N), computed here from the reported numbers)."""
    result, _ = quietly(argon, 100.0)
    fractions = result.power_fractions
    assert sum(fractions.values()) == pytest.approx(1.0 - result.power_balance, abs=1e-12)
    assert set(result.rate_coefficients) <= set(fractions) and {"elastic", "growth"} <= set(fractions)
    ionization = [label for label in result.rate_coefficients if "ioniz" in label.lower()]
    field_power = result.drift_velocity * result.reduced_field * 1e-21
    expected = sum(result.rate_coefficients[label] for label in ionization) * 15.7596 / field_power
    assert sum(fractions[label] for label in ionization) == pytest.approx(expected, rel=1e-3)
    assert 0.0 < fractions["elastic"] < 0.1 and abs(fractions["electron-electron"]) == 0.0
    row = result.to_row()
    assert row["power_fraction[elastic]"] == fractions["elastic"]
