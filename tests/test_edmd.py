"""Tests of collisionkit.edmd: invariants, conservation and the hard-sphere equation of state."""

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
    steps = np.array([(i % count, time) for i, time in updates], dtype=float).reshape(-1, 2)
    winners = _apply_queue_updates(steps, queue, tree, leaves)
    for (i, time), (winner_time, winner) in zip(steps, winners):
        reference[int(i)] = time
        assert winner_time == reference.min()
        assert winner == np.flatnonzero(reference == reference.min())[0]
