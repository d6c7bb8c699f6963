"""One source for a planetary stage's ring cutter in a case file: the ring's ``[[gears]]`` entry
(``cutter_teeth``, ``cutter_profile_shift``, ``cutter_tip_radius_coeff``) gives the pinion-type
cutter to both the rating's root section (:class:`jaxgear.rating.ShaperCutterSection`) and the Weber
stiffness model (``Weber(ring_cutter=...)``); the older ``[rating] ring_cutter_*`` spelling is
still read, for both, and the two spellings together are refused in one line."""

from __future__ import annotations

import copy
import re
import tomllib

import equinox as eqx
import jax
import numpy as np
import pytest

import fem_prep as fp
import jaxgear as jg
import jaxgear.io as jio
import jaxgear.rating as jr

#: the embedded NREL stages' cutter lines on their ring's [[gears]] entry
_GEARS_CUTTER = re.compile(
    r"(?m)^# the report's pinion-type cutter: .*\n# .*\n"
    r"cutter_teeth = (\S+) .*\ncutter_profile_shift = (\S+) .*\n"
    r"cutter_tip_radius_coeff = (\S+) .*\n"
)


def older_spelling(text: str) -> str:
    """An embedded NREL stage's text with its ring's cutter moved from the ring's ``[[gears]]``
    entry to ``[rating]`` in the older spelling (the lines as the files wrote them before)."""
    found = _GEARS_CUTTER.search(text)
    assert found, "the embedded case's cutter lines moved"
    z0, x0, rho = found.groups()
    text = text.replace(found.group(0), "")
    lines = (
        f"ring_cutter_teeth = {z0}             # the report's pinion-type cutter: z0 = {z0},\n"
        f"ring_cutter_profile_shift = {x0}    # x0 = 0,\n"
        f"ring_cutter_tip_radius_coeff = {rho}   # rho_a0 = 0.3 m_n\n"
    )
    at = text.find("\n[rating.")  # the end of [rating]'s own keys
    return text + lines if at < 0 else text[:at] + lines + text[at:]


def _data(name: str, **cutter) -> dict:
    """The embedded stage ``name`` with ``[mesh] stiffness = "weber"`` and its ring's cutter keys
    replaced by ``cutter`` (none: the ring gives no cutter in [[gears]])."""
    data = tomllib.loads(jio.embedded_case_text(name))
    data["mesh"]["stiffness"] = "weber"
    ring = next(g for g in data["gears"] if g["name"] == data["planetary"]["ring_gear"])
    for key in ("cutter_teeth", "cutter_profile_shift", "cutter_tip_radius_coeff"):
        ring.pop(key)
    ring.update(cutter)
    return data


def test_one_cutter_in_gears_reaches_the_rating_and_weber():
    """A cutter given once, on the ring's [[gears]] entry (values other than the embedded ones):
    the rating's root section and the Weber model's ring cutter are that cutter (z0, x0,
    ρ_a0/m_n as written), for both NREL stages; without the tip radius both take the default
    (None: the ring's fillet_radius_coeff)."""
    for name, (z0, x0, rho) in (("nrel-5mw-planetary", (34, 0.1, 0.25)),
                                ("nrel-5mw-stage2", (32, 0.05, 0.2))):
        case = jio.parse_train(_data(name, cutter_teeth=z0, cutter_profile_shift=x0,
                                     cutter_tip_radius_coeff=rho))
        assert case.stiffness == jg.Weber(ring_cutter=fp.ShaperCutter(z0, x0, rho))
        section = jio.ratings_of(case)[1].geometry.root_section
        assert isinstance(section, jg.rating.ShaperCutterSection)
        assert (section.teeth, float(section.profile_shift), float(section.tip_radius_coeff)) == (
            z0, x0, rho)
    case = jio.parse_train(_data("nrel-5mw-stage2", cutter_teeth=31))
    assert case.stiffness == jg.Weber(ring_cutter=fp.ShaperCutter(31, 0.0, None))
    section = jio.ratings_of(case)[1].geometry.root_section
    assert (section.teeth, float(section.profile_shift), section.tip_radius_coeff) == (31, 0.0, None)


