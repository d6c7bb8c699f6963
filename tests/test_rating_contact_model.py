"""The measured K_v, K_Hβ, K_Hα and K_γ rows of the rating state which contact
model produced them, and a measured factor is never shown beside ISO's without that caveat.

References: the contact model's words as the issue's decision writes them (the theoretical path
of contact: contact on the line of action only; the extended path: off-line contact at the tip
corners), read from the mesh models' ``extended_contact``; a lumped model's linear springs have
no tooth contact. The rows are checked in ``summary.json``'s section and in ``rating.md``."""

import copy
import dataclasses

import jax
import pytest

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.planetary as jp
from jaxgear import cli
from jaxgear.cli.planetary import measured_k_v, rating_section, stage_contact_model
from _planetary_stage import K0, SEQ, geometry, stage

from test_rating_case import _case
from test_rating_measured import _loads

jax.config.update("jax_enable_x64", True)

# the words as the decision gives them (independent of the library's constants)
THEORETICAL = "theoretical path of contact (contact on the line of action only)"
EXTENDED = "extended path of contact (off-line contact at the tip corners)"


def _meshes():
    """The case's mesh model on the theoretical path and beyond it (the case files' default)."""
    mesh = jio.parse_case(_case()).mesh_model()
    assert mesh.contact_geometry == jg.BeyondPath()  # the case files' default
    return mesh.with_contact_geometry(jg.TheoreticalPath()), mesh


def test_contact_model_reads_each_mesh_models_contact_geometry():
    """The words follow the mesh model's ``contact_geometry`` (one mesh, a scene's tuple, mixed
    meshes named by position), none for no mesh model (linear springs); a wrong entry
    refused in one line."""
    plain, extended = _meshes()
    assert plain.contact_geometry == jg.TheoreticalPath()
    assert jg.rating.contact_model(plain) == THEORETICAL
    assert jg.rating.contact_model(extended) == EXTENDED
    assert jg.rating.contact_model((extended, extended)) == EXTENDED
    assert jg.rating.contact_model((plain, extended)) == f"mesh 1: {THEORETICAL}; mesh 2: {EXTENDED}"
    assert "no tooth contact" in jg.rating.contact_model(())
    with pytest.raises(ValueError, match=r"^contact_model: meshes\[1\] = 3"):
        jg.rating.contact_model((plain, 3))


def test_every_measured_row_states_its_contact_model(tmp_path):
    """A pair's measured K_Hβ, K_Hα (the load map) and K_v (a sweep) rated with in ISO's place
    (``use_measured``): each ``rating.measured`` entry carries ``contact_model``, the words of
    the meshes it was measured on (extended here, theoretical by default); in ``rating.md`` the
    measured table's rows and the load-factor rows rated with a measured factor (K_Fα follows
    K_Hα) state it."""
    loads, _, _ = _loads()
    plain, extended = _meshes()
    d = _case(**{"rating/K_Hbeta": None, "rating/use_measured": ["K_Hbeta", "K_Halpha", "K_v"]})
    case = jio.parse_case(d)
    section = cli.rating_outputs(case, str(tmp_path), result=loads, meshes=(extended,))
    dynamics = {"model": "torsional", "slices": 8, "speeds_rad_s": [30.0, 40.0, 50.0],
                "dynamic_factor": [1.10, 1.30, 1.20]}
    summary = {"rating": section}
    cli.measured_dynamic_factor(case, str(tmp_path), summary, dynamics, meshes=(extended,))
    measured = summary["rating"]["measured"]
    assert set(measured) == {"K_Hbeta", "K_Halpha", "K_v"}
    assert all(m["contact_model"] == EXTENDED for m in measured.values())
    md = (tmp_path / "rating.md").read_text(encoding="utf-8")
    rows = [r for r in md.splitlines() if r.startswith(("| K_Hβ measured", "| K_Hα measured",
                                                       "| K_v measured"))]
    assert len(rows) == 3 and all(f"| {EXTENDED} |" in r for r in rows)
    for symbol in ("K_v", "K_Hβ", "K_Hα", "K_Fα"):  # rated with the measured ones
        row = next(r for r in md.splitlines() if f"| {symbol} | " in r and "factor" in r)
        assert f"contact model: {EXTENDED}" in row, row
    # the case's own mesh models (the case files' default: beyond the path) where the caller
    # gives none; on the theoretical path where the case says so
    default = cli.rating_outputs(case, str(tmp_path / "d"), result=loads)
    assert {m["contact_model"] for m in default["measured"].values()} == {EXTENDED}
    off = case.replace(contact_geometry=jg.TheoreticalPath())
    plain_rows = cli.rating_outputs(off, str(tmp_path / "p"), result=loads)
    assert {m["contact_model"] for m in plain_rows["measured"].values()} == {THEORETICAL}


