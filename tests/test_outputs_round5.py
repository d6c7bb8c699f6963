"""What the outputs say: a sweep with nothing to excite says so (lin-parker-1999:
constant mesh springs, no pin errors, DF = 1, not round-off); sweep.csv's column names in snake
case; titles that keep a unit with its number when wrapped; the planetary Campbell title; every
critical-speed line labelled; no "modified" rows when a case has none; which stiffness each
curve of a flexible case is. Titles and labels are read back from the matplotlib figures."""

from __future__ import annotations

import csv
import itertools
import re
import tomllib

import numpy as np
import pytest

import jaxgear.io as jio
import jaxgear.planetary as jp
from jaxgear.cli import planetary_sweep as ps, plots

pytestmark = [pytest.mark.filterwarnings("ignore:.*time step under-resolved"),
              pytest.mark.filterwarnings("ignore:.*not settled")]

LP_SPEEDS = np.array([40.0, 100.0])  # rad/s of the sun; the case's operating speed is 100
LP_RUN = {"steps_per_period": 16, "periods": 4, "keep_periods": 2}


def _capture(monkeypatch, module):
    """Replace ``module.legend_below_and_save`` by one that keeps (fig, ax) and the legend's
    labels, and still writes the file."""
    figs = []
    real = module.legend_below_and_save

    def keep(fig, ax, path, note):
        labels = real(fig, ax, path, note)
        figs.append((fig, ax, labels, note))
        return labels

    monkeypatch.setattr(module, "legend_below_and_save", keep)
    return figs


@pytest.fixture(scope="module")
def lin_parker():
    return jio.load_case("lin-parker-1999")


def _sweep_stage(case):
    """(spec, the sweep's dynamic stage, its meshes, the planar model) of a lumped case, through
    the public API (as planetary_sweep builds them)."""
    import jaxgear as jg

    spec = case.form.spec
    return (spec, spec.sharing_stage(spec.stage(case)), spec.dynamic_meshes(case, 1),
            jp.PlanarPlanetary())


def test_lin_parker_has_nothing_to_excite(lin_parker):
    """The lumped form's constant springs: the meshes' stiffness over a mesh period varies by
    0 relative to its mean (round-off at most), no pin error, no eccentricity: not excited."""
    spec, stage, meshes, model = _sweep_stage(lin_parker)
    run = ps.planetary_run(lin_parker.form, lin_parker)
    e = jp.excitation(model, stage, meshes, run, spec.ring_model.flexible)
    assert e["mesh_stiffness_variation"] < 1e-12
    assert e["excited"] is False


def test_a_pin_error_or_an_eccentricity_is_an_excitation(lin_parker):
    """The same stage with a 10 µm pin error, or a 20 µm sun eccentricity, is excited."""
    for extra in ({"tangential_pin_errors_um": [10.0, 0.0, 0.0]},
                  {"sun_eccentricity_um": 20.0}):
        data = tomllib.loads(jio.embedded_case_text("lin-parker-1999"))
        data["planetary"].update(extra)
        case = jio.parse_train(data)
        spec, stage, meshes, model = _sweep_stage(case)
        run = ps.planetary_run(case.form, case)
        e = jp.excitation(model, stage, meshes, run, spec.ring_model.flexible)
        assert e["excited"] is True, extra


