"""Tracking kernels: the Dormand-Prince tableau and its order, the dense output, fields against their potentials and
Maxwell's equations, map interpolation, surfaces, the optical-depth root and the ion drift."""

import math

import numpy as np
import pytest
from scipy import constants

from collisionkit._kernels.transport.tracking import codes as C
from collisionkit._kernels.transport.tracking.fields import (
    compile_user_field, electric_at, field_values, inside_map, magnetic_at, no_field, potential_at, weighting_field,
    weighting_potential,
)
from collisionkit._kernels.transport.tracking.geometry import lowest_surface, surface_normal, surface_value
from collisionkit._kernels.transport.tracking.integrator import (
    A, B5, C as NODES, E54, depth_crossing, error_norm, hermite_cubic, hermite_position, stage_state,
)
from collisionkit._kernels.transport.tracking.ions import drift_ions

BUFFER = np.zeros(3)
NO_META = np.zeros(C.MAP_META)
NO_VALUES = np.zeros((2, 2, 2, 3))


def _parameters(*values):
    out = np.zeros(C.FIELD_PARAMETERS)
    out[: len(values)] = values
    return out


def test_the_dormand_prince_tableau_satisfies_the_order_conditions():
    """Row sums equal the nodes; the 5th-order weights integrate t^k exactly up to k = 4; the error weights sum to 0
    (both solutions are consistent) and do not integrate t^4 exactly (the 4th-order one is only 4th order)."""
    assert np.allclose(A.sum(axis=1), NODES[:7], atol=1e-15)
    for power in range(5):
        assert abs(B5 @ NODES**power - 1.0 / (power + 1)) < 1e-14
    assert abs(E54.sum()) < 1e-15
    assert abs(E54 @ NODES**4) > 1e-5


def _integrate(h, periods=1.0):
    """The harmonic oscillator x'' = -x with fixed steps through the kernel's stages: the final error."""
    k = np.zeros((7, 7))
    y0, ys = np.zeros(7), np.zeros(7)
    y = np.array([1.0, 0, 0, 0, 0, 0, 0])
    steps = int(round(2 * math.pi * periods / h))
    h = 2 * math.pi * periods / steps
    for _ in range(steps):
        y0[:] = y
        k[0, :] = [y0[3], 0, 0, -y0[0], 0, 0, 0]
        for stage in range(1, 7):
            stage_state(y0, k, stage, h, ys)
            k[stage, :] = [ys[3], 0, 0, -ys[0], 0, 0, 0]
        y = ys.copy()
    return abs(y[0] - 1.0) + abs(y[3])


def test_the_step_is_fifth_order_and_the_error_norm_scales_as_h5():
    errors = [_integrate(h) for h in (0.2, 0.1)]
    assert 2**5 * 0.7 < errors[0] / errors[1] < 2**5 * 1.4  # global error O(h^5)
    y0, y1 = np.array([1.0, 0, 0, 1.0, 0, 0, 0]), np.zeros(7)
    norms = []
    for h in (0.1, 0.05):
        k = np.zeros((7, 7))
        k[0, :] = [1, 0, 0, -1, 0, 0, 0]
        for stage in range(1, 7):
            ys = np.zeros(7)
            stage_state(y0, k, stage, h, ys)
            k[stage, :] = [ys[3], 0, 0, -ys[0], 0, 0, 0]
            y1 = ys
        norms.append(error_norm(y0, y1, k, h, 1.0, 1e-30, 1.0, 1.0, False))
    assert 2**5 * 0.7 < norms[0] / norms[1] < 2**6 * 1.4  # local error estimate O(h^5) to O(h^6)


