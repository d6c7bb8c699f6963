"""A mesh-stiffness model written outside jaxgear: one subclass of ``jaxgear.AbstractStiffness``
in this file, used through the public API (a case, its mesh model, the quasi-static solve), and
checked against the analytic transmission error of a spur pair whose tooth stiffness varies
linearly along the path of contact."""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np

import jaxgear as jg
import jaxgear.io as jio

K0 = 1.2e10  # N/m² at the start of the path of contact
RISE = 0.5  # k grows by half of K0 along the path of contact


class Linear(jg.AbstractStiffness):
    """k(s) = k0 (1 + rise s / g_α) per unit contact-line length (N/m²)."""

    k0: float
    rise: float
    name: ClassVar[str] = "linear"

    def profile(self, pair, s, conditions):
        return self.k0 * (1.0 + self.rise * s / pair.path_of_contact)


def test_a_stiffness_model_defined_in_a_test_runs_through_the_public_api():
    # theoretical path: the reference below counts the contact lines in [0, g_α]
    case = jio.load_case("accessory-spur").replace(
        stiffness=Linear(K0, RISE), contact_geometry=jg.TheoreticalPath()
    )
    pair = case.pair
    assert pair.helix_angle == 0  # spur: straight contact lines across the face
    mesh = case.mesh_model(slices=3)
    theta = jg.mesh_positions(mesh, 40, periods=2)
    res = jg.quasi_static(mesh, None, case.torque, theta)
    # each contact line in [0, g_α] (s_i = roll + i p_b) is a spring k(s_i) b, the lines in
    # parallel: F_n = δ b Σ k(s_i), so the flank-normal TE is δ = F_n / (b Σ k(s_i)); the table's
    # linear interpolation holds a linear k exactly
    g, pb, b = pair.path_of_contact, pair.base_pitch, pair.face_width
    roll = np.mod(pair.base_radii[0] * np.asarray(theta, dtype=float), pb)
    s = roll[:, None] + pb * np.arange(-3, 4)[None, :]
    k_lines = np.where((s >= 0) & (s <= g), K0 * (1 + RISE * s / g), 0.0)
    fn = case.torque / (pair.base_radii[0] * math.cos(pair.base_helix_angle))
    np.testing.assert_allclose(res.transmission_error, fn / (b * k_lines.sum(axis=1)), rtol=1e-9)
    np.testing.assert_allclose(res.mesh_stiffness, b * k_lines.sum(axis=1), rtol=1e-9)
    assert case.stiffness_model == "linear"
    assert case.stiffness.summary()["stiffness"] == "linear"
