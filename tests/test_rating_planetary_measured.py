"""The planetary rating's measured K_Hbeta (jaxgear.cli.planetary.rating_section): the face load
factor the run's 3D lumped model computes per mesh (summary.json's `face_load`, ISO 6336-1's
linear distribution across the face) reported per rated mesh beside ISO's, and rated with in its
place only where `[rating] use_measured` names it, as a pair case's measured K_Hbeta."""

import tomllib
import warnings

import numpy as np
import pytest

import jaxgear.io as jio
from jaxgear.io import CaseWarning

#: a face_load section as the run writes it for a three-planet stage (the n sun/planet meshes,
#: then the n ring/planet meshes), values chosen so that the largest of each kind differs
FACE_LOAD = {"k_h_beta": [1.21, 1.34, 1.27, 1.12, 1.05, 1.18]}


def rated_case(tmp_path, rating_extra=""):
    """The embedded nrel-5mw-planetary (spur, ISO's K_Hbeta), ``rating_extra`` added to its
    [rating] table."""
    text = jio.embedded_case_text("nrel-5mw-planetary")
    path = tmp_path / "stage1.toml"
    path.write_text(text.replace("\n[rating]", "\n[rating]\n" + rating_extra, 1))
    return jio.load_case(str(path))


def helical_rated_case(rating_extra: dict):
    """nrel-5mw-planetary made helical (β = 8°, its own zero-backlash centre distance), whose
    K_Hbeta the run measures (a spur stage's ``use_measured = ["K_Hbeta"]`` is refused at
    load), ``rating_extra`` added to its [rating] table."""
    data = tomllib.loads(jio.embedded_case_text("nrel-5mw-planetary"))
    for g in data["gears"]:
        g["helix_angle_deg"] = 8.0
    del data["planetary"]["center_distance_mm"]
    data["rating"].update(rating_extra)
    return jio.parse_train(data)


def iso_and_measured(case, tmp_path, factor: str, **measured):
    """The rating of ``case`` (its ``use_measured`` naming ``factor``, K_γ 1.1) without the
    measurement (ISO's factor, with the one-line warning naming it) and with ``measured`` (the
    run's measurement, no warning): (ISO's section, the measured one, its rating.md)."""
    from jaxgear.cli.planetary import rating_section

    with pytest.warns(CaseWarning, match=rf"use_measured: {factor} not measured"):
        iso = rating_section(case, str(tmp_path), 1.1)
    with warnings.catch_warnings():
        warnings.simplefilter("error", CaseWarning)
        sec = rating_section(case, str(tmp_path), 1.1, **measured)
    return iso, sec, (tmp_path / "rating.md").read_text()


def test_planet_face_factors_take_each_kinds_largest_planet():
    """:func:`jaxgear.rating.planet_face_factors` on the array (no summary): the first N of
    the 2N meshes are the sun/planet meshes, the rest the planet/ring meshes, each kind's
    K_Hβ its largest planet's; a shape that is not (2N,) refused in one line."""
    from jaxgear.rating import planet_face_factors

    assert planet_face_factors(np.array(FACE_LOAD["k_h_beta"])) == (1.34, 1.18)
    assert planet_face_factors([1.0, 1.5]) == (1.0, 1.5)
    for bad in ([1.2, 1.3, 1.1], [[1.2, 1.3]], []):
        with pytest.raises(ValueError, match="planet_face_factors: k_h_beta has shape"):
            planet_face_factors(bad)


def test_the_rating_reports_each_meshs_largest_face_load_k_hbeta_not_used(tmp_path):
    """With the run's face_load, each rated mesh carries measured.K_Hbeta = the largest of the
    planets' values of its kind (sun/planet: the first n, planet/ring: the last n), its source
    naming the 3D lumped model and ISO 6336-1's linear distribution; rating.md shows the row as
    "not used above" and the rating itself is ISO's (the same factors and stresses as without
    it). No face_load, or a skipped one: no measured entry, no row."""
    from jaxgear.cli.planetary import rating_section

    case = rated_case(tmp_path)
    bare = rating_section(case, str(tmp_path), 1.1)
    md_bare = (tmp_path / "rating.md").read_text()
    sec = rating_section(case, str(tmp_path), 1.1, face_load=FACE_LOAD)
    md = (tmp_path / "rating.md").read_text()
    m = sec["measured"]["K_Hbeta"]
    assert m["value"] == [1.34, 1.18]
    assert all("3D lumped" in s and "ISO 6336-1's linear distribution" in s and "3 planets" in s
               for s in m["source"])
    assert sec["factors"] == bare["factors"] and sec["pitting"] == bare["pitting"]
    for v in (1.34, 1.18):
        assert f"| K_Hβ measured | {v:#.4g} | " in md
    assert md.count("| no (reported only) |") == 2
    assert "measured" not in bare and "K_Hβ measured" not in md_bare
    skipped = rating_section(case, str(tmp_path), 1.1, face_load={"skipped": "no supports"})
    assert "measured" not in skipped
    assert "K_Hβ measured" not in (tmp_path / "rating.md").read_text()


