"""Two-body encounters: StarCrash set-up (eqs. 34-39), exact Kepler/Coulomb propagation.

Independent routes: the seed's equations written out literally (StarCrash user
manual, J. Faber 2003, "Hyperbolic Collisions", eqs. 34-39); the closed forms of
validation-data.md ("Two-body encounters"); conservation of energy, angular
momentum and the Laplace-Runge-Lenz vector along ``state_at_time``; the
classical Kepler equations in eccentric/hyperbolic anomaly solved by bisection,
Barker's equation for the parabola; and scipy's DOP853 integration of the
relative two-body ODE at rtol = 1e-13.
"""

from __future__ import annotations

import decimal
import json
import math
import warnings

import numpy as np
import pytest
import scipy.constants as const
from hypothesis import assume, given
from hypothesis import strategies as st
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

import collisionkit as ck
from collisionkit import encounters, scattering
from collisionkit._kernels import encounters as kernels
from collisionkit.encounters import (
    GridExitWarning,
    Hyperbolic,
    TwoBodyOrbit,
    focusing_cross_section,
    merge_bodies,
    starcrash_initial_conditions,
    unit_system,
)

# --------------------------------------------------------------------------- helpers


def log_uniform(low_exponent=-6.0, high_exponent=6.0):
    """Numbers spread evenly in log between 10**low and 10**high."""
    return st.floats(low_exponent, high_exponent).map(lambda x: 10.0**x)


masses = log_uniform()
distances = log_uniform()
speeds = log_uniform()


def relative_ode(_, y, mu):
    r = y[:3]
    return np.concatenate([y[3:], -mu * r / np.sqrt(r @ r) ** 3])


def dop853(mu, r0, v0, times):
    """DOP853 solution of r'' = -mu r / r^3 from (r0, v0) at t = 0, sampled at ``times`` (one sign)."""
    scale = float(np.linalg.norm(r0))
    solution = solve_ivp(
        relative_ode, (0.0, float(times[-1])), np.concatenate([r0, v0]), method="DOP853",
        rtol=1e-13, atol=1e-22 * scale, t_eval=times, args=(mu,),
    )  # fmt: skip
    assert solution.success
    return solution.y[:3].T, solution.y[3:].T


def dop853_disagreement(orbit, times):
    """Max pointwise relative difference (position and velocity) between DOP853 and the orbit.

    The integration starts at periastron from the state built from eq. 36
    (r_p on +x, v_p on +y) and runs outwards in time in each direction: the
    inbound leg integrated forwards from far away is ill-conditioned (an
    error of rtol |r0| in the far state becomes rtol |r0| / r_p at periastron).
    """
    r0 = np.array([orbit.periastron, 0.0, 0.0])
    mu_k = orbit.kepler_parameter
    vp = math.sqrt((mu_k + abs(mu_k) * orbit.eccentricity) / orbit.periastron)  # eq. 36: r_p v_p^2 = mu_K + q
    v0 = np.array([0.0, vp, 0.0])
    worst = 0.0
    for sign in (1.0, -1.0):
        part = np.sort(sign * times[sign * times > 0])
        if part.size == 0:
            continue
        signed = sign * part
        r_num, v_num = dop853(orbit.kepler_parameter, r0, v0, signed)
        r, v = orbit.relative_state_at_time(signed)
        worst = max(
            worst,
            float(np.max(np.linalg.norm(r_num - r, axis=1) / np.linalg.norm(r, axis=1))),
            float(np.max(np.linalg.norm(v_num - v, axis=1) / np.linalg.norm(v, axis=1))),
        )
    return worst


def bisect(function, low, high):
    """Root of an increasing function on [low, high] to the last bit."""
    for _ in range(2000):
        middle = 0.5 * (low + high)
        if middle in (low, high):
            break
        if function(middle) > 0:
            high = middle
        else:
            low = middle
    return 0.5 * (low + high)


def classical_elliptic(mu, rp, e, t):
    """Perifocal state from M = E - e sin E (bisection), x = a(cos E - e), y = b sin E."""
    a = rp / (1.0 - e)
    n = math.sqrt(mu / a**3)
    period = 2.0 * math.pi / n
    mean = n * (t - period * math.floor(t / period + 0.5))
    E = bisect(lambda x: x - e * math.sin(x) - mean, -math.pi, math.pi)
    root = math.sqrt(1.0 - e * e)
    rate = n / (1.0 - e * math.cos(E))
    return (
        np.array([a * (math.cos(E) - e), a * root * math.sin(E), 0.0]),
        np.array([-a * math.sin(E) * rate, a * root * math.cos(E) * rate, 0.0]),
    )


def classical_hyperbolic(mu, rp, e, t):
    """Perifocal state from M = e sinh H - H (bisection), x = |a|(e - cosh H), y = |a| sqrt(e^2-1) sinh H."""
    a = rp / (e - 1.0)
    n = math.sqrt(mu / a**3)
    mean = n * t
    span = math.asinh(abs(mean) / (e - 1.0)) + 1.0
    H = bisect(lambda x: e * math.sinh(x) - x - mean, -span, span)
    root = math.sqrt(e * e - 1.0)
    rate = n / (e * math.cosh(H) - 1.0)
    return (
        np.array([a * (e - math.cosh(H)), a * root * math.sinh(H), 0.0]),
        np.array([-a * math.sinh(H) * rate, a * root * math.cosh(H) * rate, 0.0]),
    )


def barker_parabola(mu, rp, t):
    """Parabolic state from Barker's equation D + D^3/3 = B = 2 t sqrt(mu/p^3), D = tan(theta/2).

    With D = 2 sinh(phi), D^3 + 3D = 2 sinh(3 phi), so D = 2 sinh(asinh(3B/2) / 3).
    """
    p = 2.0 * rp
    B = 2.0 * t * math.sqrt(mu / p**3)
    D = 2.0 * math.sinh(math.asinh(1.5 * B) / 3.0)
    position = np.array([p * (1.0 - D * D) / 2.0, p * D, 0.0])
    theta = 2.0 * math.atan(D)
    speed = math.sqrt(mu / p)
    velocity = np.array([-speed * math.sin(theta), speed * (1.0 + math.cos(theta)), 0.0])
    return position, velocity


def relative_error(a, b):
    return float(np.linalg.norm(np.asarray(a) - np.asarray(b)) / np.linalg.norm(b))


def specific_invariants(mu, r, v):
    """Energy v^2/2 - mu/r, angular momentum r x v, Laplace-Runge-Lenz e-vector, and the energy scale."""
    distance = np.linalg.norm(r, axis=-1)
    speed2 = np.sum(v * v, axis=-1)
    h = np.cross(r, v)
    lrl = np.cross(v, h) / mu - r / distance[..., None]
    return 0.5 * speed2 - mu / distance, h, lrl, 0.5 * speed2 + abs(mu) / distance


# --------------------------------------------------------------------------- seed eqs. 34-39


