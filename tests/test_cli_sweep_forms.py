"""``jaxgear sweep`` is one command for every case form (jaxgear/cli/sweep.py): the case's
dynamic model (:func:`jaxgear.io.build_dynamic_model`) swept by
:func:`jaxgear.dynamics.speed_sweep` with the pairs' options, what the model cannot run refused
in one line at load by asking its contract, the outputs written by the form.

A planetary stage: a solver its model refuses is refused naming the option and the solvers its
contract accepts; the contact law given reaches the stage's runs (the sweep's dynamic factors
equal :func:`jaxgear.planetary.planetary_dynamics` with that law on the stage written by hand,
and differ from the exact law's). The planetary sweep's whole output through this path against
the record made by the planetary stage's own command before it was folded in:
tests/test_regression.py ``sweep-example-planetary-hunting`` (slow).

A gearbox (``[[stages]]``): its coupled model (a :class:`jaxgear.gearbox.GearboxModel`) refuses
a diffrax solver and a continuation the same way; its sweep's per-mesh dynamic factors equal
:func:`jaxgear.gearbox.gearbox_speed_sweep` at the same plan as recorded before the gearbox
became a dynamics model, to 1e-9 (slow).
"""

from __future__ import annotations

import json
import pathlib

import jax.numpy as jnp
import numpy as np
import pytest
import test_planetary_sweep as small

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.planetary as jp
from jaxgear import gearbox as gb
from jaxgear.cli import main, sweep as cli_sweep

# the lumped runs check definitions on a few coarse steps: under-resolved on purpose
pytestmark = [pytest.mark.filterwarnings("ignore:.*time step under-resolved"),
              pytest.mark.filterwarnings("ignore:.*not settled")]