# default tier: tests/test_rating_planetary_speed.py::
# test_use_measured_k_v_rates_each_mesh_with_the_sweeps (use_measured rates the stage's meshes
# with a measured factor, the stresses scaling by hand) and
# test_a_helical_stage_on_its_supports_rates_with_its_own_face_load below (the helical K_Hbeta)
@pytest.mark.slow
def test_use_measured_rates_with_the_face_load_k_hbeta(tmp_path):
    """`[rating] use_measured = ["K_Hbeta"]`: each mesh rated with its measured K_Hbeta in place
    of ISO's, σ_H scaling by √(K_Hβ measured / K_Hβ ISO) (σ_H ∝ √(K_A K_γ K_v K_Hβ K_Hα), the
    other factors unchanged), K_γ still in the load (K_A as given), the factor's source and
    rating.md's row saying it was used. Without a face_load (a helical stage whose supports do
    not hold it) it stays ISO's, with a one-line warning naming the factor; a spur stage's is
    refused at load (tests/test_edges_round5_rating.py)."""
    case = helical_rated_case({"use_measured": ["K_Hbeta"]})
    iso, sec, md = iso_and_measured(case, tmp_path, "K_Hbeta", face_load=FACE_LOAD)
    k_iso = np.asarray(iso["factors"]["K_Hbeta"]["value"])
    assert sec["factors"]["K_Hbeta"]["value"] == pytest.approx([1.34, 1.18], rel=1e-6)
    assert all(s.startswith("measured (rating.measured, [rating] use_measured")
               for s in sec["factors"]["K_Hbeta"]["source"])
    assert sec["factors"]["K_A"]["value"] == iso["factors"]["K_A"]["value"] == [1.25, 1.25]
    assert sec["K_gamma"] == iso["K_gamma"]
    np.testing.assert_allclose(
        np.asarray(sec["pitting"]["sigma_H_Pa"]),
        np.asarray(iso["pitting"]["sigma_H_Pa"]) * np.sqrt(np.array([1.34, 1.18]) / k_iso)[:, None],
        rtol=1e-5,
    )
    assert md.count("| yes: [rating] use_measured |") == 2


def test_a_helical_stage_on_its_supports_rates_with_its_own_face_load(tmp_path):
    """The run's path on a helical stage (nrel-5mw-planetary at β = 8°, every axial and tilting
    support given): face_load_section's K_Hbeta per mesh (the 3D model's) is the rating's
    measured K_Hbeta, the largest over the planets of each mesh kind (1e-12), shown in
    rating.md; above 1 (the helical axial forces tilt the members), below ISO's cap of 2."""
    from jaxgear.cli.planetary import face_load_section, rating_section

    data = tomllib.loads(jio.embedded_case_text("nrel-5mw-planetary"))
    for g in data["gears"]:
        g["helix_angle_deg"] = 8.0
    del data["planetary"]["center_distance_mm"]  # the helical stage's own (zero backlash)
    for m in ("sun", "ring", "carrier"):
        data["planetary"][m].update(axial_N_per_um=1000.0, tilt_Nm_per_rad=1e9)
    data["planetary"]["planet"].update(pin_axial_N_per_um=800.0, pin_tilt_Nm_per_rad=4e8)
    case = jio.parse_train(data)
    spec = case.form.spec
    fl = face_load_section(spec, spec.stage(case), spec.torques(case.torque))
    n = spec.n_planets
    k = np.asarray(fl["k_h_beta"])
    assert k.shape == (2 * n,) and np.all((k > 1.0) & (k < 2.0))
    sec = rating_section(case, str(tmp_path), fl["k_gamma"], face_load=fl)
    np.testing.assert_allclose(sec["measured"]["K_Hbeta"]["value"], [k[:n].max(), k[n:].max()],
                               rtol=1e-12)
    md = (tmp_path / "rating.md").read_text()
    for v in sec["measured"]["K_Hbeta"]["value"]:
        assert f"| K_Hβ measured | {v:#.4g} | " in md
