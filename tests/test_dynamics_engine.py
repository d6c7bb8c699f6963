"""The dynamics engines as objects: every engine implements the abstract interface
that :func:`~jaxgear.dynamics.simulate` and :func:`~jaxgear.dynamics.speed_sweep` are written
over; damping models are classes, the case file's names mapped to them at the edge; the
steady-state statistics come from one :class:`~jaxgear.dynamics.Records` pytree."""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear.dynamics as jd
import jaxgear.io as jio


@pytest.mark.parametrize("engine", [jd.DynamicModel, jd.HybridModel])
def test_every_engine_implements_the_interface(engine):
    assert issubclass(engine, jd.AbstractDynamicModel)
    assert not engine.__abstractmethods__  # prepare, independent, settings, modes, …


def test_an_engine_without_its_methods_cannot_be_built():
    class Half(jd.AbstractDynamicModel):
        scene: object
        mods: object
        torque: object

    with pytest.raises(TypeError):
        Half(None, None, 1.0)


@pytest.mark.parametrize(
    "name, kind, values",
    [
        ("rayleigh", jd.RayleighDamping, {"alpha": 25.0, "beta": 2.5e-6}),
        ("modal", jd.ModalDamping, {"ratio": 0.03}),
        ("composite", jd.CompositeDamping, {"mesh_ratio": 0.08, "structure_ratio": 0.02}),
        ("none", jd.NoDamping, {}),
    ],
)
def test_damping_names_map_to_damping_classes(name, kind, values):
    d = jio.Damping(name, **values)
    assert type(d) is kind and isinstance(d, jd.AbstractDamping)
    assert jio.DAMPING_MODELS[name] is kind
    for key, v in values.items():
        assert float(getattr(d, key)) == pytest.approx(v)


def test_an_unknown_damping_name_is_refused():
    with pytest.raises(ValueError, match="damping model = 'viscous'"):
        jio.Damping("viscous")


def test_the_default_damping_is_the_composite_one():
    d = jio.Damping()
    assert type(d) is jd.CompositeDamping
    assert float(d.mesh_ratio) == pytest.approx(0.07)
    assert float(d.structure_ratio) == pytest.approx(0.01)


def test_steady_state_statistics_from_one_records_pytree():
    """Two meshes, K = 8 records of N_s = 4 steps: each mesh's dynamic factor is its largest
    force over F_s, its TE RMS about the mean, its periodicity the last two periods' change."""
    K, P = 8, 4
    t = jnp.arange(K, dtype=jnp.float64)
    fm = jnp.stack([100.0 + 10.0 * jnp.sin(t), 200.0 + 5.0 * jnp.cos(t)], axis=1)
    te = jnp.stack([1e-6 * jnp.sin(t), 2e-6 * jnp.ones(K)], axis=1)
    r = jd.Records(
        speed=jnp.asarray(100.0),
        time_step=jnp.asarray(1e-4),
        mesh_period_angle=jnp.asarray(2 * np.pi / 20),
        theta=t,
        mesh_force=fm,
        static_force=jnp.array([100.0, 200.0]),
        transmission_error=te,
        line_force=(fm[:, :1], fm[:, 1:]),
        static_line_force=jnp.array([100.0, 200.0]),
        static_te=jnp.zeros((K, 2)),
        bearing_force=jnp.zeros((K, 0)),
        bearing_force_static=jnp.zeros((P, 0)),
        omega_excited=jnp.asarray(jnp.nan),
        final_state=(jnp.zeros(3),) * 3,
        iterations=jnp.asarray(3),
        code=jnp.asarray(0),
        rim=(jnp.zeros((K, 0)), jnp.zeros((K, 0))),
        steps_per_period=P,
        transient_steps=12,
    )
    res = jd.steady_state(r)
    assert len(res.meshes) == 2 and int(res.result) == 0
    for k, m in enumerate(res.meshes):
        f = np.asarray(fm[:, k])
        assert float(m.dynamic_factor) == pytest.approx(f.max() / float(r.static_force[k]))
        e = np.asarray(te[:, k])
        assert float(m.te_rms) == pytest.approx(np.sqrt(np.mean((e - e.mean()) ** 2)), abs=1e-18)
        change = np.abs(f[P:] - f[:P]).max() / float(r.static_force[k])
        assert float(m.periodicity) == pytest.approx(change)
    np.testing.assert_allclose(res.time, (12 + 1.5 + np.arange(K)) * 1e-4)
