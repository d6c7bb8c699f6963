"""Trains rate every mesh: a train file's ``[rating]`` (shared, per-gear values as tables by gear
name, ``[rating.<driving>-<driven>]`` replacing entries for one mesh) gives one ISO 6336 rating
per mesh at its driving gear's torque and speed; an idler is rated in both its meshes with the
mean stress influence factor of alternating bending (ISO 6336-3:2019 Y_M = 0.7).

The reference is ISO 6336-2/-3 method B by hand, in plain Python below, for the idler's second
mesh (idler → output) of the embedded idler train: the ISO 21771 geometry (working pressure angle,
contact ratio), Z_H, Z_E, Z_ε, σ_H0 and σ_F0 (Y_F, Y_S from the generated tooth form, checked
against the standard's closed form in tests/test_rating.py), the mesh's torque (the idler passes
the input's tangential force on: T_idler = T z_idler / z_input), its speed and load cycles."""

import copy
import json
import math
import tomllib
from importlib import resources

import jax
import numpy as np
import pytest
from _rating_cases import Cells, stub_table
from test_internal_case import GEARS as INTERNAL_GEARS

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.rating as jr
from fem_prep.schema import SchemaError
from jaxgear import cli

jax.config.update("jax_enable_x64", True)

TRAIN = tomllib.loads(
    resources.files("jaxgear.cases").joinpath("accessory-idler-train.toml").read_text()
)
TRAIN["material"].update(
    sigma_H_lim_MPa=1500.0, sigma_F_lim_MPa={"input": 430.0, "idler": 430.0, "output": 400.0}
)
TRAIN["operating"]["speed_rpm"] = 6000.0
TRAIN["rating"] = {
    "life_h": 20000.0,
    "viscosity_40C_mm2_s": 46.0,
    "roughness_Rz_flank_um": 3.0,
    "roughness_Rz_root_um": 10.0,
    "idler-output": {"K_Hbeta": 1.2},
}
RPM = 2 * math.pi / 60


def _train(**rating):
    d = copy.deepcopy(TRAIN)
    d["rating"].update(rating)
    return d


def _inv(t):
    return math.tan(t) - t


def _hand_idler_output():
    """σ_H0 (Pa), F_t (N), u of the idler → output mesh by hand (ISO 21771, ISO 6336-2)."""
    m, alpha, z1, z2, x1, x2, ha = 1.5e-3, math.radians(25.0), 61, 86, 0.4, 0.481, 0.9447
    target = _inv(alpha) + 2 * math.tan(alpha) * (x1 + x2) / (z1 + z2)
    lo, hi = 0.1, 1.2
    for _ in range(200):  # bisection for the working pressure angle
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if _inv(mid) < target else (lo, mid)
    aw = lo
    a = (z1 + z2) * m / 2 * math.cos(alpha) / math.cos(aw)
    d1, d2 = z1 * m, z2 * m
    rb1, rb2 = d1 / 2 * math.cos(alpha), d2 / 2 * math.cos(alpha)
    ra1, ra2 = d1 / 2 + m * (ha + x1), d2 / 2 + m * (ha + x2)
    eps_a = (math.sqrt(ra1**2 - rb1**2) + math.sqrt(ra2**2 - rb2**2) - a * math.sin(aw)) / (
        math.pi * m * math.cos(alpha)
    )
    z_h = math.sqrt(2 * math.cos(aw) / (math.cos(alpha) ** 2 * math.sin(aw)))
    z_e = math.sqrt(210e9 / (2 * math.pi * (1 - 0.3**2)))
    z_eps = math.sqrt((4 - eps_a) / 3)
    torque = 80.0 * z1 / 45  # the idler passes the input's force on
    ft = 2 * torque / d1
    u = z2 / z1
    b = 9.5e-3  # the common face width
    return z_h * z_e * z_eps * math.sqrt(ft / (d1 * b) * (u + 1) / u), ft, u, eps_a


