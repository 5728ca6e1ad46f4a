"""Tests of collisionkit.edmd: invariants, conservation and the hard-sphere equation of state."""

import itertools
import math
import time

import numba
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import optimize, stats

from collisionkit import edmd
from collisionkit._kernels import edmd as kernels


def fcc_system(cells=4, eta=0.4, seed=1, **options):
    positions, box = edmd.lattice("fcc", cells, eta)
    velocities = edmd.maxwell_boltzmann(np.ones(len(positions)), 3, rng=seed)
    return edmd.HardSphereSystem(positions, velocities, 0.5, box, **options)


def hexagonal_system(cells=12, eta=0.3, seed=1, **options):
    positions, box = edmd.lattice("hexagonal", cells, eta)
    velocities = edmd.maxwell_boltzmann(np.ones(len(positions)), 2, rng=seed)
    return edmd.HardSphereSystem(positions, velocities, 0.5, box, **options)


# ------------------------------------------------------------------ kernels


@pytest.mark.parametrize("growth", [0.0, 0.05, 0.5])
def test_pair_contact_time_matches_root_finding(growth):
    rng = np.random.default_rng(5)
    contact, scale = 1.0, 0.7
    times = np.linspace(0, 20, 40001)
    hits = misses = 0
    for _ in range(200):
        r = rng.normal(size=3) * 2
        if np.linalg.norm(r) <= contact * scale:
            continue
        u = -r * rng.uniform(0, 1) + rng.normal(size=3) * 0.5  # mostly approaching
        tau = kernels.pair_contact_time(*r, *u, contact, scale, growth, np.inf)

        def gap(t):
            return np.linalg.norm(r + np.multiply.outer(t, u), axis=-1) - contact * (scale + growth * t)

        crossing = np.flatnonzero(gap(times) <= 0)
        if crossing.size == 0:
            assert tau == math.inf or tau > times[-2]
            misses += 1
            continue
        first = crossing[0]
        expected = optimize.brentq(lambda t: float(gap(np.array(t))), times[first - 1], times[first], xtol=1e-14)
        assert tau == pytest.approx(expected, rel=1e-9, abs=1e-12)
        hits += 1
    assert hits > 30 and misses > 5


def test_boundary_root_cases():
    # a point 1 below a boundary moving up at 2: reaches it at 0.5
    assert kernels.first_root_from_below(0.0, 2.0, -1.0) == 0.5
    # thrown up against gravity it turns back before the boundary
    assert kernels.first_root_from_below(-1.0, 1.0, -1.0) == math.inf
    # accelerating towards it from rest: 0.5 t^2 = 2
    assert kernels.first_root_from_below(0.5, 0.0, -2.0) == pytest.approx(2.0, rel=1e-15)
    # round-off past the boundary but moving out: now
    assert kernels.first_root_from_below(0.0, 1.0, 1e-17) == 0.0


# ------------------------------------------------------------------ set-up


def test_lattices_have_the_requested_packing_fraction():
    for kind, dim in (("square", 2), ("hexagonal", 2), ("sc", 3), ("fcc", 3)):
        positions, box = edmd.lattice(kind, 4, 0.3)
        radii = np.full(len(positions), 0.5)
        assert edmd.packing_fraction(radii, box) == pytest.approx(0.3, rel=1e-12)
        assert positions.shape[1] == dim
    with pytest.raises(ValueError, match="close packing"):
        edmd.lattice("sc", 4, 0.6)
    with pytest.raises(ValueError, match="kind"):
        edmd.lattice("bcc", 4, 0.3)


def test_maxwell_boltzmann_has_zero_momentum_and_exact_temperature():
    masses = np.linspace(0.5, 2.0, 300)
    v = edmd.maxwell_boltzmann(masses, 3, kT=1.7, rng=3)
    np.testing.assert_allclose((masses[:, None] * v).sum(axis=0), 0.0, atol=1e-12)
    assert 0.5 * np.sum(masses[:, None] * v**2) / (1.5 * 300) == pytest.approx(1.7, rel=1e-14)


@pytest.mark.parametrize(("dim", "eta"), [(3, 0.5), (2, 0.7)])
def test_compression_reaches_the_target_without_overlaps(dim, eta):
    system = edmd.random_fluid(dim, 400, eta, rng=2)
    assert edmd.packing_fraction(system.radius, system.box[:dim]) == pytest.approx(eta, rel=1e-12)
    assert system.check() > -1e-9
    assert system.temperature() == pytest.approx(1.0, rel=1e-12)
    np.testing.assert_allclose(system.momentum(), 0.0, atol=1e-10)
    system.run(collisions=20 * 400)
    assert system.check() > -1e-9


@pytest.mark.parametrize("moved", [[0.2, 0.1], [-0.3, 0.0]])
def test_overlapping_positions_are_a_value_error_naming_the_pair(moved):
    # was a RuntimeError giving only "smallest surface gap -0.776": which of 36 discs?
    positions, box = edmd.lattice("square", 6, 0.3)
    positions = positions.copy()
    positions[17] = (positions[3] + moved) % box  # the second case wraps across x = 0
    with pytest.raises(ValueError, match=r"positions overlap: particles 3 and 17, surface gap -0\.\d+"):
        edmd.HardSphereSystem(positions, np.zeros_like(positions), 0.5, box)


def test_bad_input_is_rejected_with_names():
    positions, box = edmd.lattice("sc", 4, 0.3)
    v = np.zeros_like(positions)
    with pytest.raises(edmd.OverlapError):
        edmd.HardSphereSystem(positions, v, 0.7, box)
    with pytest.raises(ValueError, match="box"):
        edmd.HardSphereSystem(positions[:8] * 0.3, v[:8], 0.5, 2.0)
    with pytest.raises(ValueError, match="radii"):
        edmd.HardSphereSystem(positions, v, -0.5, box)
    with pytest.raises(ValueError, match="masses"):
        edmd.HardSphereSystem(positions, v, 0.5, box, masses=0.0)
    with pytest.raises(ValueError, match="restitution"):
        edmd.HardSphereSystem(positions, v, 0.5, box, restitution=1.2)
    with pytest.raises(ValueError, match="velocities"):
        edmd.HardSphereSystem(positions, v[:, :2], 0.5, box)
    with pytest.raises(ValueError, match="inside the walls"):
        edmd.HardSphereSystem(positions + box[0], v, 0.5, box, periodic=False)
    with pytest.raises(ValueError, match="packing_fraction"):
        edmd.random_fluid(3, 100, 0.55)
    system = edmd.HardSphereSystem(positions, v, 0.5, box)
    with pytest.raises(ValueError, match="collisions"):
        system.run(collisions=-1)
    with pytest.raises(ValueError, match="collisions or time"):
        system.run()


def square_system(velocities=None):
    positions, box = edmd.lattice("square", 4, 0.3)
    if velocities is None:
        velocities = edmd.maxwell_boltzmann(np.ones(16), 2, rng=1)
    return edmd.HardSphereSystem(positions, velocities, 0.5, box)


@pytest.mark.parametrize(
    ("options", "error", "name"),
    [
        (dict(collisions=10, chunk=0), ValueError, "chunk"),  # used to loop forever
        (dict(collisions=10, chunk=-5), ValueError, "chunk"),
        (dict(collisions=10, chunk=True), TypeError, "chunk"),
        (dict(collisions=10, chunk=2.5), TypeError, "chunk"),
        (dict(collisions=True), TypeError, "collisions"),
        (dict(time=True), TypeError, "time"),
        (dict(time="1"), TypeError, "time"),
        (dict(time=math.nan), ValueError, "time"),
    ],
)
def test_run_rejects_bad_counts_and_times(options, error, name):
    with pytest.raises(error, match=name):
        square_system().run(**options)


@pytest.mark.parametrize("function", [edmd.carnahan_starling, edmd.hansen_goos, edmd.henderson])
@pytest.mark.parametrize(("eta", "error"), [(-0.1, ValueError), (1.0, ValueError), (1.5, ValueError),
                                            (2.0, ValueError), (math.nan, ValueError), ([0.2, 1.0], ValueError),
                                            (True, TypeError), ("0.3", TypeError)])
