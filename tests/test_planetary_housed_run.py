"""``jaxgear run`` on a housed planetary case (a planetary case with ``[housing]``): its
modes.json, load sharing and Campbell diagram come from the case's kinds on its mount
(jaxgear.io.planetary_kind), not the grounded ones. Evidence, on lin-parker-1999 in a small box
round the stage: (1) the run's planar and torsional modes are those of the kinds on a
HousingMount built here from the public API, solved by SciPy's generalized eigensolver, and
each mode's housing kinetic energy share is that eigensolver's φ_hᵀ M_hh φ_h; (2) the same box 1000 x stiffer gives
the grounded case's modes (below 20 kHz) within 1e-4 (the ring's 1e9 N/m torsional support in
series with the box), and the static load sharing is the grounded one's in any box; (3) the steel box adds modes whose kinetic energy is
mostly the housing's, which the grounded run has not."""

import argparse
import json

import numpy as np
import pytest
import scipy.linalg as sla
from _housing import PLANETARY_BOX

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.planetary as jp
from jaxgear.cli.planetary import planetary_files
from jaxgear.scenes import HousingMount

# the box round the stage (tests/_housing.PLANETARY_BOX), as test_planetary_housing.py's
STEEL = PLANETARY_BOX.format(E=210.0, fc=3000.0)
STIFF = PLANETARY_BOX.format(E=210e3, fc=3000.0 * np.sqrt(1000.0))  # the same kept modes
PIN = "tangential_pin_errors_um = [10.0, 0.0, 0.0]\n"


def _case(tmp_path, name, table=""):
    text = jio.embedded_case_text("lin-parker-1999").replace(
        'fixed = "ring"\n', 'fixed = "ring"\n' + PIN)
    path = tmp_path / f"{name}.toml"
    path.write_text(text + table)
    return jio.load_case(str(path))


def _run(tmp_path, name, table=""):
    """The planetary run's files of the case (the writer ``jaxgear run`` calls after its
    sweep): (case, summary, modes.json)."""
    case = _case(tmp_path, name, table)
    out = tmp_path / name
    out.mkdir()
    summary = planetary_files(case.form, case, str(out), argparse.Namespace(quiet=True), True)
    return case, summary, json.loads((out / "modes.json").read_text())


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("housed_run")
    # no test here reads a figure: the runs draw none (tests/conftest.py's no_figures, for a
    # module fixture)
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("JAXGEAR_TEST_NO_FIGURES", "1")
        return {name: _run(tmp, name, table)
                for name, table in (("grounded", ""), ("steel", STEEL), ("stiff", STIFF))}


def test_run_modes_are_the_housed_models(runs):
    """modes.json of the housed run against an independent solve: the base kinds on a mount of
    the case's housing (the ring on seat 0), K and M handed to
    scipy.linalg.eigh; frequencies to 1e-8 (above 1 Hz), and each non-degenerate mode's housing
    kinetic energy share (the M-normalised shape's φ_hᵀ M_hh φ_h) to 1e-6."""
    case, summary, modes = runs["steel"]
    housing = case.housing_body().housing
    stage = case.form.spec.stage(case)
    for name, base in (("planar", jp.PlanarPlanetary()), ("torsional", jp.TorsionalPlanetary())):
        kind = base.on(HousingMount.on_axis(housing, (("ring", 0),)))
        M = np.asarray(kind.mass_matrix(stage))
        K = np.asarray(kind.stiffness_matrix(stage))
        lam, phi = sla.eigh(K, M)
        f = np.sqrt(np.clip(lam, 0.0, None)) / (2 * np.pi)
        h = housing.size
        share = np.einsum("ji,ji->i", phi[-h:], M[-h:, -h:] @ phi[-h:])
        listed = modes[name]
        got = np.array([m["frequency_Hz"] for m in listed])
        assert got.size == f.size == K.shape[0]
        above = f > 1.0
        np.testing.assert_allclose(got[above], f[above], rtol=1e-8)
        gap = np.diff(f)
        single = above & np.r_[gap > 1e-6 * f[1:], True] & np.r_[True, gap > 1e-6 * f[1:]]
        shares = np.array([m["housing_kinetic_energy_share"] for m in listed])
        np.testing.assert_allclose(shares[single], share[single], atol=1e-6)
        assert all((m["type"] == "housing") == (m["housing_kinetic_energy_share"] > 0.5)
                   for m in listed)
    assert summary["campbell"]["model"] == "planar on the housing"


def test_stiff_box_gives_the_grounded_run(runs):
    """The box 1000 x stiffer: every grounded mode below 20 kHz (planar and torsional) is met
    by a housed one within 1e-4 (measured 3.9e-5 planar, 4.4e-5 torsional: the box in series
    with the ring's 1e9 N/m support). The load sharing with a 10 µm pin error is the grounded
    one's to 1e-9 of the nominal force in either box: the housing only lets the ring turn about
    the axis (its in-plane supports stay grounded), and a rigid turn of the ring moves every
    planet's meshes alike, so the static split among the planets cannot change (measured
    2e-15)."""
    _, g_sum, g_modes = runs["grounded"]
    _, s_sum, s_modes = runs["stiff"]
    steel = runs["steel"][1]
    for name in ("planar", "torsional"):
        f0 = np.array([m["frequency_Hz"] for m in g_modes[name]])
        f1 = np.array([m["frequency_Hz"] for m in s_modes[name]])
        for f in f0[(f0 > 1.0) & (f0 < 2e4)]:
            assert np.min(np.abs(f1 / f - 1)) < 1e-4, (name, f)
        assert "housing_kinetic_energy_share" not in g_modes[name][0]
    for name in ("planar", "torsional"):
        g = g_sum["load_sharing"][name]
        nominal = np.mean(g["sun_mesh_forces_N"])
        for s in (s_sum["load_sharing"][name], steel["load_sharing"][name]):
            for key in ("sun_mesh_forces_N", "ring_mesh_forces_N"):
                np.testing.assert_allclose(s[key], g[key], rtol=0, atol=1e-9 * nominal)
            assert abs(s["k_gamma"] - g["k_gamma"]) < 1e-9
        assert g["k_gamma"] > 1.01  # the pin error shows


