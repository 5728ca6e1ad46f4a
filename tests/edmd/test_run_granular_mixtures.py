"""collisionkit.edmd.run with inelastic mixtures: a restitution per species pair, each species' temperature."""

from __future__ import annotations

import math

import numpy as np
import pytest

from collisionkit import edmd
from collisionkit._io import read_checkpoint, write_checkpoint
from collisionkit.edmd import EdmdParameters, EdmdRun

GRANULAR = dict(particles=200, packing_fraction=0.05, fractions=(0.5, 0.5), masses=(1.0, 0.25),
                restitution=((0.9, 0.8), (0.8, 0.7)), equilibration=1_000, collisions=6_000, blocks=6, seed=4)


@pytest.mark.parametrize(
    ("values", "words"),
    [
        ({"restitution": ((0.9, 0.8), (0.8, 0.7)), "fractions": None, "masses": None},
         "restitution as a matrix (one per species pair) needs fractions"),
        ({"restitution": ((0.9, 0.8), (0.7, 0.7))}, "restitution must be a symmetric matrix"),
        ({"restitution": ((0.9, 0.8),)}, "restitution must be a number or a 2 x 2 matrix"),
        ({"restitution": ((0.9, 1.2), (1.2, 0.7))}, "restitution[0][1] must be in [0, 1]; got 1.2"),
        ({"restitution": ((1.0, math.nan), (math.nan, 1.0))}, "restitution[0][1] must be finite"),
        ({"restitution": ((1.0, 0.9), (0.9, 1.0)), "transport": True},
         "transport needs restitution 1 and restitution_law constant (the Einstein-Helfand relations hold in "
         "equilibrium, which an inelastic gas never reaches); got restitution [[1.0, 0.9], [0.9, 1.0]]"),
        ({"restitution": ((1.0, 0.9), (0.9, 1.0)), "well_width": 1.5},
         "well_width cannot be combined with restitution below 1"),
    ],
)
def test_bad_restitution_matrices_name_the_entry_and_the_rule(values, words):
    with pytest.raises(ValueError) as caught:
        EdmdParameters(**GRANULAR | values)
    assert words in str(caught.value)


def test_an_elastic_matrix_is_an_elastic_run():
    parameters = EdmdParameters(**GRANULAR | dict(restitution=((1.0, 1.0), (1.0, 1.0))))
    assert parameters.elastic and not EdmdParameters(**GRANULAR).elastic
    summary = EdmdRun(parameters).run().summary()
    assert summary["elastic"] and summary["temperature_species_theory"] == [1.0, 1.0]
    assert "compressibility_factor_theory" in summary  # the equation of state applies


def test_each_pair_loses_energy_at_its_own_restitution():
    """The system gets the matrix; one A-B contact head on at unit speed loses (1 - e_AB^2) mu g^2 / 2."""
    run = EdmdRun(EdmdParameters(**GRANULAR))
    np.testing.assert_array_equal(run.system.restitution, [[0.9, 0.8], [0.8, 0.7]])
    system = edmd.HardSphereSystem([[2.0, 5.0, 5.0], [4.0, 5.0, 5.0]], [[0.5, 0.0, 0.0], [-0.5, 0.0, 0.0]], 0.5,
                                   10.0, [1.0, 0.25], species=[0, 1], restitution=run.system.restitution,
                                   elastic_below=0.0)
    system.run(collisions=1)
    reduced = 0.25 / 1.25
    assert system.energy_lost == pytest.approx(0.5 * reduced * (1.0 - 0.8**2) * 1.0**2, rel=1e-12)


def test_an_inelastic_mixture_reports_each_species_temperature_and_the_cooling_state_s():
    summary = EdmdRun(EdmdParameters(**GRANULAR)).run().summary()
    assert not summary["elastic"] and summary["restitution"] == ((0.9, 0.8), (0.8, 0.7))
    measured, errors = np.array(summary["temperature_species"]), np.array(summary["temperature_species_error"])
    theory = edmd.homogeneous_cooling_temperatures(0.05, [0.5, 0.5], [1.0, 1.0], [1.0, 0.25],
                                                   [[0.9, 0.8], [0.8, 0.7]])
    np.testing.assert_allclose(summary["temperature_species_theory"], theory, rtol=1e-12)
    assert np.dot([0.5, 0.5], measured) == pytest.approx(1.0, rel=1e-12)  # T = sum x_a T_a at every block's end
    assert np.all(errors > 0) and measured[0] > 1.0 > measured[1]  # the heavy species is the hotter
    assert "compressibility_factor_theory" not in summary
    assert summary["cooling_rate_error"] > 0 and summary["cooling_rate_theory"] == edmd.homogeneous_cooling_rate(
        0.05, [0.5, 0.5], [1.0, 1.0], [1.0, 0.25], [[0.9, 0.8], [0.8, 0.7]])
    assert abs(summary["cooling_rate_deviation_sigmas"]) < 5