def test_a_train_rates_every_mesh_and_matches_iso_by_hand_on_the_idler_mesh():
    case = jio.parse_train(_train())
    rcs = jio.ratings_of(case)
    assert len(rcs) == 2
    s_h0, ft, u, eps_a = _hand_idler_output()
    rc = rcs[1]  # idler → output: the idler as the rating's pinion
    assert float(rc.operating.torque) == pytest.approx(80.0 * 61 / 45, rel=1e-12)
    assert float(rc.operating.speed) == pytest.approx(6000.0 * RPM * 45 / 61, rel=1e-12)
    r = jr.rate(rc.geometry, rc.operating, rc.settings)
    assert float(rc.geometry.derived().transverse_contact_ratio) == pytest.approx(eps_a, rel=1e-9)
    assert float(r.pitting.sigma_H0) == pytest.approx(s_h0, rel=1e-6)
    # σ_F0 = F_t/(b m_n) Y_F Y_S per gear (face widths 10.5 and 9.5 mm: b ≤ b_mate + 2 m_n)
    form = jg.rating.tooth_form_factors(rc.geometry)
    for i, b in enumerate((10.5e-3, 9.5e-3)):
        ref = ft / (b * 1.5e-3) * float(form.Y_F[i]) * float(form.Y_S[i])
        assert float(r.bending.sigma_F0[i]) == pytest.approx(ref, rel=1e-9)
    # the mesh's own table: K_Hβ given on this mesh only
    assert r.factors.sources["K_Hbeta"] == "given" and float(r.factors.K_Hbeta) == 1.2
    assert rcs[0].settings.given.K_Hbeta is None
    # the idler: Y_M = 0.7 in both meshes (driven by the input, driving the output), the other
    # gears 1; it enters σ_FG = σ_Flim Y_ST Y_NT Y_δrelT Y_RrelT Y_X Y_M, and S_F with it
    assert [float(v) for v in rcs[0].settings.loading.mean_stress_factor] == [1.0, 0.7]
    assert [float(v) for v in r.bending.Y_M] == [0.7, 1.0]
    b = r.bending
    for i, (lim, y_m) in enumerate(((430e6, 0.7), (400e6, 1.0))):
        one_way = lim * 2.0 * b.Y_NT[i] * b.Y_delta_rel_T[i] * b.Y_R_rel_T[i] * b.Y_X[i]
        assert float(b.sigma_FG[i]) == pytest.approx(y_m * float(one_way), rel=1e-12)
        assert float(b.S_F[i]) == pytest.approx(float(b.sigma_FG[i] / b.sigma_F[i]), rel=1e-12)
    # load cycles: each flank of the idler once per turn, N_L = life · n_idler
    n_idler = 6000.0 / 60 * 45 / 61  # turns per second
    assert [float(c) for c in r.pitting.cycles] == pytest.approx(
        [20000 * 3600 * n_idler, 20000 * 3600 * n_idler / u], rel=1e-12
    )
    # per-gear table by name: the output's σ_Flim 400 N/mm², the idler's 430
    assert [float(v) for v in rc.settings.material.sigma_f_lim] == [430e6, 400e6]


def test_tooth_loading_of_roles():
    """Cycles per turn and Y_M from the meshes each gear drives in and is driven in."""
    one_way = jr.ToothLoading.of_roles((1, 0), (0, 1))  # a pair
    assert one_way.cycles_per_turn == (1.0, 1.0) and one_way.mean_stress_factor == (1.0, 1.0)
    sun = jr.ToothLoading.of_roles((3, 0), (0, 1))  # a gear driving three: same flank, 3/turn
    assert sun.cycles_per_turn == (3.0, 1.0) and sun.mean_stress_factor == (1.0, 1.0)
    with pytest.raises(ValueError, match="mean_stress_factor"):
        jr.ToothLoading((1.0, 1.0), (1.2, 1.0))


@pytest.mark.parametrize(
    ("data", "message"),
    [
        (
            _train(roughness_Rz_root_um={"input": 10.0, "idler": 10.0}),
            "gear 'output' missing",
        ),
        (_train(roughness_Rz_root_um=[10.0, 12.0]), "a number, or a table of one per gear"),
        (_train(**{"input-output": {"K_v": 1.1}}), "input-output"),
        (_train(**{"idler-output": {"K_v": 0.5}}), "K_v"),
    ],
)
def test_bad_train_rating_is_one_line_naming_the_key(data, message):
    with pytest.raises(SchemaError, match=message) as err:
        jio.parse_train(data)
    assert "\n" not in str(err.value)