def test_equations_of_state_need_a_packing_fraction_in_0_1(function, eta, error):
    with pytest.raises(error, match="eta"):
        function(eta)


def test_equations_of_state_give_the_ideal_gas_at_zero_density():
    for function in (edmd.carnahan_starling, edmd.hansen_goos, edmd.henderson):
        assert function(0.0) == 1.0
        np.testing.assert_allclose(function([0.0, 1e-12]), 1.0, rtol=1e-10)


@pytest.mark.parametrize(
    ("arguments", "error", "name"),
    [
        (dict(diameter=0), ValueError, "diameter"),
        (dict(diameter=math.inf), ValueError, "diameter"),
        (dict(mass=-1), ValueError, "mass"),
        (dict(kT=math.nan), ValueError, "kT"),
        (dict(kT=True), TypeError, "kT"),
        (dict(compressibility=0.5), ValueError, "compressibility"),
        (dict(dim=5), ValueError, "dim"),
        (dict(dim=True), TypeError, "dim"),
    ],
)
def test_enskog_collision_frequency_checks_its_arguments(arguments, error, name):
    with pytest.raises(error, match=name):
        edmd.enskog_collision_frequency(**(dict(compressibility=2.0, dim=3) | arguments))


@pytest.mark.parametrize(
    ("arguments", "error", "name"),
    [
        (dict(kT=0), ValueError, "kT"),
        (dict(kT=-1), ValueError, "kT"),
        (dict(kT=math.inf), ValueError, "kT"),
        (dict(masses=np.array([1.0, -1.0, 1.0])), ValueError, "masses"),
        (dict(masses=np.ones(1)), ValueError, "masses .*at least 2|masses .*N >= 2"),
        (dict(masses=[True, True]), TypeError, "masses"),
        (dict(dim=0), ValueError, "dim"),
        (dict(dim=2.0), TypeError, "dim"),
    ],
)
def test_maxwell_boltzmann_checks_its_arguments(arguments, error, name):
    with pytest.raises(error, match=name):
        edmd.maxwell_boltzmann(**(dict(masses=np.ones(3), dim=3) | arguments))


@pytest.mark.parametrize(
    ("arguments", "error", "name"),
    [
        (dict(kT=-1), ValueError, "kT"),  # used to blame the velocities
        (dict(diameters=-1.0), ValueError, "diameters"),
        (dict(growth_rate=True), TypeError, "growth_rate"),
        (dict(packing_fraction="0.2"), TypeError, "packing_fraction"),
        (dict(particles=True), TypeError, "particles"),
        (dict(dim=2.0), TypeError, "dim"),
    ],
)
def test_random_fluid_checks_its_arguments(arguments, error, name):
    with pytest.raises(error, match=name):
        edmd.random_fluid(**(dict(dim=2, particles=50, packing_fraction=0.2) | arguments))


@pytest.mark.parametrize(
    ("arguments", "error", "name"),
    [
        (dict(diameter=0.0), ValueError, "diameter"),
        (dict(diameter=math.nan), ValueError, "diameter"),
        (dict(diameter=-1), ValueError, "diameter"),
        (dict(cells=True), TypeError, "cells"),
        (dict(cells=0), ValueError, "cells"),
        (dict(cells=2.0), TypeError, "cells"),
        (dict(packing_fraction=math.nan), ValueError, "packing_fraction"),
        (dict(packing_fraction="0.3"), TypeError, "packing_fraction"),
    ],
)
def test_lattice_checks_its_arguments(arguments, error, name):
    with pytest.raises(error, match=name):
        edmd.lattice(**(dict(kind="sc", cells=2, packing_fraction=0.3) | arguments))


@pytest.mark.parametrize(
    ("radii", "box", "name"),
    [([-0.5], [1.0, 1.0], "radii"), ([0.5], [1.0, 1.0, 1.0, 1.0], "box"), ([0.5], [0.0, 1.0], "box"),
     ([0.5], 1.0, "box"), ([math.nan], [1.0, 1.0], "radii")],
)
def test_packing_fraction_checks_its_arguments(radii, box, name):
    with pytest.raises(ValueError, match=name):
        edmd.packing_fraction(radii, box)


def test_rescale_temperature_and_check_reject_bad_values():
    system = square_system()
    for kT in (-1.0, 0.0, math.nan):
        with pytest.raises(ValueError, match="kT"):
            system.rescale_temperature(kT)
    with pytest.raises(ValueError, match="at rest"):
        square_system(np.zeros((16, 2))).rescale_temperature(1.0)
    for tolerance in (-1.0, math.nan):
        with pytest.raises(ValueError, match="tolerance"):
            system.check(tolerance=tolerance)
    assert system.temperature() == pytest.approx(1.0, rel=1e-12)  # untouched


@pytest.mark.parametrize(
    ("options", "error", "name"),
    [
        (dict(radii="a"), TypeError, "radii"),
        (dict(masses=1 + 1j), TypeError, "masses"),
        (dict(law_speed="1"), TypeError, "law_speed"),
        (dict(law_exponent=True), TypeError, "law_exponent"),
        (dict(neighbour_shell="1"), TypeError, "neighbour_shell"),
        (dict(neighbour_shell=np.array([0.5, 0.5])), ValueError, "neighbour_shell"),
        (dict(elastic_below="1"), TypeError, "elastic_below"),
        (dict(wall_restitution="1"), TypeError, "wall_restitution"),
        (dict(wall_restitution=1.5), ValueError, "wall_restitution"),
        (dict(periodic=[True, True, False]), ValueError, "periodic"),
        (dict(periodic="no"), TypeError, "periodic"),
        (dict(periodic=[0, 2]), TypeError, "periodic"),
        (dict(box="10"), TypeError, "box"),
        (dict(species=1.7), ValueError, "species"),
        (dict(species=True), TypeError, "species"),
        (dict(restitution=np.nan), ValueError, "restitution must lie"),
        (dict(restitution_law=["constant"]), ValueError, "restitution_law"),
        (dict(gravity=[True, False]), TypeError, "gravity"),
    ],
)
def test_system_arguments_are_named_when_rejected(options, error, name):
    positions, box = edmd.lattice("square", 4, 0.3)
    arguments = dict(positions=positions, velocities=np.zeros((16, 2)), radii=0.5, box=box) | options
    with pytest.raises(error, match=name):
        edmd.HardSphereSystem(**arguments)


def test_sampler_needs_a_system():
    with pytest.raises(TypeError, match="system must be a HardSphereSystem"):
        edmd.Sampler("x", 100, 2)
    with pytest.raises(TypeError, match="system"):
        edmd.measure("x", 100, 2)
    with pytest.raises(TypeError, match="blocks"):
        edmd.Sampler(square_system(), 100, True)


# ------------------------------------------------------------------ dynamics


def test_two_spheres_collide_when_the_quadratic_says():
    positions = np.array([[2.0, 5.0, 5.0], [6.0, 5.3, 5.0]])
    velocities = np.array([[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]])
    system = edmd.HardSphereSystem(positions, velocities, 0.5, 20.0)
    system.run(collisions=1)
    expected = (4.0 - math.sqrt(1.0 - 0.3**2)) / 2.0
    assert system.elapsed == pytest.approx(expected, rel=1e-14)
    v = system.velocities()
    np.testing.assert_allclose(v.sum(axis=0), 0.0, atol=1e-15)
    assert np.sum(v**2) == pytest.approx(2.0, rel=1e-14)


def test_long_elastic_run_keeps_the_invariants():
    system = fcc_system(cells=5, eta=0.45)
    energy = system.kinetic_energy()
    for _ in range(5):
        system.run(collisions=40_000)
        assert system.check() > -1e-9  # no overlaps: no event was missed
    assert system.kinetic_energy() == pytest.approx(energy, rel=1e-12)
    np.testing.assert_allclose(system.momentum(), 0.0, atol=1e-10)
    assert system.collisions == 200_000


