"""The root-stress maximum is differentiable with respect to the tooth modifications through
``RootStressMap.soft_max`` (docs/rating.md, "The root-stress map over a tooth's passage"):
its gradient with respect to the tip relief depth, through the smooth-contact quasi-static
load map of the rated accessory pair, against central differences (float64); its bounds
max ≤ soft_max ≤ max + width log(P L N); a bad width refused in one line."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from _rating_cases import rated_accessory_case, stub_table

import jaxgear as jg

jax.config.update("jax_enable_x64", True)

WIDTH = 1e6  # Pa: the soft maximum's smoothing


def test_soft_root_stress_maximum_gradient_matches_central_differences():
    """d soft_max/d (tip relief depth) of both members on a 4-slice, 8-position model (stub FE
    table, widths 1 % of each member's largest root stress): the forward derivative (one jitted
    ``jax.jvp``) against central differences (step 1 nm) within 1e-5, and not small (a 1 µm
    deeper relief moves the soft maximum by more than 0.01 % of the maximum)."""
    case = rated_accessory_case(4, 8)
    pair, mesh = case.pair, case.mesh_model()
    contact = jg.SmoothContact(1e-7)
    table = []
    for member in (0, 1):  # unit loads over the member's roll on the whole path of contact
        roll = np.asarray(pair.roll_distance(np.array([0.0, pair.path_of_contact]), member))
        radii = np.hypot(np.linspace(roll.min(), roll.max(), 9), pair.base_radii[member])
        table.append(stub_table(jg.tooth_geometry(pair, member), radii))

    def maps(depth, width):
        tip = jg.MemberModification(tip_relief_depth=depth, tip_relief_extent=0.25)
        res = jg.quasi_static(mesh, jg.Modifications.symmetric(tip), case.torque, contact=contact)
        out = [jg.rating.root_stress_map(pair, res, m, table[m].roll, table[m].peak) for m in (0, 1)]
        soft = jnp.stack([m.soft_max(w) for m, w in zip(out, width, strict=True)])
        return soft, jnp.stack([m.max for m in out])

    @jax.jit
    def value_and_slope(d, width):
        return jax.jvp(lambda x: maps(x, width), (d,), (jnp.ones_like(d),))

    d0, h = jnp.asarray(15e-6), 1e-9
    (_, hard), _ = value_and_slope(d0, jnp.ones(2))
    width = 0.01 * hard
    (soft, hard), (slope, _) = value_and_slope(d0, width)
    (up, _), _ = value_and_slope(d0 + h, width)
    (down, _), _ = value_and_slope(d0 - h, width)
    cells = jax.eval_shape(
        lambda: jg.quasi_static(mesh, case.modifications, case.torque, contact=contact).cell_s
    ).size
    cd = (np.asarray(up) - np.asarray(down)) / (2 * h)
    np.testing.assert_allclose(slope, cd, rtol=1e-5)
    assert np.all(np.abs(np.asarray(slope)) * 1e-6 > 1e-4 * np.asarray(hard))
    assert np.all(np.asarray(hard) <= np.asarray(soft))
    assert np.all(np.asarray(soft) <= np.asarray(hard) + np.asarray(width) * np.log(cells))


def test_soft_max_refuses_a_width_not_positive():
    zeros = np.zeros((1, 1, 1))
    m = jg.rating.RootStressMap(zeros, zeros, zeros, zeros, zeros > 0)
    with pytest.raises(ValueError, match=r"^RootStressMap.soft_max: width = 0.0 is out of range"):
        m.soft_max(0.0)