def test_the_unexcited_sweep_says_df_1(lin_parker, tmp_path, monkeypatch):
    """lin-parker-1999's sweep: dynamic factor and K_γ exactly 1 (the round-off kept in
    ``excitation``), the ring spectrum at the operating speed (not one chosen by round-off),
    the figure's title and legend saying "no excitation" and its y axis without an offset
    (today: "1e-11+1", ticks −3…1); the printed line says so."""
    figs = _capture(monkeypatch, ps)
    s = ps.planetary_sweep(lin_parker.form, lin_parker, LP_SPEEDS, str(tmp_path), **LP_RUN)
    assert s["dynamic_factor"] == [1.0, 1.0] and s["k_gamma"] == [1.0, 1.0]
    assert s["k_gamma_mean_load"] == [1.0, 1.0]
    assert np.all(np.asarray(s["dynamic_factor_mesh"]) == 1.0)
    assert s["excitation"]["round_off_deviation"] < 1e-8
    assert s["ring_spectrum"]["speed_rad_s"] == 100.0
    by_title = {ax.get_title(): (ax, labels) for _, ax, labels, _ in figs}
    (title, (ax, labels)), = ((t, v) for t, v in by_title.items() if "dynamic factor" in t)
    # (a wrapped title keeps "= 1" together with a no-break space)
    assert "no excitation, dynamic factor = 1" in title.replace("\n", " ").replace("\xa0", " ")
    assert labels == ["every mesh's dynamic factor and K_γ: 1"] + [
        lab for lab in labels[1:] if lab.startswith("mesh order")]
    offset = ax.yaxis.get_major_formatter().get_offset()
    assert offset == "" and ax.get_ylim() == (0.9, 1.1)
    spectrum = next(t for t in by_title if "ring transducer" in t)
    assert "no excitation" in spectrum.replace("\n", " ")
    line = ps.sweep_lines(lin_parker, s)[0]
    assert "no excitation" in line and "dynamic factor = 1" in line
    # the CSV's columns: snake case, the mesh names' spaces and hyphens gone
    with open(tmp_path / "sweep.csv", newline="") as f:
        header = next(csv.reader(f))
    assert all(re.fullmatch(r"[a-z0-9_]+(Hz)?", h) for h in header), header
    assert "dynamic_factor_mesh_sun_planet_1" in header
    assert "dynamic_factor_mesh_ring_planet_3" in header


def test_every_crossing_line_is_labelled(tmp_path, monkeypatch):
    """The planetary dynamic-factor plot: every crossing line labelled at its top (frequency
    and order), lines closer than a label's width under one label, not one legend entry per
    order only; meshes whose curves coincide drawn once and named together (today the last
    planet's curve hides the others')."""
    figs = _capture(monkeypatch, ps)
    crossings = [{"order": 3, "frequency_Hz": 743.2, "speed_rad_s": 72.5},
                 {"order": 3, "frequency_Hz": 1102.0, "speed_rad_s": 107.6},
                 {"order": 2, "frequency_Hz": 743.2, "speed_rad_s": 108.8}]
    df = [[1.1, 1.1, 1.2, 1.25], [1.3, 1.3, 1.0, 1.0]]
    summary = {"speeds_rad_s": [20.0, 120.0], "dynamic_factor_mesh": df,
               "mesh_names": ["sun-planet 1", "sun-planet 2", "ring-planet 1", "ring-planet 2"],
               "k_gamma": [1.0, 1.0],
               "crossings": crossings, "speed_of": "input (sun)", "model": "planar",
               "ring_model": "rigid ring"}

    class Case:
        name = "x"

    ps.dynamic_factor_plot(Case, summary, str(tmp_path / "df.png"))
    (_, ax, labels, _), = figs
    texts = sorted(t.get_text() for t in ax.texts)
    assert texts == ["1102 Hz / 3, 743 Hz / 2", "743 Hz / 3"]  # 107.6 and 108.8 rad/s: one
    assert labels[:3] == ["sun-planet 1, 2 (coincide)", "ring-planet 1", "ring-planet 2"]
    assert len([ln for ln in ax.lines if ln.get_xdata()[0] == 20.0]) == 4  # 3 meshes, K_γ


def test_a_wrapped_title_keeps_units_with_their_numbers():
    """A title wider than its axes is wrapped at spaces, but never between a number and its
    unit or after a ≥ sign (today "5 %" ends a line with "5" and starts the next with "%")."""
    fig, ax = plots.new_figure()
    words = "power-helical: Campbell diagram, modes with ≥ 1% mesh strain energy (black ≥ 5 %)"
    for pad in range(40):  # wherever the break falls, "%" never starts a line
        ax.set_title("x" * pad + " " + words)
        plots.wrap_titles(fig)
        lines = ax.get_title().splitlines()
        assert len(lines) >= 1
        assert not any(line.lstrip().startswith(("%", "µm")) for line in lines)
        assert not any(line.rstrip().endswith("≥") for line in lines)