def test_closed_box_with_gravity_conserves_energy_and_keeps_particles_in():
    positions, box = edmd.lattice("sc", 6, 0.2)
    n = len(positions)
    velocities = edmd.maxwell_boltzmann(np.ones(n), 3, rng=4)
    system = edmd.HardSphereSystem(positions, velocities, 0.5, box, periodic=False, gravity=[0.0, 0.3, -1.0])

    def energy():
        return system.kinetic_energy() - np.sum(system.positions() @ np.array([0.0, 0.3, -1.0]))

    before = energy()
    system.run(collisions=30_000)
    assert energy() == pytest.approx(before, rel=1e-11)
    assert system.check() > -1e-9
    inside = system.positions()
    assert np.all(inside >= 0.5 - 1e-9) and np.all(inside <= box - 0.5 + 1e-9)
    assert system.acc[kernels.ACC_WALL_COLLISIONS] > 0


def test_polydisperse_mixture_in_a_channel():
    rng = np.random.default_rng(6)
    positions, box = edmd.lattice("sc", 6, 0.25)
    n = len(positions)
    radii = np.where(rng.random(n) < 0.5, 0.5, 0.3)
    masses = (radii / 0.5) ** 3
    velocities = edmd.maxwell_boltzmann(masses, 3, rng=rng)
    system = edmd.HardSphereSystem(positions, velocities, radii, box, masses, periodic=[True, False, True])
    energy, momentum = system.kinetic_energy(), system.momentum()
    system.run(collisions=30_000)
    assert system.check() > -1e-9
    assert system.kinetic_energy() == pytest.approx(energy, rel=1e-11)
    # walls only on y: momentum along x and z is conserved
    np.testing.assert_allclose(system.momentum()[[0, 2]], momentum[[0, 2]], atol=1e-10)


def test_neighbour_lists_are_symmetric_and_complete():
    """Every pair whose anchors are within the list radius is listed, both ways, and no pair beyond it.

    The cells hold float32 anchors, so a pair within their round-off of the
    radius may be listed too (harmless: the list is a superset).
    """
    rng = np.random.default_rng(3)
    positions, box = edmd.lattice("fcc", 4, 0.35)
    radii = np.where(rng.random(len(positions)) < 0.5, 0.5, 0.35)
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(len(radii)), 3, rng=rng), radii, box)
    system.run(collisions=20 * system.count)  # lists rebuilt one particle at a time
    shell, scale = system.params[kernels.P_SHELL], system.params[kernels.P_LIST_SCALE]
    length = system.box[:3]
    slack = kernels.ANCHOR_ROUNDING * (length.max() + 1.0)
    listed = {(i, int(j)) for i in range(system.count) for j in system.neighbours[i, : system.neighbour_count[i]]}
    within, allowed = set(), set()
    for i in range(system.count):
        separation = system.anchor - system.anchor[i]
        separation -= length * np.round(separation / length)
        distance = np.sqrt(np.sum(separation**2, axis=1))
        reach = (system.p[:, kernels.R] + system.p[i, kernels.R]) * scale + shell
        within |= {(i, int(j)) for j in np.flatnonzero(distance <= reach) if j != i}
        allowed |= {(i, int(j)) for j in np.flatnonzero(distance <= reach + 2 * slack) if j != i}
    assert within <= listed <= allowed
    assert len(within) > 8 * system.count
    assert all((j, i) in listed for i, j in listed)


def test_lists_grow_when_they_overflow_mid_run():
    """Rows cut to the longest list of the lattice: the melting fluid outgrows them at once."""
    system = fcc_system(cells=4, eta=0.45)
    width = int(system.neighbour_count.max())
    system.neighbours = np.ascontiguousarray(system.neighbours[:, :width])
    energy = system.kinetic_energy()
    system.run(collisions=40 * system.count)
    assert system.neighbours.shape[1] > width
    assert system.check() > -1e-9
    assert system.kinetic_energy() == pytest.approx(energy, rel=1e-12)


def test_cells_grow_for_a_mixture_of_small_and_large_spheres():
    rng = np.random.default_rng(8)
    diameters = np.where(rng.random(400) < 0.8, 0.2, 1.0)
    system = edmd.random_fluid(3, 400, 0.3, rng=rng, diameters=diameters, masses=diameters**3)
    assert system.cell_members.shape[1] > 12  # more small spheres per cell than the default slots
    energy = system.kinetic_energy()
    system.run(collisions=20 * system.count)
    assert system.check() > -1e-9
    assert system.kinetic_energy() == pytest.approx(energy, rel=1e-11)


def test_smallest_periodic_box_narrows_the_shell():
    """A box of 3 diameters leaves room for a shell below half a diameter; runs stay exact."""
    positions = np.array([[0.5, 0.5, 0.5], [2.0, 1.5, 1.0], [1.0, 2.2, 2.4]])
    velocities = edmd.maxwell_boltzmann(np.ones(3), 3, rng=2)
    system = edmd.HardSphereSystem(positions, velocities, 0.5, 3.0)
    assert 0 < system.params[kernels.P_SHELL] < 0.5
    energy = system.kinetic_energy()
    system.run(collisions=5000)
    assert system.check() > -1e-9
    assert system.kinetic_energy() == pytest.approx(energy, rel=1e-12)


def test_positions_are_folded_into_the_box_with_consistent_images():
    system = fcc_system(cells=3, eta=0.2)
    system.run(collisions=3000)
    folded, unwrapped = system.positions(), system.positions(unwrapped=True)
    box = system.box[:3]
    assert np.all((folded >= 0) & (folded < box))
    np.testing.assert_allclose(folded + system.image * box, unwrapped, atol=1e-12)


def test_neighbour_shell_is_validated():
    positions, box = edmd.lattice("sc", 4, 0.3)
    with pytest.raises(ValueError, match="neighbour_shell"):
        edmd.HardSphereSystem(positions, np.zeros_like(positions), 0.5, box, neighbour_shell=0.0)


def test_species_restitution_matrix_and_energy_bookkeeping():
    positions, box = edmd.lattice("sc", 6, 0.3)
    n = len(positions)
    species = np.arange(n) % 2
    matrix = np.array([[1.0, 0.7], [0.7, 1.0]])
    system = edmd.HardSphereSystem(
        positions, edmd.maxwell_boltzmann(np.ones(n), 3, rng=7), 0.5, box, species=species, restitution=matrix
    )
    before = system.kinetic_energy()
    system.run(collisions=5_000)
    lost = before - system.kinetic_energy()
    assert lost > 0
    assert system.acc[kernels.ACC_ENERGY_LOST] == pytest.approx(lost, rel=1e-10)
    np.testing.assert_allclose(system.momentum(), 0.0, atol=1e-10)


def test_bridges_law_and_the_elastic_floor():
    def head_on(speed, **options):
        positions = np.array([[4.0, 5.0, 5.0], [6.0, 5.0, 5.0]])
        velocities = np.array([[speed / 2, 0, 0], [-speed / 2, 0, 0]])
        system = edmd.HardSphereSystem(positions, velocities, 0.5, 20.0, **options)
        system.run(collisions=1)
        v = system.velocities()
        return (v[1, 0] - v[0, 0]) / speed  # separation / approach speed

    assert head_on(4.0, restitution_law="bridges", law_speed=1.0) == pytest.approx(4.0**-0.234, rel=1e-12)
    assert head_on(0.5, restitution_law="bridges", law_speed=1.0) == pytest.approx(1.0, rel=1e-12)
    assert head_on(2.0, restitution=0.5) == pytest.approx(0.5, rel=1e-12)
    assert head_on(2.0, restitution=0.5, elastic_below=3.0) == pytest.approx(1.0, rel=1e-12)


def test_checkpoint_resume_is_bit_for_bit(tmp_path):
    straight = fcc_system(cells=4, eta=0.4)
    straight.run(collisions=10_000)
    straight.run(collisions=10_000)

    interrupted = fcc_system(cells=4, eta=0.4)
    interrupted.run(collisions=10_000)
    interrupted.save(tmp_path / "state.npz")
    resumed = edmd.HardSphereSystem.load(tmp_path / "state.npz")
    resumed.run(collisions=10_000)
    np.testing.assert_array_equal(resumed.positions(), straight.positions())
    np.testing.assert_array_equal(resumed.velocities(), straight.velocities())
    np.testing.assert_array_equal(resumed.acc, straight.acc)
    assert resumed.elapsed == straight.elapsed


