"""jaxgear's quasi-static solver against the independent NumPy/brentq baseline of benchmarks/.

Both compute the rigid-mesh TE curve of docs/design.md; they share only the geometry (with the
tip-corner gap and lever tables of contact beyond the path) and the stiffness table. Exact and
smooth modes must agree to 1e-9 relative in float64, on the theoretical path and with contact
beyond it (docs/extended-contact.md).
"""

import dataclasses
import functools
import json
import math

import numpy as np
import pytest

import benchmarks as bl
import jaxgear as jg
import jaxgear.io as jio

RTOL = 1e-9
SLICES = 16
PPP = 24


def _rel(a, b):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


def _mods(kind: str):
    if kind == "none":
        return None
    if kind == "case":
        return "case"
    if kind == "tip-crown":  # parabolic tip relief, crowning, the other deviations, rounded start
        pin = jg.MemberModification(
            tip_relief_depth=12e-6,
            tip_relief_extent=0.3,
            tip_relief_shape=jg.ParabolicRelief(),
            root_relief_depth=3e-6,
            root_relief_extent=0.15,
            crowning_depth=6e-6,
            end_relief_depth=2e-6,
            end_relief_extent=0.15,
            helix_slope_deviation=4e-6,
            profile_deviation_roll=(0.0, 1.0),
            profile_deviation=(1e-6, -2e-6),
            relief_blend=0.02,
        )
        gear = jg.MemberModification(
            tip_relief_depth=8e-6,
            tip_relief_extent=0.2,
            tip_relief_shape=jg.ParabolicRelief(),
            crowning_depth=3e-6,
        )
        return jg.Modifications(pinion=pin, gear=gear)
    raise AssertionError(kind)


@functools.cache
def _setup(name: str, uniform: bool = False, extended: bool = False):
    """(case, jaxgear MeshModel, baseline mesh) with the stiffness table evaluated once; with
    ``extended`` both with contact beyond the theoretical path."""
    case = jio.load_case(name)
    if uniform:
        case = case.replace(stiffness=jg.Uniform(13e9))
    bmesh = bl.baseline_mesh(case, slices=SLICES, extended_contact=extended)
    mesh = jg.MeshModel.from_pair(
        case.pair, bmesh.stiffness_s, bmesh.stiffness_k, SLICES,
        contact_geometry=jg.BeyondPath() if extended else jg.TheoreticalPath(),
    )
    return case, mesh, bmesh


def _compare(name, mods, contact, width=1e-7, uniform=False, extended=False):
    case, mesh, bmesh = _setup(name, uniform, extended)
    if mods == "case":
        mods = case.modifications
    r = jg.quasi_static(
        mesh,
        mods,
        case.torque,
        contact=jio.contact_law_from_name(contact, width),
        positions_per_pitch=PPP,
    )
    b = bl.te_curve_numpy(
        bmesh, bl.mods_params(mods), case.torque, contact, width, positions_per_pitch=PPP
    )
    np.testing.assert_allclose(np.asarray(r.theta), b["theta"], rtol=1e-14)
    assert _rel(r.transmission_error, b["te"]) <= RTOL
    assert _rel(r.mesh_stiffness, b["mesh_stiffness"]) <= RTOL
    assert _rel(r.contact_length, b["contact_length"]) <= RTOL
    te = np.asarray(r.transmission_error)
    rms = float(r.te_rms)
    assert abs(rms - bl.te_rms(b["te"])) <= RTOL * max(rms, np.max(np.abs(te)) * 1e-6)
    return r, b


# Each distinct static structure compiles once (about 1-2 s): linear-relief modifications share
# a compilation with "none", the parabolic set ("tip-crown") needs its own, so it runs in one mode
# per case to keep the file fast.
@pytest.mark.parametrize(
    "name,mods,contact",
    [
        (name, mods, contact)
        for name in ("accessory-spur", "power-helical")
        for mods in ("none", "case")
        for contact in ("exact", "smooth")
    ]
    + [("accessory-spur", "tip-crown", "exact"), ("power-helical", "tip-crown", "smooth")],
)
def test_agrees_with_baseline(name, mods, contact):
    r, b = _compare(name, _mods(mods), contact)
    assert np.all(np.asarray(r.result) == 0)
    assert np.all(b["te"] > 0)  # positive under load


@pytest.mark.parametrize(
    "name,mods,contact",
    [("accessory-spur", "none", "exact"), ("accessory-spur", "case", "smooth"),
     ("power-helical", "none", "smooth"), ("power-helical", "case", "exact")],
)
def test_agrees_with_baseline_beyond_the_path(name, mods, contact):
    """Contact beyond the theoretical path in both codes (the case files' default): the
    baseline lays out its own cells over [−S_a, g_α + S_r] and solves Σ V k l φ(V δ − δ0) = F_n
    with the corner gap in δ0 and the pinion tip corner's lever V = λ after the end."""
    r, _ = _compare(name, _mods(mods), contact, extended=True)
    assert np.all(np.asarray(r.result) == 0)
    if mods == "none":  # the corners touch on both sides: the comparison holds the extension
        g_alpha = float(_setup(name, False, True)[1].path_of_contact)
        s = np.asarray(r.cell_s)
        loaded = np.asarray(r.line_load) > 0
        assert np.any(loaded & (s < 0)) and np.any(loaded & (s > g_alpha))