def test_a_title_of_several_lines_is_wrapped_line_by_line():
    """A title of several lines whose first is wider than its axes (the train's TE plot: "...
    lumped 3D train (shafts, bearings ...)" ran past both edges) and a long suptitle are
    wrapped, each line of the result within the width the wrap allows; short lines stay."""
    fig, ax = plots.new_figure()
    first = ("two-stage: transmission error per mesh at 70 N·m (input), modified, lumped 3D "
             "train (shafts, bearings, housing)")
    ax.set_title(first + "\nfirst 7.26 of 127 input mesh periods")
    fig.suptitle("a suptitle " * 20)
    plots.wrap_titles(fig)
    chars = int(fig.get_figwidth() * 72 * ax.get_position().width / (0.55 * ax.title.get_fontsize()))
    lines = ax.get_title().splitlines()
    assert len(lines) >= 3 and lines[-1] == "first 7.26 of 127 input mesh periods"
    assert all(len(line) <= chars for line in lines)
    assert " ".join(" ".join(lines[:-1]).split()) == " ".join(first.replace("\u00a0", " ").split())
    assert len(fig._suptitle.get_text().splitlines()) >= 2


def test_the_planetary_campbell_title_says_what_is_held(lin_parker, tmp_path, monkeypatch):
    """The Campbell diagram's title: the fixed member and the output held in rotation for the
    modes, the input free (today "ring fixed, carrier (output) held", which reads as a
    contradiction)."""
    from jaxgear.cli import planetary

    figs = _capture(monkeypatch, planetary)
    spec = lin_parker.form.spec
    planetary.campbell_section(lin_parker, spec, spec.stage(lin_parker), str(tmp_path / "c.png"))
    (_, ax, _, _), = figs
    title = " ".join(ax.get_title().split())
    assert "the ring (fixed) and the carrier (output) held in rotation, the input free" in title
    assert "(output) held\"" not in title and not title.endswith("(output) held")


def test_run_writes_one_campbell_file(lin_parker):
    """jaxgear run's sweep/ holds no second, identical campbell.png: the run's own is named."""
    assert "campbell.png" not in ps.RUN_SWEEP_FILES and "campbell.png" in ps.SWEEP_FILES


def test_plain_progress_lines_on_a_redirected_stream():
    """On a stream that is not a terminal, nested bars print plain lines: no carriage return,
    no escape code, no blank line; each state once, with its count and estimate."""
    import io

    from jaxgear.cli import progress

    log = io.StringIO()
    outer = progress(total=3, desc="outer", file=log, mininterval=0)
    for k in range(3):
        inner = progress(total=2, desc="inner", file=log, leave=False, position=1, mininterval=0)
        inner.update(2)
        inner.close()
        outer.set_postfix_str(f"stage {k}")
        outer.update()
    outer.close()
    text = log.getvalue()
    assert "\r" not in text and "\x1b" not in text
    lines = text.split("\n")
    assert lines[-1] == "" and all(lines[:-1]), lines
    assert all(line.startswith(("outer:", "inner:")) for line in lines[:-1])
    assert any(re.search(r"outer:.*\|\s*3/3 \[.*stage 2", line) for line in lines)
    assert all(a != b for a, b in itertools.pairwise(lines))  # no state twice


def test_modes_are_numbered_alike_in_the_figures_and_jaxgear_modes():
    """A coincidence with mode index 2 (0-based into the modal analysis, as sweep.json keeps
    it) is named "mode 3" in the figures, the number `jaxgear modes` prints on that mode's row
    (today the figures print "mode 2", one off)."""
    from jaxgear.cli.modes import mode_table

    coincidence_name = plots.coincidence_name

    freqs = [0.0, 1200.0, 2500.0, 4100.0]
    data = {"case": "x", "classification": "c",
            "modes": [{"frequency_Hz": f, "type": "t"} for f in freqs]}
    rows = mode_table(data)
    printed = {float(r.split()[1]): int(r.split()[0]) for r in rows if r.split()[0].isdigit()}
    c = {"mode": 2, "harmonic": 1, "frequency_Hz": 2500.0}
    number = int(re.match(r"mode (\d+) ", coincidence_name(c)).group(1))
    assert number == printed[2500.0] == 3


