"""Is a cooling gas still homogeneous? The box-scale shear modes' energy against a homogeneous gas's share."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from collisionkit._io import CheckpointError, read_checkpoint, write_checkpoint
from collisionkit.edmd import (
    EdmdParameters, EdmdRun, HardSphereSystem, homogeneity_threshold, lattice, maxwell_boltzmann, measure,
    shear_mode_energy,
)
from collisionkit.edmd.homogeneity import (
    cooling_state_shear_energy, homogeneity_summary, shear_flow_fraction, shear_instability_length, shear_mode_count,
)


def _grid(n: int, box: float, rows: int | None = None, height: float | None = None) -> np.ndarray:
    """n x rows points of a grid filling a periodic box (box x height): sums of sin^2 and cos^2 over it are exactly
    N / 2 for wavelengths of the box."""
    rows, height = rows or n, height or box
    x, y = np.meshgrid((np.arange(n) + 0.5) * box / n, (np.arange(rows) + 0.5) * height / rows, indexing="ij")
    return np.column_stack([x.ravel(), y.ravel()])


@pytest.mark.parametrize("mass", [1.0, 3.5])
@pytest.mark.parametrize("rows, height", [(20, 12.0), (15, 7.5)])
def test_a_shear_flow_across_a_grid_gives_its_mode_n_over_two(mass, rows, height):
    # u_y = A sin(k_x x): j = -i m A N / 2 and sum m^2 u_y^2 = m^2 A^2 N / 2, so the mode's ratio is N / 2; u_x =
    # B cos(3 k_y y) is orthogonal to e^{-i k_y y}: its mode's ratio is 0; the mean of the two is N / 4 (a box of
    # unequal sides: each axis its own wavelength)
    box, n = 12.0, 20
    positions = _grid(n, box, rows, height)
    velocities = np.column_stack([0.3 * np.cos(3 * 2 * np.pi / height * positions[:, 1]),
                                  0.7 * np.sin(2 * np.pi / box * positions[:, 0])])
    assert shear_mode_energy(positions, velocities, [box, height], masses=mass) == pytest.approx(n * rows / 4,
                                                                                                   rel=1e-12)


def test_the_centre_of_mass_motion_and_the_box_position_do_not_count():
    rng = np.random.default_rng(4)
    positions, velocities = rng.uniform(0, 8, (300, 3)), rng.normal(size=(300, 3))
    masses = rng.uniform(0.5, 2.0, 300)
    value = shear_mode_energy(positions, velocities, [8, 8, 8], masses)
    assert shear_mode_energy(positions + [8, -16, 3 * 8], velocities + [5.0, -2.0, 0.5], [8, 8, 8], masses) == \
        pytest.approx(value, rel=1e-9)


@pytest.mark.parametrize("dim", [2, 3])
def test_a_homogeneous_gas_gives_gamma_m_over_m(dim):
    # velocities independent of the positions and of each other: the mean over M modes of exponential ratios,
    # Gamma(M, 1/M): mean 1, variance 1/M; 2000 draws give the mean to 1/sqrt(2000 M) and the variance to
    # sqrt((kurtosis - 1) / 2000) = sqrt((2 + 6 / M) / 2000) relative
    rng = np.random.default_rng(dim)
    modes, draws = shear_mode_count(dim), 2000
    masses = rng.choice([1.0, 0.25], 400)
    values = np.array([shear_mode_energy(rng.uniform(0, 10, (400, dim)),
                                         rng.normal(size=(400, dim)) / np.sqrt(masses)[:, None], [10.0] * dim, masses)
                       for _ in range(draws)])
    assert abs(values.mean() - 1.0) < 4 / math.sqrt(draws * modes)
    assert abs(values.var() * modes - 1.0) < 4 * math.sqrt((2 + 6 / modes) / draws)


@pytest.mark.parametrize("dim", [2, 3])
def test_the_threshold_is_crossed_by_a_homogeneous_gas_as_often_as_asked(dim):
    rng = np.random.default_rng(10 + dim)
    threshold, draws = homogeneity_threshold(dim, blocks=4, false_alarm=0.2), 4000  # 0.05 a block end
    crossed = np.mean([shear_mode_energy(rng.uniform(0, 5, (300, dim)), rng.normal(size=(300, dim)), [5.0] * dim)
                       > threshold for _ in range(draws)])
    assert abs(crossed - 0.05) < 4 * math.sqrt(0.05 * 0.95 / draws)
    assert threshold == pytest.approx(stats.gamma.isf(0.05, dim * (dim - 1), scale=1 / (dim * (dim - 1))))
    assert homogeneity_threshold(dim, blocks=100) > homogeneity_threshold(dim, blocks=10)  # more looks, higher bar


def test_the_summary_names_the_first_block_above_the_threshold_and_leaves_out_unknown_blocks():
    threshold = homogeneity_threshold(2, 3)
    summary = homogeneity_summary([math.nan, 1.0, 0.5, threshold * 2, 3.0], 2, 500, 7.5)
    assert summary == {"shear_mode_energy": 3.0, "shear_mode_energy_max": threshold * 2,
                       "shear_mode_energy_expected": 1.0, "shear_mode_energy_threshold": homogeneity_threshold(2, 4),
                       "homogeneous": False, "homogeneity_lost_after": 30.0,
                       "shear_flow_energy_fraction": pytest.approx(2 * 2 * (threshold * 2 - 1) / (2 * 500))}
    assert homogeneity_summary([1.0, 2.0], 3, 500, 5.0)["homogeneity_lost_after"] is None
    assert homogeneity_summary([math.nan, math.nan], 3, 500, 5.0) == {}
    enhanced = homogeneity_summary([1.0, 3.0 * threshold], 2, 500, 5.0, expected=4.0)  # a cooling state's flows
    assert enhanced["homogeneous"] and enhanced["shear_mode_energy_threshold"] == 4.0 * homogeneity_threshold(2, 2)


def test_a_vortex_flow_s_energy_fraction_is_what_the_flow_holds():
    # u_y = A sin(k x) on a grid without noise: R = N / 4 (two modes), the flow holds all the kinetic energy
    positions = _grid(20, 12.0)
    velocities = np.column_stack([np.zeros(400), 0.7 * np.sin(2 * np.pi / 12.0 * positions[:, 0])])
    velocities[:, 0] = 0.7 * np.sin(2 * np.pi / 12.0 * positions[:, 1])  # and u_x = A sin(k y): both modes
    value = shear_mode_energy(positions, velocities, [12.0, 12.0])
    assert value == pytest.approx(200.0) and shear_flow_fraction(value, 2, 400) == pytest.approx(1.0, abs=0.01)


@pytest.mark.parametrize("call, match", [
    (lambda: shear_mode_energy(np.zeros((4, 1)), np.zeros((4, 1)), [1.0]), "shape"),
    (lambda: shear_mode_energy(np.zeros((4, 2)), np.zeros((5, 2)), [1.0, 1.0]), "shape"),
    (lambda: shear_mode_energy(np.zeros((4, 2)), np.zeros((4, 2)), [1.0, 0.0]), "box"),
    (lambda: shear_mode_energy(np.zeros((4, 2)), np.zeros((4, 2)), [1.0, 1.0, 1.0]), "box"),
    (lambda: homogeneity_threshold(4, 10), "dim"),
    (lambda: homogeneity_threshold(3, 0), "blocks"),
    (lambda: homogeneity_threshold(3, 10.5), "blocks"),
    (lambda: homogeneity_threshold(3, 10, expected=0.5), "expected"),
    (lambda: homogeneity_threshold(3, 10, false_alarm=1.0), "false_alarm"),
])
def test_bad_arguments_are_named(call, match):
    with pytest.raises(ValueError, match=match):
        call()


COOLING = dict(dim=3, particles=500, packing_fraction=0.02, restitution=0.9, seed=3, collisions=25000, blocks=10)


def test_a_small_cooling_box_stays_homogeneous_and_a_large_one_forms_vortices():
    # 500 spheres at eta 0.02 (L = 4 mean free paths) stay below the shear instability at e 0.9; 2000 discs at
    # eta 0.05 and e 0.7 (L = 32 mean free paths) form vortices within the equilibration's 40 collisions a particle
    small = EdmdRun(EdmdParameters(**COOLING)).run()
    summary = small.summary()
    assert summary["homogeneous"] is True and summary["homogeneity_lost_after"] is None
    expected = cooling_state_shear_energy(summary["box_length"], shear_instability_length(0.9, 0.02))  # L = 0.16 L_c
    assert summary["shear_mode_energy_expected"] == pytest.approx(expected) and 1.02 < expected < 1.03
    assert summary["shear_mode_energy_max"] < summary["shear_mode_energy_threshold"] == pytest.approx(
        homogeneity_threshold(3, 10, expected=expected))
    assert "it stayed homogeneous" in small.cooling_note()
    large = EdmdRun(EdmdParameters(dim=2, particles=2000, packing_fraction=0.05, restitution=0.7, seed=3,
                                   collisions=20000, blocks=10)).run()
    summary = large.summary()
    assert summary["homogeneous"] is False and summary["homogeneity_lost_after"] == pytest.approx(2.0)
    assert summary["shear_mode_energy"] > 30 * summary["shear_mode_energy_threshold"]
    assert "it did not stay homogeneous: by C = 2 collisions" in large.cooling_note()


def test_elastic_sheared_walled_and_falling_runs_report_no_homogeneity():
    elastic = EdmdRun(EdmdParameters(**COOLING | dict(restitution=1.0))).run()
    assert "homogeneous" not in elastic.summary() and elastic.measurement().block_shear_mode_energy.size == 10
    sheared = EdmdRun(EdmdParameters(**COOLING | dict(packing_fraction=0.2, shear_rate=0.2))).run().measurement()
    positions, box = lattice("sc", 6, 0.1)

    def cooling(**walls_or_gravity):
        system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(216), 3, seed=1), 0.5, box, restitution=0.9,
                                  **walls_or_gravity)
        return measure(system, collisions=3000, blocks=3)

    walled, falling = cooling(periodic=(True, True, False)), cooling(gravity=(0.0, 0.0, -0.1), periodic=(True,) * 3)
    assert math.isfinite(walled.cooling_rate)
    for measured in (sheared, walled, falling):
        assert measured.block_shear_mode_energy is None and "homogeneous" not in measured.summary()
    periodic = cooling()
    assert periodic.summary()["homogeneous"] in (True, False) and periodic.block_shear_mode_energy.size == 3


def test_an_equilibrium_fluid_gives_one_on_average_at_any_density():
    # in equilibrium the velocities are independent of the positions however dense the fluid: E = 1 exactly; the
    # last block end of 60 seeds, Gamma(6, 1/6) each: the mean to 1/sqrt(360)
    values = [EdmdRun(EdmdParameters(particles=108, packing_fraction=0.4, initial="fcc", seed=seed, collisions=2000,
                                     blocks=2)).run().measurement().block_shear_mode_energy[-1] for seed in range(60)]
    assert abs(np.mean(values) - 1.0) < 4 / math.sqrt(6 * 60)


def test_checkpoints_keep_the_record_and_older_ones_load_with_the_blocks_unknown(tmp_path):
    path = tmp_path / "run.npz"
    straight = EdmdRun(EdmdParameters(**COOLING), checkpoint=path).run()
    saved = read_checkpoint(path, "edmd")
    np.testing.assert_array_equal(saved.arrays["sampler_shear_mode_energy"],
                                  straight.measurement().block_shear_mode_energy)
    older = tmp_path / "older.npz"  # as a version before the record would have saved it, three blocks done
    arrays = {name: value for name, value in saved.arrays.items() if name != "sampler_shear_mode_energy"}
    write_checkpoint(older, "edmd", saved.parameters, saved.state, arrays)
    resumed = EdmdRun.resume(older)
    resumed.extend(5000)
    summary = resumed.run().summary()
    blocks = resumed.measurement().block_shear_mode_energy
    assert np.isnan(blocks[:10]).all() and np.isfinite(blocks[10:]).all()
    assert summary["shear_mode_energy_threshold"] == pytest.approx(
        homogeneity_threshold(3, 2, expected=summary["shear_mode_energy_expected"]))
    damaged = tmp_path / "damaged.npz"
    write_checkpoint(damaged, "edmd", saved.parameters, saved.state,
                     dict(saved.arrays) | {"sampler_shear_mode_energy": np.full(10, -1.0)})
    with pytest.raises(CheckpointError, match="sampler_"):
        EdmdRun.resume(damaged)


@pytest.mark.parametrize("fraction, growth, says, advice", [
    (0.05, -0.01, "near or past the size", "further from the instability"),
    (0.05, 0.02, "near or past the size", "fewer collisions keep it homogeneous"),
    (0.4, 0.02, "did not stay homogeneous", "fewer collisions keep it homogeneous")])
def test_the_note_tells_flows_near_the_instability_from_vortices(fraction, growth, says, advice):
    from collisionkit.edmd._summary import homogeneity_wording

    p = EdmdParameters(dim=2, particles=1000, restitution=0.8, collisions=5000, blocks=10, equilibration=2000)
    measured = {"homogeneous": False, "homogeneity_lost_after": 1.0, "shear_mode_energy_max": 40.0,
                "shear_mode_energy_threshold": 5.0, "shear_mode_energy_expected": 1.0,
                "shear_flow_energy_fraction": fraction, "shear_mode_growth": growth}
    note = homogeneity_wording(measured, p)
    assert says in note and advice in note and "at most 40" in note
    assert "C = 1 collisions per particle measured (after 4 of equilibration, which cooled it too)" in note
    later = homogeneity_wording(measured | {"homogeneity_lost_after": 3.0, "shear_mode_energy_expected": 1.5}, p)
    assert "of equilibration" not in later and "allowing for this box's cooling state, 1.5 times it" in later
    kept = homogeneity_wording(measured | {"homogeneous": True, "homogeneity_lost_after": None}, p)
    assert kept.startswith("it stayed homogeneous") and "below 5 times" in kept


def test_an_elastic_equilibration_starts_the_cooling_with_the_measurement(tmp_path, monkeypatch):
    # with it the equilibration loses nothing (every contact elastic and smooth), the floor comes back after, and a
    # large box's shear flows start near an uncorrelated gas's share and grow (vortices form during the measurement)
    parameters = dict(dim=2, particles=2000, packing_fraction=0.05, restitution=0.7, seed=3, collisions=20000,
                      blocks=10)
    elastic = EdmdRun(EdmdParameters(**parameters, elastic_equilibration=True), checkpoint=tmp_path / "run.npz")
    floor = elastic.system.elastic_below
    elastic.run()
    measured = elastic.measurement()
    assert elastic.system.energy_lost == pytest.approx(measured.energy_lost, rel=1e-12) and floor > 0
    assert elastic.system.elastic_below == floor and measured.block_temperature[0] > 0.3
    assert measured.block_shear_mode_energy[0] < 10 < 100 < measured.block_shear_mode_energy[-1]
    assert EdmdRun.resume(tmp_path / "run.npz").parameters.elastic_equilibration is True
    inelastic = EdmdRun(EdmdParameters(**parameters)).run()
    assert inelastic.system.energy_lost > 1.5 * inelastic.measurement().energy_lost  # it cooled before measuring
    assert inelastic.measurement().block_temperature[0] < 1e-3
    interrupted = EdmdRun(EdmdParameters(**parameters, elastic_equilibration=True))
    monkeypatch.setattr(type(interrupted.system), "run", lambda *args, **kwargs: (_ for _ in ()).throw(
        KeyboardInterrupt))
    with pytest.raises(KeyboardInterrupt):
        interrupted.run()
    assert interrupted.system.elastic_below == floor  # restored on the way out
    with pytest.raises(ValueError, match="elastic_equilibration must be true or false"):
        EdmdParameters(elastic_equilibration="yes")
