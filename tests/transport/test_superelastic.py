"""Superelastic collisions: the detailed-balance cross section, level populations, the kernel's tables, and thermal
equilibrium (E/N = 0: the swarm takes the gas's Maxwellian, and each excitation is balanced by its inverse)."""

import math

import numpy as np
import pytest
from scipy import constants, stats

from collisionkit.transport import (
    Gas, Process, Species, level_populations, reid_ramp, simulate_swarm, superelastic_cross_section,
)
from collisionkit.transport import _swarm_run
from collisionkit.transport._channels import JUMP_FLOOR
from collisionkit.transport._tables import CURVE_RTOL, build_tables
from collisionkit.transport.superelastic import BOLTZMANN_EV

E, ME, AMU = constants.e, constants.m_e, constants.atomic_mass


def _step():
    """An excitation table that rises, falls and is zero at its threshold (1 eV), g_k/g_0 = 3."""
    return Process("excitation", [1.0, 2.0, 5.0], [0.0, 4e-20, 1e-20], threshold=1.0, weight_ratio=3.0, label="x*")


def _two_level(population=None, jump=False, mass=4 * AMU):
    """Elastic 1e-20 m^2 and a reversible excitation of 0.1 eV (g_k/g_0 = 3), a ramp from its threshold (or a step)."""
    sigma = [1e-20, 9.9e-19] if jump else [0.0, 9.9e-19]
    return Gas((Species("two", mass, (Process("elastic", [0, 10], [1e-20, 1e-20]),
                                      Process("excitation", [0.1, 10.0], sigma, threshold=0.1, weight_ratio=3.0,
                                              label="two*", population=population))),))


def test_the_detailed_balance_cross_section_is_the_hand_computed_value():
    # sigma_sup(e) = (g0/gk) ((e + D)/e) sigma_ex(e + D): at 0.5 eV, (1/3)(1.5/0.5) sigma_ex(1.5) = (1/3)(3)(2e-20);
    # at 2 eV, (1/3)(3/2) sigma_ex(3) = (1/3)(1.5)(4e-20 - 3e-20/3) = 1.5e-20; beyond the table's end at 5 eV,
    # sigma_ex stays 1e-20: at 9 eV, (1/3)(10/9) 1e-20
    values = superelastic_cross_section(_step(), [0.5, 2.0, 9.0])
    np.testing.assert_allclose(values, [2e-20, 1.5e-20, 1e-20 * 10 / 27], rtol=1e-14)
    with pytest.raises(ValueError, match="reversible excitation"):
        superelastic_cross_section(reid_ramp().species[0].processes[1], 1.0)
    with pytest.raises(ValueError, match="energy"):
        superelastic_cross_section(_step(), 0.0)


def test_the_kernel_tables_hold_the_detailed_balance_cross_section_on_the_excited_level_s_share():
    """The superelastic column, interpolated as the kernel does, is (fraction x level population) x sigma_sup
    within the refinement tolerance, the forward column carries the ground level's share, and the threshold is
    minus the energy the electron gains."""
    gas = Gas.mixture({Gas((Species("x", 20 * AMU, (Process("elastic", [0, 10], [1e-20, 1e-20]), _step())),)): 0.25,
                       reid_ramp(): 0.75})
    temperature = 6000.0
    tables = build_tables(gas, ME, temperature)
    assert tables.labels == ("x:elastic", "x:x*", "x:x* (superelastic)", "reid:elastic", "reid:excitation")
    assert list(tables.kind) == [0, 1, 4, 0, 1] and tables.threshold[2] == pytest.approx(-1.0 * E)
    ground, levels = level_populations(gas.species[0], temperature)
    boltzmann = 3.0 * math.exp(-1.0 / (BOLTZMANN_EV * temperature))
    assert ground == pytest.approx(1 / (1 + boltzmann)) and levels[1] == pytest.approx(boltzmann / (1 + boltzmann))
    energies = np.concatenate([np.linspace(1e-3, 20.0, 4001), [0.5, 2.0, 4.0, 3.999]])
    column = np.interp(energies * E, tables.nodes, tables.sigma[:, 2])
    exact = 0.25 * levels[1] * superelastic_cross_section(_step(), energies)
    np.testing.assert_allclose(column, exact, rtol=3 * CURVE_RTOL)
    forward = np.interp(energies * E, tables.nodes, tables.sigma[:, 1])
    np.testing.assert_allclose(forward, 0.25 * ground * _step().cross_section_at(energies), rtol=1e-12, atol=1e-30)
    # the summed table the kernel rejects null trials with is the sum of the species' columns
    np.testing.assert_allclose(tables.sigma_total[:, 0], tables.sigma[:, :3].sum(axis=1), rtol=1e-15)
    # at 0 K the levels are empty: no superelastic channel, the forward process on the whole species
    cold = build_tables(gas, ME, 0.0)
    assert "x:x* (superelastic)" not in cold.labels
    np.testing.assert_allclose(np.interp(2.0 * E, cold.nodes, cold.sigma[:, 1]), 0.25 * 4e-20)