def test_baseline_extension_changes_the_curve():
    """The two contact models differ where the corners touch (so comparing across them, as the
    benchmark did, cannot agree to 1e-9): the unmodified accessory pair's TE."""
    _, b_on = _compare("accessory-spur", None, "exact", extended=True)
    _, b_off = _compare("accessory-spur", None, "exact")
    assert _rel(b_on["te"], b_off["te"]) > 1e-3


@pytest.mark.parametrize("contact", ["exact", "smooth"])
def test_agrees_with_baseline_uniform_stiffness(contact):
    _compare("accessory-spur", "case", contact, uniform=True)
    # uniform stiffness, no deviation: TE = F/(k0 L cos β_b) in both codes (spur: cos β_b = 1)
    case = _setup("accessory-spur", True)[0]
    _, b0 = _compare("accessory-spur", None, "exact", uniform=True)
    np.testing.assert_allclose(
        b0["te"], case.normal_load / (13e9 * b0["contact_length"]), rtol=1e-12
    )


def test_smooth_width_is_the_same_law():
    """A wide smoothing width (large changes) still agrees: both use w·log(1 + exp(Δ/w))."""
    _compare("power-helical", "case", "smooth", width=2e-6)


def test_baseline_rejects_bad_input():
    m = _setup("accessory-spur", True)[2]
    with pytest.raises(ValueError, match="contact"):
        bl.te_curve_numpy(m, None, 80.0, contact="penalty")
    with pytest.raises(ValueError, match="torque"):
        bl.te_curve_numpy(m, None, 0.0)
    with pytest.raises(ValueError, match="width"):
        bl.te_curve_numpy(m, None, 80.0, contact="smooth", width=0.0)


@pytest.mark.slow
def test_bench_quick(tmp_path):
    from benchmarks import bench_quasi_static

    out = bench_quasi_static(tmp_path, quick=True, progress=False, verbose=False)
    assert (tmp_path / "speed_accuracy_quasi_static.png").stat().st_size > 1000
    saved = json.loads((tmp_path / "bench_quasi_static.json").read_text())
    assert saved["targets"]["agreement_1e-9"] and out["targets"]["agreement_1e-9"]
    # like with like: the case's contact beyond the path and the theoretical path, each in both
    assert saved["settings"]["extended_contact"]
    assert set(saved["per_te_curve_by_contact_model"]) == {"case", "theoretical_path"}
    for rec in saved["per_te_curve_by_contact_model"].values():
        for mode in ("exact", "smooth"):
            pc = rec[mode]
            assert pc["jaxgear_s"] > 0 and pc["baseline_s"] > 0
            assert max(pc["max_rel_diff"].values()) <= RTOL
    assert {p["contact_model"] for p in saved["speed_accuracy"]["points"]} == set(
        saved["speed_accuracy"]["references"]
    )
    assert saved["dtype"] == "float64"
    assert np.asarray(saved["grid"]["te_rms_m"]).shape == (5, 5)
    for mode in ("exact", "smooth"):
        assert saved["cached_jit"][mode]["best_s"] > 0
    assert saved["batched"]["best_curves_per_s"] > 0
    # the per-curve blocks: the public call equals quasi_static in both dispatch modes, makes one
    # program execution, and synchronous dispatch did take effect (the program on the caller)
    for mode, where in (("async", "runtime threads"), ("sync", "calling thread")):
        rec = saved["per_curve_blocks"]["modes"][mode]
        assert rec["public_free_tip_max_rel_diff_te_to_quasi_static"] <= 1e-12
        assert rec["anatomy"]["program_executions_per_call"] == 1.0
        assert rec["anatomy"]["program_ran_on"] == where
        assert rec["ratio_baseline_over_public_free_tip_theoretical_path"]["median"] > 0
    assert not list(tmp_path.glob(".tmp-*"))


def _wide_helical(face_width_mm):
    case = jio.load_case("power-helical").replace(stiffness=jg.Uniform(13e9))
    pair = case.pair
    b = face_width_mm * 1e-3
    pair = dataclasses.replace(
        pair,
        pinion=dataclasses.replace(pair.pinion, face_width=b),
        gear=dataclasses.replace(pair.gear, face_width=b),
    )
    return case.replace(pair=pair)


def test_baseline_contact_length_wide_helical():
    """Independent check of the baseline's cells: the mean contact length of a helical pair is
    ε_α b / cos β_b, also when the overlap ratio ε_β exceeds 3 (many lines on the flank)."""
    case = _wide_helical(120.0)
    pair = case.pair
    assert pair.overlap_ratio > 3
    b = bl.te_curve_numpy(
        bl.baseline_mesh(case, slices=40, extended_contact=False),
        None,
        case.torque,
        positions_per_pitch=PPP,
    )
    expected = pair.transverse_contact_ratio * pair.face_width / math.cos(pair.base_helix_angle)
    assert abs(np.mean(b["contact_length"]) / expected - 1) < 1e-3


def test_agrees_with_baseline_wide_helical():
    """ε_β = 3.2: every contact line on the flank is kept (lines i in [0, ceil(ε_α + ε_β)])."""
    case = _wide_helical(120.0)
    bmesh = bl.baseline_mesh(case, slices=SLICES, extended_contact=False)
    mesh = jg.MeshModel.from_pair(case.pair, bmesh.stiffness_s, bmesh.stiffness_k, SLICES)
    r = jg.quasi_static(mesh, None, case.torque, positions_per_pitch=PPP)
    b = bl.te_curve_numpy(bmesh, None, case.torque, positions_per_pitch=PPP)
    assert _rel(r.contact_length, b["contact_length"]) <= RTOL
    assert _rel(r.transmission_error, b["te"]) <= RTOL