def test_starcrash_worked_example():
    """m1 = m2 = 1, rp = 1, vinf = 0.5, r0 = 10, G = 1, eqs. 34-39 by hand."""
    ic = starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, 10.0, G=1.0)
    assert ic.energy == pytest.approx(0.5 * 0.5 * 0.25, rel=1e-15, abs=0)  # eq. 34
    assert ic.v0 == pytest.approx(math.sqrt(0.65), rel=1e-15, abs=0)  # eq. 35
    assert ic.vp == pytest.approx(math.sqrt(4.25), rel=1e-15, abs=0)  # eq. 36
    assert ic.angular_momentum == pytest.approx(0.5 * math.sqrt(4.25), rel=1e-15, abs=0)  # eq. 37
    assert ic.impact_parameter == pytest.approx(math.sqrt(17.0), rel=1e-15, abs=0)  # eq. 38
    assert ic.vt == pytest.approx(0.5 * math.sqrt(17.0) / 10.0, rel=1e-15, abs=0)  # eq. 39
    assert ic.vr == pytest.approx(math.sqrt(0.65 - 0.0425), rel=1e-14, abs=0)
    assert ic.orbit.eccentricity == pytest.approx(1.125, rel=1e-15, abs=0)


@given(m1=masses, m2=masses, rp=distances, vinf=speeds, stretch=log_uniform(-6, 3))
def test_starcrash_equations_over_wide_ranges(m1, m2, rp, vinf, stretch):
    G = 1.0
    r0 = rp * (1.0 + stretch)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", GridExitWarning)
        ic = starcrash_initial_conditions(m1, m2, rp, vinf, r0, G=G)
    M, mu = m1 + m2, m1 * m2 / (m1 + m2)
    # the seed's equations, written out literally
    v0 = math.sqrt(vinf**2 + 2 * G * M / r0)
    vp = math.sqrt(vinf**2 + 2 * G * M / rp)
    J = mu * math.sqrt(rp**2 * vinf**2 + 2 * G * M * rp)
    b = J / (mu * vinf)
    vt = math.sqrt(rp**2 * vinf**2 + 2 * G * M * rp) / r0
    assert ic.energy == pytest.approx(0.5 * mu * vinf**2, rel=1e-14, abs=0)
    assert ic.v0 == pytest.approx(v0, rel=1e-14, abs=0)
    assert ic.vp == pytest.approx(vp, rel=1e-14, abs=0)
    assert ic.angular_momentum == pytest.approx(mu * vp * rp, rel=1e-14, abs=0)
    assert ic.angular_momentum == pytest.approx(J, rel=1e-14, abs=0)
    assert ic.impact_parameter == pytest.approx(b, rel=1e-14, abs=0)
    assert ic.impact_parameter == pytest.approx(math.sqrt(rp**2 + 2 * G * M * rp / vinf**2), rel=1e-14, abs=0)
    assert ic.vt == pytest.approx(vt, rel=1e-14, abs=0)
    assert ic.vt == pytest.approx(vinf * b / r0, rel=1e-14, abs=0)
    # v_r = sqrt(v0^2 - v_t^2): compare squares (the literal difference cancels near periastron)
    assert ic.vr**2 + ic.vt**2 == pytest.approx(v0**2, rel=1e-13, abs=0)
    # the arrays: centre of mass at rest at the origin, separation r0, speeds v_t and v_r
    x, v = ic.positions, ic.velocities
    assert x.shape == v.shape == (2, 3)
    assert np.allclose(m1 * x[0] + m2 * x[1], 0.0, atol=1e-14 * M * r0)
    assert np.allclose(m1 * v[0] + m2 * v[1], 0.0, atol=1e-14 * M * v0)
    separation, relative = x[1] - x[0], v[1] - v[0]
    assert np.linalg.norm(separation) == pytest.approx(r0, rel=1e-14, abs=0)
    unit = separation / np.linalg.norm(separation)
    assert np.allclose(unit, np.ones(3) / math.sqrt(3.0), rtol=0, atol=1e-15)
    assert relative @ unit == pytest.approx(-ic.vr, rel=1e-12, abs=1e-14 * v0)
    transverse = relative - (relative @ unit) * unit
    assert np.linalg.norm(transverse) == pytest.approx(ic.vt, rel=1e-12, abs=1e-14 * v0)
    assert v[0, 0] == v[0, 1] and v[1, 0] == v[1, 1]  # v_x = v_y for both stars
    # the oriented orbit starts at the initial conditions
    start_x, start_v = ic.orbit.state_at_time(-ic.time_to_periastron)
    assert np.allclose(start_x, x, rtol=0, atol=1e-11 * r0)
    assert np.allclose(start_v, v, rtol=0, atol=1e-11 * v0)


def test_stars_in_opposite_corners_and_plain_layout():
    diagonal = starcrash_initial_conditions(2.0, 1.0, 1.0, 0.5, 12.0)
    x = diagonal.positions
    assert np.all(x[1] > 0) and np.all(x[0] < 0)  # opposite corners (+,+,+) and (-,-,-)
    assert x[1][0] == x[1][1] == x[1][2]
    assert np.dot(diagonal.velocities[1] - diagonal.velocities[0], np.ones(3)) < 0  # approaching
    plain = starcrash_initial_conditions(2.0, 1.0, 1.0, 0.5, 12.0, layout="x")
    separation = plain.positions[1] - plain.positions[0]
    assert separation == pytest.approx([12.0, 0.0, 0.0], abs=1e-14)
    relative = plain.velocities[1] - plain.velocities[0]
    assert relative == pytest.approx([-diagonal.vr, diagonal.vt, 0.0], rel=1e-14, abs=0)
    assert plain.time_to_periastron == pytest.approx(diagonal.time_to_periastron, rel=1e-14, abs=0)
    assert plain.orbit.time_since_periastron(separation, relative) == pytest.approx(-plain.time_to_periastron, rel=1e-12, abs=0)


def _ratio(sep0):
    return starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, sep0, layout="x").speed_ratio


def test_grid_warning_threshold_is_where_a_star_leaves_its_corner():
    """The seed's sqrt(1/3): above it, the star in the (+,+,+) corner gets v_z > 0 (outwards)."""
    threshold_sep0 = brentq(lambda s: _ratio(s) - math.sqrt(1.0 / 3.0), 1.0 + 1e-9, 100.0, xtol=1e-14)
    with pytest.warns(GridExitWarning, match=r"sqrt\(1/3\)"):
        above = starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, threshold_sep0 * 0.99)
    assert above.speed_ratio > math.sqrt(1.0 / 3.0)
    assert above.velocities[1, 2] > 0 and above.velocities[0, 2] < 0  # both head out of the grid
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        below = starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, threshold_sep0 * 1.01)
        plain = starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, threshold_sep0 * 0.5, layout="x")
    assert below.speed_ratio < math.sqrt(1.0 / 3.0)
    assert np.all(below.velocities[1] < 0) and np.all(below.velocities[0] > 0)
    assert plain.speed_ratio > math.sqrt(1.0 / 3.0)  # no grid, no warning