def _table_summary(te_rms_mod, te_rms_unmod):
    q = {"te_mean_m": 1e-6, "te_ptp_m": 1e-6, "mesh_stiffness_mean_N_per_m": 3e8,
         "max_line_load_N_per_m": 2e5}
    return {
        "case": "x",
        "geometry": {"transverse_contact_ratio": 1.5, "overlap_ratio": 0.0,
                     "center_distance_m": 0.1, "base_pitch_m": 0.004},
        "operating": {"torque_Nm": 310.0},
        "quasi_static": {m: {**q, "te_rms_m": te_rms_mod} for m in ("exact", "smooth")},
        "quasi_static_unmodified": {m: {**q, "te_rms_m": te_rms_unmod}
                                    for m in ("exact", "smooth")},
    }


def test_no_modified_rows_without_modifications():
    """A case without modifications prints its rows once ("no modifications"), not an
    "unmodified" and an identical "modified" pair; a case whose modifications raise the TE RMS
    says by how much (power-helical's: 0.3655/0.1024 = 3.57×)."""
    import jaxgear as jg
    from jaxgear.cli.run import format_table, has_modifications

    assert not has_modifications(jg.Modifications())
    assert has_modifications(jg.Modifications.symmetric(
        jg.MemberModification(tip_relief_depth=10e-6)))
    assert has_modifications(jg.Modifications(gear=jg.MemberModification(crowning_depth=5e-6)))
    weber = jg.Weber()
    rows = format_table(_table_summary(1e-7, 1e-7), weber, modified=False).splitlines()[3:]
    assert [r.split("  ")[0] for r in rows] == ["no modifications exact",
                                                "no modifications smooth"]
    text = format_table(_table_summary(3.6552661e-7, 1.0237222e-7), weber)
    assert "raise the TE RMS 3.57× over the unmodified flanks at 310 N·m" in text
    assert "raise" not in format_table(_table_summary(0.5e-7, 1e-7), weber)


def test_coinciding_stiffness_curves_are_drawn_once_and_named(tmp_path):
    """mesh_stiffness.png: two equal curves are one line whose legend names both (today the
    second, drawn solid on top, hides the first); different curves each their own style."""
    x = np.linspace(0.0, 2.0, 50)
    k = 3e8 + 1e7 * np.sin(2 * np.pi * x)
    labels = plots.mesh_stiffness_plot(tmp_path / "k.png", x, {"a": k, "b": k.copy(),
                                                            "c": 1.2 * k}, title="t")
    assert labels == ["a = b (coincide)", "c"]


def test_the_stiffness_note_and_the_train_figures_name_their_model():
    """What each stiffness curve is (a condensed body's cells leave out its foundation term),
    and flexible-idler's figures name the model they show."""
    from jaxgear.cli.run import LUMPED_STIFFNESS_NOTE, SCENE_STIFFNESS_NOTE
    from jaxgear.cli.train import train_model_words

    assert "leave out its foundation term" in SCENE_STIFFNESS_NOTE
    assert "shafts and bearings are not in it" in LUMPED_STIFFNESS_NOTE
    case = jio.load_case("flexible-idler")
    bodies = [None if n != "idler" else object() for n in case.gear_names]
    assert train_model_words(case, bodies) == "lumped 3D train, idler a condensed FE body"
    assert train_model_words(jio.load_case("accessory-idler-train")).endswith("train")


def test_the_dynamic_pressure_map_explains_its_zero_bands():
    """The map's colour of 0 MPa has a legend entry: no contact at any kept step (a relief's
    zone or contact loss)."""
    import os
    import tempfile

    DYNAMIC_ZERO, load_map_plot = plots.DYNAMIC_ZERO, plots.load_map_plot

    with tempfile.TemporaryDirectory() as d:
        pc = load_map_plot(os.path.join(d, "m.png"), np.linspace(0, 5e-3, 6),
                           np.linspace(0, 1e-2, 3), np.ones((5, 2)) * 1e9, title="t",
                           zero_label=DYNAMIC_ZERO, unit=1e6)
    (leg,) = pc.figure.legends
    assert [t.get_text() for t in leg.get_texts()] == [DYNAMIC_ZERO]
    assert "contact_loss" in DYNAMIC_ZERO


