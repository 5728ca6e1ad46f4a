"""Species names of LXCat targets: one spelling for the many ways files write a target."""

import pytest

from collisionkit.transport._lxcat_names import is_formula, product_formula, resolve_names, target_name


@pytest.mark.parametrize(
    ("written", "name"),
    [
        ("Ar", "Ar"),
        ("Ar <-> Ar*", "Ar"),                       # a reversible excitation: the target is before the arrow
        ("Ar -> Ar*(11.5eV)", "Ar"),
        ("e + N2 -> e + N2(v=1)", "N2"),            # the electron is not the target
        ("E + N2 -> E + E + N2+, Ionization", "N2"),
        ("N2 -> N2^+", "N2"),
        ("O2 -> O2^-", "O2"),
        ("O2 -> O- + O", "O2"),
        ("e / Ar", "Ar"),                           # a SPECIES: line
        ("N2(X,v=0)", "N2"),                        # the ground state: the species itself
        ("N2(X)", "N2"),
        ("Ar(1S0)", "Ar"),
        ("N2 (v=0)", "N2"),
        ("CO(X,v=0,J=0) -> CO(X,v=0,J=2)", "CO"),
        ("Ar*", "Ar*"),                             # an excited target is another species (its own density)
        ("Ar* -> Ar(+)", "Ar*"),
        ("Ar(4p[3/2]2) -> Ar(3d'[3/2]1)", "Ar(4p[3/2]2)"),
        ("NO(v=38) -> N(4S) + O(3P)", "NO(v=38)"),
        ("O2(a1Dg)", "O2(a1Dg)"),
        ("N2+", "N2^+"),                            # charges in one spelling: the digit belongs to the formula
        ("N2^+", "N2^+"),
        ("N^2+", "N^2+"),
        ("O-", "O^-"),
        ("O^-", "O^-"),
        ("BeH+", "BeH^+"),
        ("T2^+(1sSg,v=5)", "T2^+(1sSg,v=5)"),
        ("Nitrogen", "Nitrogen"),                   # not a formula: resolved from the file (resolve_names)
        ("N2-rot", "N2-rot"),
    ],
)
def test_a_target_written_any_way_has_one_name(written, name):
    assert target_name(written) == name


def test_formulas_and_group_names():
    assert all(is_formula(name) for name in ("N2", "CO2", "Ar*", "O^-", "SF6", "NO(v=38)", "C2OH6"))
    assert not any(is_formula(name) for name in ("Nitrogen", "Oxygen", "N2-rot", "CO_anis", "CO-elec", "Reid"))


@pytest.mark.parametrize(
    ("process", "formula"),
    [
        ("E + Nitrogen <-> E + N2 (J=0-J=2), Rotational", "N2"),
        ("E + N2-vib <-> E + N2 (v=3-v=4), Vibrational", "N2"),
        ("E + Oxygen -> E + O, Elastic", "O"),
        ("E + CO-elec -> E + CO-elec, Elastic", None),  # the product is no formula either: unresolved
        ("no arrow here", None),
    ],
)
def test_the_product_of_a_process_that_keeps_its_target_names_it(process, formula):
    assert product_formula(process) == formula


def test_a_group_name_is_resolved_only_by_one_formula():
    resolved = resolve_names(["Nitrogen", "Oxygen", "Mix", "N2"],
                             {"Nitrogen": {"N2"}, "Oxygen": set(), "Mix": {"N2", "O2"}, "N2": {"N2"}})
    assert resolved == {"Nitrogen": "N2"}  # none for Oxygen (nothing keeps it), Mix (two), N2 (already a formula)
