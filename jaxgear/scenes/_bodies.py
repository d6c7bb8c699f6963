"""Condensed FE bodies placed on the shafts of a hybrid scene (NumPy, once per scene): each
body's bearing masters merged with its shaft's nodes, its other condensed DOFs appended, the
teeth's mass lumped on its rim, its rotating-frame matrices, the free rotations and the
compliance of the structure with the output held (seed II-2; docs/hybrid.md).

A body turns under the fixed mesh: its frame is at angle φ_rot = φ_0 ∓ θ_member from the fixed
frame. K, M and the centrifugal load are constant in the body frame; the shaft that carries a
body is taken in the same rotating frame (shafts and bearings are axisymmetric: their stiffness
does not change), so the structure is factored once.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import jax.numpy as jnp
import numpy as np
import scipy.linalg as sla

from .._stiffness import tooth_mass as one_tooth_mass
from ._interface import body_dof_index, body_rims, rim_mid_z
from ._shaft import ShaftSpec
from ._structure import Structure
from ._train import TrainSpec


class _BodyPlace(NamedTuple):
    """A condensed body placed on a shaft: its shaft (index), the position along it of the
    body frame's origin (m; the wheel rim's mid-face, a single-rim body's gear position), its
    spin speed per unit scene speed (signed Ω_z/Ω: the pinion's +1, a pair's gear −z1/z2), and
    for each of its rims a gear pair with its member index there (its tooth data for the tooth
    masses)."""

    body: object
    shaft: int
    gear_z: float
    speed: float
    rims: tuple  # ((GearPair, member), ...) per rim of the body


def _body_bearing_z(body, shaft: ShaftSpec, where: str, origin: float | None = None) -> tuple:
    """The shaft positions (m) where ``body``'s bearing nodes attach (the body origin's
    position ``origin``, default the shaft's gear position, plus their axial positions), after
    checking that the shaft's bearings are axisymmetric (the
    shaft of a flexible body turns with the body frame: they must look the same from every
    angle, i.e. commute with a quarter turn about z: K_xx = K_yy, ...)."""
    q = np.zeros((6, 6))
    q[0, 1] = q[3, 4] = -1.0
    q[1, 0] = q[4, 3] = q[2, 2] = q[5, 5] = 1.0
    for i, b in enumerate(shaft.bearings):
        for what, a in (("stiffness", b.stiffness_matrix()), ("damping", b.damping_matrix())):
            dg = np.abs(np.diag(a))
            scale = np.maximum(np.sqrt(np.outer(dg, dg)), np.abs(a))
            if np.any(np.abs(q @ a @ q.T - a) > 1e-6 * np.maximum(scale, scale.T)):
                raise ValueError(
                    f"{where}.bearings[{i}]: its {what} matrix is not axisymmetric about the "
                    "shaft axis (allowed on the shaft of a flexible body, which turns with the "
                    "body frame: e.g. K_xx = K_yy, K_xy = 0, K[3][3] = K[4][4], "
                    "K[0][4] = -K[1][3], no x/y-z coupling)"
                )
    coords = np.asarray(body.master_coords, float)
    bz = coords[np.asarray(body.master_kind) == 1]
    if bz.size == 0 or np.any(np.hypot(bz[:, 0], bz[:, 1]) > 1e-9):
        raise ValueError(f"{where}: the body on it needs bearing nodes on its axis")
    return tuple((shaft.gear_z if origin is None else origin) + bz[:, 2])


def _place_bodies(d: dict, places: list, tooth_density: float | None) -> dict:
    """The shafts of ``d`` (:func:`_shaft_arrays`) with condensed bodies: each body's bearing
    master DOFs merged with its shaft's nodes, its other condensed DOFs appended (NumPy).

    Args:
        d: the shaft arrays. places: a :class:`_BodyPlace` or ``None`` per member.
        tooth_density: add the mass and centrifugal load of the teeth (not in the FE body, which
            ends at the root circle) on the rim master nodes at this density [R]; ``None``: no.

    Returns:
        dict of ``K``, ``M`` (n, n), ``fc`` (n,) per unit scene speed², ``gyroscopic`` and
        ``spin_stiffness`` (:func:`_rotating_frame`), ``gidx`` (each member's global DOF of each
        condensed DOF, or ``None``), ``n``.
    """
    n_sh = d["M"].shape[0]
    n = n_sh
    blocks, rot_parts, gidxs = [], [], []
    for place in places:
        if place is None:
            gidxs.append(None)
            continue
        body = place.body
        coords = np.asarray(body.master_coords, float)
        kind = np.asarray(body.master_kind)
        dm = np.asarray(body.dof_map)
        gidx = np.full(dm.shape[0], -1)
        zs, off = d["shaft_z"][place.shaft], d["shaft_offsets"][place.shaft]
        for i, (mi, c) in enumerate(dm):
            if mi >= 0 and kind[mi] == 1:
                node = int(np.argmin(np.abs(zs - (place.gear_z + coords[mi, 2]))))
                gidx[i] = off + 6 * node + int(c)
        free = np.flatnonzero(gidx < 0)
        gidx[free] = n + np.arange(free.size)
        n += free.size
        K_b = np.array(body.K, float)
        M_b = np.array(body.M, float)
        f_b = np.array(body.f_centrifugal, float)
        Mb0 = M_b.copy()
        for grid, (pair, member) in zip(body_rims(body), place.rims, strict=True):
            if tooth_density is None:
                break
            width = float(np.ptp(coords[grid[0], 2]))
            mt, rt = one_tooth_mass(pair, member, tooth_density, width)
            zn = coords[grid[0], 2]
            share = np.zeros(zn.size)  # trapezoid weights across the face
            share[:-1] += 0.5 * np.diff(zn)
            share[1:] += 0.5 * np.diff(zn)
            share /= share.sum()
            dof = body_dof_index(body)
            for k in range(grid.shape[0]):
                for j in range(zn.size):
                    mi = int(grid[k, j])
                    e = coords[mi, :2] / np.hypot(*coords[mi, :2])
                    for c in range(3):
                        M_b[dof[(mi, c)], dof[(mi, c)]] += mt * share[j]
                    for c in range(2):
                        f_b[dof[(mi, c)]] += mt * share[j] * rt * e[c]
        blocks.append((gidx, K_b, M_b, f_b * place.speed**2))
        rot_parts.append((place.shaft, place.speed, gidx, _body_rotating(body, M_b - Mb0)))
        gidxs.append(gidx)
    K = np.zeros((n, n))
    M = np.zeros((n, n))
    K[:n_sh, :n_sh] = d["parts"].sum(axis=0)
    M[:n_sh, :n_sh] = d["M"]
    fc = np.zeros(n)
    for g, Kb, Mb, fb in blocks:
        K[np.ix_(g, g)] += Kb
        M[np.ix_(g, g)] += Mb
        fc[g] += fb
    gyro, spin_K = _rotating_frame(n, d, rot_parts)
    return dict(K=K, M=M, fc=fc, gyroscopic=gyro, spin_stiffness=spin_K, gidx=gidxs, n=n)


def _body_structure(d: dict, placed: dict, nodes: tuple) -> Structure:
    """The :class:`Structure` of shafts ``d`` with their condensed bodies ``placed``
    (:func:`_place_bodies`): one stiffness part, the bearing rows padded over the bodies'
    coordinates, the rotating-frame matrices of the turning bodies."""
    n = placed["n"]
    R = d["reaction"]
    return Structure(
        K=jnp.asarray(placed["K"]),
        M=jnp.asarray(placed["M"]),
        parts_K=None,
        C_bearing=jnp.asarray(d["bearing_C"]),
        reaction=jnp.asarray(np.concatenate([R, np.zeros((R.shape[0], n - R.shape[1]))], 1)),
        gyroscopic=jnp.asarray(placed["gyroscopic"]),
        spin_stiffness=jnp.asarray(placed["spin_stiffness"]),
        f_centrifugal=jnp.asarray(placed["fc"]),
        part_names=("structure",),
        reaction_names=d["reaction_names"],
        reaction_member=d["reaction_member"],
        nodes=nodes,
        mount=d.get("mount"),
        mount_offset=d.get("housing_offset", 0),
    )


def _shaft_rotation(d: dict, shaft: int, n: int, body=None, gidx=None) -> np.ndarray:
    """The rigid rotation about +z of shaft ``shaft`` and the condensed body on it (n,): 1 on
    each rotation φ_z of its nodes, (−y, x) on the in-plane DOFs of the body's rim masters
    (its bearing masters are shaft DOFs; its modal coordinates do not move)."""
    v = np.zeros(n)
    a = d["shaft_offsets"][shaft]
    v[a + 5 : a + 6 * d["shaft_z"][shaft].size : 6] = 1.0
    if body is not None:
        coords = np.asarray(body.master_coords, float)
        for i, (mi, c) in enumerate(np.asarray(body.dof_map)):
            if mi >= 0 and body.master_kind[mi] == 0 and c < 2:
                x, y = coords[mi, :2]
                v[gidx[i]] = -y if c == 0 else x
    return v


def _drive_compliance(K: np.ndarray, N: np.ndarray, held: int) -> np.ndarray:
    """G (n, n): the compliance on the complement of the free rotations N (n, r) with the
    output rotation ``held`` held (its row and column zero), K G b = b for every load b with
    Nᵀ b = 0 (the columns of N have disjoint supports).

    Raises:
        ValueError: a column of N that is not a free rotation of K (internal error), or a
            rigid-body mode of the structure besides them (its supports).
    """
    n = K.shape[0]
    scale = np.max(np.abs(np.diag(K)))
    for j in range(N.shape[1]):
        if np.linalg.norm(K @ N[:, j]) > 1e-7 * scale * np.linalg.norm(N[:, j]):
            raise ValueError("hybrid scene: a shaft does not turn freely (internal error)")
    keep = np.setdiff1d(np.arange(n), [held])
    Nh = N[keep] / np.linalg.norm(N[keep], axis=0)
    A = K[np.ix_(keep, keep)] + np.mean(np.diag(K)) * Nh @ Nh.T
    try:
        factor = sla.cho_factor(A)
    except np.linalg.LinAlgError:
        raise ValueError(
            "hybrid scene: the structure has a rigid-body mode besides the shafts' rotations "
            "(check the bearings: radial and axial support of every shaft)"
        ) from None
    G = np.zeros((n, n))
    G[np.ix_(keep, keep)] = sla.cho_solve(factor, np.eye(keep.size))
    return 0.5 * (G + G.T)


def _common_offset(members: list, names: list) -> float:
    """The one frame angle φ_0 (rad, at θ = 0) of a body carrying several gears: each member's
    :func:`flexible_member` offset puts its gear's teeth on its rim's stations, modulo that
    rim's pitch 2π/Z_r; the body's frame must satisfy every rim at once, φ_0 ≡ φ_r (mod 2π/Z_r),
    which has a solution when the gears' clocking on the shaft agrees with the rims' stations.

    Raises:
        ValueError: no common angle: the teeth of a later gear would sit off its stations
            (its ``clocking_deg`` against the body's stations, one line).
    """
    phis = [float(m.offset) for m in members]
    pitches = [float(m.pitch_angle) for m in members]
    Z0 = int(round(2 * math.pi / pitches[0]))
    for a in range(Z0):
        phi = phis[0] + a * pitches[0]
        off = [((phi - p) / q + 0.5) % 1.0 - 0.5 for p, q in zip(phis, pitches, strict=True)]
        if max(abs(o) for o in off) < 1e-6:
            return phi
    Zs = [int(round(2 * math.pi / q)) for q in pitches]
    best = min(
        range(Z0),
        key=lambda a: abs(((phis[0] + a * pitches[0] - phis[1]) / pitches[1] + 0.5) % 1.0 - 0.5),
    )
    frac = ((phis[0] + best * pitches[0] - phis[1]) / pitches[1] + 0.5) % 1.0 - 0.5
    step = 360.0 / math.lcm(*Zs)
    raise ValueError(
        f"gears {names[0]!r} and {names[1]!r} on one body: with the teeth of {names[0]!r} on "
        f"their rim stations, those of {names[1]!r} sit {abs(frac):.3g} of a pitch off theirs "
        f"(allowed: a clocking_deg of {names[1]!r} at which both sit on their stations, which "
        f"moves by multiples of {step:.6g} deg = 360/lcm({', '.join(map(str, Zs))}))"
    )


_J6 = np.zeros((6, 6))
_J6[1, 0] = _J6[4, 3] = 1.0  # ez × (.) on the translations and on the rotation vector
_J6[0, 1] = _J6[3, 4] = -1.0


def _body_rotating(body, added_mass):
    """The body's rotating-frame matrices per unit spin speed about +z (condensed DOFs):
    (Coriolis Gy, spin softening + stress stiffening S + Kσ), from fem_prep, plus the lumped
    tooth masses ``added_mass`` (n_c, n_c) on the rim nodes: Gy += m J, and S −= m e eᵀ on the
    radial direction e only. A tooth's centrifugal force turns with the rim that carries it
    (the load stiffness of the rim's hoop prestress from the teeth, which the body's Kσ does not
    hold), so a rigid turn about the axis stays neutral; the rest of that prestress's stiffening
    is left out. ``body``: a ``fem_prep.CondensedBody`` (its rotating-frame matrices are
    required fields of the body file)."""
    nc = np.asarray(body.K).shape[0]
    gy = np.array(body.gyroscopic, float)
    sk = np.zeros((nc, nc))
    for part in (body.spin_softening, body.stress_stiffening):
        sk += np.asarray(part, float)
    dof = body_dof_index(body)
    kind = np.asarray(body.master_kind)
    coords = np.asarray(body.master_coords, float)
    for (mi, c), i in dof.items():
        if c != 0 or kind[mi] != 0:
            continue
        j = dof[(mi, 1)]
        mt = added_mass[i, i]
        gy[j, i] += mt
        gy[i, j] -= mt
        e = coords[mi, :2] / np.hypot(*coords[mi, :2])
        sk[np.ix_([i, j], [i, j])] -= mt * np.outer(e, e)
    return gy, sk


def _rotating_frame(n, d, parts):
    """Gyroscopic (n, n) per unit scene speed and spin stiffness (n, n) per unit scene speed² of
    the members whose frames turn: each flexible body at Ω_z = w Ω (``parts``: (shaft, w,
    global DOFs, (Gy, S)) per body; a pair's pinion w = +1, its gear −z1/z2) and the shaft that
    carries it.

    The rotating-frame equations of a body turning at Ω_z about +z: M Ẍ + 2 Ω_z Gy Ẋ + (K +
    Ω_z² (S + Kσ)) X = … (Coriolis, spin softening, centrifugal stress stiffening; fem_prep
    condenses Gy, S, Kσ of the FE body). A shaft on the axis is axisymmetric: its fixed-frame
    model seen from the turning frame gives Gy = M J and S = −M P (J = ez × on the translations
    and the rotation vector, P = J ᵀJ), with no polar gyroscopic term (as the lumped model)."""
    gyro = np.zeros((n, n))
    spin_K = np.zeros((n, n))
    # the shafts end where a housing's coordinates begin (:func:`couple_housing`)
    offsets = (*d["shaft_offsets"], d.get("housing_offset", d["M"].shape[0]))
    for shaft, w, gidx, (gy, sk) in parts:
        gyro[np.ix_(gidx, gidx)] += 2.0 * w * gy
        spin_K[np.ix_(gidx, gidx)] += w * w * sk
        a, b = offsets[shaft], offsets[shaft + 1]
        Ms = d["M"][a:b, a:b]
        J = np.kron(np.eye((b - a) // 6), _J6)
        if np.abs(Ms @ J - J @ Ms).max() > 1e-9 * np.abs(Ms).max():
            raise ValueError("hybrid scene: a flexible body's shaft mass is not axisymmetric")
        gyro[a:b, a:b] += 2.0 * w * Ms @ J
        spin_K[a:b, a:b] += w * w * (Ms @ J @ J)
    return gyro, spin_K


def _shaft_bodies(spec: TrainSpec) -> tuple[dict, list]:
    """The condensed body of each shaft of the train ``spec`` that carries flexible gears, and
    where it sits: ``({shaft: (body, origin z (m))}, each shaft's bearing-node positions (m))``
    (:func:`_body_bearing_z`); the origin is the mid-face of the body's wheel rim (rim 0), at
    that gear's position.

    Raises:
        ValueError (one line, mm): a shaft carrying a flexible gear and a rigid one or two
            bodies, a body's rims not matching its gears, a gear position that is not where the
            body puts its rim, what :func:`_body_bearing_z` refuses.
    """
    shafts, names, on = spec.shafts, spec.names, spec.shaft_gears
    bodies, rims, gname = spec.gear_bodies, spec.gear_rims, spec.gear_labels
    n_shafts = len(shafts)
    # one body per shaft: its gears, each on its rim; the body origin along the shaft
    shaft_body: dict = {}  # shaft -> (body, origin z (m))
    bodies_z = [[] for _ in range(n_shafts)]
    for s_ in range(n_shafts):
        flex = [g for g in on[s_] if bodies[g] is not None]
        if not flex:
            continue
        where = f"shaft {names[s_]!r}"
        rigid = [g for g in on[s_] if bodies[g] is None]
        if rigid:
            raise ValueError(
                f"{where}: carries the flexible gear {gname[flex[0]]!r} and the rigid gear "
                f"{gname[rigid[0]]!r} (allowed: a shaft's gears all on one condensed body, "
                "which turns with the shaft)"
            )
        body = bodies[flex[0]]
        if any(bodies[g] is not body for g in flex):
            raise ValueError(
                f"{where}: its gears {', '.join(repr(gname[g]) for g in flex)} name different "
                "bodies (allowed: one condensed body per shaft, carrying all its gears)"
            )
        n_rims = len(body_rims(body))
        used = [rims[g] for g in flex]
        if len(flex) != n_rims or sorted(used) != list(range(n_rims)):
            raise ValueError(
                f"{where}: its body has {n_rims} rim(s) and the shaft {len(flex)} gear(s) on "
                f"rims {used} (allowed: one gear on each rim, rim 0 the webbed wheel's, rim 1 "
                "the [pinion_rim])"
            )
        pos = shafts[s_].gear_positions
        g0 = next(g for g in flex if rims[g] == 0)
        origin = pos[on[s_].index(g0)]
        for g in flex:
            want = origin + rim_mid_z(body, rims[g])
            got = pos[on[s_].index(g)]
            if abs(got - want) > 1e-6:
                raise ValueError(
                    f"{where}: gear_positions_mm {gname[g]} = {got * 1e3:.6g}, but its body puts "
                    f"rim {rims[g]} at {want * 1e3:.6g} mm ({gname[g0]} at {origin * 1e3:.6g} mm "
                    f"+ {rim_mid_z(body, rims[g]) * 1e3:.6g} mm in the body frame)"
                )
        shaft_body[s_] = (body, origin)
        bodies_z[s_].extend(_body_bearing_z(body, shafts[s_], where, origin))
    return shaft_body, bodies_z


def _gear_roles(meshes) -> dict:
    """Each gear's first mesh and its member index there (0 driving, 1 driven):
    ``{gear: (mesh, member)}``."""
    role = {}
    for k, (_, (g, h)) in enumerate(meshes):
        role.setdefault(g, (k, 0))
        role.setdefault(h, (k, 1))
    return role


def _check_rim_widths(spec: TrainSpec) -> None:
    """Each condensed gear's rim as wide as the faces of its meshes.

    Raises:
        ValueError: a rim width that is not the face width of one of the gear's meshes (one
            line, mm).
    """
    rims, gname, meshes = spec.gear_rims, spec.gear_labels, spec.meshes
    for g, body in enumerate(spec.gear_bodies):
        if body is None:
            continue
        z = np.asarray(body.master_coords, float)[body_rims(body)[rims[g]][0], 2]
        for plane, (a, b) in meshes:
            face = float(plane.face_width)
            if g in (a, b) and abs(np.ptp(z) - face) > 1e-6 * face:
                raise ValueError(
                    f"{gname[g]!r}: its body's rim {rims[g]} is {np.ptp(z) * 1e3:.6g} mm wide, "
                    f"the face of mesh {gname[a]}-{gname[b]} {face * 1e3:.6g} mm (allowed: equal; "
                    "fem_prep rim_width_mm or [pinion_rim] width_mm)"
                )
