"""collisionkit._params: the checks every run's parameters use, and the flag / Python name spellings."""

from __future__ import annotations

import dataclasses
import math
from typing import ClassVar

import pytest
from hypothesis import given
from hypothesis import strategies as st

from collisionkit._params import Parameters, check_integer, check_real, check_unchanged


@dataclasses.dataclass(frozen=True)
class Run(Parameters):
    reduced_field: float = 1.0
    packing_fraction: float = 0.3

    FLAGS: ClassVar = {"reduced_field": "E-N"}


@given(st.floats(allow_nan=False, allow_infinity=False, min_value=-1e6, max_value=1e6))
def test_check_real_accepts_exactly_the_closed_interval(value):
    inside = 0.0 <= value <= 1.0
    if inside:
        assert check_real("x", value, 0.0, 1.0) == value
    else:
        with pytest.raises(ValueError, match=r"x must be in \[0, 1\]"):
            check_real("x", value, 0.0, 1.0)


def test_check_real_and_integer_refuse_what_is_not_a_number():
    for bad in (True, "0.3", None, [1.0]):
        with pytest.raises(TypeError, match="must be a number"):
            check_real("eta", bad)
    with pytest.raises(ValueError, match="must be finite"):
        check_real("eta", math.nan)
    assert check_real("ratio", math.inf, 1.0, allow_inf=True) == math.inf
    with pytest.raises(ValueError, match=r"eta must be > 0"):
        check_real("eta", 0.0, 0.0, low_open=True)
    assert check_integer("n", 3.0, 1) == 3 and isinstance(check_integer("n", 3.0, 1), int)
    with pytest.raises(TypeError, match="n must be an integer"):
        check_integer("n", 2.5, 1)


def test_every_spelling_names_one_parameter():
    assert [Run.name_of(key) for key in ("E-N", "e_n", "reduced_field", "packing-fraction", "Packing_Fraction")] == \
        ["reduced_field", "reduced_field", "reduced_field", "packing_fraction", "packing_fraction"]
    assert Run.from_mapping({"E-N": 2.0}) == Run(reduced_field=2.0)
    with pytest.raises(ValueError, match="given twice"):
        Run.from_mapping({"E-N": 2.0, "reduced_field": 3.0})
    with pytest.raises(ValueError, match="unknown parameter 'x'; allowed: E-N, packing-fraction"):
        Run.from_mapping({"x": 1})


def test_a_resumed_run_refuses_changed_physics_by_name():
    saved = Run(reduced_field=2.0)
    check_unchanged(saved, {"E-N": 2.0}, "c.npz")  # the same value: fine
    with pytest.raises(ValueError, match=r"reduced_field = 3 differs from the checkpoint c.npz \(reduced_field = 2\)"):
        check_unchanged(saved, {"E-N": 3.0}, "c.npz")