def test_grid_warning_is_a_user_warning_subclass():
    assert issubclass(GridExitWarning, UserWarning)
    with pytest.warns(GridExitWarning):
        starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, 1.0)  # r0 = rp: all transverse


def test_write_initial_conditions(tmp_path):
    ic = starcrash_initial_conditions(1.0, 3.0, 2.0, 0.3, 20.0)
    json_path, text_path = ic.write(tmp_path / "ic", units=unit_system("nbody"))
    data = json.loads(json_path.read_text())
    assert data["impact_parameter"] == ic.impact_parameter
    assert data["units"]["name"] == "nbody"
    assert np.array_equal(np.array(data["positions"]), ic.positions)
    assert np.array_equal(np.array(data["velocities"]), ic.velocities)
    table = np.loadtxt(text_path)
    assert table.shape == (2, 8)
    assert np.array_equal(table[:, 0], [1, 2]) and np.array_equal(table[:, 1], [1.0, 3.0])
    assert np.array_equal(table[:, 2:5], ic.positions) and np.array_equal(table[:, 5:], ic.velocities)
    assert sorted(p.name for p in (tmp_path / "ic").iterdir()) == ["initial_conditions.json", "initial_conditions.txt"]


# --------------------------------------------------------------------------- validation-data.md


@given(m1=masses, m2=masses, rp=distances, vinf=speeds)
def test_reference_formulas_for_gravity(m1, m2, rp, vinf):
    """validation-data.md: b, e (two forms), deflection (two forms), a."""
    orbit = Hyperbolic(m1, m2, periastron=rp, v_inf=vinf, G=1.0)
    mu_g = m1 + m2
    b = math.sqrt(rp**2 + 2 * mu_g * rp / vinf**2)
    e = 1 + rp * vinf**2 / mu_g
    assert orbit.impact_parameter == pytest.approx(b, rel=1e-14, abs=0)
    assert orbit.eccentricity == pytest.approx(e, rel=1e-14, abs=0)
    assert orbit.eccentricity == pytest.approx(math.sqrt(1 + b**2 * vinf**4 / mu_g**2), rel=1e-10, abs=0)
    assert orbit.deflection_angle == pytest.approx(2 * math.atan(mu_g / (b * vinf**2)), rel=1e-14, abs=0)
    assert orbit.deflection_angle == pytest.approx(2 * math.asin(1 / e), rel=1e-7, abs=1e-15)
    assert orbit.semi_major_axis == pytest.approx(-mu_g / vinf**2, rel=1e-14, abs=0)


@pytest.mark.parametrize("k", [2.0, -2.0])
def test_rutherford_for_coulomb_orbits(k):
    """validation-data.md: tan(chi/2) = |k| / (mu v^2 b), dsigma/dOmega = (k/(2 mu v^2))^2 / sin^4(chi/2)."""
    m1, m2, v = 1.0, 3.0, 2.0
    mu = m1 * m2 / (m1 + m2)
    orbit = Hyperbolic.from_impact_parameter(m1, m2, 0.7, v, k=k)
    assert orbit.attractive is (k < 0)
    assert orbit.impact_parameter == pytest.approx(0.7, rel=1e-14, abs=0)
    chi = orbit.deflection_angle
    assert math.tan(chi / 2) == pytest.approx(abs(k) / (mu * v**2 * 0.7), rel=1e-14, abs=0)
    assert float(orbit.differential_cross_section(1.0)) == pytest.approx(
        (k / (2 * mu * v**2)) ** 2 / math.sin(0.5) ** 4, rel=1e-14
    )
    closest = float(scattering.coulomb_closest_approach(0.7, k, mu, v))
    assert orbit.periastron == pytest.approx(closest, rel=1e-15, abs=0)
    # energy at periastron: v_p^2 / 2 + (k / mu) / r_p = v^2 / 2
    assert 0.5 * orbit.periastron_speed**2 + k / mu / orbit.periastron == pytest.approx(0.5 * v**2, rel=1e-14, abs=0)


def test_repulsive_head_on_is_radial():
    orbit = Hyperbolic.from_impact_parameter(1.0, 1.0, 0.0, 1.0, k=1.0)
    assert orbit.periastron == pytest.approx(4.0, rel=1e-15, abs=0)  # 2 k / (mu v^2)
    assert orbit.deflection_angle == pytest.approx(math.pi, rel=1e-15, abs=0)
    r, v = orbit.relative_state_at_time(np.array([-3.0, 0.0, 5.0]))
    assert np.allclose(r[:, 1:], 0.0) and np.all(r[:, 0] >= 4.0)
    assert v[1] == pytest.approx([0.0, 0.0, 0.0], abs=1e-15)
    assert np.sign(v[0, 0]) == -1 and np.sign(v[2, 0]) == 1  # comes in along x, goes back out
    energy = 0.5 * np.sum(v * v, axis=1) + 2.0 / np.linalg.norm(r, axis=1)
    assert energy == pytest.approx(0.5, rel=1e-14, abs=0)


@pytest.mark.parametrize("b", [1e-8, 1e-6, 1e-4, 1e-2])
def test_near_head_on_repulsion_keeps_the_impact_parameter(b):
    # h^2 = r_p (mu_K + q) = r_p |mu_K| (e - 1) cancels as e -> 1: 9e-4 relative error at b = 1e-6 when
    # h came from r_p; from b v (or |r x v| of a state) it keeps every digit
    m1, m2, v, k = 1.0, 1.0, 1.0, 1.0
    mu = m1 * m2 / (m1 + m2)
    orbit = Hyperbolic.from_impact_parameter(m1, m2, b, v, k=k)
    assert orbit.impact_parameter == pytest.approx(b, rel=4e-16, abs=0)
    assert orbit.angular_momentum == pytest.approx(mu * b * v, rel=4e-16, abs=0)
    assert orbit.deflection_angle == pytest.approx(2 * math.atan(k / (mu * v**2 * b)), rel=4e-16, abs=0)
    far = 1e3
    state = TwoBodyOrbit.from_state(m1, m2, [-far, b], [v, 0.0], k=k)
    v_inf = math.sqrt(v**2 + 2 * (k / mu) / math.hypot(far, b))  # energy: v^2 / 2 + (k / mu) / r
    assert state.impact_parameter == pytest.approx(b * v / v_inf, rel=1e-15, abs=0)


def test_tiny_speeds_and_unit_names(tmp_path):
    # v_inf^2 rounding to 0 was a ZeroDivisionError; a unit system given by name an AttributeError
    with pytest.raises(ValueError, match="v_inf must be > 1.49e-154"):
        Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1e-200)
    with pytest.raises(ValueError, match="v_inf"):
        Hyperbolic.from_impact_parameter(1.0, 1.0, 1.0, 1e-160)
    ic = encounters.starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, 10.0)
    json_path, _ = ic.write(tmp_path, units="cgs")
    assert json.loads(json_path.read_text())["units"]["name"] == encounters.unit_system("cgs").name
    with pytest.raises(TypeError, match="units"):
        ic.write(tmp_path, units=3)