def test_the_scalar_step_of_the_null_collision_method_is_the_array_step():
    """motion.field_step (registers) against the array stages of the integrator (the path-length method's form) in a
    counter's field with an oblique uniform B: the same end state and error norm to rounding."""
    from collisionkit._kernels.transport.tracking.fields import electric_at, magnetic_at
    from collisionkit._kernels.transport.tracking.motion import field_step

    e_par = _parameters(0.0, 0.0, 25e-6, 0.01, 1500.0, math.log(0.01 / 25e-6))
    b_par = _parameters(0.01, -0.02, 0.03)
    qm = -constants.e / constants.m_e
    fields = (C.E_COAXIAL, e_par, NO_META, NO_VALUES, no_field(), C.B_UNIFORM, b_par, NO_META, NO_VALUES, no_field())

    def accel(p, v):
        e = electric_at(*fields[:5], BUFFER, *p)
        b = magnetic_at(*fields[5:], BUFFER, *p)
        return qm * (np.array(e) + np.cross(v, b))

    rng = np.random.default_rng(5)
    for _ in range(5):
        p0, v0, h = rng.normal(size=3) * 1e-3, rng.normal(size=3) * 1e6, 10.0 ** rng.uniform(-11, -9)
        k, y0, ys = np.zeros((7, 7)), np.zeros(7), np.zeros(7)
        y0[:3], y0[3:6] = p0, v0
        k[0, :3], k[0, 3:6] = v0, accel(p0, v0)
        for stage in range(1, 7):
            stage_state(y0, k, stage, h, ys, 6)
            k[stage, :3], k[stage, 3:6] = ys[3:6], accel(ys[:3], ys[3:6])
        norm = error_norm(y0, ys, k, h, 0.01, 1e3, 1e-6, 1e-5, False)
        position, velocity, end_accel, error = field_step(tuple(p0), tuple(v0), tuple(k[0, 3:6]), h, qm, *fields[:5],
                                                          *fields[5:], BUFFER, 0.01, 1e3, 1e-6)
        assert np.allclose(position, ys[:3], rtol=1e-13, atol=1e-18)
        assert np.allclose(velocity, ys[3:6], rtol=1e-13, atol=1e-6)
        assert np.allclose(end_accel, k[6, 3:6], rtol=1e-12)
        assert error == pytest.approx(norm, rel=1e-6, abs=1e-9)


def test_the_quintic_hermite_interpolant_is_exact_for_quintics_and_its_derivative_is_the_velocity():
    rng = np.random.default_rng(3)
    c = rng.normal(size=6)
    h = 0.7

    def x(t):
        return sum(c[i] * t**i for i in range(6))

    def v(t):
        return sum(i * c[i] * t ** (i - 1) for i in range(1, 6))

    def a(t):
        return sum(i * (i - 1) * c[i] * t ** (i - 2) for i in range(2, 6))

    for theta in (0.0, 0.13, 0.5, 0.91, 1.0):
        position, velocity = hermite_position(x(0), v(0), a(0), x(h), v(h), a(h), h, theta)
        assert abs(position - x(theta * h)) < 1e-12 and abs(velocity - v(theta * h)) < 1e-12
    d = rng.normal(size=4)
    f = lambda t: d[0] + d[1] * t + d[2] * t**2 + d[3] * t**3  # noqa: E731
    df = lambda t: d[1] + 2 * d[2] * t + 3 * d[3] * t**2  # noqa: E731
    assert abs(hermite_cubic(f(0), df(0), f(h), df(h), h, 0.37) - f(0.37 * h)) < 1e-12


@pytest.mark.parametrize("target", [0.05, 0.6, 1.9])
def test_the_optical_depth_crossing_is_the_root_of_the_cubic(target):
    nu0, nu1, h = 1.0, 3.0, 1.0
    depth1 = 2.1
    s = depth_crossing(nu0, depth1, nu1, h, target, h, depth1)
    assert 0.0 < s <= h
    assert abs(hermite_cubic(0.0, nu0, depth1, nu1, h, s / h) - target) < 1e-11


