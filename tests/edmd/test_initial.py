"""Tests of collisionkit.edmd.initial: lattices, Maxwell-Boltzmann velocities, compressed random fluids."""

import math
import re

import numpy as np
import pytest

from collisionkit import edmd


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
    v = edmd.maxwell_boltzmann(masses, 3, kT=1.7, seed=3)
    np.testing.assert_allclose((masses[:, None] * v).sum(axis=0), 0.0, atol=1e-12)
    assert 0.5 * np.sum(masses[:, None] * v**2) / (1.5 * 300) == pytest.approx(1.7, rel=1e-14)


@pytest.mark.parametrize(("dim", "eta"), [(3, 0.5), (2, 0.7)])
def test_compression_reaches_the_target_without_overlaps(dim, eta):
    system = edmd.random_fluid(dim, 400, eta, seed=2)
    assert edmd.packing_fraction(system.radius, system.box[:dim]) == pytest.approx(eta, rel=1e-12)
    assert system.check() > -1e-9
    assert system.temperature() == pytest.approx(1.0, rel=1e-12)
    np.testing.assert_allclose(system.momentum(), 0.0, atol=1e-10)
    system.run(collisions=20 * 400)
    assert system.check() > -1e-9


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
        (dict(cells=2.5), TypeError, "cells"),  # a whole float (2.0) counts as 2
        (dict(packing_fraction=math.nan), ValueError, "packing_fraction"),
        (dict(packing_fraction="0.3"), TypeError, "packing_fraction"),
    ],
)
def test_lattice_checks_its_arguments(arguments, error, name):
    with pytest.raises(error, match=name):
        edmd.lattice(**(dict(kind="sc", cells=2, packing_fraction=0.3) | arguments))


@pytest.mark.parametrize("dim", [2, 3])
def test_random_fluid_refuses_packing_fractions_above_the_limit(dim):
    limit = edmd.MAX_PACKING_FRACTION[dim]
    message = f"packing_fraction (dim={dim}) must be a finite number in (0, {limit:g}]"
    with pytest.raises(ValueError, match=re.escape(message)):
        edmd.random_fluid(dim, 100, 1.01 * limit)


def test_random_fluid_reports_the_fraction_of_the_compression_done():
    fractions = []
    edmd.random_fluid(2, 30, 0.2, seed=1, progress=fractions.append)
    assert len(fractions) > 1 and fractions == sorted(fractions)
    assert all(0.0 < fraction <= 1.0 for fraction in fractions)
    assert fractions[-1] == pytest.approx(1.0, rel=1e-12)


def test_the_seed_may_be_an_integer_a_generator_or_none():
    masses = np.ones(50)
    velocities = edmd.maxwell_boltzmann(masses, 3, seed=4)
    np.testing.assert_array_equal(edmd.maxwell_boltzmann(masses, 3, seed=4), velocities)
    np.testing.assert_array_equal(edmd.maxwell_boltzmann(masses, 3, seed=np.random.default_rng(4)), velocities)
    assert not np.array_equal(edmd.maxwell_boltzmann(masses, 3, seed=None), velocities)
    from_generator = edmd.random_fluid(2, 30, 0.2, seed=np.random.default_rng(9))
    np.testing.assert_array_equal(from_generator.positions(), edmd.random_fluid(2, 30, 0.2, seed=9).positions())


@pytest.mark.parametrize(
    ("kind", "dim", "particles", "cells"),
    [("fcc", 3, 500, 5), ("sc", 3, 27, 3), ("square", 2, 16, 4), ("hexagonal", 2, 288, 12)],
)
def test_lattice_cells_gives_the_cells_of_a_lattice_of_that_many_sites(kind, dim, particles, cells):
    assert edmd.lattice_cells(kind, dim, particles) == cells
    assert len(edmd.lattice(kind, cells, 0.3)[0]) == particles
    assert edmd.LATTICE_DIM[kind] == dim and edmd.LATTICE_BASIS[kind] * cells**dim == particles


@pytest.mark.parametrize(
    ("arguments", "error", "message"),
    [
        (("fcc", 2, 500), ValueError, "initial fcc is a 3D lattice; it cannot start a 2D run"),
        (("hexagonal", 2, 100), ValueError,
         "initial hexagonal needs particles = 2 * cells^2 (e.g. 18, 32, 50, 72); got 100"),
        (("sc", 3, 30), ValueError, "initial sc needs particles = 1 * cells^3 (e.g. 27, 64, 125, 216); got 30"),
        (("bcc", 3, 16), ValueError, "kind must be one of"),
        (("sc", 4, 27), ValueError, "dim must be 2 or 3"),
        (("sc", 3, 27.5), TypeError, "particles"),  # a whole float (27.0) counts as 27
    ],
)
def test_lattice_cells_names_what_is_wrong(arguments, error, message):
    with pytest.raises(error, match=re.escape(message)):
        edmd.lattice_cells(*arguments)
