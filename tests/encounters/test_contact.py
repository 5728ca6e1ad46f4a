"""Contact of two bodies on an orbit, the hand-off to the collision core, mergers and focusing.

Independent routes: energy conservation for the speed at contact,
:func:`collisionkit.resolve_contact` called directly, conservation of mass,
momentum and angular momentum in a merger, and eq. 38 at r_p = R1 + R2 for
the focusing cross section.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given

import collisionkit as ck
from collisionkit.encounters import Hyperbolic, TwoBodyOrbit, focusing_cross_section, merge_bodies
from tests.encounters.reference import distances, masses, speeds


def test_contact_when_periastron_inside_the_radii():
    orbit = Hyperbolic(1.0, 3.0, periastron=1.0, v_inf=0.5)
    assert not orbit.contact(0.5, 0.5).touches  # graze: r_p = R1 + R2
    assert not orbit.contact(0.2, 0.3).touches
    miss = orbit.contact(0.2, 0.3)
    assert miss.time == math.inf and np.all(np.isnan(miss.positions))
    contact = orbit.contact(1.0, 0.5)
    assert contact.touches and contact.time < 0
    R, mu_k = 1.5, 4.0
    assert np.linalg.norm(contact.positions[1] - contact.positions[0]) == pytest.approx(R, rel=1e-14, abs=0)
    speed = math.sqrt(0.25 + 2 * mu_k / R)  # energy conservation
    assert contact.relative_speed == pytest.approx(speed, rel=1e-14, abs=0)
    assert contact.tangential_speed == pytest.approx(orbit.specific_angular_momentum / R, rel=1e-13, abs=0)
    assert contact.normal_speed == pytest.approx(math.sqrt(speed**2 - (orbit.specific_angular_momentum / R) ** 2), rel=1e-12, abs=0)
    assert contact.normal @ (contact.positions[1] - contact.positions[0]) == pytest.approx(R, rel=1e-14, abs=0)


def test_elastic_and_inelastic_impacts_through_the_collision_core():
    orbit = Hyperbolic(1.0, 3.0, periastron=0.5, v_inf=0.5)
    elastic = orbit.impact(0.6, 0.4)
    v_before = elastic.contact.velocities
    n = elastic.contact.normal
    u = elastic.velocities_after
    expected = ck.resolve_contact(1.0, v_before[0], 3.0, v_before[1], n)
    assert np.array_equal(u, np.stack(expected))
    assert 1.0 * u[0] + 3.0 * u[1] == pytest.approx([0, 0, 0], abs=1e-14)
    assert elastic.energy_lost == pytest.approx(0.0, abs=1e-14)
    assert (u[1] - u[0]) @ n == pytest.approx(elastic.contact.normal_speed, rel=1e-13, abs=0)  # normal velocity reversed
    sticky = orbit.impact(0.6, 0.4, restitution=0.0)
    w = sticky.velocities_after
    assert (w[1] - w[0]) @ n == pytest.approx(0.0, abs=1e-14)  # common normal velocity
    mu = 0.75
    assert sticky.energy_lost == pytest.approx(0.5 * mu * elastic.contact.normal_speed**2, rel=1e-13, abs=0)
    assert orbit.impact(0.1, 0.1) is None


def test_merger_keeps_mass_momentum_and_angular_momentum():
    orbit = Hyperbolic(1.0, 3.0, periastron=0.5, v_inf=0.5)
    merged = orbit.impact(0.6, 0.4, merge=True)
    assert merged.velocities_after is None
    body = merged.merged
    assert body.mass == 4.0
    assert body.position == pytest.approx([0, 0, 0], abs=1e-15)
    assert body.velocity == pytest.approx([0, 0, 0], abs=1e-15)
    assert body.spin == pytest.approx(orbit.angular_momentum_vector, rel=1e-13, abs=0)
    assert merged.energy_lost == pytest.approx(0.5 * 0.75 * merged.contact.relative_speed**2, rel=1e-13, abs=0)
    moving = merge_bodies(2.0, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], 2.0, [3.0, 0.0, 0.0], [0.0, -1.0, 0.0])
    assert moving.position == pytest.approx([2.0, 0.0, 0.0]) and moving.velocity == pytest.approx([0.0, 0.0, 0.0])
    assert moving.spin == pytest.approx([0.0, 0.0, -4.0])  # mu (x2 - x1) x (v2 - v1) = 1 * 2 * -2


@given(m1=masses, m2=masses, radius=distances, v_inf=speeds)
def test_focusing_cross_section_is_pi_b_max_squared(m1, m2, radius, v_inf):
    sigma = float(focusing_cross_section(m1, m2, 0.25 * radius, 0.75 * radius, v_inf))
    assert sigma == pytest.approx(math.pi * radius**2 * (1 + 2 * (m1 + m2) / (radius * v_inf**2)), rel=1e-14, abs=0)
    b_max = math.sqrt(sigma / math.pi)
    grazing = TwoBodyOrbit.from_impact_parameter(m1, m2, b_max, v_inf)
    assert grazing.periastron == pytest.approx(radius, rel=1e-10, abs=0)


def test_focusing_cross_section_for_repulsion_and_arrays():
    # head-on distance 2 k / (mu v^2) = 4: no contact for R1 + R2 below it
    assert float(focusing_cross_section(1.0, 1.0, 1.0, 1.0, 1.0, k=1.0)) == 0.0
    sigma = focusing_cross_section(1.0, 1.0, np.array([3.0, 5.0]), 1.0, 1.0, k=1.0)
    assert sigma == pytest.approx(math.pi * np.array([16.0 - 16.0, 36.0 - 24.0]), abs=1e-13)


def test_focusing_cross_section_needs_a_positive_contact_distance():
    # kills E55 (encounters.py:1119 R1 + R2 range (0, inf] -> [0, inf]): documented R1 + R2 > 0.
    with pytest.raises(ValueError, match=r"radius1 \+ radius2"):
        focusing_cross_section(1.0, 1.0, 0.0, 0.0, 1.0)