def _gradient(function, point, step=1e-7):
    out = np.zeros(3)
    for axis in range(3):
        delta = np.zeros(3)
        delta[axis] = step * max(1.0, abs(point[axis]))
        out[axis] = (function(*(point + delta)) - function(*(point - delta))) / (2 * delta[axis])
    return out


@pytest.mark.parametrize("kind, parameters, point", [
    (C.E_PLATES, _parameters(2e-3, 300.0), np.array([1e-3, -2e-3, 7e-4])),
    (C.E_COAXIAL, _parameters(1e-4, -2e-4, 25e-6, 1e-2, 1500.0, math.log(400)), np.array([2e-3, 1e-3, 0.3])),
    (C.E_POINT, _parameters(0.1, 0.2, 0.3, 2.5, 1e-6), np.array([0.4, -0.1, 0.5])),
    (C.E_UNIFORM, _parameters(1.0, -2.0, 3.0), np.array([0.4, -0.1, 0.5])),
])
def test_every_analytic_electric_field_is_minus_the_gradient_of_its_potential(kind, parameters, point):
    field = np.array(electric_at(kind, parameters, NO_META, NO_VALUES, no_field(), BUFFER, *point))
    gradient = _gradient(lambda x, y, z: potential_at(kind, parameters, x, y, z), point)
    assert np.allclose(field, -gradient, rtol=1e-6, atol=1e-9 * np.abs(field).max())


def _magnetic(kind, parameters):
    return lambda x, y, z: np.array(magnetic_at(kind, parameters, NO_META, NO_VALUES, no_field(), BUFFER, x, y, z))


def _jacobian(function, point, step=1e-6):
    columns = []
    for axis in range(3):
        delta = np.zeros(3)
        delta[axis] = step
        columns.append((function(*(point + delta)) - function(*(point - delta))) / (2 * step))
    return np.array(columns).T  # J[i, j] = dB_i / dx_j


def test_the_dipole_field_is_divergence_and_curl_free_and_has_its_axis_and_equator_values():
    dipole = _parameters(0.0, 0.0, 0.0, 0.2, -0.1, 0.5, 1e-9)
    jacobian = _jacobian(_magnetic(C.B_DIPOLE, dipole), np.array([0.3, 0.2, -0.4]))
    scale = np.abs(jacobian).max()
    assert abs(np.trace(jacobian)) < 1e-6 * scale
    assert np.allclose(jacobian, jacobian.T, atol=1e-6 * scale)  # curl B = 0
    axial = _parameters(0, 0, 0, 0, 0, 1.0, 1e-9)
    assert np.allclose(_magnetic(C.B_DIPOLE, axial)(0, 0, 2.0), [0, 0, 2e-7 / 8])  # mu0 m / (2 pi r^3)
    assert np.allclose(_magnetic(C.B_DIPOLE, axial)(2.0, 0, 0), [0, 0, -1e-7 / 8])


def test_the_mirror_field_is_divergence_free_with_its_axial_profile():
    mirror = _parameters(0.0, 0.0, 0.1, 0.02, 0.5)
    field = _magnetic(C.B_MIRROR, mirror)
    jacobian = _jacobian(field, np.array([0.01, -0.02, 0.3]))
    assert abs(np.trace(jacobian)) < 1e-8
    assert np.allclose(field(0, 0, 0.1 + 0.5), [0, 0, 0.04])  # B0 (1 + (z/L)^2) with z = L


