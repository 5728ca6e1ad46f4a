"""Slab problem (Krasov, sec. 5.5): transmission x > d and reflection x < 0.

Reference values: /work/shared/reference/validation-data.md ("Slab with isotropic scattering").
"""

import math

import numpy as np
import pytest
from scipy import special

from collisionkit.transport import simulate_slab


def _within(result, value, expected, error, sigmas=4.0):
    return abs(value - expected) <= sigmas * error


@pytest.mark.parametrize("tau", [0.5, 2.0, 6.0])
def test_rod_model_transmission_is_one_over_one_plus_half_tau(tau):
    r = simulate_slab(tau, model="rod", particles=200_000, seed=1)
    assert r.transmission_error < 0.002
    assert abs(r.transmission - 1 / (1 + tau / 2)) < 4 * r.transmission_error
    assert r.reflection + r.transmission == pytest.approx(1.0, abs=1e-12)


@pytest.mark.parametrize("incidence", ["normal", "isotropic"])
def test_no_absorption_means_reflection_plus_transmission_is_one(incidence):
    r = simulate_slab(3.0, 1.0, incidence=incidence, particles=50_000, seed=2)
    assert r.absorption == 0.0
    assert r.reflection + r.transmission == pytest.approx(1.0, abs=1e-12)
    assert sum(r.transmitted_angles) + sum(r.reflected_angles) == pytest.approx(1.0)


def test_pure_absorption_gives_exp_minus_tau_and_two_e3():
    # uncollided transmission is exact: exp(-tau) for a normal beam, 2 E_3(tau) for an isotropic flux
    normal = simulate_slab(1.5, 0.0, particles=200_000, seed=3)
    assert abs(normal.transmission - math.exp(-1.5)) < 4 * normal.transmission_error
    iso = simulate_slab(1.5, 0.0, incidence="isotropic", particles=200_000, seed=3)
    assert abs(iso.transmission - 2 * special.expn(3, 1.5)) < 4 * iso.transmission_error


def test_thin_slab_limit_reflection_is_half_the_single_scatterings():
    # tau -> 0: one collision at most, probability tau, half of isotropic scatterings go back:
    # R = tau/2 + O(tau^2) (normal incidence)
    tau = 0.01
    r = simulate_slab(tau, 1.0, particles=400_000, seed=4)
    assert abs(r.reflection - tau / 2) < 4 * r.reflection_error + tau**2


def test_heavy_target_energy_loss_shows_in_the_energy_distribution():
    r = simulate_slab(2.0, 1.0, mass_ratio=2.0, particles=50_000, seed=5)
    assert r.reflected_energies[:-1].sum() > 0.5 * r.reflection  # most reflected particles lost energy
    alpha = ((2.0 - 1) / (2.0 + 1)) ** 2
    low = r.energy_edges[1:] <= alpha**6
    assert r.reflected_energies[low].sum() < 0.2 * r.reflection


def test_results_do_not_depend_on_threads_and_input_is_checked():
    a = simulate_slab(1.0, 0.7, particles=6400, seed=9, threads=1)
    b = simulate_slab(1.0, 0.7, particles=6400, seed=9, threads=2)
    assert a.to_dict() == b.to_dict()
    for kwargs, message in ((dict(thickness=-1.0), "thickness"), (dict(thickness=1.0, albedo=1.5), "albedo"),
                            (dict(thickness=1.0, incidence="oblique"), "incidence"),
                            (dict(thickness=1.0, mass_ratio=0.5), "mass_ratio")):
        with pytest.raises(ValueError, match=message):
            simulate_slab(**kwargs)


@pytest.mark.parametrize(
    "args, kwargs, error, message",
    [
        ((1.0,), dict(threads=-1), ValueError, "threads must be an integer >= 1; got -1"),
        ((1.0,), dict(threads=0), ValueError, "threads must be an integer >= 1; got 0"),
        (("1",), {}, TypeError, "thickness"),
        ((np.nan,), {}, ValueError, "thickness"),
        ((True,), {}, TypeError, "thickness .* not a bool"),
        ((1.0, np.array([0.5, 0.5])), {}, ValueError, "albedo must be a single number"),
        ((1.0, True), {}, TypeError, "albedo .* not a bool"),
        ((1.0,), dict(mass_ratio=np.nan), ValueError, "mass_ratio"),
        ((1.0,), dict(particles=True), TypeError, "particles must be an integer >= 64"),
        ((1.0,), dict(particles=1e5 + 0.5), TypeError, "particles must be an integer >= 64"),  # 1e5 counts
        ((1.0,), dict(seed=-1), ValueError, "seed must be an integer >= 0"),
        ((1.0,), dict(angle_bins=0), ValueError, r"angle_bins must be an integer in \[1, 10000\]"),
        ((1.0,), dict(incidence=["normal"]), ValueError, "incidence"),
    ],
)
def test_bad_arguments_are_refused_with_their_names(args, kwargs, error, message):
    with pytest.raises(error, match=message):
        simulate_slab(*args, **kwargs)


@pytest.mark.parametrize("options", [{"incidence": "isotropic"}, {"mass_ratio": 4.0}])
def test_the_rod_model_refuses_what_it_cannot_model(options):
    # the 1D rod kernel ignored both: T = 0.5014 with or without them, under an 'isotropic incidence' title
    with pytest.raises(ValueError, match="rod model is one-dimensional"):
        simulate_slab(2.0, model="rod", particles=1000, seed=1, threads=1, **options)