@pytest.mark.parametrize(
    "rating_key, value, written",
    [("ring_cutter_teeth", 30, "30"), ("ring_cutter_tip_radius_coeff", 0.3, "0.3"),
     ("ring_cutter_teeth", "thirty", "'thirty'")],
)
def test_both_spellings_are_refused_in_one_line_naming_both_keys(rating_key, value, written):
    """The embedded stage 2 (its cutter on the ring's [[gears]] entry) with a [rating]
    ring_cutter_* key too, the same cutter, another key of it or a value that is no number:
    refused in one line naming both keys, before any work."""
    data = tomllib.loads(jio.embedded_case_text("nrel-5mw-stage2"))
    data["rating"][rating_key] = value
    with pytest.raises(jio.SchemaError) as err:
        jio.parse_train(data)
    text = str(err.value)
    assert "\n" not in text
    assert text.startswith(
        f"[rating] {rating_key} = {written} and [gears.ring2] cutter_teeth = 30: the ring's "
        "cutter is given twice; give it once, on the ring's [[gears]] entry"
    ), text
    assert "[rating] ring_cutter_* is their older spelling" in text


RATE = eqx.filter_jit(jr.rate)  # compiled once per stage, shared by both spellings


def _rated(case) -> list:
    return [jax.tree_util.tree_leaves(RATE(rc.geometry, rc.operating, rc.settings))
            for rc in jio.ratings_of(case)]


@pytest.mark.parametrize("name, z0", [
    ("nrel-5mw-planetary", 36),
    # default tier: tests/test_ring_cutter_keys.py::test_older_spelling_alone_rates_identically_and_reaches_weber[nrel-5mw-planetary-36]
    pytest.param("nrel-5mw-stage2", 30, marks=pytest.mark.slow)])
def test_older_spelling_alone_rates_identically_and_reaches_weber(tmp_path, name, z0):
    """An embedded NREL stage with its cutter in the older ``[rating] ring_cutter_*`` spelling:
    the same root section and every rating value of both meshes within 1e-12 of the [[gears]]
    spelling; with ``[mesh] stiffness = "weber"`` the stiffness model takes that cutter too."""
    path = tmp_path / f"{name}.toml"
    path.write_text(older_spelling(jio.embedded_case_text(name)), encoding="utf-8")
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    assert data["rating"]["ring_cutter_teeth"] == z0
    assert not any(k.startswith("cutter_") for g in data["gears"] for k in g)
    old, new = jio.load_case(str(path)), jio.load_case(name)
    a, b = (jio.ratings_of(c)[1].geometry.root_section for c in (old, new))
    assert (a.teeth, float(a.profile_shift), float(a.tip_radius_coeff)) == (z0, 0.0, 0.3)
    assert (b.teeth, float(b.profile_shift), float(b.tip_radius_coeff)) == (z0, 0.0, 0.3)
    for mesh_old, mesh_new in zip(_rated(old), _rated(new), strict=True):
        assert len(mesh_old) == len(mesh_new) > 20
        for u, v in zip(mesh_old, mesh_new, strict=True):
            np.testing.assert_allclose(np.asarray(u), np.asarray(v), rtol=1e-12, atol=0)
    weber = copy.deepcopy(data)
    weber["mesh"]["stiffness"] = "weber"
    case = jio.parse_train(weber)
    assert case.stiffness == jg.Weber(ring_cutter=fp.ShaperCutter(z0, 0.0, 0.3))


def test_weber_without_any_cutter_still_refused_naming_the_gears_key():
    """Neither spelling and ``stiffness = "weber"``: the internal mesh is refused in one line that
    names the [[gears]] key (the one source)."""
    with pytest.raises(ValueError, match=r"^\[mesh\] stiffness = 'weber': .*cutter_teeth "
                                         r"\(\[\[gears\]\]\)$"):
        jio.parse_train(_data("nrel-5mw-stage2"))