def test_map_interpolation_is_exact_for_linear_fields_and_clamps_outside_the_box():
    origin, spacing, shape = np.array([-1e-3, 0.0, 2e-3]), np.array([1e-3, 5e-4, 2e-3]), (4, 5, 3)
    axes = [origin[d] + spacing[d] * np.arange(shape[d]) for d in range(3)]
    x, y, z = np.meshgrid(*axes, indexing="ij")
    gradient = np.array([[1.0, 2.0, -3.0], [0.5, -1.0, 2.0], [4.0, 0.0, 1.0]]) * 1e6
    values = np.ascontiguousarray(np.stack([x, y, z], axis=-1) @ gradient.T + np.array([1.0, 2.0, 3.0]))
    meta = np.zeros(C.MAP_META)
    meta[0:3], meta[3:6], meta[6:9], meta[9], meta[12:15] = origin, spacing, shape, 3, 1.0 / spacing
    point = np.array([0.3e-3, 1.1e-3, 4.5e-3])
    exact = gradient @ point + np.array([1.0, 2.0, 3.0])
    assert np.allclose(electric_at(C.E_MAP, np.zeros(8), meta, values, no_field(), BUFFER, *point), exact)
    assert inside_map(meta, *point) and not inside_map(meta, 0.0, 0.0, 1.0)
    corner = np.array(electric_at(C.E_MAP, np.zeros(8), meta, values, no_field(), BUFFER, -5.0, -5.0, -5.0))
    assert np.allclose(corner, values[0, 0, 0])


def test_a_user_field_is_called_by_the_kernels():
    def swirl(x, y, z, out):
        out[0] = -y
        out[1] = x
        out[2] = 0.5

    out = np.zeros((2, 3))
    field_values(True, C.B_USER, np.zeros(8), NO_META, NO_VALUES, compile_user_field(swirl),
                 np.array([[1.0, 2.0, 3.0], [0.0, -1.0, 0.0]]), out)
    assert out.tolist() == [[-2.0, 1.0, 0.5], [1.0, 0.0, 0.5]]


def test_weighting_potentials_are_one_on_the_readout_zero_on_the_other_electrode_and_fields_their_gradients():
    plates = _parameters(2e-3)
    assert weighting_potential(C.W_PLATES, plates, 0, 0, 2e-3) == 1.0 and weighting_potential(C.W_PLATES, plates,
                                                                                              0, 0, 0) == 0
    coax = _parameters(0.0, 0.0, 25e-6, 1e-2, math.log(400))
    assert abs(weighting_potential(C.W_COAXIAL, coax, 25e-6, 0, 0) - 1) < 1e-15
    assert abs(weighting_potential(C.W_COAXIAL, coax, 0, 1e-2, 0)) < 1e-15
    for kind, parameters in ((C.W_PLATES, plates), (C.W_COAXIAL, coax)):
        point = np.array([3e-4, 4e-4, 1e-3])
        field = np.array(weighting_field(kind, parameters, *point))
        gradient = _gradient(lambda x, y, z: weighting_potential(kind, parameters, x, y, z), point, 1e-9)
        assert np.allclose(field, -gradient, rtol=1e-5)


def _surfaces():
    return np.array([
        [C.PLANE, C.ABSORB, 0, 0, 1.0, 0, 0, -1.0, 0, 0, 0, 0],
        [C.CYLINDER, C.REFLECT, 0, 0, 0, 0, 0, 1.0, 2.0, 1.0, 0, 0],
        [C.SPHERE, C.TRANSPARENT, 0, 0, 0, 0, 0, 0, 0.5, -1.0, 0, 0],
    ])


def test_signed_distances_normals_and_the_lowest_surface():
    surfaces = _surfaces()
    point = np.array([1.2, 0.9, -0.3])
    rho, r = math.hypot(1.2, 0.9), np.linalg.norm(point)
    distances = [surface_value(surfaces, k, *point) for k in range(3)]
    assert np.allclose(distances, [1.3, 2.0 - rho, r - 0.5])
    assert lowest_surface(surfaces, *point) == (pytest.approx(2.0 - rho), 1)
    assert np.allclose(surface_normal(surfaces, 1, *point), [1.2 / rho, 0.9 / rho, 0.0])
    assert lowest_surface(np.zeros((0, C.SURFACE_COLUMNS)), 0.0, 0.0, 0.0) == (math.inf, -1)