def test_gravity_and_coulomb_add():
    """V = (k - G m1 m2) / r: gravity cancelled by an equal repulsion leaves no force."""
    with pytest.raises(ValueError, match="vanishes"):
        Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0, G=2.0, k=2.0)
    both = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0, G=2.0, k=1.0)
    assert both.kepler_parameter == pytest.approx(2.0 * 2.0 - 1.0 / 0.5)
    assert both.coulomb_strength == pytest.approx(1.0 - 2.0)


# --------------------------------------------------------------------------- propagation


@given(
    m1=masses, m2=masses, rp=distances, vinf=speeds,
    tau=st.lists(st.floats(-1e6, 1e6), min_size=1, max_size=8),
)  # fmt: skip
def test_conservation_along_state_at_time(m1, m2, rp, vinf, tau):
    orbit = Hyperbolic(m1, m2, periastron=rp, v_inf=vinf)
    mu_k = orbit.kepler_parameter
    times = np.array(tau) * rp / orbit.periastron_speed
    x, v = orbit.state_at_time(times)
    assert x.shape == v.shape == (len(tau), 2, 3)
    M = m1 + m2
    assert np.all(np.abs(m1 * x[:, 0] + m2 * x[:, 1]) <= 1e-13 * M * np.abs(x[:, 1] - x[:, 0]).max())
    assert np.all(np.abs(m1 * v[:, 0] + m2 * v[:, 1]) <= 1e-13 * M * np.abs(v[:, 1] - v[:, 0]).max())
    r, u = x[:, 1] - x[:, 0], v[:, 1] - v[:, 0]
    energy, h, lrl, scale = specific_invariants(mu_k, r, u)
    assert np.all(np.abs(energy - 0.5 * vinf**2) <= 1e-12 * scale)
    # r x v and the Laplace-Runge-Lenz vector of rounded r, v are only good to eps |r| |v| (and
    # eps |r| |v|^2 / mu for the e-vector): nearly parallel r and v far out
    rv = (np.linalg.norm(r, axis=1) * np.linalg.norm(u, axis=1))[:, None]
    h0 = orbit.specific_angular_momentum
    assert np.all(np.abs(h - h0 * orbit.basis[2]) <= 1e-12 * (h0 + rv))
    lrl_scale = 1.0 + rv[:, 0] * np.linalg.norm(u, axis=1) / mu_k
    assert np.all(np.abs(np.linalg.norm(lrl, axis=1) - orbit.eccentricity) <= 1e-12 * (orbit.eccentricity + lrl_scale))
    assert np.all(np.linalg.norm(r, axis=1) >= rp * (1 - 1e-14))
    # the sign of r.v is the sign of t (inbound before periastron)
    sigma = np.sum(r * u, axis=1)
    far = np.abs(times) > 1e-6 * rp / orbit.periastron_speed
    assert np.all(np.sign(sigma[far]) == np.sign(times[far]))


@pytest.mark.parametrize("e", [0.0, 0.1, 0.5, 0.9])
def test_elliptic_against_dop853_over_several_periods(e):
    orbit = TwoBodyOrbit(1.0, 2.0, periastron=1.0, eccentricity=e)
    times = np.linspace(-1.5 * orbit.period, 3.5 * orbit.period, 501)[1:]  # 5 periastron passages
    assert dop853_disagreement(orbit, times) < 1e-9


@pytest.mark.parametrize("vinf", [2e-5, 0.01, 1.0, 100.0])  # 2e-5: e = 1 + 1.3e-10
def test_hyperbolic_against_dop853_at_long_times(vinf):
    orbit = Hyperbolic(1.0, 2.0, periastron=1.0, v_inf=vinf)
    unit = orbit.periastron / orbit.periastron_speed
    tail = np.geomspace(1e-3, 1e6, 150) * unit
    times = np.concatenate([-tail, tail])
    assert dop853_disagreement(orbit, times) < 1e-9


@pytest.mark.parametrize("e", [1.0 - 1e-10, 1.0, 1.0 + 1e-10])
def test_near_parabolic_against_dop853(e):
    orbit = TwoBodyOrbit(1.0, 1.0, periastron=1.0, eccentricity=e)
    tail = np.geomspace(1e-3, 1e6, 150)
    assert dop853_disagreement(orbit, np.concatenate([-tail, tail])) < 1e-9


def test_repulsive_coulomb_against_dop853():
    orbit = Hyperbolic(1.0, 1.0, periastron=2.0, v_inf=1.0, k=0.3)
    assert not orbit.attractive and orbit.eccentricity > 1
    tail = np.geomspace(1e-3, 1e5, 120)
    assert dop853_disagreement(orbit, np.concatenate([-tail, tail])) < 1e-9


@pytest.mark.parametrize("e", [0.01, 0.3, 0.9, 0.999])
def test_elliptic_against_classical_kepler_equation(e):
    mu, rp = 3.0, 0.7
    orbit = TwoBodyOrbit(1.0, 2.0, periastron=rp, eccentricity=e)
    # near apoastron of e = 0.999 the speed is 1/45 of sqrt(mu/a): the reference's own
    # error (from E near pi) is then a fraction of sqrt(mu/a), not of |v|
    speed_scale = math.sqrt(mu / orbit.semi_major_axis)
    for t in np.linspace(-3.3, 7.9, 41) * orbit.period:
        r, v = orbit.relative_state_at_time(t)
        r_ref, v_ref = classical_elliptic(mu, rp, e, t)
        assert relative_error(r, r_ref) < 1e-11
        assert np.linalg.norm(v - v_ref) < 1e-11 * max(np.linalg.norm(v_ref), speed_scale)


@pytest.mark.parametrize("e", [1.001, 1.5, 30.0])
def test_hyperbolic_against_classical_kepler_equation(e):
    mu, rp = 3.0, 0.7
    orbit = TwoBodyOrbit(1.0, 2.0, periastron=rp, eccentricity=e)
    for t in np.concatenate([-np.geomspace(1e-4, 1e7, 30), np.geomspace(1e-4, 1e7, 30)]):
        r, v = orbit.relative_state_at_time(t)
        r_ref, v_ref = classical_hyperbolic(mu, rp, e, t)
        assert relative_error(r, r_ref) < 1e-10 and relative_error(v, v_ref) < 1e-10


def test_parabola_against_barker_and_neighbours_across_e_equals_one():
    mu, rp = 2.0, 1.0
    parabola = TwoBodyOrbit(1.0, 1.0, periastron=rp, eccentricity=1.0)
    assert parabola.kind == "parabolic" and parabola.v_inf == 0.0
    assert parabola.deflection_angle == math.pi and parabola.impact_parameter == math.inf
    below = TwoBodyOrbit(1.0, 1.0, periastron=rp, eccentricity=1.0 - 1e-10)
    above = TwoBodyOrbit(1.0, 1.0, periastron=rp, eccentricity=1.0 + 1e-10)
    assert (below.kind, above.kind) == ("elliptic", "hyperbolic")
    for t in [-1e3, -3.0, -1e-6, 0.0, 2e-8, 0.5, 40.0, 1e3]:
        r, v = parabola.relative_state_at_time(t)
        r_ref, v_ref = barker_parabola(mu, rp, t)
        assert relative_error(r, r_ref) < 1e-13 and relative_error(v, v_ref) < 1e-13
        for neighbour in (below, above):  # a change of 1e-10 in e moves the state by about that
            r_n, v_n = neighbour.relative_state_at_time(t)
            assert relative_error(r_n, r) < 1e-7 and relative_error(v_n, v) < 1e-7


