"""collisionkit.edmd.run with mixtures (fractions, diameters, masses): checks, the particles, summary, checkpoints."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from collisionkit import edmd
from collisionkit._io import read_checkpoint, write_checkpoint
from collisionkit.edmd import EdmdParameters, EdmdRun
from collisionkit.edmd._run_checks import species_counts

BINARY = dict(particles=120, packing_fraction=0.3, fractions=(0.25, 0.75), diameters=(1.0, 0.6), masses=(1.0, 0.3),
              equilibration=2_000, collisions=4_000, blocks=4, seed=5)


@given(particles=st.integers(2, 10_000), weights=st.lists(st.floats(0.01, 1.0), min_size=1, max_size=6))
@settings(max_examples=200, deadline=None)
def test_species_counts_split_the_particles_by_the_largest_remainders(particles, weights):
    fractions = [weight / sum(weights) for weight in weights]
    counts = species_counts(particles, fractions)
    assert sum(counts) == particles
    assert all(abs(count - particles * fraction) < 1.0 for count, fraction in zip(counts, fractions))


@pytest.mark.parametrize(
    ("values", "words"),
    [
        ({"fractions": (0.5, 0.6)}, "fractions must sum to 1; got [0.5, 0.6]"),
        ({"fractions": (0.0, 1.0)}, "fractions[0] must be in (0, 1]; got 0"),
        ({"fractions": "0.5"}, "fractions must be a sequence of numbers"),
        ({"fractions": (1.0 / 27,) * 27}, "fractions must give 1 to 26 species; got 27"),
        ({"fractions": (0.999, 0.001), "particles": 100}, "leave a species without particles among 100"),
        ({"fractions": (0.5, 0.5), "diameters": (1.0,)}, "diameters must give one value per species (2"),
        ({"fractions": (0.5, 0.5), "diameters": (1.0, 0.09)}, "diameters[1] must be in [0.1, 1]"),
        ({"fractions": (0.5, 0.5), "diameters": (0.9, 0.5)}, "the largest must be 1"),
        ({"fractions": (0.5, 0.5), "masses": (1.0, 1e4)}, "masses[1] must be in [0.001, 1000]"),
        ({"diameters": (1.0, 0.5)}, "diameters needs fractions"),
        ({"masses": (1.0,)}, "masses needs fractions"),
        ({"fractions": (0.5, 0.5), "initial": "fcc", "particles": 108}, "needs initial random"),
    ],
)
def test_bad_mixtures_name_the_parameter_and_what_it_allows(values, words):
    with pytest.raises(ValueError) as caught:
        EdmdParameters(**values)
    assert words in str(caught.value)


def test_the_run_holds_each_species_with_its_diameter_and_mass_and_conserves_energy():
    run = EdmdRun(EdmdParameters(**BINARY))
    system = run.system
    assert run.parameters.species_counts == (30, 90)
    assert np.array_equal(np.bincount(system.species), [30, 90])
    assert np.array_equal(2 * system.radius, np.where(system.species == 0, 1.0, 0.6))
    assert np.array_equal(system.mass, np.where(system.species == 0, 1.0, 0.3))
    assert edmd.packing_fraction(system.radius, system.box[:3]) == pytest.approx(0.3, rel=1e-12)
    energy = run.system.kinetic_energy()
    momentum = (system.mass[:, None] * system.velocities()).sum(axis=0)
    run.run()
    assert run.system.kinetic_energy() == pytest.approx(energy, rel=1e-12)
    np.testing.assert_allclose((system.mass[:, None] * system.velocities()).sum(axis=0), momentum, atol=1e-11)


def test_a_mixture_s_summary_compares_with_the_mixture_theory_at_the_composition_run():
    run = EdmdRun(EdmdParameters(**BINARY)).run()
    summary = run.summary()
    composition = [0.25, 0.75]  # 30 and 90 of 120
    assert summary["species_counts"] == [30, 90]
    assert summary["theory"] == "BMCSL (Mansoori et al. 1971)"
    theory = edmd.mixture_compressibility(summary["packing_fraction"], composition, [1.0, 0.6])
    assert summary["compressibility_factor_theory"] == theory
    assert summary["compressibility_factor_relative_deviation"] == summary["compressibility_factor"] / theory - 1
    assert summary["collision_frequency_theory"] == edmd.mixture_collision_frequency(
        summary["packing_fraction"], composition, [1.0, 0.6], [1.0, 0.3], 3, 1.0)
    # one species' formulas do not hold: no Z -> omega relation, no single contact distance
    for key in ("collision_frequency_from_pressure", "contact_value", "compressibility_factor_carnahan_starling"):
        assert key not in summary
    assert summary["parameters"]["fractions"] == [0.25, 0.75]
    assert math.isnan(run.measurement().contact_value)


def test_one_species_given_as_a_mixture_runs_the_same_trajectory_as_one_species():
    plain = EdmdRun(EdmdParameters(**BINARY | dict(fractions=None, diameters=None, masses=None))).run()
    as_mixture = EdmdRun(EdmdParameters(**BINARY | dict(fractions=(1.0,), diameters=(1.0,), masses=(1.0,)))).run()
    assert np.array_equal(plain.system.positions(), as_mixture.system.positions())
    assert "contact_value" in plain.summary() and "contact_value" in as_mixture.summary()
    assert as_mixture.summary()["theory"] == "BMCSL (Mansoori et al. 1971)"


def test_a_disc_mixture_is_compared_with_the_syh_equation_of_state():
    run = EdmdRun(EdmdParameters(**BINARY | dict(dim=2, packing_fraction=0.5))).run()
    summary = run.summary()
    assert summary["theory"] == "SYH (Santos et al. 1999)"
    assert summary["compressibility_factor_theory"] == edmd.mixture_compressibility(
        summary["packing_fraction"], [0.25, 0.75], [1.0, 0.6], dim=2)


def test_a_mixture_resumes_bit_for_bit_and_keeps_its_species(tmp_path):
    straight = EdmdRun(EdmdParameters(**BINARY)).run()
    path = tmp_path / "run.npz"
    run = EdmdRun(EdmdParameters(**BINARY), checkpoint=path)
    run.save()
    resumed = EdmdRun.resume(path, fractions=[0.25, 0.75], diameters=(1.0, 0.6))  # given again: must agree
    resumed.run()
    assert np.array_equal(resumed.system.positions(), straight.system.positions())
    assert resumed.summary()["compressibility_factor"] == straight.summary()["compressibility_factor"]
    with pytest.raises(ValueError, match="masses = .* differs from the checkpoint"):
        EdmdRun.resume(path, masses=(1.0, 0.5))


@pytest.mark.parametrize("change", [dict(fractions=[0.5, 0.5]), dict(masses=[1.0, 0.4]), dict(diameters=[1.0, 0.5]),
                                    dict(fractions=None, diameters=None, masses=None)])
def test_a_checkpoint_whose_particles_are_not_its_parameters_species_is_refused(tmp_path, change):
    path = tmp_path / "run.npz"
    EdmdRun(EdmdParameters(**BINARY), checkpoint=path).save()
    saved = read_checkpoint(path, "edmd")
    write_checkpoint(path, "edmd", saved.parameters | change, saved.state, saved.arrays)
    with pytest.raises(ValueError, match="species, diameters or masses are not those its parameters give"):
        EdmdRun.resume(path)


def test_a_mixture_s_transport_run_reports_its_interdiffusion_and_no_one_species_enskog_values():
    parameters = EdmdParameters(**BINARY | dict(transport=True, collisions=12_000, blocks=4))
    summary = EdmdRun(parameters).run().summary()
    assert math.isfinite(summary["interdiffusion"]) and summary["interdiffusion_error"] > 0
    assert not [key for key in summary if key.endswith("_enskog")]


def test_a_sheared_mixture_reports_its_viscosity_without_one_species_enskog_value():
    from collisionkit.cli._edmd_report import rows

    run = EdmdRun(EdmdParameters(**BINARY | dict(shear_rate=0.2, thermostat=True, collisions=8_000)))
    summary = run.run().summary()
    assert math.isfinite(summary["shear_viscosity"]) and "shear_viscosity_enskog" not in summary
    assert summary["species_counts"] == [30, 90]
    assert rows(summary)[0][2] == "shear rate G = 0.2"  # the theory column without Enskog's value


def _partial_and_total(system, bins=200):
    from collisionkit.edmd import _pair_distribution

    r_max = float(system.box[: system.dim].min() / 2)
    kinds = int(system.species.max()) + 1
    partial = _pair_distribution.partial_histograms(system, r_max, bins, kinds)
    return partial, _pair_distribution.pair_histogram(system, r_max, bins)


@pytest.mark.parametrize("shear_rate", [0.0, 0.3])
def test_the_partial_pair_histograms_add_up_to_the_total_one(shear_rate):
    """sum_ab H_ab = H (three species, in the engine's particle order; under Lees-Edwards shear too)."""
    parameters = EdmdParameters(**BINARY | dict(fractions=(0.2, 0.3, 0.5), diameters=(1.0, 0.7, 0.5),
                                                masses=(1.0, 2.0, 0.5), shear_rate=shear_rate))
    run = EdmdRun(parameters)
    run.system.run(collisions=3_000)
    run.system._sort_by_cell()  # particles renumbered in memory: the species must follow them
    assert not np.array_equal(run.system.ids, np.arange(run.system.count))
    partial, total = _partial_and_total(run.system)
    np.testing.assert_allclose(partial.sum(axis=(0, 1)), total, atol=1e-9)
    np.testing.assert_array_equal(partial, partial.transpose(1, 0, 2))
    assert partial[2, 2].sum() > 0 and partial[0, 1].sum() > 0
    # no pair closer than its contact distance: each partial histogram is empty inside its own core
    edges = np.linspace(0.0, float(run.system.box[:3].min() / 2), 201)
    diameters = np.array([1.0, 0.7, 0.5])
    for a, b in np.ndindex(3, 3):
        inside = edges[1:] <= 0.5 * (diameters[a] + diameters[b]) * (1 - 1e-9)
        assert partial[a, b][inside].sum() == 0


def test_a_mixture_measures_its_partial_rdfs_and_contact_values_and_resumes_with_them(tmp_path):
    path = tmp_path / "run.npz"
    straight = EdmdRun(EdmdParameters(**BINARY)).run()
    m = straight.measurement()
    assert m.partial_rdf.shape == (2, 2, m.rdf.size) and m.contact_values.shape == (2, 2)
    summary = straight.summary()
    assert np.array(summary["contact_values_theory"]) == pytest.approx(
        edmd.mixture_contact_values(summary["packing_fraction"], [0.25, 0.75], [1.0, 0.6]))
    run = EdmdRun(EdmdParameters(**BINARY), checkpoint=path)
    run.save()
    EdmdRun.resume(path).run()  # writes its blocks to its checkpoint: resumed again, the same partials
    again = EdmdRun.resume(path)
    np.testing.assert_array_equal(again.measurement().partial_rdf, m.partial_rdf)
    assert again.summary()["contact_values"] == summary["contact_values"]
    # each species' D, resumed with its per-species MSD; their number-weighted mean is the D of all
    assert again.summary()["self_diffusion_species"] == summary["self_diffusion_species"]
    assert np.dot([0.25, 0.75], m.species_diffusion) == pytest.approx(m.diffusion_coefficient, rel=1e-12)
    assert np.all(m.species_diffusion_error > 0)
    assert EdmdRun(EdmdParameters(**BINARY | dict(fractions=None, diameters=None, masses=None))).run() \
        .measurement().partial_rdf is None  # one species: none


@pytest.mark.parametrize("damage", [{"sampler_partial_histograms": np.zeros((3, 3, 500))},
                                    {"sampler_partial_histograms": None},
                                    {"sampler_lag_species_all": np.zeros((2, 3))},
                                    {"sampler_lag_species_all": np.full((2, 2), np.nan)},
                                    {"sampler_lag_species_groups": np.zeros((2, 2, 5))}])
def test_a_checkpoint_with_damaged_species_records_is_refused(tmp_path, damage):
    path = tmp_path / "run.npz"
    EdmdRun(EdmdParameters(**BINARY), checkpoint=path).run()
    saved = read_checkpoint(path, "edmd")
    arrays = {name: value for name, value in (dict(saved.arrays) | damage).items() if value is not None}
    write_checkpoint(path, "edmd", saved.parameters, saved.state, arrays)
    with pytest.raises(ValueError, match="measurement arrays"):
        EdmdRun.resume(path)


@pytest.mark.parametrize(
    ("values", "words"),
    [
        ({"well_width": ((1.5, 1.4), (1.4, 1.3)), "fractions": None, "diameters": None, "masses": None},
         "well_width as a matrix (one per species pair) needs fractions"),
        ({"well_width": ((1.5, 1.4), (1.3, 1.3))}, "well_width must be a symmetric matrix"),
        ({"well_width": ((1.5,),)}, "well_width must be a number or a 2 x 2 matrix"),
        ({"well_width": ((1.5, 0.5), (0.5, 1.5))}, "well_width[0][1] must be in (1, 5]; got 0.5"),
        ({"well_width": 1.5, "well_depth": ((0.0, 0.0), (0.0, 0.0))}, "some pair of species needs a well"),
        ({"well_width": 1.5, "well_depth": ((1.0, -1.0), (-1.0, 1.0))}, "well_depth[0][1] must be in [0, 1000]"),
    ],
)
def test_bad_well_matrices_name_the_entry_and_the_rule(values, words):
    with pytest.raises(ValueError) as caught:
        EdmdParameters(**BINARY | values)
    assert words in str(caught.value)


def test_a_well_per_species_pair_runs_from_the_parameters_as_the_system_takes_it(tmp_path):
    """The run's system gets the matrices (A-A 1.5 / 1, A-B 1.4 / 0.5, B-B none); the energy is kept; T* is of the
    deepest well; the run resumes bit for bit."""
    wells = dict(well_width=((1.5, 1.4), (1.4, 1.3)), well_depth=((1.0, 0.5), (0.5, 0.0)))
    run = EdmdRun(EdmdParameters(**BINARY | wells | dict(particles=300)), checkpoint=tmp_path / "run.npz")
    np.testing.assert_array_equal(run.system.well_depth, [[1.0, 0.5], [0.5, 0.0]])
    np.testing.assert_array_equal(run.system.well_width, [[1.5, 1.4], [1.4, 1.3]])
    run.run()
    summary = run.summary()
    assert summary["well_depth"] == ((1.0, 0.5), (0.5, 0.0)) and summary["potential_energy"] < 0
    assert summary["reduced_temperature"] == summary["temperature_mean"]
    resumed = EdmdRun.resume(tmp_path / "run.npz", well_depth=[[1.0, 0.5], [0.5, 0.0]])
    assert resumed.finished and resumed.summary()["potential_energy"] == summary["potential_energy"]