# -- the 3D planetary mesh's tilting stiffness ------------------------------------------------

BETA_B = np.radians(28.5)
FACE = 0.03  # m
K_S, K_R = 5e8, 6e8  # N/m along the tooth normal


def _spatial_stage(**tilts):
    import jaxgear as jg

    lumped = jp.PlanetaryMember.lumped
    return jp.PlanetaryStage(
        sun=lumped(0.4, 0.39, 0.0387, 1e8), ring=lumped(2.35, 3.0, 0.1375, 1e8, 1e9),
        carrier=lumped(5.43, 6.29, 0.0884, 1e8), planet=lumped(0.66, 0.61, 0.05015, 1e8),
        planet_angles=np.radians([0.0, 100.0, 230.0]), sun_pressure_angle=np.radians(24.6),
        ring_pressure_angle=np.radians(22.0), sun_mesh_stiffness=K_S, ring_mesh_stiffness=K_R,
        helix_angle=BETA_B, face_width=FACE, **tilts)


def _tilt_entry(stage, member):
    """K's entry on ``member``'s (``"s"`` sun, ``"r"`` ring) tilt about x."""
    import jaxgear as jg

    model = jp.SpatialPlanetary()
    i = model.dof_names(stage).index(f"theta_x_{member}")
    return float(np.asarray(model.stiffness_matrix(stage))[i, i])


@pytest.mark.parametrize("member", ["s", "r"])
def test_the_mesh_tilting_stiffness_is_k_b2_cos2_beta_over_12(member):
    """The tilting stiffness a mesh adds to its central member's tilt about x, written here:
    a tilt theta about e_perp = d x e_z (d the transverse line of action (-sin φ, cos φ, 0),
    φ = ψ_n − α_s for a sun mesh, ψ_n + α_r for a ring mesh) moves the face point z by
    z cos β_b theta along the tooth normal, so over the face (k/b) ∫ (z cos β_b)² dz =
    k b² cos²β_b / 12 per unit theta_perp², and theta_perp = theta_x cos φ. Removing it
    (kappa = 0) lowers K_xx by Σ_n k b² cos²β_b/12 cos²φ_n (the docs said k b²/12: 1/cos²β_b
    = 1.30× that at 28.5°); a given kappa replaces it: K_xx(kappa) − K_xx(0) = Σ_n kappa
    cos²φ_n."""
    psi = np.radians([0.0, 100.0, 230.0])
    phi = psi - np.radians(24.6) if member == "s" else psi + np.radians(22.0)
    k = K_S if member == "s" else K_R
    key = "sun_mesh_tilt_stiffness" if member == "s" else "ring_mesh_tilt_stiffness"
    spread = _tilt_entry(_spatial_stage(), member)
    none = _tilt_entry(_spatial_stage(**{key: 0.0}), member)
    expected = k * FACE**2 * np.cos(BETA_B) ** 2 / 12 * np.sum(np.cos(phi) ** 2)
    assert spread - none == pytest.approx(expected, rel=1e-9)
    kappa = 2.0e4  # N m/rad
    given = _tilt_entry(_spatial_stage(**{key: kappa}), member)
    assert given - none == pytest.approx(kappa * np.sum(np.cos(phi) ** 2), rel=1e-9)


def test_the_mesh_tilting_stiffness_from_a_case_file(tmp_path):
    """[planetary] sun_/ring_mesh_tilt_stiffness_Nm_per_rad reach the stage (N·m/rad); a
    negative value is refused in one line naming the key."""
    data = tomllib.loads(jio.embedded_case_text("lin-parker-1999"))
    data["planetary"].update(sun_mesh_tilt_stiffness_Nm_per_rad=2.0e4,
                             ring_mesh_tilt_stiffness_Nm_per_rad=3.0e4)
    case = jio.parse_train(data)
    stage = case.form.spec.stage(case)
    assert float(stage.sun_mesh_tilt_stiffness) == 2.0e4
    assert float(stage.ring_mesh_tilt_stiffness) == 3.0e4
    data["planetary"]["ring_mesh_tilt_stiffness_Nm_per_rad"] = -1.0
    with pytest.raises(ValueError, match="ring_mesh_tilt_stiffness_Nm_per_rad.*-1.*allowed"):
        jio.parse_train(data)
    plain = jio.load_case("lin-parker-1999")
    assert plain.form.spec.stage(plain).sun_mesh_tilt_stiffness is None