def test_state_at_time_shapes_and_symmetry():
    orbit = Hyperbolic(1.0, 2.0, periastron=1.0, v_inf=0.5)
    x, v = orbit.state_at_time(3.0)
    assert x.shape == v.shape == (2, 3)
    grid = np.linspace(-4.0, 4.0, 12).reshape(3, 4)
    x, v = orbit.state_at_time(grid)
    assert x.shape == v.shape == (3, 4, 2, 3)
    x_list, _ = orbit.state_at_time(list(grid[0]))
    assert np.array_equal(x_list, x[0])
    # mirror symmetry about the apse line: (x, y) -> (x, -y), (vx, vy) -> (-vx, vy)
    r_in, v_in = orbit.relative_state_at_time(-2.5)
    r_out, v_out = orbit.relative_state_at_time(2.5)
    assert np.array_equal(r_in * [1, -1, 1], r_out) and np.array_equal(v_in * [-1, 1, 1], v_out)
    assert orbit.relative_state_at_time(0.0)[0] == pytest.approx([1.0, 0.0, 0.0], abs=0)


# --------------------------------------------------------------------------- times at separations


@given(m1=masses, m2=masses, rp=distances, vinf=speeds, stretch=log_uniform(-6, 6))
def test_time_at_separation_round_trip(m1, m2, rp, vinf, stretch):
    orbit = Hyperbolic(m1, m2, periastron=rp, v_inf=vinf)
    r = rp * (1.0 + stretch)
    t_in = orbit.time_at_separation(r)
    t_out = orbit.time_at_separation(r, branch="outbound")
    assert t_in < 0 < t_out and t_out == -t_in
    separation, velocity = orbit.relative_state_at_time(t_in)
    assert np.linalg.norm(separation) == pytest.approx(r, rel=1e-12, abs=0)
    assert separation @ velocity < 0  # on the way in
    assert orbit.time_since_periastron(separation, velocity) == pytest.approx(t_in, rel=1e-9, abs=0)


@pytest.mark.parametrize("e", [1.2, 3.0])
def test_time_at_separation_against_hyperbolic_anomaly(e):
    mu, rp = 2.0, 1.5
    orbit = TwoBodyOrbit(1.0, 1.0, periastron=rp, eccentricity=e)
    a = rp / (e - 1)
    n = math.sqrt(mu / a**3)
    for r in [1.5, 2.0, 10.0, 1e4]:
        H = math.acosh((1 + r / a) / e)
        assert orbit.time_at_separation(r) == pytest.approx(-(e * math.sinh(H) - H) / n, rel=1e-12, abs=0)


def test_time_at_separation_elliptic_and_arrays():
    e, mu, rp = 0.6, 2.0, 1.0
    orbit = TwoBodyOrbit(1.0, 1.0, periastron=rp, eccentricity=e)
    a = rp / (1 - e)
    n = math.sqrt(mu / a**3)
    r = np.array([1.0, 1.3, 2.5, orbit.apoastron])
    E = np.arccos(np.clip((1 - r / a) / e, -1.0, 1.0))
    times = orbit.time_at_separation(r, branch="outbound")
    assert times.shape == (4,)
    assert times == pytest.approx((E - e * np.sin(E)) / n, rel=1e-13, abs=0)
    assert times[-1] == pytest.approx(0.5 * orbit.period, rel=1e-14, abs=0)


def test_time_since_periastron_refuses_states_off_the_orbit():
    # both returned 0.0 before
    orbit = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0)
    with pytest.raises(ValueError, match="not on this orbit"):
        orbit.time_since_periastron([100.0, 0.0, 0.0], [0.0, 0.0, 5.0])
    with pytest.raises(ValueError, match="separation"):
        orbit.time_since_periastron([0.0, 0.0, 0.0], [0.0, 0.0, 0.0])
    for t in (-1e6, -3.0, 0.0, 2.5, 1e8):  # the orbit's own states pass, far out too
        assert orbit.time_since_periastron(*orbit.relative_state_at_time(t)) == pytest.approx(t, rel=1e-12, abs=1e-12)


def test_time_since_periastron_at_periastron_is_accurate():
    orbit = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0)
    for t in [-1e-9, 1e-12, 3e-7]:
        r, v = orbit.relative_state_at_time(t)
        assert orbit.time_since_periastron(r, v) == pytest.approx(t, rel=1e-9, abs=0)


# --------------------------------------------------------------------------- constructors


@given(
    m1=masses, m2=masses,
    r=st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1)).filter(lambda p: np.linalg.norm(p) > 0.1),
    v=st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1)),
    length=distances, speed_ratio=log_uniform(-2, 2),
)  # fmt: skip
def test_from_state_round_trip(m1, m2, r, v, length, speed_ratio):
    r_vec = np.array(r) * length
    mu_k = m1 + m2
    circular = math.sqrt(mu_k / np.linalg.norm(r_vec))
    v_vec = np.array(v)
    assume(np.linalg.norm(np.cross(r_vec / np.linalg.norm(r_vec), v_vec)) > 1e-3 * np.linalg.norm(v_vec))
    v_vec = v_vec / np.linalg.norm(v_vec) * circular * speed_ratio
    orbit = TwoBodyOrbit.from_state(m1, m2, r_vec, v_vec)
    assert isinstance(orbit, Hyperbolic) == (orbit.kind == "hyperbolic")
    energy, h, lrl, _ = specific_invariants(mu_k, r_vec, v_vec)
    assert orbit.specific_energy == pytest.approx(energy, rel=1e-12, abs=1e-12 * circular**2)
    assert orbit.specific_angular_momentum == pytest.approx(np.linalg.norm(h), rel=1e-12, abs=0)
    assert orbit.eccentricity == pytest.approx(np.linalg.norm(lrl), rel=1e-8, abs=1e-8)
    t = orbit.time_since_periastron(r_vec, v_vec)
    r_back, v_back = orbit.relative_state_at_time(t)
    assert relative_error(r_back, r_vec) < 1e-8
    assert relative_error(v_back, v_vec) < 1e-8


def _exact_specific_energy(mu_k, r_vec, v_vec):
    """v^2/2 - mu_K/r of float vectors, evaluated to 40 digits (no cancellation of its own)."""
    with decimal.localcontext() as context:
        context.prec = 40
        r2 = sum(decimal.Decimal(float(x)) ** 2 for x in r_vec)
        v2 = sum(decimal.Decimal(float(x)) ** 2 for x in v_vec)
        return v2 / 2 - decimal.Decimal(mu_k) / r2.sqrt()