def test_steel_box_adds_housing_modes(runs):
    """The steel box: modes whose kinetic energy is mostly the housing's (share > 0.5, typed
    "housing") below the box's cut-off, which the grounded run has not; the summary counts
    them and the grounded stage's own modes keep their types."""
    _, g_sum, g_modes = runs["grounded"]
    _, s_sum, s_modes = runs["steel"]
    housing = [m for m in s_modes["planar"] if m["type"] == "housing"]
    assert len(housing) >= 3 and min(m["frequency_Hz"] for m in housing) < 3000.0
    assert all(m["housing_kinetic_energy_share"] > 0.5 for m in housing)
    assert not any(m["type"] == "housing" for m in g_modes["planar"])
    assert s_sum["modes"]["planar_housing_dominated"] == len(housing)
    assert "planar_housing_dominated" not in g_sum["modes"]
    assert s_sum["modes"]["planar_type_counts"]["housing"] == len(
        {round(m["frequency_Hz"], 6) for m in housing})


def test_planetary_kind(runs):
    """jaxgear.io.planetary_kind: a grounded case's kind as given; a housed case's the kind on a
    mount with the held ring on seat ``housing_seat`` (its axis rows only), the dynamic
    model's mount; a case that is not a planetary stage's refused in one line."""
    kind = jp.SpatialPlanetary()
    grounded, steel = runs["grounded"][0], runs["steel"][0]
    assert jio.planetary_kind(grounded, kind) is kind
    housed = jio.planetary_kind(steel, kind)
    assert housed.unmounted() is kind and housed.seat_indices() == (("ring", 0),)
    assert housed.mount().joints[0].rows == (2, 5) and not housed.mount().fixed_frame
    model, _ = jio.build_dynamic_model(steel)
    assert model.mount().joints == housed.mount().joints
    with pytest.raises(TypeError, match="planetary_kind") as e:
        jio.planetary_kind(jio.load_case("power-helical"), kind)
    assert "\n" not in str(e.value)


def _helical(table=None):
    """lin-parker-1999 made helical (20°, 30 mm face) on axial and tilting supports, a 10 µm
    pin error (tests/test_planetary_spatial_sharing.py's stage), with the housing ``table``."""
    import tomllib

    data = tomllib.loads(jio.embedded_case_text("lin-parker-1999"))
    data["planetary"].update(helix_angle_deg=20.0, face_width_mm=30.0,
                             tangential_pin_errors_um=[10.0, 0.0, 0.0])
    for m in ("sun", "ring", "carrier"):
        data["planetary"][m].update(axial_N_per_um=100.0, tilt_Nm_per_rad=1e6)
    data["planetary"]["planet"].update(pin_axial_N_per_um=80.0, pin_tilt_Nm_per_rad=4e5)
    if table is not None:
        data["housing"] = tomllib.loads(table)["housing"]
    return jio.parse_train(data)


@pytest.mark.slow  # 1-3 min on the shared 2-core host (the face load's contact solve, twice);
# its fast twin: test_stiff_box_gives_the_grounded_run (the planar and torsional kinds)
def test_helical_stage_in_a_stiff_box(tmp_path):
    """A helical stage: the run's 3D modes and face load come from the housed 3D kind (the
    ring's torsional and axial supports on the seat). In the box 1000 x stiffer its 3D modes
    below 20 kHz are the grounded run's within 1e-4 (measured 7.8e-5) and its K_Hβ (1.350) and
    K_γ within 1e-6 (measured 3e-14: the ring's axial and rotational freedom, all the box adds,
    moves every planet alike)."""
    out = {}
    for name, table in (("grounded", None), ("stiff", STIFF)):
        case = _helical(table)
        (tmp_path / name).mkdir()
        out[name] = (planetary_files(case.form, case, str(tmp_path / name),
                                     argparse.Namespace(quiet=True), True),
                     json.loads((tmp_path / name / "modes.json").read_text()))
    (g, g_modes), (s, s_modes) = out["grounded"], out["stiff"]
    f0 = np.array([m["frequency_Hz"] for m in g_modes["spatial"]])
    f1 = np.array([m["frequency_Hz"] for m in s_modes["spatial"]])
    assert "housing_kinetic_energy_share" in s_modes["spatial"][0]
    for f in f0[(f0 > 1.0) & (f0 < 2e4)]:
        assert np.min(np.abs(f1 / f - 1)) < 1e-4, f
    np.testing.assert_allclose(s["face_load"]["k_h_beta"], g["face_load"]["k_h_beta"],
                               rtol=0, atol=1e-6)
    assert abs(s["face_load"]["k_gamma"] - g["face_load"]["k_gamma"]) < 1e-6
    assert g["face_load"]["k_h_beta_max"] > 1.0