def test_the_lumped_springs_hold_the_given_tilting_stiffness():
    """ConstantMeshes' two springs per mesh (the sweep's, the load sharing's) sit at the same
    points as the matrix's: the cells' stiffness Σ k_c V_c V_cᵀ equals the mesh part of
    SpatialPlanetary's K (K less its bearings and pins: K with zero mesh stiffness)."""
    import dataclasses

    import jaxgear as jg

    model = jp.SpatialPlanetary()
    stage = _spatial_stage(sun_mesh_tilt_stiffness=2.0e4, ring_mesh_tilt_stiffness=3.0e4)
    meshes = jp.ConstantMeshes(0.01, face_points=model.face_points)
    zero = (np.zeros(3), np.zeros(3))
    row = meshes.cell_row(model, stage, 0.0, zero)
    V, k = np.asarray(row.V), np.asarray(row.k * row.length)
    cells = np.einsum("ci,c,cj->ij", V, k, V)
    bare = dataclasses.replace(stage, sun_mesh_stiffness=0.0, ring_mesh_stiffness=0.0)
    mesh_part = np.asarray(model.stiffness_matrix(stage)) - np.asarray(
        model.stiffness_matrix(bare))
    np.testing.assert_allclose(cells, mesh_part, atol=1e-9 * np.abs(mesh_part).max())


def test_the_torsional_models_conventions():
    """What TorsionalPlanetary's docstring and docs/planetary.md say, against numbers written
    here: the carrier's mass on u_c is I_c/r_c² + N m_p (the planets' mass rides on it), and
    the carrier enters the sun and ring meshes as −u_c cos α_s and −u_c cos α_r."""
    import jaxgear as jg

    stage = _spatial_stage()
    model = jp.TorsionalPlanetary()
    m = np.asarray(model.mass_matrix(stage))
    assert m[0, 0] == pytest.approx(6.29 + 3 * 0.66, rel=1e-12)  # I_c/r_c² + N m_p
    assert m[3, 3] == pytest.approx(0.61, rel=1e-12)  # a planet: I_p/r_p² alone
    v_s, v_r = (np.asarray(v) for v in model.mesh_deflection_rows(stage))
    np.testing.assert_allclose(v_s[:, 0], -np.cos(np.radians(24.6)), rtol=1e-12)
    np.testing.assert_allclose(v_r[:, 0], -np.cos(np.radians(22.0)), rtol=1e-12)
    np.testing.assert_allclose(v_s[:, 2], 1.0)  # u_s
    np.testing.assert_allclose(v_s[:, 3:], np.eye(3))  # + u_n
    np.testing.assert_allclose(v_r[:, 1], 1.0)  # u_r
    np.testing.assert_allclose(v_r[:, 3:], -np.eye(3))  # − u_n


# -- the documentation's references ------------------------------------------------------------


