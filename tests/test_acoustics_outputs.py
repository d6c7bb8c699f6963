"""Radiated noise from a housing (issue 66, items 2 and 4): the housing's outer skin closed by
caps over its bores (fem_prep.housing.closed_outer_surface) against the box's analytic area and
volume, and the acoustic outputs of ``jaxgear run`` (jaxgear.cli's acoustic_outputs, the
``[acoustics]`` table) on radiators whose power is known: a baffled rigid piston (Rayleigh),
a pulsating sphere (ERP and BEM)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fem_prep.housing import (
    Bore,
    Foot,
    HousingBox,
    Tet4,
    closed_outer_surface,
    mesh_box,
    outer_surface,
)

L, W, H, T = 0.3, 0.2, 0.16, 0.01
BORES = (Bore("x-", (0.1, 0.08), 0.025), Bore("x+", (0.1, 0.08), 0.025), Bore("z+", (0.2, 0.1), 0.03))


def _housing(size=0.02, element=None):
    box = HousingBox(L, W, H, T, bores=BORES, feet=(Foot((0.0, 0.03), (0.0, 0.03)),))
    return mesh_box(box, size, element=element)


@pytest.mark.parametrize("element", [None, Tet4()])
def test_closed_outer_surface_is_the_box(element):
    """The skin with its bores capped: every edge in exactly two triangles, every normal
    outward (n · (x - centre) > 0 on a box), area 2(LW + LH + WH) and enclosed volume L W H
    exactly (the caps lie in the walls' outer planes), one cap per bore, each in its wall's
    plane and of area π r² up to the staircase of cells (within perimeter × cell diagonal), the
    skin's area plus the caps' the box's."""
    hm = _housing(element=element)
    skin = outer_surface(hm)
    rs = closed_outer_surface(hm, skin)
    s = rs.surface
    edges = np.sort(np.concatenate([s.triangles[:, [0, 1]], s.triangles[:, [1, 2]],
                                    s.triangles[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    assert np.all(counts == 2)
    centre = np.array([L / 2, W / 2, H / 2])
    assert np.all(np.sum(s.normals * (s.centroids - centre), axis=1) > 0)
    box_area = 2 * (L * W + L * H + W * H)
    assert s.areas.sum() == pytest.approx(box_area, rel=1e-12)
    v = s.vertices[s.triangles]
    volume = np.einsum("ij,ij->", v[:, 0], np.cross(v[:, 1], v[:, 2])) / 6
    assert volume == pytest.approx(L * W * H, rel=1e-12)
    assert len(rs.cap_vertices) == len(BORES)
    assert skin.area + rs.cap_area == pytest.approx(box_area, rel=1e-12)
    h = 0.02 * math.sqrt(2)
    cap_of_triangle = s.triangles[rs.cap_triangles, 2]  # the fan's centre
    for b, c in zip(BORES, rs.cap_vertices, strict=True):
        axis = "xyz".index(b.wall[0])
        plane = 0.0 if b.wall[1] == "-" else (L, W, H)[axis]
        mine = rs.cap_triangles[cap_of_triangle == c]
        pts = np.unique(s.triangles[mine])
        assert np.allclose(s.vertices[pts, axis], plane, atol=1e-12)
        area = s.areas[mine].sum()
        assert abs(area - math.pi * b.radius**2) <= 2 * math.pi * b.radius * h


def test_closed_outer_surface_normal_operator():
    """The vertex normal displacement of a rigid translation u = (1, 0, 0): +1 on the x+ wall's
    vertices off its edges, -1 on the x- wall's, 0 on the y and z walls', and on each cap's
    centre the wall's value (the rim's mean: the cap interpolates)."""
    hm = _housing()
    rs = closed_outer_surface(hm)
    s = rs.surface
    u = np.tile([1.0, 0.0, 0.0], hm.n_dofs // 3)
    d = rs.normal_operator @ u
    x = s.vertices
    inner = np.all((x > 1e-9) & (x < np.array([L, W, H]) - 1e-9), axis=1)
    on = lambda axis, value: np.isclose(x[:, axis], value) & np.all(  # noqa: E731
        [(x[:, k] > 1e-9) & (x[:, k] < (L, W, H)[k] - 1e-9) for k in range(3) if k != axis],
        axis=0)
    assert not inner.any()
    assert np.allclose(d[on(0, L)], 1.0) and np.allclose(d[on(0, 0.0)], -1.0)
    for axis in (1, 2):
        for value in (0.0, (L, W, H)[axis]):
            assert np.allclose(d[on(axis, value)], 0.0, atol=1e-12)
    expected = [-1.0, 1.0, 0.0]  # the x-, x+ and z+ bores
    assert np.allclose(d[rs.cap_vertices], expected, atol=1e-12)


def test_closed_outer_surface_refuses_bad_input():
    with pytest.raises(TypeError, match="HousingMesh"):
        closed_outer_surface("box")
    with pytest.raises(ValueError, match="DOFs"):
        closed_outer_surface(_housing(), outer_surface(_housing(0.04)))
