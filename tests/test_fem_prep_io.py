"""Outputs: CLI build (summary.json / npz / vtu), validating npz loader, cache."""

import hashlib
import json

import meshio
import numpy as np
import pytest
from _examples import load_example

from fem_prep import build, cache_dir, cache_key, load_body, load_condensed, main

BODY = """
name = "io-wheel"
[body]
bore_radius_mm = 8.0
hub_outer_radius_mm = 12.0
hub_width_mm = 10.0
web_thickness_mm = 2.0
rim_inner_radius_mm = 24.0
rim_outer_radius_mm = 28.0
rim_width_mm = 8.0
[[bearings]]
axial_position_mm = -4.0
[[bearings]]
axial_position_mm = 4.0
coupling = "averaging"
[mesh]
size_mm = 5.0
circumferential_size_mm = 10.0
[condensation]
method = "craig-bampton"
modes = 12
teeth = 10
axial_master_nodes = 2
[centrifugal]
speed_rad_s = 1500.0
[modal]
n_frequencies = 8
vtu_modes = 3
"""


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    root = tmp_path_factory.mktemp("fp")
    body = root / "io-wheel.toml"
    body.write_text(BODY)
    mp = pytest.MonkeyPatch()
    mp.setenv("FEM_PREP_CACHE", str(root / "cache"))
    out = root / "out"
    rc = main(["build", str(body), "--out", str(out), "--quiet"])
    yield root, body, out, rc
    mp.undo()


def test_cli_build_writes_outputs(built):
    root, body, out, rc = built
    assert rc == 0
    summary = json.loads((out / "summary.json").read_text())
    for key in (
        "n_nodes",
        "n_dofs",
        "mass_kg",
        "n_master_dofs",
        "n_modes",
        "frequencies_full_hz",
        "frequencies_condensed_hz",
        "centrifugal_rim_radial_displacement_m",
    ):
        assert key in summary
    assert summary["n_dofs"] == 3 * summary["n_nodes"]
    assert summary["rim_coupling"] == "distributing"  # the default
    assert summary["n_master_dofs"] == 10 * 2 * 3 + 2 * 6
    assert len(summary["frequencies_full_hz"]) == 8
    # mass against the analytic volume of the three annuli
    import math

    v = math.pi * ((28**2 - 24**2) * 8 + (24**2 - 12**2) * 2 + (12**2 - 8**2) * 10) * 1e-9
    # (quadratic geometry: arcs of 36 deg are interpolated, volume exact to ~1e-4)
    assert summary["mass_kg"] == pytest.approx(7800 * v, rel=1e-3)
    c = load_condensed(out / "io-wheel.npz")
    # 12 fixed-interface modes + the static correction vector of the centrifugal load
    assert c.K.shape == (summary["n_master_dofs"] + 12 + 1,) * 2
    assert c.input_sha256 == hashlib.sha256(body.read_text().encode()).hexdigest()
    assert np.allclose(c.K, c.K.T) and np.allclose(c.M, c.M.T)
    m = meshio.read(out / "io-wheel.vtu")
    assert "centrifugal_displacement" in m.point_data
    assert sum(k.startswith("mode_") for k in m.point_data) == 3
    assert m.points.shape[1] == 3


def test_recovery_reproduces_a_rigid_motion(built):
    """The masters of a small rigid motion (translation t, rotation w: rim masters at their
    stored positions t + w x x_m, bearing nodes t + w x x_b and w, modal coordinates 0) recover
    t + w x x at every recovery node (the coupling reproduces rigid motions, seed (2.9))."""
    _, _, out, _ = built
    c = load_condensed(out / "io-wheel.npz")
    rng = np.random.default_rng(0)
    t, w = rng.standard_normal(3) * 1e-6, rng.standard_normal(3) * 1e-5
    q = np.zeros(c.n_dofs)
    for dof, (node, comp) in enumerate(c.dof_map):
        if node < 0:
            continue
        if comp < 3:
            q[dof] = (t + np.cross(w, c.master_coords[node]))[comp]
        else:
            q[dof] = w[comp - 3]
    u = (c.recovery.astype(float) @ q).reshape(-1, 3)
    ref = t + np.cross(w, c.recovery_coords)
    assert np.max(np.abs(u - ref)) < 1e-5 * np.max(np.abs(ref))  # float32 recovery


