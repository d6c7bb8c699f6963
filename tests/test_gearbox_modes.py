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


def test_a_two_pair_chain_listed_through_its_model_against_an_eigen_solution_written_here():
    """Two parallel pairs on constant mesh springs joined by a shaft (stage 1's wheel to stage
    2's pinion), free at both ends: :meth:`GearboxModel.natural_modes` against
    ``scipy.linalg.eigh`` of (K, M) written here from the inertias, the base radii (a pair's
    mesh deflection r_p θ_p + r_w θ_w), the mesh and the shaft stiffnesses: one rigid mode at
    0 Hz, the elastic frequencies to 1e-9, each stage's kinetic-energy share Σ_{j∈s} M_jj φ_j²
    (M-normalised φ) to 1e-9; ``jaxgear modes``' rows (:func:`jaxgear.cli.modes.typed_modes`)
    name the stage of the larger share."""
    import scipy.linalg

    import jaxgear.gearbox as gb
    from jaxgear.cli.modes import typed_modes

    inertias, radii, mesh = ((0.02, 0.3), (0.05, 0.8)), ((0.04, 0.1), (0.05, 0.12)), (5e8, 8e8)
    shaft = 2e6
    chain = gb.GearboxTorsional(
        tuple(gb.PairGearboxStage(i, r, k, input=0) for i, r, k in zip(inertias, radii, mesh)),
        (shaft,))
    model = gb.GearboxModel(chain, gb.GearboxRun(100.0, 1e6))
    modes = model.natural_modes()

    M = np.diag(np.concatenate(inertias))
    K = np.zeros((4, 4))
    for s, (r, k) in enumerate(zip(radii, mesh)):
        v = np.zeros(4)
        v[2 * s:2 * s + 2] = r
        K += k * np.outer(v, v)
    b = np.array([0.0, 1.0, -1.0, 0.0])  # stage 1's wheel (its output) to stage 2's pinion
    K += shaft * np.outer(b, b)
    lam, phi = scipy.linalg.eigh(K, M)
    f_ref = np.sqrt(np.clip(lam, 0.0, None)) / (2 * np.pi)
    shares = np.stack([np.sum(np.diag(M)[2 * s:2 * s + 2, None] * phi[2 * s:2 * s + 2] ** 2,
                              axis=0) for s in range(2)])

    f = np.asarray(modes.frequency)
    assert np.asarray(modes.rigid).tolist() == [True, False, False, False]
    assert f[0] == 0.0 and f_ref[0] < 1e-6 * f_ref[-1]
    np.testing.assert_allclose(f[1:], f_ref[1:], rtol=1e-9)
    assert modes.groups == ("stage1", "stage2")
    np.testing.assert_allclose(np.asarray(modes.kinetic)[:, 1:], shares[:, 1:], atol=1e-9)
    rows = typed_modes(model, modes)["torsional_chain"]
    assert [r["type"] for r in rows] == ["rigid body"] + [
        f"stage{int(np.argmax(shares[:, j])) + 1}" for j in range(1, 4)]
    assert len({r["type"] for r in rows[1:]}) == 2  # both stages hold a mode
