"""The slip-layer thickness ρ' of the relative notch sensitivity factor Y_δrelT (ISO 6336-3,
method B) of a through-hardened gear, from its 0.2 % proof stress σ_0.2.

Reference: ISO 6336-3's table of ρ' (2006 edition, 13.3), the rows of through-hardened wrought
steel V typed in below (σ_0.2 = 500, 600, 800, 1000 N/mm²: ρ' = 0.0281, 0.0194, 0.0064,
0.0014 mm); Y_δrelT = (1 + √(ρ' χ*))/(1 + √(ρ' χ*_T)), χ* = (1 + 2 q_s)/5 mm⁻¹, χ*_T = 1.2 mm⁻¹,
written out by hand here. The row σ_0.2 = 1000 N/mm² is checked against a published report in
tests/test_rating_kisssoft.py (the NREL 5 MW rings' printed Y_δrelT 1.005 and 1.003).
"""

import math

import equinox as eqx
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.rating as jr
from _rating_cases import rated_accessory_data

#: ISO 6336-3 (2006, 13.3): ρ' (mm) of through-hardened steel by σ_0.2 (N/mm²)
ISO_ROWS = {500.0: 0.0281, 600.0: 0.0194, 800.0: 0.0064, 1000.0: 0.0014}


def test_proof_stress_gives_the_table_rows_and_linear_between():
    """ρ' of jg.rating.ThroughHardened(proof_stress=σ_0.2) at each row of the standard's table, and
    halfway between rows the mean of the two (the table's rows only are the standard's; linear
    in between is this module's reading); the default is the 500 N/mm² row; a proof stress
    outside the table, or ρ' given twice, is refused in one line."""
    for s, rho in ISO_ROWS.items():
        assert jr.ThroughHardened(proof_stress=s * 1e6).slip_layer == pytest.approx(
            rho * 1e-3, rel=1e-12
        )
    for lo, hi in ((500.0, 600.0), (600.0, 800.0), (800.0, 1000.0)):
        mid = jr.ThroughHardened(proof_stress=(lo + hi) / 2 * 1e6).slip_layer
        assert mid == pytest.approx((ISO_ROWS[lo] + ISO_ROWS[hi]) / 2 * 1e-3, rel=1e-12)
    assert jr.ThroughHardened().slip_layer == pytest.approx(0.0281e-3, rel=1e-12)
    assert jr.ThroughHardened(slip_layer_m=0.01e-3).slip_layer == 0.01e-3
    with pytest.raises(ValueError, match=r"proof_stress = 4\.5e\+08 Pa is out of range"):
        jr.ThroughHardened(proof_stress=450e6)
    with pytest.raises(ValueError, match=r"proof_stress = 1\.1e\+09 Pa is out of range"):
        jr.ThroughHardened(proof_stress=1100e6)
    with pytest.raises(ValueError, match=r"slip_layer_m and proof_stress both given"):
        jr.ThroughHardened(slip_layer_m=0.01e-3, proof_stress=800e6)
    with pytest.raises(ValueError, match=r"slip_layer_m = 0 m is out of range"):
        jr.ThroughHardened(slip_layer_m=0.0)


def _y_delta_by_hand(rho_mm: float, q_s: float) -> float:
    chi = (1 + 2 * q_s) / 5
    return (1 + math.sqrt(rho_mm * chi)) / (1 + math.sqrt(rho_mm * 1.2))


def test_case_key_proof_stress_selects_rho_and_y_delta_rel_t():
    """``[material] proof_stress_MPa`` (per gear as ``treatment``) sets a through-hardened
    gear's ρ' from the table and so its Y_δrelT, by hand from the rating's q_s; a
    surface-hardened gear keeps its one ρ' (case hardened: 0.0030 mm); a value outside
    [500, 1000] is refused in one line naming the key."""
    d = rated_accessory_data(4, 8)
    d["material"].update(
        treatment=["case_hardened", "through_hardened"], proof_stress_MPa=[900.0, 800.0]
    )
    case = jio.rating_of(jio.parse_case(d))
    t = case.settings.material.treatment
    assert isinstance(t, jr.PairTreatment)
    np.testing.assert_allclose(t.slip_layer, [0.0030e-3, 0.0064e-3], rtol=1e-12)
    b = eqx.filter_jit(jr.rate)(case.geometry, case.operating, case.settings).bending
    q = np.asarray(b.form.q_s)
    want = [_y_delta_by_hand(0.0030, q[0]), _y_delta_by_hand(0.0064, q[1])]
    np.testing.assert_allclose(b.Y_delta_rel_T, want, rtol=1e-12)
    d["material"].update(treatment="through_hardened", proof_stress_MPa=600.0)
    t = jio.rating_of(jio.parse_case(d)).settings.material.treatment
    assert isinstance(t, jr.ThroughHardened) and t.slip_layer == pytest.approx(0.0194e-3)
    d["material"]["proof_stress_MPa"] = 450.0
    with pytest.raises(ValueError, match=r"proof_stress_MPa = 450.*allowed \[500, 1000\]"):
        jio.parse_case(d)


def test_planetary_case_proof_stress_by_gear_name(tmp_path):
    """In a planetary case ``proof_stress_MPa`` is a table by gear name like ``treatment``: the
    through-hardened ring at its report's yield point, 1000 N/mm², gets the table's 0.0014 mm."""
    text = jio.embedded_case_text("nrel-5mw-planetary")
    line = "proof_stress_MPa = 1000.0 "  # the case's own: one number for every gear
    assert line in text
    extra = "proof_stress_MPa = { sun1 = 850.0, planet1 = 850.0, ring1 = 1000.0 } #"
    path = tmp_path / "c.toml"
    path.write_text(text.replace(line, extra))
    case = jio.load_case(str(path))
    sun_mesh, ring_mesh = jio.ratings_of(case)
    t = ring_mesh.settings.material.treatment
    assert t.gear.slip_layer == pytest.approx(0.0014e-3, rel=1e-12)
    assert t.gear.brinell_hardness == 240.0
    assert isinstance(sun_mesh.settings.material.treatment, jr.CaseHardened)