# ------------------------------------------------------------------ found by a mutation audit


def test_pure_absorber_collides_once_per_absorbed_particle():
    """albedo 0, normal beam: a particle collides at most once, with probability 1 - exp(-d); so the mean
    number of collisions per particle is 1 - exp(-d) (binomial error). Kills: collisions_per_particle halved,
    the kernel counting a collision twice."""
    d, n = 1.2, 100_000
    r = simulate_slab(d, 0.0, particles=n, seed=6)
    p = 1 - math.exp(-d)
    assert abs(r.collisions_per_particle - p) < 4.5 * math.sqrt(p * (1 - p) / n)
    assert r.collisions_per_particle == pytest.approx(r.absorption, rel=1e-12)


def test_energy_spectra_are_split_by_exit_side_and_sum_to_the_probabilities():
    """Infinitely heavy targets keep the energy: every transmitted particle is in the last energy bin of the
    transmitted spectrum, every reflected one in the reflected spectrum; the spectra sum to T and R
    (d = 0.5: T ~ 0.7, R ~ 0.2, far apart). Kills: transmitted spectrum read from the reflected row, the
    kernel filing reflected energies under transmitted."""
    r = simulate_slab(0.5, 0.9, particles=20_000, seed=7, energy_bins=5)
    assert r.transmission - r.reflection > 0.3
    assert r.transmitted_energies.sum() == pytest.approx(r.transmission, rel=1e-12)
    assert r.reflected_energies.sum() == pytest.approx(r.reflection, rel=1e-12)
    assert r.transmitted_energies[-1] == pytest.approx(r.transmission, rel=1e-12)


def test_reflection_of_a_weakly_scattering_half_space_peaks_at_normal_exit():
    """Single scattering (albedo 0.2, d = 20, normal beam) dominates reflection: a collision at depth x
    (density e^-x), isotropic scattering, escape at cosine mu with probability e^(-x/mu) give a reflected
    density (albedo / 2) mu / (1 + mu) in mu; per half of [0, 1]: 0.0945 and 0.2123 times albedo / 2
    (ratio 2.25; multiple scattering, ~20 %, flattens it a little). About 1500 reflections give the ratio
    to ~7 %. 10 bins: with 2 bins int(mu * bins) -> int(-mu * bins) would be invisible (index -1 is the
    last bin). Kills: reflected angles binned at int(mu * bins) (negative: mirrored) or reversed."""
    r = simulate_slab(20.0, 0.2, particles=100_000, seed=8, angle_bins=10)
    single = 0.1 * (1 - math.log(2))  # (albedo / 2) * (1 - ln 2): single-scattering reflection
    assert r.reflection == pytest.approx(single, rel=0.3)
    low, high = r.reflected_angles[:5].sum(), r.reflected_angles[5:].sum()
    assert 1.7 < high / low < 2.8  # a mirrored histogram gives 0.69


def test_equal_masses_never_turn_back_in_one_collision():
    # mass_ratio = 1 (neutrons on hydrogen) was refused; in one collision the lab angle is at most 90 degrees
    # (cos = sqrt((1 + c) / 2)), so a thin slab reflects only after two collisions, O(d^2), while A = 2 reflects
    # after one, O(d)
    thin = dict(thickness=0.05, particles=100_000, seed=8)
    equal = simulate_slab(mass_ratio=1.0, **thin)
    heavier = simulate_slab(mass_ratio=2.0, **thin)
    assert np.isfinite([equal.transmission, equal.reflection]).all()
    assert equal.transmission + equal.reflection + equal.absorption == pytest.approx(1.0, abs=1e-12)
    assert equal.reflection < 2e-3  # two collisions: probability below d^2 / 2 = 1.25e-3
    assert heavier.reflection > 5 * equal.reflection + 4 * heavier.reflection_error


def test_the_result_does_not_depend_on_the_collision_budget_of_a_kernel_call(monkeypatch):
    # histories cut short by the budget go on in the next call with the same random numbers
    from collisionkit.transport import slab

    reference = simulate_slab(3.0, 0.9, mass_ratio=4.0, particles=640, seed=5, threads=2).to_dict()
    monkeypatch.setattr(slab, "COLLISIONS_PER_CALL", 7)
    progress = []
    cut = simulate_slab(3.0, 0.9, mass_ratio=4.0, particles=640, seed=5, threads=2, progress=progress.append)
    assert cut.to_dict() == reference
    assert progress[-1] == 1.0 and progress == sorted(progress)


def test_ctrl_c_stops_a_thick_slab_within_a_second():
    # issue 16, item 9: one kernel call ran a batch's histories to their end (here 1.6e5 histories of about
    # d = 2e4 collisions each, a minute a batch), and Ctrl-C waited for every batch to end
    import _thread
    import signal
    import threading
    import time

    from tests.sweep.helpers import deadline

    simulate_slab(1.0, particles=64, seed=1, threads=2)  # compiled first: Ctrl-C during a compile waits for it
    # Python's own Ctrl-C handler (interrupt_main does nothing under SIG_DFL or SIG_IGN, which a library run
    # earlier in the session may have left)
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.5, _thread.interrupt_main)
    start = time.perf_counter()
    timer.start()
    try:
        with deadline(20.0), pytest.raises(KeyboardInterrupt):
            simulate_slab(20_000.0, particles=10**7, seed=1, threads=2)
    finally:
        signal.signal(signal.SIGINT, previous)
    assert time.perf_counter() - start < 2.0
