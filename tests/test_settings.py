"""Settings as objects: the contact law, the integrator and the steady-state window are checked
when they are made (one-line ValueErrors naming the setting, its value and the allowed range),
and the solvers refuse anything else with a line naming the argument (the former keyword API
included)."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import pytest

import jaxgear as jg
import jaxgear.io as jio
from jaxgear.dynamics import (
    DiffraxIntegrator,
    Newmark,
    SteadyState,
    dynamic_model,
    simulate,
    speed_sweep,
)
from jaxgear.scenes import TorsionalDynamics, disc_inertia


@pytest.mark.parametrize(
    "make, match",
    [
        (
            lambda: jg.ExactContact(0),
            r"max_iterations = 0 is out of range: allowed an integer >= 1",
        ),
        (lambda: jg.ExactContact(2.5), r"max_iterations = 2.5"),
        (
            lambda: jg.ExactContact("ten"),
            r"max_iterations = 'ten' is out of range: allowed an integer >= 1",
        ),
        (
            lambda: jg.ExactContact(None),
            r"max_iterations = None is out of range: allowed an integer >= 1",
        ),
        (lambda: jg.SmoothContact(0.0), r"width = 0.0 m: allowed a finite width > 0"),
        (lambda: jg.SmoothContact(float("nan")), r"width = nan m"),
        (lambda: jg.SmoothContact(1e-7, True), r"max_iterations = True"),
        (lambda: Newmark(3), r"steps_per_period = 3 is out of range: allowed an integer >= 4"),
        (lambda: DiffraxIntegrator("rk4"), r"solver = 'rk4': allowed a diffrax solver name"),
        (lambda: DiffraxIntegrator(rtol=0.0), r"rtol = 0.0: allowed a tolerance > 0"),
        (lambda: DiffraxIntegrator(adjoint="both"), r"adjoint = 'both'"),
        (lambda: SteadyState(1, 1), r"periods = 1 is out of range: allowed an integer >= 2"),
        (lambda: SteadyState(4, 5), r"keep_periods = 5 must be <= periods = 4"),
        (lambda: SteadyState(4, 0), r"keep_periods = 0 is out of range"),
    ],
)
def test_bad_settings_are_one_line_errors_when_made(make, match):
    with pytest.raises(ValueError, match=match) as err:
        make()
    assert "\n" not in str(err.value)


def test_a_traced_width_is_a_leaf_and_differentiable():
    """The width is traced (no recompilation per width) and the TE RMS has a derivative in it
    that matches a central difference."""
    case = jio.load_case("accessory-spur")
    mesh = case.mesh_model(slices=3)

    def rms(w):
        law = jg.SmoothContact(w)
        return jg.quasi_static(mesh, None, case.torque, contact=law, positions_per_pitch=8).te_rms

    w0, h = 2e-7, 1e-9
    # the gradient and the differences' values from one compiled program; the width traced
    value_and_grad = jax.jit(jax.value_and_grad(rms))
    g = float(value_and_grad(jnp.asarray(w0))[1])
    up, down = (float(value_and_grad(jnp.asarray(w0 + d))[0]) for d in (h, -h))
    fd = (up - down) / (2 * h)
    assert g == pytest.approx(fd, rel=1e-4)


def test_the_solvers_refuse_what_is_not_a_setting():
    case = jio.load_case("accessory-spur").replace(slices=2)
    mesh = case.mesh_model()
    with pytest.raises(ValueError, match=r"contact = 'smooth': allowed jaxgear.ExactContact"):
        jg.quasi_static(mesh, None, case.torque, contact="smooth")
    p = case.pair
    scene = TorsionalDynamics(
        mesh,
        disc_inertia(case.density, p.tip_radii[0], p.pinion.face_width),
        disc_inertia(case.density, p.tip_radii[1], p.gear.face_width),
    ).reduced()
    model = dynamic_model(scene, None, case.torque, positions_per_pitch=16)
    with pytest.raises(ValueError, match=r"integrator = 'newmark': allowed"):
        simulate(model, 500.0, integrator="newmark")
    with pytest.raises(ValueError, match=r"window = 60: allowed jaxgear.dynamics.SteadyState"):
        speed_sweep(model, [500.0, 600.0], window=60)
    # the lumped dynamics compare the last two kept periods
    with pytest.raises(ValueError, match=r"keep_periods = 1 is out of range: allowed an integer"):
        simulate(model, 500.0, integrator=Newmark(16), window=SteadyState(4, 1))
    assert jio.Case.contact_law(case, "smooth") == jg.SmoothContact(case.smooth_width)
    with pytest.raises(ValueError, match="contact = 'penalty'"):
        case.contact_law("penalty")