@given(
    r=st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1)).filter(lambda p: np.linalg.norm(p) > 0.1),
    v=st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1)),
    length=distances, excess=log_uniform(-7, 1),
)  # fmt: skip
def test_from_state_energy_holds_to_its_condition_number_for_a_long_time(r, v, length, excess):
    """E(t = 1e10) = E(state) to eps (v^2/2)/|E|: the conditioning of E = v^2/2 - mu/r, nothing more.

    Near a parabola (excess -> 0) E is a small difference of v^2/2 and mu/r, so
    the state fixes it only to eps v^2/(2|E|); the propagation must add nothing
    to that, out to 1e10 time units (both energies evaluated exactly).
    """
    r_vec = np.array(r) * length
    v_vec = np.array(v)
    assume(np.linalg.norm(np.cross(r_vec / np.linalg.norm(r_vec), v_vec)) > 1e-3 * np.linalg.norm(v_vec))
    escape = math.sqrt(2 * 2.0 / np.linalg.norm(r_vec))
    v_vec = v_vec / np.linalg.norm(v_vec) * escape * (1 + excess)
    orbit = TwoBodyOrbit.from_state(1.0, 1.0, r_vec, v_vec)
    assume(orbit.kind == "hyperbolic")
    start = _exact_specific_energy(2.0, r_vec, v_vec)
    later = _exact_specific_energy(2.0, *orbit.relative_state_at_time(1e10))
    condition = float(v_vec @ v_vec) / 2 / abs(float(start))
    assert abs(float((later - start) / start)) <= 8 * np.finfo(float).eps * (condition + 1)


def test_from_state_two_dimensional_and_bound():
    orbit = TwoBodyOrbit.from_state(1.0, 1.0, [2.0, 0.0], [0.1, 0.8])
    assert orbit.kind == "elliptic"
    t = orbit.time_since_periastron([2.0, 0.0], [0.1, 0.8])
    r, v = orbit.relative_state_at_time(t)
    assert r == pytest.approx([2.0, 0.0, 0.0], abs=1e-14) and v == pytest.approx([0.1, 0.8, 0.0], abs=1e-14)
    r_next, _ = orbit.relative_state_at_time(t + orbit.period)
    assert r_next == pytest.approx(r, abs=1e-13)  # closes after a period


@given(m1=masses, m2=masses, b=distances, vinf=speeds)
def test_from_impact_parameter_inverts_eq_38(m1, m2, b, vinf):
    orbit = TwoBodyOrbit.from_impact_parameter(m1, m2, b, vinf)
    assert isinstance(orbit, Hyperbolic)
    assert orbit.impact_parameter == pytest.approx(b, rel=1e-12, abs=0)
    again = Hyperbolic(m1, m2, periastron=orbit.periastron, v_inf=vinf)
    assert again.deflection_angle == pytest.approx(orbit.deflection_angle, rel=1e-12, abs=0)


def test_bound_orbit_elements():
    orbit = TwoBodyOrbit(2.0, 2.0, periastron=1.0, eccentricity=0.5)
    assert orbit.apoastron == pytest.approx(3.0)
    assert orbit.semi_major_axis == pytest.approx(2.0)
    assert orbit.period == pytest.approx(2 * math.pi * math.sqrt(8.0 / 4.0))
    assert math.isnan(orbit.v_inf) and math.isnan(orbit.impact_parameter) and math.isnan(orbit.deflection_angle)
    assert orbit.energy == pytest.approx(-1.0 * 4.0 / (2 * 2.0))  # -mu G M / (2a)
    with pytest.raises(ValueError, match="hyperbolic"):
        orbit.asymptotes()


def test_asymptotes_are_the_far_velocities():
    orbit = Hyperbolic(1.0, 2.0, periastron=1.0, v_inf=0.7)
    incoming, outgoing, centre = orbit.asymptotes()
    assert math.acos(incoming @ outgoing) == pytest.approx(orbit.deflection_angle, rel=1e-13, abs=0)
    _, v_far = orbit.relative_state_at_time(np.array([-1e9, 1e9]))
    assert v_far[0] / np.linalg.norm(v_far[0]) == pytest.approx(incoming, abs=1e-7)
    assert v_far[1] / np.linalg.norm(v_far[1]) == pytest.approx(outgoing, abs=1e-7)
    r_far, _ = orbit.relative_state_at_time(1e9)
    offset = r_far - centre  # the outgoing asymptote passes through the centre
    assert np.linalg.norm(np.cross(offset, outgoing)) < 1e-6
    assert centre == pytest.approx([orbit.semi_major_axis * -orbit.eccentricity, 0, 0], rel=1e-14, abs=0)


# --------------------------------------------------------------------------- contact and hand-off


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


@given(m1=masses, m2=masses, radius=distances, vinf=speeds)
def test_focusing_cross_section_is_pi_b_max_squared(m1, m2, radius, vinf):
    sigma = float(focusing_cross_section(m1, m2, 0.25 * radius, 0.75 * radius, vinf))
    assert sigma == pytest.approx(math.pi * radius**2 * (1 + 2 * (m1 + m2) / (radius * vinf**2)), rel=1e-14, abs=0)
    b_max = math.sqrt(sigma / math.pi)
    grazing = TwoBodyOrbit.from_impact_parameter(m1, m2, b_max, vinf)
    assert grazing.periastron == pytest.approx(radius, rel=1e-10, abs=0)


def test_focusing_cross_section_for_repulsion_and_arrays():
    # head-on distance 2 k / (mu v^2) = 4: no contact for R1 + R2 below it
    assert float(focusing_cross_section(1.0, 1.0, 1.0, 1.0, 1.0, k=1.0)) == 0.0
    sigma = focusing_cross_section(1.0, 1.0, np.array([3.0, 5.0]), 1.0, 1.0, k=1.0)
    assert sigma == pytest.approx(math.pi * np.array([16.0 - 16.0, 36.0 - 24.0]), abs=1e-13)


# --------------------------------------------------------------------------- units


def test_unit_systems():
    assert unit_system("si").G == const.G
    assert unit_system("cgs").G == pytest.approx(const.G * 1e3, rel=1e-15, abs=0)
    assert unit_system("nbody").G == 1.0
    assert unit_system("solar").G == pytest.approx(4 * math.pi**2, rel=1e-4, abs=0)  # Kepler: 1 AU, 1 yr
    assert unit_system("stellar").G == pytest.approx(1.9076e5, rel=1e-4, abs=0)  # G Msun / Rsun in (km/s)^2
    assert set(encounters.UNIT_SYSTEMS) == {"nbody", "si", "cgs", "solar", "stellar"}


