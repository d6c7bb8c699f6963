"""``jaxgear modes`` on a gearbox case.

The records under ``tests/data/gearbox/modes_recorded/`` are the ``modes.json`` that
``jaxgear modes`` wrote for three gearbox cases before it went through the gearbox's dynamic
model (the chain's own tables of ``jaxgear/cli/gearbox.py``, commit 12c914ab): an unhoused
planetary + pair chain, an unhoused chain with a lumped 3D stage, and a chain on a shared
housing. The listing through the model must keep them: the frequencies to 1e-9 relative, each
mode's type, and its energy shares (summed over a repeated frequency, where the eigenvectors
of the repeated subspace are any of its bases; the mesh holding most strain energy by its
share, its name being any of the planets' where they tie).
"""

from __future__ import annotations

import itertools
import json
import pathlib

import numpy as np
import pytest

from jaxgear.cli import main

DATA = pathlib.Path(__file__).parent / "data" / "gearbox"
RECORDED = DATA / "modes_recorded"


def _clusters(rows):
    """The rows grouped by frequency (relative 1e-9: a repeated mode's rows together)."""
    out, key = [], None
    for i, r in enumerate(rows):
        f = r["frequency_Hz"]
        if key is None or abs(f - key) > 1e-9 * max(abs(f), 1.0):
            out.append([])
        out[-1].append(i)
        key = f
    return out


def _same_modes(got: dict, ref: dict):
    assert got.keys() == ref.keys()
    for key in ("case", "model", "classification"):
        assert got[key] == ref[key]
    (name,) = [k for k, v in ref.items() if isinstance(v, list)]
    g, r = got[name], ref[name]
    assert len(g) == len(r)
    f_got = np.array([m["frequency_Hz"] for m in g])
    f_ref = np.array([m["frequency_Hz"] for m in r])
    np.testing.assert_allclose(f_got, f_ref, rtol=1e-9, atol=1e-9 * f_ref.max())
    assert [m["type"] for m in g] == [m["type"] for m in r]
    for rows in _clusters(r):
        assert all(g[i].keys() == r[i].keys() for i in rows)
        for key in ("stage_energy", "housing_energy", "mesh_total"):
            if key in r[rows[0]]:
                s_got = np.sum([np.atleast_1d(g[i][key]) for i in rows], axis=0)
                s_ref = np.sum([np.atleast_1d(r[i][key]) for i in rows], axis=0)
                np.testing.assert_allclose(s_got, s_ref, atol=1e-8)
        if len(rows) == 1 and "mesh" in r[rows[0]]:
            i = rows[0]
            # the largest mesh share (its mesh's name is any of the planets' where they tie)
            assert g[i]["stage"] == r[i]["stage"]
            np.testing.assert_allclose(g[i]["mesh_energy"], r[i]["mesh_energy"], atol=1e-8)


@pytest.mark.parametrize(
    "name",
    [
        "two-stage-gearbox",
        "two-pair-lumped",
        pytest.param("planar-pair-housed", marks=pytest.mark.slow),  # the housing: 30 s
    ],
)
def test_jaxgear_modes_on_a_gearbox_keeps_the_recorded_modes(name, tmp_path, capsys):
    assert main(["modes", str(DATA / f"{name}.toml"), "--out", str(tmp_path / "m")]) == 0
    assert f"{name}: natural frequencies" in capsys.readouterr().out
    got = json.loads((tmp_path / "m" / "modes.json").read_text())
    _same_modes(got, json.loads((RECORDED / f"{name}.json").read_text()))


def test_the_recorded_clusters_hold_the_repeated_modes():
    """The comparison's grouping on the record: the planetary stage's three-fold mode of
    two-stage-gearbox (4676 Hz, its three planets) is one group, the others alone."""
    rows = json.loads((RECORDED / "two-stage-gearbox.json").read_text())["torsional_chain"]
    sizes = [len(c) for c in _clusters(rows)]
    assert sizes == [1, 1, 1, 1, 3, 1, 1]
    assert list(itertools.chain(*_clusters(rows))) == list(range(len(rows)))