def test_a_measured_row_without_its_contact_model_cannot_be_made_or_shown(tmp_path):
    """The row type requires the contact model (no argument: TypeError; empty: ValueError), and
    a ``summary.json`` section whose measured entry lost it cannot be written as ``rating.md``."""
    with pytest.raises(TypeError):
        jg.rating.MeasuredFactor(1.2, "a sweep")  # no contact model
    with pytest.raises(ValueError, match=r"^MeasuredFactor: contact_model = ' ' is out of range"):
        jg.rating.MeasuredFactor(1.2, "a sweep", " ")
    row = jg.rating.MeasuredFactor(1.2, "a sweep", EXTENDED, False, "why")
    assert row.entry() == {"value": 1.2, "source": "a sweep", "contact_model": EXTENDED,
                           "comparable": False, "note": "why"}
    loads, _, _ = _loads()
    case = jio.parse_case(_case(**{"rating/K_Hbeta": None}))
    section = cli.rating_outputs(case, str(tmp_path), result=loads)
    cli.rating_table_lines(case, section)  # complete: written
    bare = copy.deepcopy(section)
    del bare["measured"]["K_Halpha"]["contact_model"]
    with pytest.raises(ValueError, match=r"^measured factor K_Halpha: no contact_model"):
        cli.rating_table_lines(case, bare)


def test_planetary_rows_state_the_stage_meshes_contact_model(tmp_path):
    """A planetary stage: its contact meshes' words from their sun and ring mesh models
    (ContactMeshes), none for constant mesh springs; the K_v rows of the sweep carry the words they are given; the rating's K_γ
    from the run's load sharing (linear springs) states it has no tooth contact, in the section
    and in rating.md, and a K_γ the case gives is shown without it."""
    geo = geometry(**SEQ)
    st = stage(geo, 3)
    contact = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(K0))
    assert stage_contact_model(contact) == THEORETICAL
    beyond = jg.BeyondPath()
    ext = dataclasses.replace(
        contact,
        sun_mesh=dataclasses.replace(contact.sun_mesh, contact_geometry=beyond),
        ring_mesh=dataclasses.replace(contact.ring_mesh, contact_geometry=beyond),
    )
    assert stage_contact_model(ext) == EXTENDED
    assert "no tooth contact" in stage_contact_model(jp.ConstantMeshes(contact.mesh_period()))
    sweep = {"speeds_rad_s": [1.0, 2.0], "mesh_names": ["s1", "s2", "r1", "r2"],
             "dynamic_factor_mesh": [[1.1, 1.2, 1.3, 1.4], [1.2, 1.3, 1.4, 1.5]],
             "model": "planar", "ring_model": "rigid"}
    sharing = {"planar": {"sun_mesh_forces_N": [1.0, 1.0], "ring_mesh_forces_N": [1.0, 1.0]}}
    k_v = measured_k_v(sweep, 1.5, sharing, stage_contact_model(ext))
    assert [k["contact_model"] for k in k_v] == [EXTENDED] * 2
    sec = rating_section(jio.load_case("nrel-5mw-planetary"), str(tmp_path), 1.2, k_v=k_v)
    springs = jg.rating.contact_model(())
    assert sec["K_gamma"]["contact_model"] == [springs] * 2
    assert sec["measured"]["K_v"]["contact_model"] == [EXTENDED] * 2
    md = (tmp_path / "rating.md").read_text(encoding="utf-8")
    assert md.count(f"contact model: {springs}) |") == 2  # the K_γ rows
    assert md.count(f"| {EXTENDED} |") == 2  # the K_v measured rows


def test_k_v_far_below_resonance_is_comparable_only_with_contact_beyond_the_path():
    """Far below the first mode a K_v measured on the theoretical path is the entering pairs'
    step transient, not ISO's K_v (not comparable); with contact beyond the path the pairs take
    their load gradually and the measured overload is comparable with ISO's below resonance."""
    sweep = {"speeds_rad_s": [1.0, 2.0], "mesh_names": ["s1", "s2", "r1", "r2"],
             "dynamic_factor_mesh": [[1.1, 1.2, 1.3, 1.4], [1.2, 1.3, 1.4, 1.5]],
             "model": "planar", "ring_model": "rigid",
             "mesh_frequency_Hz": [5.0, 10.0], "natural_frequencies_Hz": [60.0, 90.0]}
    sharing = {"planar": {"sun_mesh_forces_N": [1.0, 1.0], "ring_mesh_forces_N": [1.0, 1.0]}}
    theo = measured_k_v(sweep, 1.5, sharing, THEORETICAL)
    ext = measured_k_v(sweep, 1.5, sharing, EXTENDED)
    assert [k["comparable"] for k in theo] == [False, False]
    assert all("theoretical start of contact" in k["note"] for k in theo)
    assert [k["comparable"] for k in ext] == [True, True]
    assert all("takes its load gradually" in k["note"] for k in ext)