def test_a_checkpoint_of_another_engine_format_is_refused():
    state = fcc_system(cells=2, eta=0.3).state_dict()
    edmd.HardSphereSystem.from_state_dict(state)  # its own format: fine
    del state["format"]  # as written before formats were numbered
    with pytest.raises(ValueError, match="engine format 1"):
        edmd.HardSphereSystem.from_state_dict(state)


def test_the_measured_rate_leaves_out_compiling_the_event_loop(monkeypatch):
    # stand in for numba's first compilation (tens of seconds on a cold cache) with a pause in the first call
    original = edmd.HardSphereSystem._run_events
    calls = []

    def slow_first_call(self, collisions, t_stop):
        if not calls:
            time.sleep(2.0)
        calls.append(collisions)
        return original(self, collisions, t_stop)

    monkeypatch.setattr(edmd.HardSphereSystem, "_run_events", slow_first_call)
    m = edmd.measure(fcc_system(cells=3, eta=0.3), collisions=4_000, blocks=2)
    assert calls[0] == 0 and m.collisions == 4_000  # compiled by a run of no collisions, before the clock
    assert m.wall_seconds < 1.0


def test_the_measured_rate_counts_the_sampling_of_each_block(monkeypatch):
    # the collisions_per_second is the wall clock of the measurement phase: g(r) and the
    # other samples are part of it, so a slow sample must slow the reported rate
    original = edmd._pair_histogram

    def slow_histogram(*args, **kwargs):
        time.sleep(0.5)
        return original(*args, **kwargs)

    monkeypatch.setattr(edmd, "_pair_histogram", slow_histogram)
    m = edmd.measure(fcc_system(cells=3, eta=0.3), collisions=4_000, blocks=2)
    assert m.wall_seconds >= 2 * 0.5
    assert m.collisions_per_second <= 4_000 / (2 * 0.5)


def brute_force_pair_histogram(points, box, periodic, r_max, bins):
    """Every ordered pair by numpy broadcasting: the independent route for the cell-list kernel."""
    separation = points[None, :, :] - points[:, None, :]
    for k, wrapped in enumerate(periodic):
        if wrapped:
            separation[..., k] -= box[k] * np.round(separation[..., k] / box[k])
    distance = np.sqrt(np.sum(separation**2, axis=-1))
    distance = distance[~np.eye(len(points), dtype=bool)]
    return np.histogram(distance, bins=bins, range=(0.0, r_max))[0]


@given(
    dim=st.sampled_from([2, 3]),
    count=st.integers(2, 120),
    sides=st.lists(st.floats(1.0, 9.0), min_size=3, max_size=3),
    periodic=st.lists(st.booleans(), min_size=3, max_size=3),
    reach=st.floats(0.05, 0.5),
    seed=st.integers(0, 2**32 - 1),
)
def test_pair_distance_histogram_counts_every_pair_once_each_way(dim, count, sides, periodic, reach, seed):
    # cells of 1, 2, 3 or more per axis, walls and periodic axes mixed (a channel), 2D and 3D
    box, periodic = np.array(sides[:dim]), np.array(periodic[:dim])
    points = np.random.default_rng(seed).uniform(0.0, box, size=(count, dim))
    r_max = reach * box.min()
    counts = edmd._pair_distance_histogram(points, box, periodic, r_max, 40)
    np.testing.assert_array_equal(counts, brute_force_pair_histogram(points, box, periodic, r_max, 40))


def test_g_of_r_is_zero_inside_contact():
    # snapshots were taken at the last collision, whose pair sits at contact: 400 discs gave g = 0.115 in the bin
    # just inside contact, which hard discs cannot have (and an inflated contact value)
    system = edmd.random_fluid(2, 400, 0.3, rng=1)
    m = edmd.measure(system, collisions=40_000, blocks=20)
    step = m.rdf_r[1] - m.rdf_r[0]
    assert np.all(m.rdf[m.rdf_r + step / 2 <= 2 * np.max(system.radius)] == 0.0)


def test_g_of_r_of_a_dilute_gas_tends_to_one():
    # beyond two diameters a hard-disc gas has g = 1 + O(n^2); the N^2 normalisation gave (N - 1) / N = 0.95 here
    system = edmd.random_fluid(2, 20, 0.02, rng=2)
    m = edmd.measure(system, collisions=2000 * 20, blocks=2000)
    far = m.rdf[m.rdf_r > 4 * np.max(system.radius)]
    error = far.std() / math.sqrt(far.size)  # independent bins
    assert abs(far.mean() - 1.0) < 4 * error, (far.mean(), error)


# ------------------------------------------------------------------ physics validation


def reference_check(measurement, reference, tolerance=0.005):
    z, error = measurement.compressibility_factor, measurement.compressibility_factor_error
    assert error < 0.3 * tolerance * reference  # the run is long enough to test at this tolerance
    assert abs(z - reference) < tolerance * reference


@pytest.mark.slow
@pytest.mark.parametrize("eta", [0.2, 0.4])
def test_hard_sphere_equation_of_state(eta):
    """Z within 0.5 % of Hansen-Goos (J. Chem. Phys. 144, 164506, 2016)."""
    system = fcc_system(cells=6, eta=eta, seed=11)
    system.run(collisions=100 * system.count)
    m = edmd.measure(system, collisions=1_000 * system.count, blocks=20)
    reference_check(m, float(edmd.hansen_goos(eta)))
    # Enskog: omega = (2d / sigma) (Z - 1) sqrt(kT / (pi m)), within the statistical errors
    expected = float(edmd.enskog_collision_frequency(m.compressibility_factor, 3, kT=m.temperature))
    spread = math.hypot(m.collision_frequency_error, expected * m.compressibility_factor_error / (m.compressibility_factor - 1))
    assert abs(m.collision_frequency - expected) < 4 * spread + 1e-3 * expected
    # contact value: Z = 1 + 4 eta g(sigma), g from the pair distribution extrapolated to contact
    from_pressure = (m.compressibility_factor - 1) / (4 * eta)
    assert abs(m.contact_value - from_pressure) < 4 * m.contact_value_error + 0.01 * from_pressure


@pytest.mark.slow
def test_hard_disc_equation_of_state():
    """Z within 0.5 % of Henderson (Mol. Phys. 30, 971, 1975) at eta = 0.3."""
    system = hexagonal_system(cells=16, eta=0.3, seed=12)
    system.run(collisions=100 * system.count)
    m = edmd.measure(system, collisions=1_000 * system.count, blocks=20)
    reference_check(m, float(edmd.henderson(0.3)))
    expected = float(edmd.enskog_collision_frequency(m.compressibility_factor, 2, kT=m.temperature))
    assert m.collision_frequency == pytest.approx(expected, rel=0.01)


@pytest.mark.parametrize("dim", [2, 3])
def test_speeds_follow_maxwell_boltzmann(dim):
    system = fcc_system(cells=8, eta=0.3) if dim == 3 else hexagonal_system(cells=32, eta=0.3)
    system.run(collisions=30 * system.count)
    speeds = np.linalg.norm(system.velocities(), axis=1)
    scale = math.sqrt(system.temperature())
    law = stats.maxwell(scale=scale) if dim == 3 else stats.rayleigh(scale=scale)
    assert stats.kstest(speeds, law.cdf).pvalue > 1e-3
    # a lattice start is not Maxwellian in position, but the run has had time to relax the speeds
    assert abs(np.mean(speeds) - law.mean()) < 4 * law.std() / math.sqrt(len(speeds))


