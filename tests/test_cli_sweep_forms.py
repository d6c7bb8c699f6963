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
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np
import pytest
import test_planetary_sweep as small

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.planetary as jp
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
