"""The Rayleigh-damping CaseWarning: a damping ratio belongs to a mode at its natural frequency.

ξ(ω) = α/(2ω) + β ω/2 of C = α M + β K is evaluated at the natural frequency of the modes the
mesh excites, here checked against the mesh mode of the dynamic model the sweep runs
(:func:`jaxgear.io.build_dynamic_model`'s modal analysis, the elastic mode with the
largest mesh strain energy), not at an excitation frequency: a case whose mesh mode has
ξ = 0.1 by construction was warned 'above critical' (ξ = 1.3 at the mesh frequency of the
sweep's lowest speed, 45 × 100 rad/s).
"""

import copy
import tomllib
import warnings

import jax
import numpy as np
import pytest

import jaxgear.dynamics as jd
import jaxgear.io as jio

jax.config.update("jax_enable_x64", True)


def _data(alpha: float, beta: float) -> dict:
    """accessory-spur with a torsional scene of light gear bodies and Rayleigh damping α (1/s),
    β (s): its mesh mode is at 58 600 rad/s (53 400 by the warning's estimate), far above the
    mesh frequency at 100 rad/s (4 500 rad/s)."""
    data = tomllib.loads(jio.embedded_case_text("accessory-spur"))
    data["scene"] = {
        "model": "torsional",
        "pinion_inertia_kg_m2": 1e-4,
        "gear_inertia_kg_m2": 1e-3,
        "damping": {"model": "rayleigh", "alpha_per_s": alpha, "beta_s": beta},
    }
    return copy.deepcopy(data)


def _mesh_mode() -> float:
    """The natural frequency (rad/s) of the dynamic model's mesh mode."""
    model, _ = jio.build_dynamic_model(jio.parse_case(_data(0.0, 0.0)), slices=8)
    modes = model.modes
    energy = np.where(np.asarray(modes.rigid), -1.0, np.asarray(modes.energy[0]))
    return float(np.asarray(modes.omega)[int(np.argmax(energy))])


def test_rayleigh_warning_at_the_mesh_mode():
    """ξ = 0.1 at the mesh mode (α alone, or α and β sharing it) parses without a warning; ξ = 2
    there warns, naming the term that dominates at that frequency."""
    w = _mesh_mode()
    assert 45e3 < w < 80e3, w  # the old rule's 100 rad/s mesh frequency: α/(2·4500) > 1
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        jio.parse_case(_data(0.2 * w, 0.0))
        jio.parse_case(_data(0.1 * w, 0.1 / w))
    for (alpha, beta), key in (((4.0 * w, 0.0), "alpha_per_s"), ((0.0, 4.0 / w), "beta_s")):
        with pytest.warns(jio.CaseWarning) as record:
            jio.parse_case(_data(alpha, beta))
        (msg,) = [str(r.message) for r in record if issubclass(r.category, jio.CaseWarning)]
        assert msg.startswith(f"[scene.damping] {key} = "), msg
        assert "natural frequency" in msg and "above critical" in msg, msg
