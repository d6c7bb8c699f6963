"""Gradients of the TE RMS through the contact solver vs central finite differences (float64).

Objective: TE RMS in µm (O(1)) of the power-helical pair (Weber stiffness, symmetric linear tip
relief, lead crowning), as a function of p = (relief depth in µm, relief extent Γ, crowning depth
in µm). Smooth mode is differentiable everywhere; exact mode is differentiated with the active
set (and the argmax of e) held, valid away from the parameter values where a cell enters or
leaves contact; the finite-difference steps used here are checked not to cross such a kink.
"""

import functools

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from jax.test_util import check_grads

import jaxgear as jg
import jaxgear.io as jio

P0 = np.array([10.0, 0.2, 5.0])  # tip relief depth (µm), extent Γ, crowning depth (µm)
# central-difference steps, same units; the depth's is half the theoretical path's 1e-3: the
# corner cells' smooth contact beyond the path (the case files' default) curves TE RMS more
STEPS = np.array([5e-4, 1e-5, 1e-3])


@functools.cache
def _setup():
    case = jio.load_case("power-helical")
    mesh = case.mesh_model(slices=8)
    return case, mesh, jg.mesh_positions(mesh, 16)


def _te_rms_um(p, contact, setup):
    case, mesh, theta = setup
    mm = jg.MemberModification(
        tip_relief_depth=p[0] * 1e-6, tip_relief_extent=p[1], crowning_depth=p[2] * 1e-6
    )
    res = jg.quasi_static(
        mesh,
        jg.Modifications.symmetric(mm),
        case.torque,
        theta,
        contact=case.contact_law(contact),
    )
    return res.te_rms * 1e6


@functools.cache
def _jitted(contact):
    # build the mesh eagerly: a cached object created while tracing would hold tracers
    f = jax.jit(functools.partial(_te_rms_um, contact=contact, setup=_setup()))
    return f, jax.jit(jax.grad(f))


def _central(f, p, i, h):
    e = np.zeros(3)
    e[i] = h
    return (float(f(jnp.asarray(p + e))) - float(f(jnp.asarray(p - e)))) / (2 * h)


# default tier for "exact": the "smooth" case here (the same claim, another contact law); the
# exact law's derivatives in default: tests/test_optimise_speed.py's exact-contact Jacobian
@pytest.mark.parametrize("contact", ["smooth", pytest.param("exact", marks=pytest.mark.slow)])
def test_grad_te_rms_matches_central_differences(contact):
    f, grad = _jitted(contact)
    g = np.asarray(grad(jnp.asarray(P0)))
    assert np.all(np.isfinite(g))
    # the design point is generic: every parameter matters
    assert np.all(np.abs(g) > 1e-3)
    for i, (name, h) in enumerate(zip(("depth", "extent", "crowning"), STEPS)):
        fd = _central(f, P0, i, h)
        fd_half = _central(f, P0, i, h / 2)
        # Richardson check: both steps agree (no kink crossed, truncation negligible)
        assert fd_half == pytest.approx(fd, rel=2e-7), name
        assert g[i] == pytest.approx(fd, rel=1e-5), name


def test_check_grads_smooth_fwd_and_rev():
    f, _ = _jitted("smooth")
    check_grads(f, (jnp.asarray(P0),), order=1, modes=["fwd", "rev"], eps=1e-4)


def test_grad_wrt_torque_smooth():
    """d(TE mean)/dT by autodiff vs central differences: the mesh compliance at the operating point."""
    case, mesh, theta = _setup()

    def te_mean_um(torque):
        return (
            jg.quasi_static(
                mesh, case.modifications, torque, theta, contact=case.contact_law("smooth")
            ).te_mean
            * 1e6
        )

    f = jax.jit(te_mean_um)
    t0, h = case.torque, 1e-2
    g = float(jax.jit(jax.grad(te_mean_um))(jnp.asarray(t0)))
    fd = (float(f(jnp.asarray(t0 + h))) - float(f(jnp.asarray(t0 - h)))) / (2 * h)
    assert g > 0  # TE grows with load
    assert g == pytest.approx(fd, rel=1e-6)


# default tier: tests/test_gradients.py::test_hessian_matches_finite_differences_of_the_gradient
# (the same second derivatives through the smooth contact, fwd-over-rev, against differences)
@pytest.mark.slow
def test_check_grads_smooth_second_order_fwd_and_rev():
    """Second derivatives of TE RMS (relief depth, extent, crowning) through the smooth contact:
    the implicit-function derivatives (jax.lax.custom_root) are exact at every order."""
    f, _ = _jitted("smooth")
    check_grads(f, (jnp.asarray(P0),), order=2, modes=["fwd", "rev"], eps=1e-4)


def test_hessian_matches_finite_differences_of_the_gradient():
    """Autodiff Hessian vs central differences of the autodiff gradient (the issue's reproducer:
    a stopped Jacobian in the implicit step gave H[0,1] of the wrong sign)."""
    f, grad = _jitted("smooth")
    H = np.asarray(jax.jit(jax.hessian(f))(jnp.asarray(P0)))
    for j, h in enumerate(STEPS):
        e = np.zeros(3)
        e[j] = h
        col = (np.asarray(grad(jnp.asarray(P0 + e))) - np.asarray(grad(jnp.asarray(P0 - e)))) / (
            2 * h
        )
        np.testing.assert_allclose(H[:, j], col, rtol=2e-4, atol=1e-6 * np.abs(H).max())
    np.testing.assert_allclose(H, H.T, rtol=1e-8, atol=1e-10 * np.abs(H).max())


def test_te_rms_gradient_is_finite_at_zero_fluctuation():
    """One position (or a perfect relief): TE RMS = 0 and its gradient is finite (0), not NaN."""
    case, mesh, _ = _setup()

    def rms(depth):
        mm = jg.MemberModification(tip_relief_depth=depth, tip_relief_extent=0.2)
        return jg.quasi_static(
            mesh,
            jg.Modifications.symmetric(mm),
            case.torque,
            jnp.zeros(1),
            contact=jg.SmoothContact(),
        ).te_rms

    value, g = jax.jit(jax.value_and_grad(rms))(jnp.asarray(5e-6))  # one compiled program
    assert float(value) == 0.0
    assert np.isfinite(float(g))