def test_the_api_pages_are_grouped_by_task():
    """The API pages: a section per task (geometry, stiffness, quasi-statics on the jaxgear
    page; stage and model kinds on the planetary one; the rating on the rating one), every public
    name in exactly one, none left to "Other" in the six model packages; quasi_static under
    "Contact and quasi-statics", among the first third of the page's names (today #32 of 98,
    after the private modules' import order); a subpackage's names on its own page, not the top
    level's (PlanetaryStage, rate)."""
    from docs._gen import api_pages

    for module in ("jaxgear", "jaxgear.scenes", "jaxgear.dynamics", "jaxgear.planetary",
                   "jaxgear.io", "optimise"):
        names, _ = api_pages.public_names(module)
        groups = api_pages.sections(module, names)
        assert "Other" not in [t for t, _ in groups], module
        flat = [n for _, g in groups for n in g]
        assert sorted(flat) == sorted(names) and len(flat) == len(set(flat)), module
    names, _ = api_pages.public_names("jaxgear")
    groups = dict(api_pages.sections("jaxgear", names))
    assert "quasi_static" in groups["Contact and quasi-statics"]
    assert "GearPair" in groups["Geometry"]
    assert "PlanetaryStage" not in names and "rate" not in names
    order = [n for g in groups.values() for n in g]
    assert order.index("quasi_static") < len(order) / 3
    text = api_pages.page("jaxgear", "the model")
    assert "## Geometry" in text and "## Planetary stages" not in text
    assert text.index("## Contact and quasi-statics") < text.index("::: jaxgear.quasi_static")
    planetary = dict(api_pages.sections("jaxgear.planetary",
                                        api_pages.public_names("jaxgear.planetary")[0]))
    assert "PlanetaryStage" in planetary["Stage and model kinds"]
    rating = dict(api_pages.sections("jaxgear.rating", api_pages.public_names("jaxgear.rating")[0]))
    assert "rate" in rating["Rating"]
    assert "::: jaxgear.rating.rate" in api_pages.page("jaxgear.rating", "load capacity")


def test_the_case_file_reference_shows_the_optimise_defaults():
    """[optimise] in the case-file reference: its keys with defaults show them (objective
    'te_rms', method 'lbfgs', reduce 'max', max_iterations 100, lp_order 8), none of them
    "required" (every one is optional); the defaults are the ones jaxgear optimise takes."""
    from docs._gen import schema_reference
    from jaxgear.cli import settings_from_case

    text = schema_reference.pages()["case-file.md"]
    table = text.split("## `[optimise]`", 1)[1].split("\n## ", 1)[0]
    rows = {r.split("|")[1].strip(" `"): [c.strip() for c in r.split("|")[2:-1]]
            for r in table.splitlines() if r.startswith("| `")}
    assert not [k for k, r in rows.items() if "required" in r], rows
    assert rows["objective"][2] == "'te_rms'" and rows["method"][2] == "'lbfgs'"
    assert rows["reduce"][2] == "'max'" and rows["max_iterations"][2] == "100"
    assert rows["lp_order"][2] == "8"
    settings = settings_from_case(jio.load_case("power-helical"))
    case_table = jio.load_case("power-helical").optimise or {}
    for key in ("objective", "method", "reduce", "max_iterations"):
        if key not in case_table:
            assert repr(settings[key]) == rows[key][2] or str(settings[key]) == rows[key][2]


def test_modes_table_says_where_it_merges_repeated_modes():
    """Two modes of one type at one frequency (a symmetric train's repeated mode) share a row
    numbered with both (3-4, × 2) and the table says so under it; a planetary pair whose rows
    carry their multiplicity reads the same; distinct modes keep their own numbers."""
    from jaxgear.cli.modes import mode_table

    rows = [{"frequency_Hz": f, "type": t} for f, t in
            [(0.0, "rigid"), (900.0, "torsional"), (1500.0, "bending"), (1500.0, "bending"),
             (1500.0, "axial"), (2100.0, "bending")]]
    table = mode_table({"case": "x", "classification": "c", "modes": rows})
    body = [r.split() for r in table[2:] if r.split()[0][0].isdigit()]
    assert [b[0] for b in body] == ["1", "2", "3-4", "5", "6"]
    assert body[2] == ["3-4", "1500", "bending", "×", "2"]
    assert "repeated or degenerate" in table[-1]
    # a planetary stage's degenerate pair (each row says multiplicity 2)
    pair = [{"frequency_Hz": 700.0, "type": "translational", "multiplicity": 2}] * 2
    table = mode_table({"case": "p", "classification": "c", "planar": pair})
    assert any(r.split()[0] == "1-2" and r.endswith("translational × 2") for r in table)
    # nothing merged: no note
    table = mode_table({"case": "x", "classification": "c", "modes": rows[:3]})
    assert "repeated" not in table[-1]
