"""Unit systems: G in N-body, SI, cgs, solar and stellar units; one encounter in two of them."""

from __future__ import annotations

import math

import pytest
import scipy.constants as const

from collisionkit import encounters
from collisionkit.encounters import Hyperbolic, TwoBodyOrbit, unit_system


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
