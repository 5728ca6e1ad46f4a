"""Restitution laws: the viscoelastic contact against its published expansion, the kernels' fit against the contact
solved directly, the engine against the law, and the Maxwellian cooling rate against closed forms and runs."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.special import beta, gamma, gammaincc

from collisionkit import edmd
from collisionkit.edmd import EdmdParameters, EdmdRun, maxwellian_cooling, maxwellian_cooling_rate
from collisionkit.edmd import restitution_coefficient

from . import viscoelastic_contact as contact

# ------------------------------------------------------------------ the contact itself


def test_first_order_loss_is_the_dissipation_along_the_elastic_hertz_path():
    """1 - e -> C1 P: the loss over the undamped path, 3 P (2/5) B(3/5, 3/2) (5/4)^(3/5) / 1.5 per unit P (an
    independent derivation of Ramirez et al.'s C1 = sqrt(pi) Gamma(3/5) / (2^(1/5) 5^(2/5) Gamma(21/10)) =
    1.15344). Kills: a damping force without its 3/2 (P -> 1.5 P), a wrong C1."""
    derived = 2.0 * (2.0 / 5.0) * beta(0.6, 1.5) * 1.25**0.6
    assert contact.C1 == pytest.approx(derived, rel=1e-14)
    assert contact.C1 == pytest.approx(1.15344, abs=1e-5)
    damping = 1e-5
    assert (1.0 - contact.restitution_of_damping(damping)) / damping == pytest.approx(contact.C1, rel=2e-5)


def test_second_order_matches_ramirez_et_al():
    """With the contact ending at xi = 0, e = 1 - C1 P + C2 P^2 with C2 = 0.79826 (Ramirez, Poeschel, Brilliantov &
    Schwager, PRE 60, 4465 (1999)); ending when the force vanishes adds a P^(5/2) term (Schwager & Poeschel 2008):
    the difference grows as P^(5/2). Kills: the force criterion replaced by the surfaces parting (no
    difference)."""
    damping = 1e-4
    zero = contact.restitution_of_damping(damping, end="zero")
    assert (zero - 1.0 + contact.C1 * damping) / damping**2 == pytest.approx(0.79826, abs=2e-4)
    differences = [contact.restitution_of_damping(p) - contact.restitution_of_damping(p, end="zero")
                   for p in (1e-3, 4e-3)]
    assert all(difference > 0 for difference in differences)  # the force lets go early: less work against damping
    assert math.log(differences[1] / differences[0]) / math.log(4.0) == pytest.approx(2.5, abs=0.05)


def test_kernel_series_is_the_contact_solved_directly():
    """The kernels' Chebyshev series at 40 log-uniform q in [1e-6, 1e4] within 1e-9 of fresh solutions; beyond
    q_max its tail within 1e-4. Kills: a leading coefficient changed in its 9th digit, the mapping without its
    square root."""
    rng = np.random.default_rng(5)
    q = 10.0 ** rng.uniform(-6.0, 4.0, 40)
    exact = np.array([contact.restitution_of_q(value) for value in q])
    np.testing.assert_allclose(restitution_coefficient(q**5, "viscoelastic"), exact, rtol=1e-9)  # u_n / u_c = q^5
    far = np.array([2e4, 1e5])
    np.testing.assert_allclose(restitution_coefficient(far**5, "viscoelastic"),
                               [contact.restitution_of_q(value) for value in far], rtol=1e-4)


def test_nearly_elastic_contacts_keep_the_relative_accuracy_of_their_loss():
    """Below q = 1e-5 the law is 1 - q + (3/5) q^2 (3/5 = C2 / C1^2 of Ramirez et al.): the contact solved directly
    leaves 0.18 q^(5/2) beyond it (the force criterion's own term), and the loss 1 - e just above the switch is
    within 1e-5 of the solution's; the two sides meet within 1e-10. Kills: the series' ln e(0) = 5e-12 kept
    (1 - e off by 5e-4 at q = 1e-8), 0.79826 q^2 (C2 unscaled)."""
    from collisionkit._kernels.edmd.restitution_laws import VISCOELASTIC_Q_SERIES

    for q in (3e-4, 1e-3):
        remainder = (contact.restitution_of_q(q) - 1.0 + q - 0.6 * q * q) / q**2.5
        assert 0.15 < remainder < 0.19
    for q in (1.5e-5, 1e-4):
        loss = 1.0 - restitution_coefficient(q**5, "viscoelastic")
        assert loss == pytest.approx(1.0 - contact.restitution_of_q(q), rel=1e-5)
    assert 1.0 - restitution_coefficient(1e-40, "viscoelastic") == pytest.approx(1e-8, rel=1e-7)  # (e rounds to 1e-16)
    below, above = restitution_coefficient(np.array([0.999999, 1.000001]) ** 5 * VISCOELASTIC_Q_SERIES**5,
                                           "viscoelastic")
    assert abs(below - above) < 1e-10


# ------------------------------------------------------------------ the engine applies the law


def _head_on(speed, **options):
    """Separation over approach speed of one head-on collision of two unit spheres."""
    positions = np.array([[4.0, 5.0, 5.0], [6.0, 5.0, 5.0]])
    velocities = np.array([[speed / 2, 0, 0], [-speed / 2, 0, 0]])
    system = edmd.HardSphereSystem(positions, velocities, 0.5, 20.0, **options)
    assert system.run(collisions=1) == 1
    v = system.velocities()
    return (v[1, 0] - v[0, 0]) / speed


@pytest.mark.parametrize("speed", [1e-3, 0.3, 2.0, 50.0])
def test_engine_gives_the_viscoelastic_law(speed):
    """The kernel's e at u_n = speed, u_c = 1e-2, is the contact's at q = (u_n / u_c)^(1/5) (within the kernel's
    round-off), and a smaller constant caps it. Kills: q = (u_n/u_c) without the fifth root, max for min."""
    exact = contact.restitution_of_q((speed / 1e-2) ** 0.2)
    assert _head_on(speed, restitution_law="viscoelastic", law_speed=1e-2) == pytest.approx(exact, rel=1e-9)
    capped = _head_on(speed, restitution=0.3, restitution_law="viscoelastic", law_speed=1e-2)
    assert capped == pytest.approx(min(0.3, exact), rel=1e-9)


def test_library_law_is_the_engine_law():
    """restitution_coefficient gives what the engine applies, for each law, cap and floor."""
    cases = [(3.0, {"restitution_law": "bridges", "law_speed": 0.5, "law_exponent": 0.4}),
             (0.4, {"restitution_law": "bridges", "law_speed": 0.5}),
             (3.0, {"restitution_law": "viscoelastic", "law_speed": 1e-3, "restitution": 0.95}),
             (3.0, {"restitution_law": "viscoelastic", "law_speed": 1e-3, "elastic_below": 5.0}),
             (3.0, {"restitution": 0.7})]
    for speed, options in cases:
        library = {"law": options.get("restitution_law", "constant"), "restitution": options.get("restitution", 1.0),
                   "law_speed": options.get("law_speed", 1.0), "law_exponent": options.get("law_exponent", 0.234),
                   "elastic_below": options.get("elastic_below", 0.0)}
        assert _head_on(speed, **options) == pytest.approx(restitution_coefficient(speed, **library), rel=1e-9)


def test_restitution_coefficient_refuses_bad_arguments():
    with pytest.raises(ValueError, match="law must be one of constant, bridges, viscoelastic"):
        restitution_coefficient(1.0, "hertz")
    with pytest.raises(ValueError, match="law_speed"):
        restitution_coefficient(1.0, "viscoelastic", law_speed=0.0)
    with pytest.raises(ValueError, match="speed"):
        restitution_coefficient(-1.0, "viscoelastic")
    with pytest.raises(ValueError, match="restitution"):
        restitution_coefficient(1.0, restitution=1.5)


# ------------------------------------------------------------------ the Maxwellian cooling rate


@pytest.mark.parametrize("dim", [2, 3])
def test_constant_restitution_gives_haff(dim):
    """(1 - e^2)/d, and with an elastic floor u_f the loss from u_n > u_f only:
    (1 - e^2)(a^2 + 2) e^(-a^2/2) / (2d), a = u_f / sqrt(2kT/m). Kills: sigma^2 = kT/m, a floor ignored."""
    assert maxwellian_cooling_rate(1.3, dim, restitution=0.8) == pytest.approx(0.36 / dim, rel=1e-10)
    kT, mass, floor = 0.7, 2.0, 0.5
    a = floor / math.sqrt(2 * kT / mass)
    expected = 0.36 * (a * a + 2) * math.exp(-a * a / 2) / (2 * dim)
    assert maxwellian_cooling_rate(kT, dim, mass, restitution=0.8, elastic_below=floor) == pytest.approx(
        expected, rel=1e-9)


def test_bridges_rate_has_a_closed_form():
    """For e = (u/u_c)^-p above u_c: the integral is (a^2 + 2) e^(-a^2/2) - a^(2p) 2^(1-p) Gamma(2-p)
    Q(2-p, a^2/2), a = u_c / sigma (the incomplete gamma function). Kills: the exponent's sign, the law
    applied below u_c."""
    kT, p, u_c = 0.8, 0.234, 0.6
    a = u_c / math.sqrt(2 * kT)
    integral = (a * a + 2) * math.exp(-a * a / 2) - a ** (2 * p) * 2 ** (1 - p) * gamma(2 - p) * gammaincc(
        2 - p, a * a / 2)
    assert maxwellian_cooling_rate(kT, 3, law="bridges", law_speed=u_c) == pytest.approx(integral / 6, rel=1e-9)


def test_slightly_viscoelastic_gas_cools_at_a_rate_growing_as_t_to_the_tenth():
    """1 - e^2 ~ 2 (u/u_c)^(1/5): rate = (2/d) Gamma(21/10) (4kT/m)^(1/10) u_c^(-1/5) (whence T ~ t^(-5/3),
    Brilliantov & Poeschel, PRE 61, 5573 (2000)). At u_c = 1e25, q ~ 1e-5: first order holds to 1e-4."""
    for kT in (1e-2, 1.0, 1e2):
        expected = (2.0 / 3.0) * gamma(2.1) * (4 * kT) ** 0.1 * 1e25**-0.2
        assert maxwellian_cooling_rate(kT, 3, law="viscoelastic", law_speed=1e25) == pytest.approx(expected,
                                                                                                  rel=1e-4)


def test_maxwellian_cooling_follows_its_rate():
    """kT(C) is Haff's exponential for a constant e; for a law, d ln kT/dC at each point is minus the rate there.
    Kills: the rate taken at kT0 throughout."""
    C = np.linspace(0.0, 30.0, 7)
    np.testing.assert_allclose(maxwellian_cooling(C, 2.0, 2, restitution=0.7), 2.0 * np.exp(-0.51 * C / 2),
                               rtol=1e-7)
    law = {"law": "viscoelastic", "law_speed": 10.0}
    C = np.array([5.0, 5.001, 40.0, 40.001])
    kT = maxwellian_cooling(C, 1.0, 3, **law)
    for at in (0, 2):
        slope = -math.log(kT[at + 1] / kT[at]) / 0.001
        assert slope == pytest.approx(maxwellian_cooling_rate(math.sqrt(kT[at] * kT[at + 1]), 3, **law), rel=1e-4)
    assert kT[2] < kT[0] * math.exp(-35 * maxwellian_cooling_rate(kT[2], 3, **law))  # it slowed as it cooled


# ------------------------------------------------------------------ runs


def test_run_parameters_take_a_law_and_refuse_what_it_does_not_use():
    p = EdmdParameters(restitution_law="viscoelastic", law_speed=1e4)
    assert not p.elastic and p.to_dict()["restitution_law"] == "viscoelastic"
    refusals = [({"law_speed": 2.0}, "law_speed needs restitution_law bridges or viscoelastic"),
                ({"restitution_law": "viscoelastic", "law_exponent": 0.3}, "law_exponent needs restitution_law bridges"),
                ({"restitution_law": "elastic"}, "restitution_law must be one of constant, bridges, viscoelastic"),
                ({"restitution_law": "bridges", "law_speed": 1e31}, r"law_speed must be in \(0, 1e\+30\]"),
                ({"restitution_law": "bridges", "law_exponent": 0.0}, "law_exponent"),
                ({"restitution_law": "bridges", "transport": True}, "transport needs restitution 1 and "),
                ({"restitution_law": "bridges", "well_width": 1.5}, "well_width cannot be combined with restitution")]
    for options, message in refusals:
        with pytest.raises(ValueError, match=message):
            EdmdParameters(**options)
    positions = np.array([[4.0, 5.0, 5.0], [6.0, 5.0, 5.0]])
    with pytest.raises(ValueError, match="square wells run without a restitution_law"):
        edmd.HardSphereSystem(positions, np.zeros((2, 3)), 0.5, 20.0, restitution_law="viscoelastic", well_width=1.5)


def _law_run(seed, **law):
    parameters = EdmdParameters(particles=2000, packing_fraction=0.02, equilibration=0, collisions=100_000,
                                blocks=20, seed=seed, restitution_law="viscoelastic", **law)
    return EdmdRun(parameters).run().summary()


def test_viscoelastic_gas_cools_at_the_maxwellian_rate():
    """A dilute viscoelastic gas (u_c = 1e3: e from 0.6 to 0.95 as it cools 10^5-fold) against the Maxwellian rate
    block by block: within 5 of its errors plus 1 % (the velocity distribution's own correction: -0.24 to -0.48 %
    over 10 seeds at u_c 1e8 and 1e3, as -0.46 % for constant e = 0.9). No a2 theory with a law. Kills: the theory
    at the run's first kT (0.145 instead of ~0.093), the law ignored by the engine (a constant-1 gas: no cooling)."""
    summary = _law_run(3, law_speed=1e3)
    assert summary["restitution_law"] == "viscoelastic" and summary["temperature"] < 1e-3
    # the error of the rate is the blocks' scatter about the theory (~0.3 %), not about their mean (~5 %)
    assert summary["cooling_rate_error"] < 0.01 * summary["cooling_rate"]
    deviation = summary["cooling_rate"] / summary["cooling_rate_theory"] - 1.0
    assert abs(summary["cooling_rate_deviation_sigmas"]) < 5.0
    assert abs(deviation) < 0.01 + 5.0 * summary["cooling_rate_error"] / summary["cooling_rate_theory"]
    assert "sonine_a2_theory" not in summary


@pytest.mark.slow
def test_law_cooling_errors_match_the_scatter_of_seeds():
    """The deviation in sigmas (from the blocks' residuals about the theory) scatters over 12 seeds as a unit
    normal about its mean offset: standard deviation within the 99 % range of a chi with 11 degrees of freedom
    (0.49-1.56). Kills: the residuals' error taken from the blocks' rates themselves (sd ~0.3), or a
    per-block error without its 1 / sqrt(blocks) (sd ~0.27)."""
    sigmas = [_law_run(seed, law_speed=1e8)["cooling_rate_deviation_sigmas"] for seed in range(1, 13)]
    assert 0.49 < float(np.std(sigmas, ddof=1)) < 1.56


def test_a_mixture_with_a_law_says_it_has_no_cooling_theory():
    """A binary mixture with the viscoelastic law gets its species' temperatures measured but no theory, and its
    note says so instead of pointing at a cooling theory."""
    parameters = EdmdParameters(particles=200, packing_fraction=0.05, fractions=(0.5, 0.5), masses=(1.0, 0.5),
                                restitution_law="viscoelastic", law_speed=10.0, equilibration=0, collisions=4000,
                                blocks=4, seed=2)
    run = EdmdRun(parameters).run()
    summary = run.summary()
    assert "cooling_rate_theory" not in summary and "temperature_species_theory" not in summary
    assert len(summary["temperature_species"]) == 2
    assert "no cooling theory is given for a mixture with a restitution law" in run.cooling_note()