@pytest.mark.slow
def test_homogeneous_cooling_follows_haff_law():
    """T = T0 exp(-2 (1 - e^2) C / (d N)) while the gas stays homogeneous (e = 0.9, small N)."""
    e = 0.9
    means = []
    for seed in (11, 12, 13, 14):
        equilibrium = fcc_system(cells=4, eta=0.1, seed=seed)  # N = 256
        equilibrium.run(collisions=20 * equilibrium.count)
        system = edmd.HardSphereSystem(
            equilibrium.positions(), equilibrium.velocities(), 0.5, equilibrium.box[:3], restitution=e
        )
        t0 = system.temperature()
        ratios = []
        for _ in range(5):
            system.run(collisions=system.count)  # two collisions per particle
            expected = t0 * math.exp(-2 * (1 - e * e) * system.collisions / (3 * system.count))
            ratios.append(system.temperature() / expected)
        system.check()
        # the Sonine correction is under 0.4 %; T of a 256-particle gas fluctuates by ~2 %
        assert np.all(np.abs(np.array(ratios) - 1) < 0.06)
        means.append(np.mean(ratios))
    # one run's mean scatters by ~1.2 % (8 seeds); the mean of four by ~0.6 %: 4 sigma
    assert abs(np.mean(means) - 1) < 0.025


@numba.njit
def _apply_queue_updates(updates, queue, tree, leaves):
    """Apply (particle, time) updates through the kernel; return the tree's winner after each."""
    winners = np.empty((len(updates), 2))
    for k in range(len(updates)):
        kernels.queue_update(int(updates[k, 0]), updates[k, 1], queue, tree, leaves)
        winners[k, 0] = tree[1, 0]
        winners[k, 1] = tree[1, 1]
    return winners


@settings(max_examples=60, deadline=None)
@given(
    count=st.integers(1, 40),
    updates=st.lists(st.tuples(st.integers(0, 39), st.sampled_from([0.0, 0.5, 1.0, 2.0, math.inf])), max_size=60),
)
def test_event_queue_gives_the_earliest_event_lowest_index_on_ties(count, updates):
    blocks = -(-count // kernels.QUEUE_BLOCK)
    leaves = 1 << max(blocks - 1, 1).bit_length()
    queue = np.full(blocks * kernels.QUEUE_BLOCK, math.inf)
    queue[:count] = np.linspace(3.0, 4.0, count)
    tree = np.zeros((2 * leaves, 2))
    kernels.tree_build(tree, queue, leaves)
    reference = queue[:count].copy()
    assert tree[1, 1] == 0
    steps = np.array([(i % count, when) for i, when in updates], dtype=float).reshape(-1, 2)
    winners = _apply_queue_updates(steps, queue, tree, leaves)
    for (i, when), (winner_time, winner) in zip(steps, winners):
        reference[int(i)] = when
        assert winner_time == reference.min()
        assert winner == np.flatnonzero(reference == reference.min())[0]


# ------------------------------------------------------------------ found by a mutation audit


def _taylor(function, order):
    """Taylor coefficients c_0..c_order of function(eta) at 0, from a least-squares fit on [1e-3, 0.02]."""
    eta = np.linspace(1e-3, 0.02, 60)
    return np.polyfit(eta, np.asarray(function(eta), dtype=float), order + 2)[::-1][: order + 1]


def test_equations_of_state_reproduce_the_exact_virial_coefficients():
    """Z = 1 + B2 eta + B3 eta^2 + ...: hard spheres B2 = 4, B3 = 10 exactly, B4 = 18.3648 (Boltzmann);
    Carnahan-Starling's are the integers n^2 + n - 2 (4, 10, 18). Hard discs: B2 = 2, B3 = 16/3 - 4 sqrt(3)/pi
    = 3.1280 exactly; Henderson gives 25/8. Kills: carnahan_starling -eta^3 -> +eta^3 (B4 = 20),
    hansen_goos (1 - eta)^3 -> (1 - eta)^2 (B2 = -5), henderson eta^2/8 -> eta^2/4 (B3 = 3.25)."""
    cs = _taylor(edmd.carnahan_starling, 4)
    np.testing.assert_allclose(cs[:4], [1.0, 4.0, 10.0, 18.0], rtol=1e-4)
    hg = _taylor(edmd.hansen_goos, 4)
    np.testing.assert_allclose(hg[:3], [1.0, 4.0, 10.0], rtol=1e-4)
    assert hg[3] == pytest.approx(18.3648, rel=1e-3)
    disc = _taylor(edmd.henderson, 3)
    np.testing.assert_allclose(disc[:2], [1.0, 2.0], rtol=1e-5)
    assert disc[2] == pytest.approx(16 / 3 - 4 * math.sqrt(3) / math.pi, rel=2e-3)
    # and the two hard-sphere equations agree within 0.3 % up to eta = 0.45 (both fit simulation data to that)
    eta = np.linspace(0.05, 0.45, 9)
    np.testing.assert_allclose(edmd.carnahan_starling(eta), edmd.hansen_goos(eta), rtol=3e-3)


@pytest.mark.parametrize(("dim", "diameter", "kT", "mass"), [(3, 1.0, 1.0, 1.0), (3, 2.0, 1.5, 3.0), (2, 0.5, 2.0, 0.7)])
def test_enskog_collision_frequency_is_the_kinetic_theory_rate(dim, diameter, kT, mass):
    """Independent derivation: omega = n <v_rel> S g, with <v_rel> = sqrt(2) <v> and the cross 'section'
    S = pi sigma^2 (3D) or 2 sigma (2D); the same g(sigma) gives Z - 1 = (2 pi / 3) n sigma^3 g (3D) or
    (pi / 2) n sigma^2 g (2D). Kills: 2 d / sigma -> d / sigma, sqrt(kT / (pi m)) -> sqrt(kT / (2 pi m))."""
    n, g = 0.37, 1.23
    mean_speed = math.sqrt(8 * kT / (math.pi * mass)) if dim == 3 else math.sqrt(math.pi * kT / (2 * mass))
    if dim == 3:
        z = 1 + 2 * math.pi / 3 * n * diameter**3 * g
        expected = n * math.sqrt(2) * mean_speed * math.pi * diameter**2 * g
    else:
        z = 1 + math.pi / 2 * n * diameter**2 * g
        expected = n * math.sqrt(2) * mean_speed * 2 * diameter * g
    got = float(edmd.enskog_collision_frequency(z, dim, diameter=diameter, kT=kT, mass=mass))
    assert got == pytest.approx(expected, rel=1e-12)


@pytest.fixture(scope="module")
def dense_discs_of_diameter_two():
    """288 discs of diameter 2 (not 1, so that a virial missing its contact distance shows) at eta = 0.3."""
    positions, box = edmd.lattice("hexagonal", 12, 0.3, diameter=2.0)
    n = len(positions)
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(n), 2, rng=5), 1.0, box)
    system.run(collisions=30 * n)
    # 502 bins up to 5 diameters: contact (bin edge 100.4) falls inside a bin, not on an edge
    return system, edmd.measure(system, collisions=200 * n, blocks=10, rdf_bins=502)


def test_pressure_of_discs_of_diameter_two_follows_henderson(dense_discs_of_diameter_two):
    """Z within 5 standard errors + 0.5 % of Henderson (0.3 % accurate at eta = 0.3, and O(1/N) for N = 288);
    P = Z n kT by definition (elastic: kT = 1 exactly). Kills: virial += impulse (no contact distance),
    the virial divided without d, the pressure without d or without its ideal part n kT."""
    system, m = dense_discs_of_diameter_two
    reference = float(edmd.henderson(0.3))
    assert m.compressibility_factor_error < 0.01 * reference
    assert abs(m.compressibility_factor - reference) < 5 * m.compressibility_factor_error + 0.005 * reference
    n_kT = system.count * m.temperature / system.volume
    assert m.pressure == pytest.approx(m.compressibility_factor * n_kT, rel=1e-9)
    assert m.pressure_error == pytest.approx(m.compressibility_factor_error * n_kT, rel=1e-9)


def test_collision_frequency_of_discs_matches_enskog_from_the_measured_pressure(dense_discs_of_diameter_two):
    """omega = (4 / sigma) (Z - 1) sqrt(kT / (pi m)) holds exactly in equilibrium (both sides ~ g(sigma));
    the two estimates share the run, so 5 combined standard errors bound the difference."""
    system, m = dense_discs_of_diameter_two
    expected = float(edmd.enskog_collision_frequency(m.compressibility_factor, 2, diameter=2.0, kT=m.temperature))
    spread = math.hypot(m.collision_frequency_error,
                        expected * m.compressibility_factor_error / (m.compressibility_factor - 1))
    assert abs(m.collision_frequency - expected) < 5 * spread + 0.005 * expected