def test_same_encounter_in_si_and_solar_units():
    solar, si = unit_system("solar"), unit_system("si")
    v_kms = 30.0
    in_solar = Hyperbolic(1.0, 0.5, periastron=2.0, v_inf=v_kms * 1e3 / solar.length_si * solar.time_si, G=solar.G)
    in_si = Hyperbolic(solar.mass_si, 0.5 * solar.mass_si, periastron=2.0 * solar.length_si, v_inf=v_kms * 1e3, G=si.G)
    assert in_solar.eccentricity == pytest.approx(in_si.eccentricity, rel=1e-13, abs=0)
    t_solar = in_solar.time_at_separation(50.0) * solar.time_si
    t_si = in_si.time_at_separation(50.0 * solar.length_si)
    assert t_solar == pytest.approx(t_si, rel=1e-12, abs=0)
    earth = TwoBodyOrbit(1.0, 3.0e-6, periastron=1.0, eccentricity=0.0, G=solar.G)
    assert earth.period == pytest.approx(1.0, rel=1e-4, abs=0)  # a = 1 AU around the Sun: a (Julian) year


# --------------------------------------------------------------------------- kernels


@pytest.mark.parametrize("z", [-50.0, -2.000001, -1.999999, -0.5, 0.5, 1.999999, 2.000001, 9.0, 39.0])
def test_stumpff_functions_against_closed_forms(z):
    """Series (|z| < 2) and closed forms agree with the definitions on both sides of the switch."""
    y = math.sqrt(abs(z))
    if z > 0:
        exact = (math.cos(y), math.sin(y) / y, (1 - math.cos(y)) / z, (y - math.sin(y)) / y**3)
    else:
        exact = (math.cosh(y), math.sinh(y) / y, (math.cosh(y) - 1) / -z, (math.sinh(y) - y) / y**3)
    assert kernels.stumpff(z) == pytest.approx(exact, rel=1e-13, abs=0)


def test_stumpff_functions_near_zero():
    for z in (0.0, 1e-12, -1e-12, 1e-3):
        c0, c1, c2, c3 = kernels.stumpff(z)
        assert (c2, c3) == pytest.approx((0.5 - z / 24 + z**2 / 720 - z**3 / 40320, 1 / 6 - z / 120 + z**2 / 5040 - z**3 / 362880), rel=1e-15, abs=0)
        assert (c0, c1) == pytest.approx((1 - z * c2, 1 - z * c3), rel=1e-16, abs=0)


# --------------------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    ("arguments", "match"),
    [
        (dict(m1=0.0), "m1"),
        (dict(m2=-1.0), "m2"),
        (dict(periastron=0.0), "periastron"),
        (dict(periastron=-2.0), "periastron"),
        (dict(v_inf=0.0), "v_inf"),
        (dict(v_inf=-1.0), "v_inf"),
        (dict(periastron=float("nan")), "periastron must be finite"),
        (dict(m1=float("inf")), "m1 must be finite"),
        (dict(G=-1.0), "G"),
    ],
)
def test_hyperbolic_rejects_bad_input(arguments, match):
    values = dict(m1=1.0, m2=1.0, periastron=1.0, v_inf=1.0) | arguments
    with pytest.raises(ValueError, match=match):
        Hyperbolic(**values)


def test_bad_types_and_ranges():
    with pytest.raises(TypeError, match="m1"):
        Hyperbolic("1", 1.0, periastron=1.0, v_inf=1.0)
    with pytest.raises(TypeError, match="single number"):
        Hyperbolic([1.0, 2.0], 1.0, periastron=1.0, v_inf=1.0)
    with pytest.raises(ValueError, match=r"periastron must be >= .*head-on"):
        Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0, k=1.0)
    with pytest.raises(ValueError, match="eccentricity"):
        TwoBodyOrbit(1.0, 1.0, periastron=1.0, eccentricity=-0.1)
    with pytest.raises(ValueError, match=r"eccentricity must lie in \[1.0"):
        TwoBodyOrbit(1.0, 1.0, periastron=1.0, eccentricity=0.5, k=1.0)
    with pytest.raises(ValueError, match="vanishes"):
        Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0, G=0.0)
    with pytest.raises(ValueError, match="impact_parameter"):
        Hyperbolic.from_impact_parameter(1.0, 1.0, 0.0, 1.0)
    with pytest.raises(ValueError, match="radial"):
        TwoBodyOrbit.from_state(1.0, 1.0, [1.0, 0.0, 0.0], [-1.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="separation"):
        TwoBodyOrbit.from_state(1.0, 1.0, [0.0, 0.0, 0.0], [1.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="units"):
        unit_system("imperial")


def test_starcrash_rejects_bad_input():
    with pytest.raises(ValueError, match="sep0 must be >= rp"):
        starcrash_initial_conditions(1.0, 1.0, 2.0, 0.5, 1.0)
    with pytest.raises(ValueError, match="v_inf"):
        starcrash_initial_conditions(1.0, 1.0, 1.0, 0.0, 10.0)
    with pytest.raises(ValueError, match="m2"):
        starcrash_initial_conditions(1.0, 0.0, 1.0, 0.5, 10.0)
    with pytest.raises(ValueError, match="sep0"):
        starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, float("nan"))
    with pytest.raises(ValueError, match="G"):
        starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, 10.0, G=0.0)
    with pytest.raises(ValueError, match="layout"):
        starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, 10.0, layout="y")


def test_methods_reject_bad_input():
    orbit = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0)
    with pytest.raises(ValueError, match=r"r must lie in \[1.0"):
        orbit.time_at_separation(0.5)
    with pytest.raises(ValueError, match="branch"):
        orbit.time_at_separation(2.0, branch="up")
    with pytest.raises(ValueError, match="t must be finite"):
        orbit.state_at_time([0.0, float("nan")])
    with pytest.raises(ValueError, match="radius1"):
        orbit.contact(-1.0, 1.0)
    with pytest.raises(ValueError, match="v_inf"):
        focusing_cross_section(1.0, 1.0, 1.0, 1.0, 0.0)
    bound = TwoBodyOrbit(1.0, 1.0, periastron=1.0, eccentricity=0.5)
    with pytest.raises(ValueError, match="r must lie in"):
        bound.time_at_separation(3.5)  # beyond apoastron 3
    with pytest.raises(ValueError, match="apoastron"):
        bound.contact(2.0, 2.0)


# ------------------------------------------------------------------ edge cases found by a mutation audit