def test_a_table_that_jumps_at_its_threshold_is_held_below_the_floor():
    """sigma_ex(D) > 0 makes sigma_sup ~ D sigma_ex(D) / e: held at its value at JUMP_FLOOR x D below it."""
    gas = _two_level(jump=True)
    tables = build_tables(gas, ME, 1000.0)
    floor = JUMP_FLOOR * 0.1
    process = gas.species[0].processes[1]
    _, levels = level_populations(gas.species[0], 1000.0)
    held = levels[1] * float(superelastic_cross_section(process, floor))
    low = np.interp(np.array([0.0, 0.3 * floor, floor]) * E, tables.nodes, tables.sigma[:, 2])
    np.testing.assert_allclose(low, held, rtol=1e-12)
    assert np.interp(2 * floor * E, tables.nodes, tables.sigma[:, 2]) == pytest.approx(
        levels[1] * float(superelastic_cross_section(process, 2 * floor)), rel=3 * CURVE_RTOL)


def test_level_populations_split_the_species_and_set_values_replace_boltzmann():
    species = Species("m", 28 * AMU, (
        Process("elastic", [0, 10], [1e-20, 1e-20]),
        Process("excitation", [0.2, 10], [0, 1e-20], threshold=0.2, weight_ratio=3.0, label="a"),
        Process("excitation", [0.5, 10], [0, 1e-20], threshold=0.5, weight_ratio=5.0, label="b"),
        Process("excitation", [9.0, 20], [0, 1e-20], threshold=9.0, label="one-way")))
    temperature = 2000.0
    kt = BOLTZMANN_EV * temperature
    a, b = 3 * math.exp(-0.2 / kt), 5 * math.exp(-0.5 / kt)
    ground, levels = level_populations(species, temperature)
    assert ground == pytest.approx(1 / (1 + a + b))
    assert levels == pytest.approx((0.0, a / (1 + a + b), b / (1 + a + b), 0.0))
    assert ground + sum(levels) == pytest.approx(1.0)
    gas = Gas((species,)).with_populations({"m:a": 0.1})
    ground, levels = level_populations(gas.species[0], temperature)
    assert levels[1] == 0.1 and ground == pytest.approx(0.9 / (1 + b)) and levels[2] == pytest.approx(ground * b)
    assert level_populations(species, 0.0) == (1.0, (0.0, 0.0, 0.0, 0.0))
    with pytest.raises(ValueError, match="sum to 1.2"):
        level_populations(Gas((species,)).with_populations({"m:a": 0.6, "m:b": 0.6}).species[0], 300.0)
    with pytest.raises(ValueError, match="'m:one-way' is not a reversible excitation of the gas; choices: m:a, m:b"):
        Gas((species,)).with_populations({"m:one-way": 0.1})


@pytest.mark.parametrize(
    "kwargs, words",
    [
        (dict(kind="elastic", weight_ratio=2.0), "applies to excitation only"),
        (dict(kind="excitation", population=0.1), "applies to a reversible excitation"),
        (dict(kind="excitation", weight_ratio=2.0, population=1.0), r"population must lie in \[0, 1\)"),
        (dict(kind="excitation", weight_ratio=2.0, rate_coefficient=1e-15), "needs a cross-section table"),
        (dict(kind="elastic", scattering="forward"), "forward scattering transfers no momentum"),
        (dict(kind="excitation", weight_ratio=2.0, superelastic_scattering="bent"), "superelastic_scattering must be"),
    ],
)
def test_impossible_reversible_processes_are_refused(kwargs, words):
    kind = kwargs.pop("kind")
    with pytest.raises(ValueError, match=words):
        Process(kind, [0.1, 10], [0.0, 1e-20], threshold=0.1 if kind == "excitation" else 0.0, **kwargs)