def test_g_of_r_is_reported_at_the_bin_centres(dense_discs_of_diameter_two):
    """A histogram bin [r_k, r_k + dr) estimates g at its centre: the first non-empty bin is the one holding
    contact, so its reported r is within dr / 2 of sigma = 2 (here sigma = 100.4 dr). Kills: rdf_r = upper
    bin edges (g plotted, and extrapolated to contact, half a bin too far out)."""
    system, m = dense_discs_of_diameter_two
    dr = m.rdf_r[1] - m.rdf_r[0]
    assert m.rdf_r[0] == pytest.approx(dr / 2, rel=1e-9)
    first = m.rdf_r[np.flatnonzero(m.rdf > 0)[0]]
    assert abs(first - 2.0) < dr / 2


@pytest.fixture(scope="module")
def dilute_spheres():
    """256 spheres (diameter 1, mass 1, kT 1) at eta = 0.05: Enskog's g(sigma) from Carnahan-Starling is exact
    to 1e-4 there."""
    positions, box = edmd.lattice("fcc", 4, 0.05)
    n = len(positions)
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(n), 3, rng=6), 0.5, box)
    system.run(collisions=30 * n)
    m = edmd.measure(system, collisions=400 * n, blocks=20)
    eta = 0.05
    density = n / system.volume
    contact = (1 - eta / 2) / (1 - eta) ** 3  # Carnahan-Starling g(sigma)
    return system, m, density, contact


def test_collision_frequency_mean_free_time_and_path_of_a_dilute_gas(dilute_spheres):
    """omega = 4 n sigma^2 g(sigma) sqrt(pi kT / m) exactly in equilibrium; mean free time 1 / omega; mean free
    path <v> / omega = 1 / (sqrt(2) pi n sigma^2 g) (Chapman & Cowling). Tolerance: 5 standard errors of omega
    plus 1 % (finite N, g). Kills: omega = 2 C / (N t) -> C / (N t), 1/omega -> 2/omega, <v>/omega -> <v> omega."""
    system, m, density, g = dilute_spheres
    omega = 4 * density * g * math.sqrt(math.pi)
    relative = 5 * m.collision_frequency_error / m.collision_frequency + 0.01
    assert m.collision_frequency == pytest.approx(omega, rel=relative)
    assert m.mean_free_time == pytest.approx(1 / omega, rel=relative)
    assert m.mean_free_path == pytest.approx(1 / (math.sqrt(2) * math.pi * density * g), rel=relative)
    assert m.mean_speed == pytest.approx(math.sqrt(8 / math.pi), rel=0.02)  # Maxwell: <v> = sqrt(8 kT / (pi m))


def test_self_diffusion_of_a_dilute_gas_is_enskogs(dilute_spheres):
    """D from the mean squared displacement, <r^2> = 2 d D t, against Enskog's D_E = 3 / (8 n sigma^2 g)
    sqrt(kT / (pi m)): at eta = 0.05 the exact D is within a few % of D_E (Alder, Gass & Wainwright 1970;
    higher Chapman-Enskog orders +1.8 %), and N = 256 lowers it by the finite-size term, ~5 %. The band
    [0.8, 1.25] D_E holds that and the statistical error (~3 %); it kills 2 d -> d (2 D_E) and d -> 2 d."""
    system, m, density, g = dilute_spheres
    enskog = 3 / (8 * density * g) / math.sqrt(math.pi)
    assert 0.8 * enskog < m.diffusion_coefficient < 1.25 * enskog


def test_rescale_temperature_scales_every_velocity_by_the_square_root_of_the_ratio():
    """kT = 2K / (d N) is quadratic in the velocities: reaching kT' multiplies each by sqrt(kT' / kT).
    Kills: sqrt(kT / current) -> kT / current."""
    positions, box = edmd.lattice("square", 6, 0.3)
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(36), 2, kT=1.7, rng=3), 0.5, box)
    before = system.velocities()
    system.rescale_temperature(0.25)
    assert system.temperature() == pytest.approx(0.25, rel=1e-12)
    np.testing.assert_allclose(system.velocities(), before * math.sqrt(0.25 / 1.7), rtol=1e-12)


def test_energy_lost_counts_only_the_measurement():
    """The measurement's energy_lost is the kinetic energy lost during it (exact bookkeeping: sum of
    (1 - e^2) mu u_n^2 / 2), not since the system was made. Kills: energy_lost without - start_lost."""
    positions, box = edmd.lattice("sc", 5, 0.2)
    n = len(positions)
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(n), 3, rng=2), 0.5, box, restitution=0.9)
    system.run(collisions=2 * n)
    before = system.kinetic_energy()
    assert system.acc[kernels.ACC_ENERGY_LOST] > 0.01 * before  # lost before the measurement starts
    m = edmd.measure(system, collisions=2 * n, blocks=2)
    assert m.energy_lost == pytest.approx(before - system.kinetic_energy(), rel=1e-9)


@pytest.mark.parametrize(
    ("options", "name"),
    [
        (dict(species=[0, 1] * 18, restitution=[[1.0, 0.5], [0.9, 1.0]]), "symmetric"),
        (dict(species=[0, -1] * 18, restitution=[[1.0, 0.5], [0.5, 1.0]]), "species"),
        (dict(gravity=[0.0, -1.0, 0.0]), "gravity"),
    ],
)
def test_inconsistent_species_restitution_and_gravity_are_refused(options, name):
    """Kills the dropped checks: an asymmetric restitution matrix (e_ij != e_ji makes the collision rule
    depend on which particle is i), a negative species (indexes the matrix from the end), a 3-vector gravity
    for discs."""
    positions, box = edmd.lattice("square", 6, 0.3)
    with pytest.raises(ValueError, match=name):
        edmd.HardSphereSystem(positions, np.zeros((36, 2)), 0.5, box, **options)


@pytest.mark.parametrize("x", [0.2, 4.8])
def test_a_particle_overlapping_a_wall_is_refused(x):
    """Centres inside [0, L] are not enough: a sphere of radius 0.5 at x = 0.2 (or L - 0.2) overlaps the wall.
    Kills: the dropped wall-overlap check of the constructor; wall_gap without the radius at the upper wall."""
    positions = np.array([[x, 2.0, 2.0], [2.5, 2.5, 2.5]])
    with pytest.raises(ValueError, match="inside the walls"):
        edmd.HardSphereSystem(positions, np.zeros((2, 3)), 0.5, 5.0, periodic=False)


def test_slow_contacts_stay_inelastic_above_the_default_elastic_floor():
    """The default floor is 1e-6 of the rms speed: a head-on approach at 0.05 (rms 1.4 from two fast
    bystanders) keeps e = 0.5. Kills: elastic_below = 1e-6 rms -> 0.1 rms."""
    positions = np.array([[4.0, 5.0, 5.0], [6.0, 5.0, 5.0], [1.0, 15.0, 15.0], [9.0, 15.0, 10.0]])
    velocities = np.array([[0.025, 0, 0], [-0.025, 0, 0], [2.0, 0, 0], [-2.0, 0, 0]])
    system = edmd.HardSphereSystem(positions, velocities, 0.5, 20.0, restitution=0.5)
    assert system.run(collisions=1) == 1
    v = system.velocities()
    assert (v[1, 0] - v[0, 0]) / 0.05 == pytest.approx(0.5, rel=1e-12)


def test_block_errors_are_standard_errors_of_the_mean():
    """For n independent blocks of unit variance the squared standard error averages 1/n exactly
    (E s^2 = 1); 4000 replicas of 10 blocks pin it to 1 % (sd of the average of s^2 / n). Kills: std / n."""
    rng = np.random.default_rng(1)
    squared = [edmd._block_error(rng.normal(size=10)) ** 2 for _ in range(4000)]
    assert np.mean(squared) == pytest.approx(0.1, rel=0.05)


