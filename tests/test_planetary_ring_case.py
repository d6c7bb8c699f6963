"""The ring's model in a planetary case file ([planetary.ring] model, body): the names mapped to
jaxgear.RigidRing / CondensedRing by jaxgear.io, and the refusals in one line before any work
(an unknown model, a missing or unknown body, a body with a rigid ring, a ring body whose tooth
count or root radius disagree with the ring gear)."""

import copy
import tomllib

import pytest

import fem_prep as fp
import jaxgear as jg
import jaxgear.io as jio
from _toml import case_toml
from jaxgear.cli import main

NREL2 = "nrel-5mw-stage2"
NREL2_RING = "nrel-5mw-stage2-ring"


def _with_ring(tmp_path, **ring):
    data = copy.deepcopy(tomllib.loads(jio.embedded_case_text(NREL2)))
    data["planetary"]["ring"].update(ring)
    path = tmp_path / "case.toml"
    path.write_text(case_toml(data))
    return path


def test_names_map_to_ring_objects(tmp_path):
    """No model: the rigid ring; model = "condensed" with the embedded NREL stage-2 ring: its
    body (93 stations, the ring gear's root radius within 2 %), not built until asked."""
    rigid = jio.load_case(NREL2).form.spec.ring_model
    assert not rigid.flexible and isinstance(rigid.ring(), jg.RigidRing)
    case = jio.load_case(_with_ring(tmp_path, model="condensed", body=NREL2_RING))
    spec = case.form.spec.ring_model
    assert spec.flexible and spec.body == fp.load_ring_body(NREL2_RING)
    assert spec.body.condensation.teeth == 93
    assert spec.body.root_radius == pytest.approx(float(case.pairs[1].root_radii[1]), rel=1e-4)
    explicit = jio.load_case(_with_ring(tmp_path, model="rigid")).form.spec.ring_model
    assert isinstance(explicit.ring(), jg.RigidRing)


def test_a_ring_body_file_by_path(tmp_path):
    text = fp.embedded_ring_text(NREL2_RING)
    body = tmp_path / "my-ring.toml"
    body.write_text(text.replace('name = "nrel-5mw-stage2-ring"', 'name = "mine"'))
    spec = jio.load_case(_with_ring(tmp_path, model="condensed", body=str(body))).form.spec
    assert spec.ring_model.body.name == "mine"


@pytest.mark.parametrize(
    "ring, words",
    [
        (dict(model="elastic"), "[planetary.ring] model = 'elastic'"),
        (dict(model="condensed"), "[planetary.ring] body: missing required key"),
        (dict(model="rigid", body=NREL2_RING),
         "[planetary.ring] body = 'nrel-5mw-stage2-ring': allowed only with model = \"condensed\""),
        (dict(model="condensed", body="no-such-ring"),
         "[planetary.ring] body = 'no-such-ring': ring body 'no-such-ring' not found"),
        (dict(model="condensed", body="seq-test-ring"),
         "has 53 tooth stations ([condensation] teeth); the ring gear has 93 teeth"),
        (dict(model="condensed", body="BODY_900"),
         "root_radius_mm = 900 differs from the ring gear's root radius 1000.3 mm by 10"),
    ],
)
def test_bad_ring_keys_are_one_line_before_any_work(tmp_path, capsys, ring, words):
    if ring.get("body") == "BODY_900":
        text = fp.embedded_ring_text(NREL2_RING)
        body = tmp_path / "small.toml"
        body.write_text(text.replace("root_radius_mm = 1000.30", "root_radius_mm = 900.0"))
        ring = {**ring, "body": str(body)}
    path = _with_ring(tmp_path, **ring)
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and "\n" not in err, err
    assert not out.exists()