def _equilibrium(population, monkeypatch, seed=3):
    """E/N = 0 at 1000 K on the two-level gas (heavy targets: the excitation pair, not elastic recoil, sets the
    energy): the result and the energies of the swarm's particles at the end (independent: a conservative swarm)."""
    captured = {}
    original = _swarm_run.SwarmRun._result

    def keep_the_energies(self, *args):
        captured["energies"] = self._current_energies()
        return original(self, *args)

    monkeypatch.setattr(_swarm_run.SwarmRun, "_result", keep_the_energies)
    kt = BOLTZMANN_EV * 1000.0
    result = simulate_swarm(_two_level(population), 0.0, gas_temperature=1000.0, particles=4000, seed=seed,
                            threads=2, initial_energy=1.5 * kt, tolerances={"mean_energy": 2e-3},
                            collision_budget=5e7)
    return result, captured["energies"], kt


def test_at_zero_field_a_superelastic_pair_holds_the_swarm_at_the_gas_maxwellian(monkeypatch):
    """Detailed balance makes the Maxwell-Boltzmann distribution at T_g stationary: the final energies of 4000
    independent electrons pass a Kolmogorov-Smirnov test against the gamma(3/2, kT) law (p > 1e-3; the statistic
    would be 0.24 with the excited level overpopulated, see below), <e> = 3/2 kT within 4 standard errors, and
    every excitation is undone by a superelastic collision as often (rates equal within 4 combined errors)."""
    result, energies, kt = _equilibrium(None, monkeypatch)
    assert result.converged and energies.size == 4000
    assert stats.kstest(energies, stats.gamma(1.5, scale=kt).cdf).pvalue > 1e-3
    assert abs(result.mean_energy - 1.5 * kt) < 4 * result.mean_energy_error
    assert result.mean_energy_error < 3e-3 * 1.5 * kt
    forward, inverse = result.rate_coefficients["two:two*"], result.rate_coefficients["two:two* (superelastic)"]
    errors = result.rate_coefficient_errors
    assert forward > 0 and abs(forward - inverse) < 4 * math.hypot(errors["two:two*"], errors["two:two* (superelastic)"])
    assert result.rate_coefficients["two:elastic"] > 0


def test_an_overpopulated_excited_level_heats_the_swarm_above_the_gas(monkeypatch):
    """The control of the test above: a level population of 0.6 (Boltzmann: 0.48 at 1000 K) gives energy to the
    swarm, far beyond its errors and the KS test's reach."""
    result, energies, kt = _equilibrium(0.6, monkeypatch)
    assert result.mean_energy > 1.5 * kt + 20 * result.mean_energy_error
    assert stats.kstest(energies, stats.gamma(1.5, scale=kt).cdf).pvalue < 1e-10


@pytest.mark.parametrize("jump", [False, True])
def test_the_trial_frequency_bounds_superelastic_and_anisotropic_rates_in_whole_runs(jump, monkeypatch):
    """With the kernel's check on, no trial finds a true rate above the trial bound: a warm gas (moving targets)
    with a superelastic inverse (held below its floor when the table jumps at the threshold), anisotropic laws on
    every kind and a field; the early null rejection is off in checked runs, so the unchecked run is compared too
    (the same collisions: the summed table rejects exactly the trials the processes would)."""
    from collisionkit.transport import swarm

    two = _two_level(jump=jump, mass=20 * ME).species[0]
    extra = tuple(Process("excitation", [e, 30.0], [0.0, 2e-20], threshold=e, label=f"x{e}") for e in (0.5, 1.5))
    # five processes (with the inverse): enough for the kernel's early rejection against the summed table
    gas = Gas((Species(two.name, two.mass, two.processes + extra),)).with_scattering(
        {"elastic": "okhrimovskyy", "excitation": "vahedi-surendra", "superelastic": "forward"})
    from collisionkit._kernels.transport.advance import EARLY_REJECTION
    assert len(gas.species[0].processes) + 1 >= EARLY_REJECTION
    options = dict(gas_temperature=3000.0, particles=640, seed=21, threads=2, tolerances={"mean_energy": 0.05},
                   collision_budget=2e6)
    plain = simulate_swarm(gas, 20.0, **options)
    monkeypatch.setattr(swarm, "CHECK_BOUND", True)
    checked = simulate_swarm(gas, 20.0, **options)
    assert checked.rate_coefficients["two:two* (superelastic)"] > 0
    assert checked.null_collisions > 0.01 * checked.collisions
    assert checked.extras["bound_violations"] == 0
    assert (plain.collisions, plain.null_collisions, plain.mean_energy) == (
        checked.collisions, checked.null_collisions, checked.mean_energy)