def test_contact_value_error_matches_the_scatter_of_poisson_pair_counts():
    """Synthetic histograms: pairs per bin Poisson with mean 2000 g(r), g = 2 - 3x + 5x^2 (x = r - sigma),
    counted twice as the sampler does. Over 400 replicas the scatter of the extrapolated contact value
    matches its reported error: var / mean(error^2) lies in [0.75, 1.3] (chi^2 with 399 dof: +-3.5 sd);
    counting each pair once in the Poisson weights makes the errors sqrt(2) too small (ratio 2)."""
    rng = np.random.default_rng(2)
    sigma = 1.0
    r = np.arange(1.0025, 1.2, 0.005)
    x = r - sigma
    g_true = 2 - 3 * x + 5 * x**2
    values, errors = [], []
    for _ in range(400):
        counts = 2.0 * rng.poisson(2000 * g_true)
        value, error = edmd._contact_value(r, counts / 4000.0, counts, sigma)
        values.append(value)
        errors.append(error)
    values, errors = np.array(values), np.array(errors)
    assert abs(values.mean() - 2.0) < 4 * values.std() / math.sqrt(values.size)
    ratio = values.var(ddof=1) / np.mean(errors**2)
    assert 0.75 < ratio < 1.3, ratio


def test_the_anchor_drift_check_catches_a_particle_beyond_half_the_shell():
    """check() guards the neighbour-list invariant |x - anchor| <= shell / 2; a particle 0.6 shell away must
    raise. Kills: allowed = 0.5 shell -> 5 shell."""
    system = edmd.HardSphereSystem(*_square_lattice_with_velocities())
    system.check()
    system.anchor[0, 0] -= 0.6 * system.params[kernels.P_SHELL]
    with pytest.raises(RuntimeError, match="drifted"):
        system.check()


def _square_lattice_with_velocities():
    positions, box = edmd.lattice("square", 6, 0.3)
    return positions, edmd.maxwell_boltzmann(np.ones(36), 2, rng=4), 0.5, box


def test_snapshot_ahead_of_time_follows_the_parabola_under_gravity():
    """_folded(ahead=t) must equal the state after a free flight of t (no event before it): x + v t + g t^2/2.
    Kills: the g t^2 / 2 term dropped from the g(r) snapshot."""
    positions, box = edmd.lattice("sc", 4, 0.1)
    n = len(positions)
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(n), 3, rng=8), 0.5, box,
                                   periodic=False, gravity=[0.0, 0.0, -3.0])
    system.run(collisions=200)
    system.synchronise()
    ahead = 0.5 * system._time_to_next_event()
    predicted = system._folded(ahead=ahead)[0].copy()
    system.run(time=ahead)
    system.synchronise()
    np.testing.assert_allclose(system.pos, predicted, rtol=0, atol=1e-12)


@pytest.mark.parametrize(("e", "hits", "impulse", "final"), [(1.0, 6, 20.0, (1.0, 2.0)), (0.8, 5, 12.024, (0.64, 1.024))])
def test_wall_bounces_count_impulse_and_restitution_exactly(e, hits, impulse, final):
    """Two spheres (r = 0.5, m = 1) fly along x between walls at 0 and 10 on parallel lines (no pair contact),
    from x = 5 at +1 and -2, for t = 20. Each bounce reverses v_x times e and gives the wall m (1 + e) |v|:
    elastic, A hits at 4.5, 13.5 and B at 2.25, 6.75, 11.25, 15.75 (impulse 2 + 2 + 4 x 4 = 20); e = 0.8,
    A at 4.5, 15.75 and B at 2.25, 7.875, 14.906 (1.8 (1 + 0.8) + 1.8 (2 + 1.6 + 1.28) = 12.024).
    Kills: wall impulse m |v| (no 1 + e), v -> -v (wall restitution ignored), two counts per bounce."""
    positions = np.array([[5.0, 2.0, 5.0], [5.0, 7.0, 5.0]])
    velocities = np.array([[1.0, 0.0, 0.0], [-2.0, 0.0, 0.0]])
    system = edmd.HardSphereSystem(positions, velocities, 0.5, 10.0, periodic=[False, True, True],
                                   wall_restitution=e)
    system.run(time=20.0)
    assert system.collisions == 0
    assert system.acc[kernels.ACC_WALL_COLLISIONS] == hits
    assert system.acc[kernels.ACC_WALL_IMPULSE] == pytest.approx(impulse, rel=1e-12)
    np.testing.assert_allclose(np.abs(system.velocities()[:, 0]), final, rtol=1e-12)


def test_the_diffusion_error_matches_the_scatter_of_independent_runs():
    """D's time origins overlap, so its error comes from groups of particles, not blocks; the groups'
    standard error is honest if 16 independent runs (velocities from 16 seeds, equilibrated) scatter as it
    says: (n - 1) s^2 / sigma^2 follows chi^2(n - 1), in its central 1 - 2e-4 band (a factor of two wrong in
    the error fails it). Measured: variance ratio 1.64 here (1.36 at 600 collisions per particle)."""
    values, errors = [], []
    for seed in range(16):
        positions, box = edmd.lattice("fcc", 4, 0.2)
        system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(256), 3, rng=seed), 0.5, box)
        system.run(collisions=20 * 256)
        m = edmd.measure(system, collisions=150 * 256, blocks=10)
        values.append(m.diffusion_coefficient)
        errors.append(m.diffusion_coefficient_error)
    dof = len(values) - 1
    low, high = stats.chi2.ppf([1e-4, 1 - 1e-4], dof) / dof
    ratio = np.var(values, ddof=1) / np.mean(np.square(errors))
    assert low < ratio < high, ratio


def test_mean_free_time_and_path_errors_follow_from_the_collision_frequency():
    """tau = 1 / omega and l = <v> / omega: their errors are omega's relative error times the value."""
    m = edmd.measure(fcc_system(cells=3, eta=0.3), collisions=20_000, blocks=5)
    relative = m.collision_frequency_error / m.collision_frequency
    assert m.mean_free_time_error == pytest.approx(relative * m.mean_free_time, rel=1e-12)
    assert m.mean_free_path_error == pytest.approx(relative * m.mean_free_path, rel=1e-12)
    assert m.summary()["diffusion_coefficient_error"] == m.diffusion_coefficient_error > 0


def test_a_sampler_checkpoint_from_before_the_msd_groups_resumes_without_a_diffusion_error():
    system = fcc_system(cells=3, eta=0.3)
    sampler = edmd.Sampler(system, collisions=9_000, blocks=3)
    sampler.run_block()
    state = sampler.state_dict()
    del state["sampler_msd_groups"]  # as written before the groups were recorded
    resumed = edmd.Sampler.from_state_dict(system, state)
    while not resumed.finished:
        resumed.run_block()
    m = resumed.result()
    assert math.isfinite(m.diffusion_coefficient) and math.isnan(m.diffusion_coefficient_error)


def test_fewer_particles_than_msd_groups_give_no_diffusion_error():
    positions, box = edmd.lattice("square", 2, 0.3)  # 4 discs, 8 groups
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(4), 2, rng=1), 0.5, box)
    m = edmd.measure(system, collisions=400, blocks=4)
    assert math.isfinite(m.diffusion_coefficient) and math.isnan(m.diffusion_coefficient_error)


def _first_time_at_zero(a, b, c):
    """Smallest t > 0 where a t^2 + b t + c rises through 0 (inf if never), elementwise: a particle reaching a
    wall it moves towards (one just bounced off it sits at c ~ 0 moving away)."""
    a, b, c = np.broadcast_arrays(*(np.asarray(value, dtype=float) for value in (a, b, c)))
    linear = np.where(b > 0, -c / np.where(b > 0, b, 1.0), np.inf)
    discriminant = b * b - 4 * a * c
    root = np.sqrt(np.maximum(discriminant, 0.0))
    safe_a = np.where(a != 0, a, 1.0)
    roots = np.stack([(-b - root) / (2 * safe_a), (-b + root) / (2 * safe_a)])
    rising = 2 * a * roots + b > 0
    roots = np.where((roots > 0) & rising & (discriminant >= 0), roots, np.inf).min(axis=0)
    return np.where(a == 0, linear, roots)