@pytest.mark.parametrize(
    ("r", "v"),
    [([1.0, 0.0, 0.0], [0.0, 3.0, 0.0]), ([1.0, 0.0, 0.0], [0.0, -3.0, 0.0]), ([0.0, 2.0, 0.0], [0.1, 0.0, 0.8])],
)
def test_angular_momentum_vector_of_an_orbit_from_a_state_is_mu_r_cross_v(r, v):
    # kills E06 (encounters.py:249 W = P x Q -> Q x P): from_state builds the basis from the state,
    # and W must point along r x v (the orbit's own angular momentum), not against it.
    # Independent value: J = mu r x v with mu = m1 m2 / (m1 + m2) = 0.5; r x v is exact here.
    orbit = TwoBodyOrbit.from_state(1.0, 1.0, r, v)
    np.testing.assert_allclose(orbit.angular_momentum_vector, 0.5 * np.cross(r, v), rtol=1e-14, atol=1e-15)
    # and the propagated state keeps that direction
    x, u = orbit.relative_state_at_time(0.3)
    np.testing.assert_allclose(np.cross(x, u), np.cross(r, v), rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize(("k", "sign"), [(0.3, -1.0), (None, 1.0)])
def test_semi_latus_rectum_is_positive_for_attraction_and_repulsion(k, sign):
    # kills E27 (encounters.py:472 h^2 / |mu_K| -> h^2 / mu_K): for a repulsive orbit p came out
    # negative. Independent: the conic r = p / (1 + sign e cos theta) at periastron gives
    # p = r_p (1 + e) (attraction) or r_p (e - 1) (repulsion), with the module's
    # e = |1 + r_p v_inf^2 / mu_K| (rel 1e-13: a few roundings). Repulsion: mu_K = -k / mu = -0.6,
    # e = 2 / 0.6 - 1, p = 2 (e - 1) = 8 / 3; gravity: mu_K = 2, e = 2, p = 6.
    m1, m2, rp, v_inf = 1.0, 1.0, 2.0, 1.0
    orbit = Hyperbolic(m1, m2, periastron=rp, v_inf=v_inf, k=k) if k else Hyperbolic(m1, m2, periastron=rp, v_inf=v_inf)
    mu_k = (m1 + m2) if k is None else -k * (m1 + m2) / (m1 * m2)
    e = abs(1.0 + rp * v_inf**2 / mu_k)
    expected = rp * (e + sign)
    assert orbit.semi_latus_rectum > 0
    assert orbit.semi_latus_rectum == pytest.approx(expected, rel=1e-13)


def test_states_a_few_1e_9_off_the_orbit_are_refused():
    # kills E43 (encounters.py:82 ON_ORBIT_TOLERANCE 1e-9 -> 1e-8): the documented tolerance is
    # 1e-9 relative in energy or angular momentum. A velocity scaled by 1 + 3e-9 changes the
    # energy by between 3e-9 and 6e-9 of its scale (v^2 / (v^2 / 2 + mu / r) lies in (1, 2)):
    # refused; the orbit's own state (agreeing to ~1e-15) and one 1e-11 off are accepted.
    orbit = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0)
    r, v = orbit.relative_state_at_time(-3.0)
    assert orbit.time_since_periastron(r, v * (1 + 1e-11)) == pytest.approx(-3.0, rel=1e-8)
    with pytest.raises(ValueError, match="not on this orbit"):
        orbit.time_since_periastron(r, v * (1 + 3e-9))


def test_parabolic_orbit_has_no_asymptotes_or_cross_sections():
    # kills E44 (encounters.py:705 `beta >= 0` -> `beta > 0`): a parabola (v_inf = 0) must get the
    # named "needs a hyperbolic orbit" error, not a ZeroDivisionError from 1 / v_inf^2.
    parabola = TwoBodyOrbit(1.0, 1.0, periastron=1.0, eccentricity=1.0)
    assert parabola.kind == "parabolic"
    for call in (parabola.asymptotes, lambda: parabola.differential_cross_section(1.0),
                 lambda: parabola.focusing_cross_section(0.5, 0.5)):
        with pytest.raises(ValueError, match="hyperbolic"):
            call()


def test_repulsive_periastron_below_the_head_on_distance_is_refused():
    # kills E51 (encounters.py:921 head-on distance 2 |mu_K| / v^2 -> |mu_K| / v^2).
    # Independent: head-on, all of E = mu v^2 / 2 becomes k / r at the turning point:
    # r = 2 k / (mu v^2) = 2 * 1 / (0.5 * 1) = 4 for m1 = m2 = 1, k = 1, v = 1.
    with pytest.raises(ValueError, match="head-on"):
        Hyperbolic(1.0, 1.0, periastron=3.0, v_inf=1.0, k=1.0)
    ok = Hyperbolic(1.0, 1.0, periastron=4.0, v_inf=1.0, k=1.0)
    assert ok.eccentricity == pytest.approx(1.0, abs=1e-15)  # exactly head-on: radial, e = 1


def test_focusing_cross_section_needs_a_positive_contact_distance():
    # kills E55 (encounters.py:1119 R1 + R2 range (0, inf] -> [0, inf]): documented R1 + R2 > 0.
    with pytest.raises(ValueError, match=r"radius1 \+ radius2"):
        focusing_cross_section(1.0, 1.0, 0.0, 0.0, 1.0)


@pytest.mark.parametrize(("r", "D"), [(2.0, 1.0), (10.0, 3.0), (1.25, 0.5)])
def test_parabolic_time_at_separation_from_barkers_equation(r, D):
    # kills EK29 (_kernels/encounters.py:228 parabolic anomaly `2 * half` -> `half`): no test timed a
    # separation on an exact parabola. Independent route, Barker's equation: with p = 2 r_p,
    # r = r_p (1 + D^2), D = tan(theta / 2), and t = sqrt(p^3 / mu_K) (D + D^3 / 3) / 2.
    # m1 = m2 = 1, G = 1: mu_K = 2, r_p = 1, p = 2. rel 1e-14: a few roundings on each side.
    parabola = TwoBodyOrbit(1.0, 1.0, periastron=1.0, eccentricity=1.0)
    assert parabola.kind == "parabolic"
    expected = 0.5 * math.sqrt(2.0**3 / 2.0) * (D + D**3 / 3.0)
    assert parabola.time_at_separation(r, branch="outbound") == pytest.approx(expected, rel=1e-14)
    assert parabola.time_at_separation(r) == pytest.approx(-expected, rel=1e-14)


def test_repulsive_orbit_from_periastron_and_eccentricity():
    # kills E08 (encounters.py `abs(mu_k) * e` -> `mu_k * e` in TwoBodyOrbit.__init__): for a
    # repulsive force the mutant made beta = |mu_K| (e - 1) / r_p > 0, a bound "orbit".
    # Independent route: repulsive hyperbola r = p / (e cos f - 1), so r_p = p / (e - 1),
    # p = h^2 / |mu_K|, and energy v_p^2 = v_inf^2 - 2 |mu_K| / r_p. With m1 = m2 = 1, k = 1:
    # mu_K = -2; r_p = 1, e = 3 -> p = 2, h = v_p = 2, v_inf^2 = 8. Values are a few roundings
    # from exact, hence rtol 1e-14.
    orbit = TwoBodyOrbit(1.0, 1.0, periastron=1.0, eccentricity=3.0, k=1.0)
    assert orbit.kind == "hyperbolic" and not orbit.attractive
    assert orbit.eccentricity == pytest.approx(3.0, rel=1e-14)
    assert orbit.semi_latus_rectum == pytest.approx(2.0, rel=1e-14)
    assert orbit.periastron_speed == pytest.approx(2.0, rel=1e-14)
    assert orbit.v_inf == pytest.approx(math.sqrt(8.0), rel=1e-14)
    assert orbit.specific_energy == pytest.approx(4.0, rel=1e-14)  # v_inf^2 / 2