def test_ions_drift_along_the_field_of_a_counter_in_the_analytic_time():
    """dr/dt = K V / (r ln(b/a)) outward for a positive ion: t = ln(b/a) (b^2 - r0^2) / (2 K V) to the cathode."""
    a, b, voltage, mobility, r0 = 25e-6, 1e-2, 1500.0, 1.5e-4, 1e-4
    surfaces = np.array([[C.CYLINDER, C.ABSORB, 0, 0, 0, 0, 0, 1, a, -1, 0, 0],
                         [C.CYLINDER, C.ABSORB, 0, 0, 0, 0, 0, 1, b, 1, 0, 0]])
    births = np.array([[0, 0.0, r0, 0.0, 0.0], [0, 1e-6, 0.0, -r0, 0.0]])
    records = np.zeros((2, C.RECORD_COLUMNS))
    induced = np.zeros(1)
    logarithm = math.log(b / a)
    drift_ions(births, records, induced, np.zeros(0), C.E_COAXIAL, _parameters(0, 0, a, b, voltage, logarithm),
               NO_META, NO_VALUES, no_field(), C.W_COAXIAL, _parameters(0, 0, a, b, logarithm), surfaces, mobility,
               1.602176634e-19, 1e-9,
               a, 1.0, 10**6, 0.0, 1.0)
    expected = math.log(b / a) * (b**2 - r0**2) / (2 * mobility * voltage)
    assert np.allclose(records[:, C.RECORD_TIME] - births[:, 1], expected, rtol=1e-6)
    assert records[:, C.RECORD_SURFACE].tolist() == [1.0, 1.0]
    # Shockley-Ramo: the induced charge is -q (phi_w(b) - phi_w(r0)) = q ln(b/r0) / ln(b/a) for each ion
    assert induced[0] == pytest.approx(2 * 1.602176634e-19 * math.log(b / r0) / math.log(b / a), rel=1e-6)


@pytest.mark.parametrize("shape, spacing", [((40, 30), (1.0, 2.0)), ((12, 9, 10), (1.0, 0.5, 2.0))])
def test_the_local_bound_of_a_map_covers_the_field_within_the_reach_and_is_local(shape, spacing):
    """electric_bound of a map: at random points and reaches, never below |E| at random points within the reach
    (the interpolated field there); for a reach below one cell, no more than the largest |value| of the grid points
    within two cells (the first level: a cell and its neighbours); beyond the grid's size, the grid's largest value."""
    from collisionkit.transport.tracking import FieldMap
    from collisionkit._kernels.transport.tracking.fields import electric_bound

    rng = np.random.default_rng(7)
    values = rng.normal(size=(*shape, 3)) * np.exp(rng.normal(size=(*shape, 1)) * 2)
    fieldmap = FieldMap((0.0,) * len(shape), spacing, values)
    kind, parameters, meta, grid, user = fieldmap.arrays()
    blocks = fieldmap.blocks()
    top = (np.array(shape) - 1) * spacing
    magnitude = np.linalg.norm(values, axis=-1)
    for _ in range(300):
        centre = np.zeros(3)
        centre[: len(shape)] = rng.uniform(0, top)
        reach = rng.uniform(0, 8.0) * 10.0 ** rng.uniform(-2, 1)
        bound = electric_bound(kind, parameters, meta, blocks, *centre, reach)
        offsets = rng.normal(size=(50, 3))
        offsets *= reach * rng.uniform(0, 1, (50, 1)) / np.linalg.norm(offsets, axis=1, keepdims=True)
        nearby = fieldmap.at(centre + offsets)
        assert np.linalg.norm(nearby, axis=1).max() <= bound * (1 + 1e-12)
        if reach < min(spacing):
            cell = (centre[: len(shape)] / spacing).astype(int)
            window = tuple(slice(max(c - 1, 0), c + 3) for c in cell)
            assert bound <= magnitude[window].max()
    assert electric_bound(kind, parameters, meta, blocks, 5.0, 5.0, 0.0, 1000.0) == meta[10]