def _one_line_refusal(capsys, argv, out) -> str:
    assert main([*argv, "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert not out.exists()
    return err[0]


def test_a_planetary_sweep_refuses_a_solver_in_one_line(tmp_path, capsys):
    """``--solver tsit5`` on a planetary stage: its model (a PlanetaryModel) runs Newmark only
    (its ``check_integrator``); the refusal names the option, its value and the solvers the
    model accepts, before any file."""
    argv = ["sweep", "lin-parker-1999", "--speeds", "150:900:2", "--solver", "tsit5"]
    err = _one_line_refusal(capsys, argv, tmp_path / "out")
    assert err.endswith("--solver = tsit5: a PlanetaryModel does not run it (allowed: newmark)"), err
    # the model's own contract says so (the cli does not know it)
    model, _ = jio.build_dynamic_model(jio.load_case("lin-parker-1999"))
    with pytest.raises(ValueError, match="Newmark"):
        model.check_integrator(jio.spec_integrator(jio.SceneSpec(solver="tsit5")))


def test_a_planetary_sweep_refuses_a_vtu_speed_in_one_line(tmp_path, capsys):
    argv = ["sweep", "lin-parker-1999", "--speeds", "150:900:2", "--vtu-speed", "300"]
    err = _one_line_refusal(capsys, argv, tmp_path / "out")
    assert "--vtu-speed = 300.0: a PlanetaryModel has no condensed body" in err, err


# the stage on its contact cells compiles two Newmark loops (the sweep, the runs of the kernel
# with each law): about 20 s of CPU; the fast twins of the path: the refusals above (the
# dispatch and the contract)
@pytest.mark.slow
def test_the_contact_law_given_reaches_a_planetary_sweep(tmp_path, no_figures):
    """``--contact smooth`` on tests/test_planetary_sweep.py's small stage (19/17/-53, its
    contact cells, a 10 um pin error): each mesh's dynamic factor of the common path
    (check_sweep, sweep_files) equals the stage kernel planetary_dynamics called here with the
    smooth law of the case's width (on the case's stage, meshes and ring, at the carrier and
    mesh speeds of Willis written here, 24 steps, 6 periods, 2 kept), to 1e-12; the exact
    law's differ (the law is not dropped on the way)."""
    case = jio.load_case(str(_small_case(tmp_path)))
    opts = dict(small.RUN, contact="smooth")
    cli_sweep.check_sweep(case.form, case, **opts)
    s = cli_sweep.sweep_files(case.form, case, small.SPEEDS, str(tmp_path), **opts)
    assert s["contact"] == "SmoothContact"
    model, _ = jio.build_dynamic_model(case)
    base = model.run
    run = jp.PlanetaryRun(base.sun_torque, damping_ratio=base.damping_ratio,
                          tangential_pin_errors=base.tangential_pin_errors,
                          radial_pin_errors=base.radial_pin_errors, **small.RUN)
    _, _, _, r_r = small._by_hand(case)

    def factors(law):
        out = []
        for w in small.SPEEDS:  # ring fixed, carrier in: Omega = w, v = r_br w
            d = jp.planetary_dynamics(model.kind, model.stage, model.meshes, run,
                                      jnp.asarray(w), jnp.asarray(r_r * w), law, model.ring)
            out.append(np.concatenate([np.asarray(x) for x in d.dynamic_factors]))
        return np.array(out)

    smooth = factors(jg.SmoothContact(case.smooth_width, 100))
    np.testing.assert_allclose(s["dynamic_factor_mesh"], smooth, rtol=1e-12)
    assert np.max(np.abs(smooth - factors(jg.ExactContact()))) > 1e-4
    assert s["result"] == [0, 0]


def _small_case(folder):
    path = folder / "small-stage.toml"
    path.write_text(small.CASE)
    return path


# -- a gearbox: the two-stage gearbox case file of docs/gearbox.md ---------------------------

GEARBOX = str(pathlib.Path(__file__).parent / "data" / "gearbox" / "two-stage-gearbox.toml")


@pytest.mark.parametrize(
    ("extra", "words"),
    [(["--solver", "tsit5"],
      "--solver = tsit5: a GearboxModel does not run it (allowed: newmark)"),
     (["--direction", "both"],
      "--direction = both: a GearboxModel sweeps independent speeds only (allowed: independent)"),
     (["--vtu-speed", "80"], "--vtu-speed = 80.0: a GearboxModel has no condensed body"),
     # a block is the planetary meshes' period, two of the pair's (docs/gearbox.md): 128
     # steps at 64 per pair period; 2^22 / 128 = 32768 blocks at most
     (["--periods", "40000"],
      "--periods = 40000: out of range, allowed <= 32768 blocks of 128 steps")],
    ids=["solver", "direction", "vtu", "periods"],
)
def test_a_gearbox_sweep_refuses_what_its_model_cannot_run(tmp_path, capsys, extra, words):
    argv = ["sweep", GEARBOX, "--speeds", "60:120:2", *extra]
    err = _one_line_refusal(capsys, argv, tmp_path / "out")
    assert words in err, err


# the coupled run's compilation (nine meshes' contact cells in one Newmark loop) takes about a
# minute of CPU on the loaded machine; the fast twin: the refusals above (the dispatch, the
# model from the case, its contract)
@pytest.mark.slow
def test_a_gearbox_sweep_is_the_coupled_sweep_at_the_same_plan(tmp_path, capsys):
    """``jaxgear sweep`` on the two-stage gearbox (planetary 20/30/-80, carrier in; the spur
    pair its sun drives through a 5e5 N m/rad shaft, which also holds the output) at two input
    speeds, 32 steps per period of the fastest excited mesh, 4 blocks, 2 kept: every mesh's
    dynamic factor in sweep.json equals jaxgear.gearbox.gearbox_speed_sweep of the case's
    coupled chain at the same plan (its torque, the output hold, K_m over 32 positions) as
    recorded before the gearbox became a dynamics model (its own Newmark loop:
    tests/data/gearbox/two_stage_sweep_reference.json, record_two_stage_sweep.py), to 1e-9;
    the meshes named by mesh_names, the worst mesh per speed, the files written."""
    ref = json.loads((pathlib.Path(GEARBOX).parent / "two_stage_sweep_reference.json")
                     .read_text(encoding="utf-8"))
    plan = ref["plan"]
    out = tmp_path / "out"
    w = ref["input_speeds_rad_s"]
    argv = ["sweep", GEARBOX, "--speeds", f"{w[0]}:{w[1]}:2", "--steps-per-period",
            str(plan["steps_per_period"]), "--periods", str(plan["periods"]), "--keep-periods",
            str(plan["keep_periods"]), "--out", str(out), "--quiet"]
    assert main(argv) == 0
    assert "two-stage-gearbox: 2 input speeds, 9 meshes" in capsys.readouterr().out
    s = json.loads((out / "sweep.json").read_text())
    assert {p.name for p in out.iterdir()} >= {"sweep.json", "sweep.csv", "dynamic_factor.png"}
    model, _ = jio.build_dynamic_model(jio.load_case(GEARBOX))
    assert model.run.mean_positions == plan["mean_positions"]  # the record's K_m
    assert float(model.run.input_torque) == ref["input_torque_Nm"]
    assert float(model.run.output_stiffness) == ref["output_hold_Nm_per_rad"]
    assert s["speeds_rad_s"] == w and s["mesh_names"] == ref["mesh_names"]
    assert s["mesh_names"] == list(gb.mesh_names(model.chain))
    np.testing.assert_allclose(s["dynamic_factor_mesh"], ref["dynamic_factors"], rtol=1e-9)
    np.testing.assert_allclose(s["dynamic_factor"], np.max(ref["dynamic_factors"], axis=1),
                               rtol=1e-9)
    np.testing.assert_allclose(s["static_force_N"], ref["static_forces_N"][0], rtol=1e-9)
    assert s["result"] == ref["result"] and s["steps_integrated"] == ref["steps"][0]
    header = (out / "sweep.csv").read_text().splitlines()[0].split(",")
    assert "dynamic_factor_mesh_2_pair" in header, header