def brute_force_collisions(x, v, radii, masses, box, count, walls=False, gravity=None, restitution=1.0):
    """Event-driven hard spheres the slow, obvious way: the earliest event over every pair and every
    neighbouring periodic image (root of |r + u t| = r_i + r_j: both fall alike, so the relative flight is
    straight) or, in a closed box, every particle and wall (x +- r = 0 or L on the parabola x + v t + g t^2 / 2);
    all particles moved to it; the rule along the line of centres with restitution e, or the normal velocity
    reversed at a wall. Returns [(time, velocities)] after each of the first ``count`` pair collisions."""
    x, v = x.astype(float).copy(), v.astype(float).copy()
    dim = x.shape[1]
    g = np.zeros(dim) if gravity is None else np.asarray(gravity, dtype=float)
    offsets = [(0.0,) * dim] if walls else list(itertools.product((-1.0, 0.0, 1.0), repeat=dim))
    shifts = np.array(offsets) * box
    first, second = np.triu_indices(len(x), 1)
    contact = radii[first] + radii[second]
    t, after = 0.0, []
    while len(after) < count:
        r = x[second][:, None, :] + shifts[None, :, :] - x[first][:, None, :]
        u = (v[second] - v[first])[:, None, :]
        b = np.sum(r * u, axis=-1)
        c = np.sum(r * r, axis=-1) - contact[:, None] ** 2
        discriminant = b * b - np.sum(u * u, axis=-1) * c
        hits = (b < 0) & (discriminant >= 0)
        tau = np.full(b.shape, np.inf)
        tau[hits] = c[hits] / (-b[hits] + np.sqrt(discriminant[hits]))
        pair = np.argmin(tau.min(axis=1))
        step = tau[pair].min()
        wall_step = np.full(x.shape, np.inf)
        if walls:
            upper = _first_time_at_zero(0.5 * g, v, x + radii[:, None] - box)
            lower = _first_time_at_zero(-0.5 * g, -v, radii[:, None] - x)
            wall_step = np.minimum(upper, lower)
        wall = wall_step.min() < step
        step = min(step, wall_step.min())
        x = x + v * step + 0.5 * g * step**2
        v = v + g * step
        t += step
        if wall:
            particle, axis = np.unravel_index(np.argmin(wall_step), wall_step.shape)
            v[particle, axis] = -v[particle, axis]
            continue
        if not walls:
            x %= box
        i, j = first[pair], second[pair]
        normal = x[j] - x[i]
        if not walls:
            normal -= box * np.round(normal / box)  # the nearest image at contact (a flight may cross an edge)
        normal /= np.linalg.norm(normal)
        reduced = masses[i] * masses[j] / (masses[i] + masses[j])
        impulse = (1 + restitution) * reduced * np.dot(v[i] - v[j], normal)
        v[i] -= impulse / masses[i] * normal
        v[j] += impulse / masses[j] * normal
        after.append((t, v.copy()))
    return after


@pytest.mark.parametrize("dim, mixture, walls, falling, e", [
    (3, False, False, False, 1.0), (3, True, False, False, 1.0), (2, False, False, False, 1.0),
    (2, True, False, False, 1.0), (3, True, True, False, 1.0), (2, True, True, False, 1.0),
    (3, True, True, True, 0.9), (2, False, True, True, 0.8)])
def test_the_engine_finds_the_same_collisions_as_brute_force(dim, mixture, walls, falling, e):
    """No event missed, none invented, in the right order: the first 100 pair collisions of a dense system
    (neighbour lists, rebuilds, stale events, periodic images or walls) against an all-pairs search; after each
    pair collision the time and every velocity agree; also under gravity (parabolic flights to the walls)
    with inelastic collisions. Round-off grows by the Lyapunov instability: the largest
    velocity difference goes from 1e-14 to 2e-10 over these 100 collisions (walled 3D mixture; 4e-7 at 150,
    0.1 at 300), while a missed or wrong event changes velocities by order 1."""
    rng = np.random.default_rng(dim + 10 * mixture + 100 * walls)
    positions, box = edmd.lattice("fcc" if dim == 3 else "hexagonal", 2 if dim == 3 else 6, 0.35)
    n = len(positions)
    radii = np.where(rng.random(n) < 0.5, 0.5, 0.35) if mixture else np.full(n, 0.5)
    masses = (radii / 0.5) ** dim
    velocities = edmd.maxwell_boltzmann(masses, dim, rng=rng)
    side = np.asarray(box, dtype=float)[:dim]
    if walls:  # the lattice's sites, shrunk into a box one diameter larger, stay clear of each other and the walls
        side = side + 1.0
        positions = positions + 0.5
    gravity = np.eye(dim)[-1] * -2.0 + np.eye(dim)[0] * 0.5 if falling else None
    system = edmd.HardSphereSystem(positions, velocities, radii, side, masses, periodic=not walls, gravity=gravity,
                                   restitution=e)
    expected = brute_force_collisions(positions, velocities, radii, masses, side, 100, walls=walls, gravity=gravity,
                                      restitution=e)
    for time_expected, velocities_expected in expected:
        assert system.run(collisions=1) == 1
        assert system.elapsed == pytest.approx(time_expected, rel=1e-8)
        np.testing.assert_allclose(system.velocities(), velocities_expected, rtol=0, atol=1e-7)


def test_the_diffusion_coefficient_averages_over_every_block_end_as_a_time_origin():
    """An independent numpy computation from the block-end positions: MSD at lag k blocks averaged over all
    origins b - k (k up to blocks // 2), slope of the longer lags (k >= 0.3 K) against the mean time lag."""
    system = fcc_system(cells=3, eta=0.3, seed=4)
    sampler = edmd.Sampler(system, collisions=12 * 3_000, blocks=12)
    positions, times = [system.positions(unwrapped=True)], [system.elapsed]
    while not sampler.finished:
        sampler.run_block()
        positions.append(system.positions(unwrapped=True))
        times.append(system.elapsed)
    positions, times = np.array(positions), np.array(times)
    lags = np.arange(1, 12 // 2 + 1)
    msd = [np.mean(np.sum((positions[k:] - positions[:-k]) ** 2, axis=-1)) for k in lags]
    lag_times = [np.mean(times[k:] - times[:-k]) for k in lags]
    first = math.ceil(0.3 * len(lags)) - 1
    expected = np.polyfit(lag_times[first:], msd[first:], 1)[0] / 6
    assert sampler.result().diffusion_coefficient == pytest.approx(expected, rel=1e-12)


def test_a_sampler_resumed_from_its_state_gives_the_same_diffusion_coefficient():
    def finished(sampler):
        while not sampler.finished:
            sampler.run_block()
        return sampler.result()

    straight = finished(edmd.Sampler(fcc_system(cells=3, eta=0.3, seed=5), collisions=8 * 2_000, blocks=8))
    system = fcc_system(cells=3, eta=0.3, seed=5)
    sampler = edmd.Sampler(system, collisions=8 * 2_000, blocks=8)
    for _ in range(5):
        sampler.run_block()
    state, system_state = sampler.state_dict(), system.state_dict()
    restored = edmd.HardSphereSystem.from_state_dict(system_state)
    resumed = finished(edmd.Sampler.from_state_dict(restored, state))
    assert resumed.diffusion_coefficient == straight.diffusion_coefficient
    assert resumed.diffusion_coefficient_error == straight.diffusion_coefficient_error


def test_a_sampler_checkpoint_from_before_the_time_origins_falls_back_to_one_origin():
    system = fcc_system(cells=3, eta=0.3)
    sampler = edmd.Sampler(system, collisions=8 * 2_000, blocks=8)
    sampler.run_block()
    state = {key: value for key, value in sampler.state_dict().items() if not key.startswith("sampler_lag_")}
    resumed = edmd.Sampler.from_state_dict(system, state)
    while not resumed.finished:
        resumed.run_block()
    m = resumed.result()
    later = m.msd_time > 0.3 * m.msd_time[-1]
    assert m.diffusion_coefficient == pytest.approx(np.polyfit(m.msd_time[later], m.msd[later], 1)[0] / 6, rel=1e-12)
    assert m.diffusion_coefficient_error > 0
