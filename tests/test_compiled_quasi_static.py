"""``jaxgear.compile_quasi_static``: the same curves as ``quasi_static``, differentiable, and
one-line errors for bad input."""

import subprocess
import sys

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.io as jio

P = 16  # positions per pitch: a short curve keeps the compilations small


@pytest.fixture(scope="module")
def setup():
    c = jio.load_case("accessory-spur")
    mesh = c.mesh_model(slices=10)
    return mesh, c.modifications, float(c.torque)


@pytest.fixture(scope="module")
def compiled(setup):
    mesh, mods, _ = setup
    return jg.compile_quasi_static(mesh, mods, positions_per_pitch=P)


def _rel(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


def test_equals_quasi_static_for_other_designs_and_torques(setup, compiled):
    mesh, mods, torque = setup
    tip = jg.MemberModification(tip_relief_depth=22e-6, tip_relief_extent=0.31)
    other = jg.Modifications(pinion=tip, gear=mods.gear)
    for m, t in ((mods, torque), (other, 0.6 * torque)):
        ref = jg.quasi_static(mesh, m, t, positions_per_pitch=P)
        got = compiled(compiled.design_vector(m), t)
        for name in ("transmission_error", "mesh_stiffness", "contact_length", "line_load"):
            assert _rel(getattr(got, name), getattr(ref, name)) < 1e-12, name
        # the Modifications object itself is accepted too
        assert _rel(compiled(m, t).transmission_error, ref.transmission_error) < 1e-12
    # design_vector and modifications are inverse maps
    x = compiled.design_vector(other)
    np.testing.assert_array_equal(compiled.design_vector(compiled.modifications(x)), x)
    np.testing.assert_array_equal(compiled.design_vector(mods), compiled.design0)


@pytest.fixture(scope="module")
def coarse_rms(setup):
    """TE RMS of a coarse curve (8 positions): the derivative programs are the largest
    compilations here."""
    mesh, mods, _ = setup
    return jg.compile_quasi_static(mesh, mods, positions_per_pitch=8, output=lambda r: r.te_rms)


def _central(f, x0, torque, k, rel=1e-6):
    """Central differences of ``f`` in design entry ``k`` (``k = None``: the torque)."""
    if k is None:
        h = rel * torque
        return (f(x0, torque + h) - f(x0, torque - h)) / (2 * h)
    h = rel * max(abs(float(x0[k])), 1e-6)
    e = jnp.zeros_like(x0).at[k].set(h)
    return (f(x0 + e, torque) - f(x0 - e, torque)) / (2 * h)


def test_forward_derivative_matches_finite_differences(setup, coarse_rms):
    """Forward mode (``jax.jvp``) through the compiled solve, in a design direction and in the
    torque, against central differences of the compiled call."""
    _, _, torque = setup
    f, x0 = coarse_rms, coarse_rms.design0
    k = 0  # the pinion's tip-relief depth: the TE RMS depends on it
    v = jnp.zeros_like(x0).at[k].set(1.0)
    _, dx = jax.jvp(f, (x0, jnp.asarray(torque)), (v, jnp.asarray(0.0)))
    _, dt = jax.jvp(f, (x0, jnp.asarray(torque)), (jnp.zeros_like(x0), jnp.asarray(1.0)))
    fd_x, fd_t = _central(f, x0, torque, k), _central(f, x0, torque, None, 1e-4)
    assert abs(float(fd_x)) > 0 and abs(float(dx) - float(fd_x)) < 1e-5 * abs(float(fd_x))
    assert abs(float(dt) - float(fd_t)) < 1e-5 * abs(float(fd_t))


@pytest.mark.slow
def test_gradient_matches_finite_differences(setup, coarse_rms):
    """Reverse mode (``jax.grad``, what an optimiser calls; a 6 s compilation: the forward
    test above checks the same derivatives fast) against central differences."""
    _, _, torque = setup
    f, x0 = coarse_rms, coarse_rms.design0
    gx, gt = jax.grad(f, argnums=(0, 1))(x0, jnp.asarray(torque))
    k = int(np.argmax(np.abs(np.asarray(gx))))  # the most sensitive design entry
    fd_x, fd_t = _central(f, x0, torque, k), _central(f, x0, torque, None, 1e-4)
    assert abs(float(gx[k]) - float(fd_x)) < 1e-5 * abs(float(fd_x))
    assert abs(float(gt) - float(fd_t)) < 1e-5 * abs(float(fd_t))


def test_output_and_vmap(setup):
    mesh, mods, torque = setup
    f = jg.compile_quasi_static(mesh, mods, positions_per_pitch=P, output=lambda r: r.te_rms)
    ts = jnp.asarray([0.5, 1.0, 1.5]) * torque
    batch = jax.vmap(lambda t: f(f.design0, t))(ts)
    for t, got in zip(ts, batch, strict=True):
        ref = jg.quasi_static(mesh, mods, float(t), positions_per_pitch=P).te_rms
        assert abs(float(got) - float(ref)) < 1e-12 * float(ref)


def test_bad_input_is_refused_in_one_line(setup, compiled):
    mesh, mods, torque = setup
    with pytest.raises(ValueError, match=r"torque = -3.*allowed > 0"):
        compiled(compiled.design0, -3.0)
    with pytest.raises(ValueError, match=r"torque = nan"):
        compiled(compiled.design0, float("nan"))
    with pytest.raises(ValueError, match=rf"design has shape \(3,\): allowed \({compiled.size},\)"):
        compiled(jnp.zeros(3), torque)
    with pytest.raises(ValueError, match="another structure than the template"):
        compiled((mods,), torque)  # a tuple of one per mesh: not the template's structure
    with pytest.raises(ValueError, match="output = 3"):
        jg.compile_quasi_static(mesh, mods, output=3)
    with pytest.raises(ValueError, match="scene"):
        jg.compile_quasi_static("mesh", mods)
    with pytest.raises(ValueError, match="positions_per_pitch"):
        jg.compile_quasi_static(mesh, mods, positions_per_pitch=0)


def test_free_leaves_are_the_design_and_the_others_fixed(setup):
    """``with_free``: the design vector is the named leaves only; a call equals ``quasi_static`` of
    the template with those leaves replaced by hand; a change in a fixed leaf is refused."""
    mesh, mods, torque = setup
    f = jg.compile_quasi_static(
        mesh, mods, positions_per_pitch=P, output=lambda r: r.transmission_error
    ).with_free(lambda m: (m.pinion.tip_relief_depth, m.pinion.tip_relief_extent))
    assert f.design0.shape == (2,)
    np.testing.assert_array_equal(
        f.design0, [mods.pinion.tip_relief_depth, mods.pinion.tip_relief_extent]
    )
    pinion = jg.MemberModification(
        tip_relief_depth=22e-6,
        tip_relief_extent=0.31,
        root_relief_depth=mods.pinion.root_relief_depth,
        root_relief_extent=mods.pinion.root_relief_extent,
        crowning_depth=mods.pinion.crowning_depth,
        end_relief_depth=mods.pinion.end_relief_depth,
        end_relief_extent=mods.pinion.end_relief_extent,
        helix_slope_deviation=mods.pinion.helix_slope_deviation,
        profile_deviation_roll=mods.pinion.profile_deviation_roll,
        profile_deviation=mods.pinion.profile_deviation,
    )
    by_hand = jg.Modifications(pinion=pinion, gear=mods.gear)
    ref = jg.quasi_static(mesh, by_hand, torque, positions_per_pitch=P).transmission_error
    assert _rel(f(jnp.asarray([22e-6, 0.31]), torque), ref) < 1e-12
    np.testing.assert_array_equal(f.design_vector(by_hand), [22e-6, 0.31])
    other = jg.Modifications(pinion=pinion, gear=jg.MemberModification())
    with pytest.raises(ValueError, match="leaf that is not free"):
        f.design_vector(other)
    # a subtree names its array leaves: the pinion's, in its tree order
    g = f.with_free(lambda m: m.pinion)
    pin = np.concatenate([np.ravel(x) for x in jax.tree_util.tree_leaves(mods.pinion)])
    np.testing.assert_array_equal(g.design0, pin)
    x = g.design0.at[0].set(7e-6)  # the first leaf: the tip relief depth
    assert float(g.modifications(x).pinion.tip_relief_depth) == 7e-6
    for a, b in zip(
        jax.tree_util.tree_leaves(g.modifications(x).gear),
        jax.tree_util.tree_leaves(mods.gear),
        strict=True,
    ):
        np.testing.assert_array_equal(a, b)
    with pytest.raises(ValueError, match="free = 3"):
        f.with_free(3)
    with pytest.raises(ValueError, match="free = "):
        f.with_free(lambda m: m.pinion.tip_relief_shape)


def _tip(mods, depth, extent):
    """``mods`` with the pinion's tip relief (depth, extent) replaced."""
    import equinox as eqx

    where = lambda m: (m.pinion.tip_relief_depth, m.pinion.tip_relief_extent)
    return eqx.tree_at(where, mods, (jnp.asarray(depth), jnp.asarray(extent)))


def test_free_tip_curves_equal_quasi_static(setup):
    """The concrete-call program, its design- and torque-free part computed once at the first
    call, gives ``quasi_static``'s curves for two tip-relief designs and two torques (the
    residuals handed to the rest in the right order), and still refuses a bad torque or design
    shape in one line."""
    mesh, mods, torque = setup
    f = jg.compile_quasi_static(mesh, mods, positions_per_pitch=P).with_free(
        lambda m: (m.pinion.tip_relief_depth, m.pinion.tip_relief_extent)
    )
    for (depth, extent), t in (((22e-6, 0.31), torque), ((9e-6, 0.18), 0.6 * torque)):
        ref = jg.quasi_static(mesh, _tip(mods, depth, extent), t, positions_per_pitch=P)
        got = f(jnp.asarray([depth, extent]), t)
        for name in ("transmission_error", "mesh_stiffness", "contact_length", "line_load"):
            assert _rel(getattr(got, name), getattr(ref, name)) < 1e-12, name
    with pytest.raises(ValueError, match=r"torque = -3.*allowed > 0"):
        f(f.design0, -3.0)
    with pytest.raises(ValueError, match=r"design has shape \(3,\): allowed \(2,\)"):
        f(jnp.zeros(3), torque)


def test_every_call_path_gives_quasi_static(setup):
    """The three ways a concrete call runs give ``quasi_static``'s curve: a JAX design vector
    with a Python torque (the lean per-call path), a NumPy design with a NumPy torque and a
    :class:`Modifications` (the general path), and the program without its design- and
    torque-free part computed once (``with_hoisting(0)``: the fallback when that part is too
    large or JAX's partial evaluation is unavailable; ``with_free`` keeps the choice)."""
    mesh, mods, torque = setup
    tip = lambda m: (m.pinion.tip_relief_depth, m.pinion.tip_relief_extent)
    ref = jg.quasi_static(mesh, _tip(mods, 22e-6, 0.31), 0.8 * torque, positions_per_pitch=P)
    x = np.asarray([22e-6, 0.31])
    te = jg.compile_quasi_static(
        mesh, mods, positions_per_pitch=P, output=lambda r: r.transmission_error
    )
    for f in (te.with_free(tip), te.with_hoisting(0).with_free(tip)):
        for design, t in (
            (jnp.asarray(x), 0.8 * torque),
            (x, np.float64(0.8 * torque)),
            (_tip(mods, 22e-6, 0.31), jnp.asarray(0.8 * torque)),
        ):
            assert _rel(f(design, t), ref.transmission_error) < 1e-12, type(design)
    for bad in (-1, 1.5, True):
        with pytest.raises(ValueError, match=rf"max_bytes = {bad}: allowed an integer >= 0"):
            te.with_hoisting(bad)


def test_a_failed_position_raises_as_quasi_static_does(setup):
    """A NaN tip-relief depth makes a non-finite contact state: the compiled call raises
    ``quasi_static``'s error (the same message) on the lean and the general path, and with
    ``throw=False`` returns the non-finite result code at every position instead."""
    import equinox as eqx

    mesh, mods, torque = setup
    bad = _tip(mods, np.nan, 0.31)
    with pytest.raises(eqx.EquinoxRuntimeError, match="non-finite state") as ref:
        jg.quasi_static(mesh, bad, torque, positions_per_pitch=P)
    message = str(ref.value).split(": ", 1)[1]
    tip = lambda m: (m.pinion.tip_relief_depth, m.pinion.tip_relief_extent)
    f = jg.compile_quasi_static(mesh, mods, positions_per_pitch=P, output=lambda r: r.te_rms)
    f = f.with_free(tip)
    for design in (jnp.asarray([np.nan, 0.31]), bad):
        with pytest.raises(eqx.EquinoxRuntimeError) as got:
            f(design, torque)
        assert str(got.value) == f"compiled quasi_static: {message}"
    codes = jg.compile_quasi_static(
        mesh, mods, positions_per_pitch=P, output=lambda r: r.result, throw=False
    ).with_free(tip)(jnp.asarray([np.nan, 0.31]), torque)
    np.testing.assert_array_equal(codes, int(jg.ContactResult.non_finite))


_SYNC_SCRIPT = """
import jax
jax.config.update("jax_enable_x64", True)
jax.config.update("jax_cpu_enable_async_dispatch", False)
import jax.numpy as jnp, numpy as np, equinox as eqx
import jaxgear as jg, jaxgear.io as jio

c = jio.load_case("accessory-spur")
mesh, mods, torque = c.mesh_model(slices=10), c.modifications, float(c.torque)
tip = lambda m: (m.pinion.tip_relief_depth, m.pinion.tip_relief_extent)
f = jg.compile_quasi_static(mesh, mods, positions_per_pitch=16).with_free(tip)
worst = 0.0
for (depth, extent), t in (((22e-6, 0.31), torque), ((9e-6, 0.18), 0.6 * torque)):
    m = eqx.tree_at(tip, mods, (jnp.asarray(depth), jnp.asarray(extent)))
    ref = jg.quasi_static(mesh, m, t, positions_per_pitch=16)
    got = f(jnp.asarray([depth, extent]), t)
    for name in ("transmission_error", "mesh_stiffness", "contact_length", "line_load"):
        a, b = np.asarray(getattr(got, name)), np.asarray(getattr(ref, name))
        worst = max(worst, float(np.max(np.abs(a - b)) / np.max(np.abs(b))))
try:
    f(jnp.asarray([np.nan, 0.31]), torque)
    raised = False
except eqx.EquinoxRuntimeError:
    raised = True
print(repr(worst), raised)
"""


@pytest.mark.slow
def test_synchronous_cpu_dispatch_gives_quasi_static():
    """The documented setting for a loop of small calls, JAX's synchronous CPU dispatch (set
    before the backend starts, so in a fresh process): the compiled call still gives
    ``quasi_static``'s curves for two designs and torques and still raises on a failed position
    (the default tests check the same with JAX's default dispatch)."""
    done = subprocess.run(
        [sys.executable, "-c", _SYNC_SCRIPT],
        check=False,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    worst, raised = done.stdout.split()[-2:]
    assert float(worst) < 1e-12
    assert raised == "True"