def test_cache_hit_avoids_recomputation(built, monkeypatch, tmp_path):
    root, body, out, _ = built
    monkeypatch.setenv("FEM_PREP_CACHE", str(root / "cache"))

    # a mark in the cache entry's summary: a hit hands it on, a recomputation would rewrite it
    entry = cache_dir() / cache_key(load_body(body))
    summary = json.loads((entry / "summary.json").read_text())
    (entry / "summary.json").write_text(json.dumps({**summary, "mark": "from the cache"}))
    s = build(body, tmp_path / "again")
    assert s["cache_hit"] is True and s["mark"] == "from the cache"
    assert json.loads((tmp_path / "again" / "summary.json").read_text())["mark"] == "from the cache"
    assert (tmp_path / "again" / "io-wheel.npz").is_file()
    # same body with other comments/whitespace hits the same cache entry
    body2 = tmp_path / "io-wheel.toml"
    body2.write_text("# a comment\n" + BODY)
    assert build(body2, tmp_path / "again2")["cache_hit"] is True


def _rewrite(src, dst, **changes):
    with np.load(src) as z:
        d = {k: z[k] for k in z.files}
    for k, v in changes.items():
        if v is None:
            d.pop(k)
        else:
            d[k] = v
    with open(dst, "wb") as fh:
        np.savez(fh, **d)


def test_loader_rejects_bad_files(built, tmp_path):
    _, _, out, _ = built
    src = out / "io-wheel.npz"
    data = src.read_bytes()
    trunc = tmp_path / "trunc.npz"
    trunc.write_bytes(data[: len(data) // 2])
    with pytest.raises(ValueError, match="truncated or corrupt"):
        load_condensed(trunc)
    junk = tmp_path / "junk.npz"
    junk.write_bytes(b"not a zip file at all")
    with pytest.raises(ValueError, match="truncated or corrupt"):
        load_condensed(junk)
    p = tmp_path / "missing.npz"
    _rewrite(src, p, K=None)
    with pytest.raises(ValueError, match="missing key.*K"):
        load_condensed(p)
    p = tmp_path / "shape.npz"
    with np.load(src) as z:
        M = z["M"]
    _rewrite(src, p, M=M[:-1])
    with pytest.raises(ValueError, match="M has shape"):
        load_condensed(p)
    p = tmp_path / "hash.npz"
    _rewrite(src, p, input_toml=np.array(BODY.replace("1500.0", "1600.0")))
    with pytest.raises(ValueError, match="hash mismatch"):
        load_condensed(p)
    p = tmp_path / "version.npz"
    _rewrite(src, p, format_version=np.array(99))
    with pytest.raises(ValueError, match="format_version 99"):
        load_condensed(p)
    with pytest.raises(FileNotFoundError):
        load_condensed(tmp_path / "nothing.npz")


def test_cli_errors_and_bodies(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text(BODY.replace("teeth = 10", "teeth = 10\ncolour = 1"))
    assert main(["build", str(bad), "--out", str(tmp_path / "o"), "--quiet", "--no-cache"]) == 2
    assert "colour" in capsys.readouterr().err
    assert main(["build", str(tmp_path / "none.toml"), "--quiet"]) == 2
    assert main(["bodies"]) == 0
    assert "accessory-wheel" in capsys.readouterr().out


def test_atomic_write_leaves_no_temp_files(built):
    _, _, out, _ = built
    assert not [p for p in out.iterdir() if p.name.endswith(".tmp")]


@pytest.mark.slow
def test_example_runs(tmp_path):

    mod = load_example("fem_prep_modes_error")
    curves = mod.main(str(tmp_path / "e.png"))
    assert curves["craig-bampton"][-1] < curves["craig-bampton"][0]
    assert (tmp_path / "e.png").is_file()


@pytest.mark.slow
def test_bench_quick_is_a_smoke_test(tmp_path):
    """`fem-prep bench --quick` runs the whole benchmark path on a 17-station wheel in seconds
    (no baseline, two-point error curve) and reports failures as data, not as `{'error': ''}`."""
    QUICK_TEETH = 17  # the wheel of --quick: 17 angular stations (docs/fem_prep-evidence.md)

    assert main(["bench", "--quick", "--out", str(tmp_path)]) == 0
    rec = json.loads((tmp_path / "bench.json").read_text())
    assert rec["quick"] and len(rec["cases"]) == 1
    case = rec["cases"][0]
    assert "error" not in case, case
    assert case["solver"] in ("cholmod", "pardiso")
    assert case["n_master_dofs"] == QUICK_TEETH * 5 * 3 + 3 * 6
    assert rec["error_curve"]["modes"] == [0, 10]
    assert rec["error_curve"]["craig-bampton"][1] < rec["error_curve"]["craig-bampton"][0]
    for name in ("bench.json", "bench.png", "modes_error.png"):
        assert (tmp_path / name).stat().st_size > 0