def test_the_cooling_rate_is_the_mean_slope_of_ln_kt_over_the_blocks_and_only_of_a_gas_that_cools():
    """-d ln kT / dC from the block ends (C: 2 per pair collision / N), from the second block on; an elastic run and a
    sheared one (a steady state) have none."""
    run = EdmdRun(EdmdParameters(**GRANULAR | dict(fractions=None, masses=None, restitution=0.9))).run()
    temperatures = np.array(run.sampler.records["temperature"])
    per_block = 2 * 1_000 / 200
    rates = -np.log(temperatures[1:] / temperatures[:-1]) / per_block
    summary = run.summary()
    assert summary["cooling_rate"] == pytest.approx(rates.mean(), rel=1e-12)
    assert summary["cooling_rate_error"] == pytest.approx(rates.std(ddof=1) / math.sqrt(5), rel=1e-12)
    assert summary["cooling_rate_theory"] == pytest.approx((1 - 0.81) / 3, rel=1e-12)
    elastic = EdmdRun(EdmdParameters(**GRANULAR | dict(restitution=1.0))).run().summary()
    sheared = EdmdRun(EdmdParameters(**GRANULAR | dict(restitution=0.9, shear_rate=0.5))).run().summary()
    assert "cooling_rate" not in elastic and "cooling_rate" not in sheared and "cooling_rate_theory" not in sheared


def test_species_temperatures_resume_bit_for_bit_and_older_checkpoints_without_them_still_load(tmp_path,
                                                                                              monkeypatch):
    path = tmp_path / "run.npz"
    straight = EdmdRun(EdmdParameters(**GRANULAR)).run().summary()
    real, calls = edmd.HardSphereSystem.run, []

    def killed_in_the_fourth_block(system, *args, **kwargs):
        calls.append(1)
        if len(calls) == 5:  # the equilibration's chunk, three blocks, then the kill
            raise KeyboardInterrupt
        return real(system, *args, **kwargs)

    run = EdmdRun(EdmdParameters(**GRANULAR), checkpoint=path)  # (the random start's compression runs it too)
    monkeypatch.setattr(edmd.HardSphereSystem, "run", killed_in_the_fourth_block)
    with pytest.raises(KeyboardInterrupt):
        run.run()
    monkeypatch.undo()
    saved = read_checkpoint(path, "edmd")
    assert len(saved.arrays["sampler_species_temperature"]) == 3
    older = tmp_path / "older.npz"  # the same run as a version before the record would have saved it
    write_checkpoint(older, "edmd", saved.parameters, saved.state,
                     {name: value for name, value in saved.arrays.items() if name != "sampler_species_temperature"})
    resumed = EdmdRun.resume(path, restitution=[[0.9, 0.8], [0.8, 0.7]])  # given again as lists: must agree
    assert resumed.run().summary()["temperature_species"] == straight["temperature_species"]
    blocks = np.array(resumed.sampler.records["species_temperature"])
    finished_older = EdmdRun.resume(older).run()  # its first three blocks' temperatures unknown: the last three count
    summary = finished_older.summary()
    np.testing.assert_allclose(summary["temperature_species"], blocks[3:].mean(axis=0), rtol=1e-12)
    assert np.isnan(finished_older.measurement().block_species_temperatures[:3]).all()
    assert summary["compressibility_factor"] == straight["compressibility_factor"]


@pytest.mark.parametrize("rows", [np.ones((6, 3)), np.ones((5, 2)), np.full((6, 2), [0.5, np.inf]),
                                  np.full((6, 2), [-5.0, 7.0]), np.full((6, 2), [1.2, 1.2])])
def test_a_checkpoint_with_damaged_species_temperatures_is_refused(tmp_path, rows):
    path = tmp_path / "run.npz"
    EdmdRun(EdmdParameters(**GRANULAR), checkpoint=path).run()
    saved = read_checkpoint(path, "edmd")
    write_checkpoint(path, "edmd", saved.parameters, saved.state,
                     dict(saved.arrays) | {"sampler_species_temperature": rows})
    with pytest.raises(ValueError, match="measurement arrays"):
        EdmdRun.resume(path)


def test_a_cooling_gas_has_the_mean_free_path_of_the_elastic_gas_at_its_density():
    """The mean free path does not depend on kT: block by block (the ends' mean speeds over the block's collision
    frequency, the cooling taken out) a gas cooling from kT 1 to 0.002 gives the elastic gas's (it gave 4.8 +- 1.4
    against 5.59 +- 0.02 from the run's pooled speeds over its mean frequency). The 1 % allows for the cooling
    state's own velocity distribution (a2 = -0.015 changes mean speed over collision rate by about a2 / 8, and a
    reviewer's 30 seeds found the two 0.1 % apart)."""
    run = dict(particles=1000, packing_fraction=0.02, equilibration=0, collisions=50_000, seed=2)
    elastic = EdmdRun(EdmdParameters(**run)).run().summary()
    cooling = EdmdRun(EdmdParameters(**run | dict(restitution=0.9))).run().summary()
    error = math.hypot(elastic["mean_free_path_error"], cooling["mean_free_path_error"])
    assert abs(cooling["mean_free_path"] - elastic["mean_free_path"]) < 4 * error + 0.01 * elastic["mean_free_path"]
    assert cooling["mean_free_path_error"] < 0.01 * cooling["mean_free_path"] and cooling["temperature"] < 0.01


def test_an_elastic_gas_has_maxwell_s_velocity_cumulant_and_a_mixture_of_masses_none():
    """a2 = d <v^4> / ((d+2) <v^2>^2) - 1 is 0 for Maxwell's distribution: within 4 errors (each ~0.005 for 2000
    particles and 10 blocks; the microcanonical correction, about -2 / (d N), is far below)."""
    summary = EdmdRun(EdmdParameters(particles=2000, packing_fraction=0.1, collisions=40_000, seed=3)).run().summary()
    assert summary["sonine_a2_theory"] == 0.0 and 0 < summary["sonine_a2_error"] < 0.01
    assert abs(summary["sonine_a2"]) < 4 * summary["sonine_a2_error"]
    assert "sonine_a2" not in EdmdRun(EdmdParameters(**GRANULAR)).run().summary()  # unlike masses: no one a2