def test_a_rating_of_an_internal_mesh_is_refused_in_one_line(tmp_path, capsys):
    """A planet → ring train with ``[rating]``: ``jaxgear run`` exits 2 with one stderr line
    naming the internal mesh and its gear before any work, nothing written (it failed on the
    ring's negative reference diameter in ISO 1328-1 before)."""
    text = (
        INTERNAL_GEARS
        + '\n[[meshes]]\ndriving = "planet"\ndriven = "ring"\nangle_deg = 0.0\n'
        + '[mesh]\nstiffness = "uniform"\nstiffness_per_length_N_per_mm_per_um = 12.0\n'
        + "[operating]\ntorque_Nm = 150.0\nspeed_rpm = 1000.0\n"
        + "[material]\nsigma_H_lim_MPa = 1500.0\nsigma_F_lim_MPa = 430.0\n"
        + _rating_text()
    )
    message = "[rating]: mesh planet-ring is internal (ring: teeth -90): the rating covers"
    with pytest.raises(SchemaError) as err:
        jio.parse_train(tomllib.loads(text))
    assert str(err.value).startswith(message) and "\n" not in str(err.value)
    path, out = tmp_path / "internal.toml", tmp_path / "out"
    path.write_text(text)
    assert cli.main(["run", str(path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and message in err, err
    assert not out.exists()


def _rating_text() -> str:
    """TRAIN's ``[rating]`` keys as TOML text."""
    keys = ("life_h", "viscosity_40C_mm2_s", "roughness_Rz_flank_um", "roughness_Rz_root_um")
    return "[rating]\n" + "".join(f"{k} = {TRAIN['rating'][k]}\n" for k in keys)


def test_train_rating_keys_without_a_rating_table_are_refused():
    d = copy.deepcopy(TRAIN)
    del d["rating"]
    with pytest.raises(SchemaError, match="sigma_F_lim_MPa.*read by the \\[rating\\] table only"):
        jio.parse_train(d)


def test_train_rating_outputs_per_mesh_lists_and_a_table_per_mesh(tmp_path):
    case = jio.parse_train(_train())
    section = cli.rating_outputs(case, str(tmp_path))
    assert section["meshes"] == ["input-idler", "idler-output"]
    assert section["method"] == "ISO 6336:2019 method B"
    s_f = section["bending"]["S_F"]
    assert len(s_f) == 2 and all(len(v) == 2 for v in s_f)
    assert section["bending"]["Y_M"] == [[1.0, 0.7], [0.7, 1.0]]
    assert section["factors"]["K_Hbeta"]["source"] == ["ISO 6336-1 method B", "given"]
    json.dumps(section)
    table = (tmp_path / "rating.md").read_text(encoding="utf-8")
    assert table.count("\n## ") == 2
    assert "mesh idler-output" in table and "| Y_M | 0.7000 / 1.000 |" in table


def test_train_measured_factors_and_root_stress_per_mesh(tmp_path):
    """Per-mesh load maps (two hand-made ones: two lines of two slices at one position) give
    each mesh its measured K_Hβ, K_Hα (by hand) and its root-stress map (a stub FE table,
    by hand); ``use_measured = ["K_Halpha"]`` rates each mesh with its own; K_v is accepted
    (measured per mesh from the train's sweep)."""
    case = jio.parse_train(_train(use_measured=["K_Halpha"]))
    g = [float(p.path_of_contact) for p in case.pairs]
    maps = []
    for k, (a, b) in enumerate(((2.0, 1.0), (3.0, 3.0))):
        s = np.array([[[0.3 * g[k]] * 2, [0.8 * g[k]] * 2]])
        maps.append(
            Cells(
                line_load=np.array([[[a, a], [b, b]]]) * 1e5,
                cell_s=s,
                cell_z=np.array([[[1e-3, 5e-3]] * 2]),
                cell_mask=np.ones((1, 2, 2), dtype=bool),
            )
        )
    section = cli.rating_outputs(case, str(tmp_path), tuple(maps), root_stress=stub_table)
    k_ha = section["measured"]["K_Halpha"]["value"]
    assert k_ha == pytest.approx([2.0 / 1.5, 1.0], rel=1e-12)  # line means over the mean
    assert section["measured"]["K_Hbeta"]["value"] == pytest.approx([1.0, 1.0])
    # rated within ISO 6336-1 clause 8's limit, spur: 1/Z_ε² = 3/(4 − ε_α)
    caps = [3 / (4 - float(p.transverse_contact_ratio)) for p in case.pairs]
    want = [min(k, c) for k, c in zip(k_ha, caps, strict=True)]
    assert section["factors"]["K_Halpha"]["value"] == pytest.approx(want, rel=1e-12)
    assert want[0] < k_ha[0]  # the limit acts on the first mesh
    assert all(s.startswith("measured") for s in section["factors"]["K_Halpha"]["source"])
    for k, pair in enumerate(case.pairs):
        loads = (
            [(2e5, 0.3 * g[k]), (1e5, 0.8 * g[k])]
            if k == 0
            else [(3e5, 0.3 * g[k]), (3e5, 0.8 * g[k])]
        )
        want = [max(w * 1e3 * float(pair.roll_distance(x, i)) for w, x in loads) for i in (0, 1)]
        assert section["root_stress"]["max_Pa"][k] == pytest.approx(want, rel=1e-9)
        name = f"root_stress_map_{case.mesh_name(k)}.png"
        assert (tmp_path / name).stat().st_size > 10_000
    # K_v is measured per mesh from the train's sweep (tests/test_rating_train_speed.py)
    rcs = jio.ratings_of(jio.parse_train(_train(use_measured=["K_v"])))
    assert [rc.use_measured for rc in rcs] == [("K_v",), ("K_v",)]
