"""The independent reference: a 2-D plane-strain FE contact model of a loaded spur pair
(several teeth, exact frictionless unilateral contact) that finds where loaded teeth touch
beyond the theoretical path of contact: premature engagement (the driven gear's tip corner on
the driving flank before the theoretical start) and late disengagement (the driving tip corner
on the driven flank after the theoretical end).

Written separately from jaxgear's contact, stiffness and cell code (none of it is imported):
jaxgear gives only the pair's geometric scalars (:class:`jaxgear.GearPair`: radii, centre
distance, operating pressure angle, start roll, path of contact, base pitch); fem_prep gives the
exact generated tooth forms (:func:`fem_prep.generate_tooth`: involute + trochoidal fillet from
the rack, sharp tip corner) and its mapped sector mesh (:func:`fem_prep.mesh_sector`).

Model (per unit face width, plane strain, E, ν of the case):

* Each member: ``n_teeth`` teeth on the full rim ring down to the bore radius (default
  0.5 r_f, fe2d's default), quadratic triangles (scikit-fem ``ElementTriP2``), element size h
  at the teeth; the bore clamped.  Each body's stiffness is condensed onto the candidate contact
  nodes: every vertex and mid-edge node of the drive flank (from the fillet's 45° point r_P to
  the tip corner) of the middle three teeth, by one solve per node and direction: the nodal
  compliance matrix G (2N × 2N, m/(N/m)).
* The pinion drives (clockwise, its right flank), the gear is held at its bore at the
  kinematic angle φ₂ = φ₂⁰ + θ z₁/z₂; the pinion's bore is a rigid ring at φ₁ = φ₁⁰ + θ + Δθ,
  Δθ (rad) unknown, loaded by the torque T' = T / b (N·m/m).  A rigid rotation of a body
  clamped at its bore is its zero-energy mode, so the pinion clamped at its bore plus the rigid
  rotation Δθ is exactly the rigid bore ring.
* Contact pairs, node to segment, single pass, per tooth pair: the gear's flank points above its
  operating pitch circle against the pinion's drive flank (approach: the gear's tip corner among
  them), and the pinion's flank points above its operating pitch circle against the gear's flank
  (recess: the pinion's tip corner). Coast flanks and friction are left out. The gap g_i is the
  signed distance of the slave point from the master flank, computed by brute force between
  discretised surfaces in their rigid positions: the slave point's exact surface point and a
  polyline of 3000 exact points of the master flank (fillet + involute; chord sag < 1e-10 m),
  measured along the master segment's normal (the closest segment among those next to the
  nearest polyline vertex); never the involute formula. The slave points are 8 per slave facet
  (P2-interpolated, so that the rigid contact point never falls far between two of them). Both
  sides' displacements at a contact point are the P2 edge interpolation of their flank nodes
  (the same shape functions spread the force); W gets 1e-9 of its mean diagonal (singular with
  more points than nodes).
* With n_i the contact normal (out of the pinion), a_i = n_i · (y, −x) the pinion's lever at
  the contact point (its centre at the origin), and W = B₁G₁B₁ᵀ + B₂G₂B₂ᵀ the combined normal
  compliance of the candidate pairs: p ≥ 0, g + W p − Δθ a ≥ 0, pᵀ(g + W p − Δθ a) = 0,
  aᵀp = T'.  For a given Δθ the complementarity problem is the QP min ½pᵀWp + (g − Δθa)ᵀp,
  p ≥ 0, solved by NNLS (scipy, on the Cholesky factor of W); aᵀp is monotone in Δθ,
  whose root is found by Brent's method.

Positions: the roll distance s = r_b1 θ along the line of action from the theoretical start of
contact A (θ = 0: the gear's tip corner at A with the teeth rigid), measured by the gear's
position (the driven member held at its kinematic angle); the pinion's extra rotation Δθ is
the transmission error, reported as r_b1 Δθ (m, > 0: the loaded pinion is ahead of its
kinematic position).  The loaded start of contact s_start(T) is the root of the entering pair's
smallest deformed gap under the load carried by the other pairs (Brent); the end of contact
s_end(T) likewise for the leaving pair, measured from A (theoretical end: g_α).

Usage: ``python benchmarks/extended_contact_fe.py [--quick]`` writes
docs/bench/extended_contact_fe.json (keys in :func:`main`'s docstring).
"""

from __future__ import annotations

import argparse
import json
import math
import pathlib
import time
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import skfem
from scipy.optimize import brentq, nnls
from scipy.spatial import cKDTree
from skfem.models.elasticity import lame_parameters, linear_elasticity

import fem_prep
from fem_prep import ToothGeometry, generate_tooth

__all__ = [
    "Body",
    "ContactState",
    "PairModel",
    "accessory_spur_pair",
    "build_body",
    "build_pair",
    "contact_point",
    "end_of_contact",
    "main",
    "onset_breakdown",
    "scan",
    "single_pair_stiffness",
    "start_of_contact",
]

N_MASTER = 3000  # exact points of each master flank polyline
HARRIS_TORQUES = (5.0, 10.0, 20.0, 40.0, 60.0, 80.0, 120.0, 160.0)  # N·m, the record's map


# ------------------------------------------------------------------------------------------
# one body: mesh, condensed compliance of its flank nodes, exact surface


@dataclass
class Body:
    """One member's FE body condensed on its drive-flank nodes (local frame: tooth 0 on +y,
    teeth at clockwise angles j·2π/z, right flank at x > 0)."""

    geometry: ToothGeometry
    form: object  # fem_prep ToothForm (exact surface)
    teeth: int
    size: float
    rim_radius: float
    n_dofs: int
    n_elements: int
    node_radii: dict  # tooth j -> (2n+1,) radii of the flank nodes (vertex, mid, vertex, ...)
    node_index: dict  # tooth j -> (2n+1,) rows of the node in G (node k -> dofs 2k, 2k+1)
    vertex_radii: dict  # tooth j -> (n+1,) vertex radii of the flank facets
    G: np.ndarray  # (2N, 2N) nodal compliance (m per N/m), local frame
    split_radius: float
    seconds: float

    def surface_point(self, r, tooth: int = 0) -> np.ndarray:
        """Exact drive-flank point(s) (m, local frame) of tooth ``tooth`` at radii r."""
        r = np.asarray(r, dtype=float)
        x = self.form.half_thickness(r)
        y = np.sqrt(np.maximum(r * r - x * x, 0.0))
        pts = np.stack([x, y], -1)
        return pts @ _rot(-tooth * 2 * math.pi / self.teeth).T

    def slave_radii(self, tooth: int, n_sub: int) -> np.ndarray:
        """Radii (m) of the contact points on tooth ``tooth``'s flank: ``n_sub`` per facet
        (equally spaced in the facet's parameter, its first vertex included) and the tip
        corner last."""
        rv = self.vertex_radii[tooth]
        t = np.arange(n_sub) / n_sub
        r = (rv[:-1, None] + t[None, :] * np.diff(rv)[:, None]).ravel()
        return np.concatenate([r, rv[-1:]])

    def shape(self, r, tooth: int) -> tuple[np.ndarray, np.ndarray]:
        """P2 edge interpolation at flank radii r: node rows (n, 3) of G and weights (n, 3)."""
        rv = self.vertex_radii[tooth]
        r = np.clip(np.asarray(r, dtype=float), rv[0], rv[-1])
        k = np.clip(np.searchsorted(rv, r) - 1, 0, len(rv) - 2)
        t = (r - rv[k]) / (rv[k + 1] - rv[k])
        w = np.stack([(1 - t) * (1 - 2 * t), 4 * t * (1 - t), t * (2 * t - 1)], -1)
        idx = self.node_index[tooth]
        rows = np.stack([idx[2 * k], idx[2 * k + 1], idx[2 * k + 2]], -1)
        return rows, w


def _rot(angle: float) -> np.ndarray:
    """Counter-clockwise rotation matrix by ``angle`` (rad)."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s], [s, c]])


def build_body(
    g: ToothGeometry,
    *,
    size: float,
    rim_radius: float | None = None,
    n_teeth: int = 5,
    youngs_modulus: float = 210e9,
    poisson_ratio: float = 0.3,
    loaded_teeth: tuple[int, ...] = (-1, 0, 1),
) -> Body:
    """Mesh ``n_teeth`` teeth on the rim ring (P2, size h at the teeth), clamp the bore and
    condense the stiffness onto the drive-flank nodes of ``loaded_teeth`` (by solves)."""
    t0 = time.perf_counter()
    prof = fem_prep.tooth_profile(g)
    form = generate_tooth(g, n_fillet=400, n_involute=2000, n_tip=4)
    rim = 0.5 * prof.root_radius if rim_radius is None else float(rim_radius)
    sm = fem_prep.mesh_sector(prof, rim, size, n_teeth=n_teeth)
    mesh = sm.mesh
    z = prof.teeth
    tau = 2 * math.pi / z
    ib = skfem.Basis(mesh, skfem.ElementVector(skfem.ElementTriP2()))
    K = skfem.asm(linear_elasticity(*lame_parameters(youngs_modulus, poisson_ratio)), ib)
    rmid = 0.5 * (rim + prof.root_radius)
    fixed = ib.get_dofs(lambda x: np.hypot(x[0], x[1]) < rmid).all()
    free = np.setdiff1d(np.arange(ib.N), fixed)
    fac = fem_prep.factorize(K[free][:, free].tocsc())
    tree = cKDTree(mesh.p.T)
    fac_of = {tuple(sorted(f)): i for i, f in enumerate(mesh.facets.T)}
    node_dofs, node_radii, node_index, vertex_radii = [], {}, {}, {}
    for j in loaded_teeth:
        fl = sm.flank @ _rot(-j * tau).T
        d, v = tree.query(fl)
        if np.max(d) > 1e-9 * size:
            raise RuntimeError("flank vertices not found in the mesh")
        dofs, radii = [], []
        for k in range(len(v)):
            dofs.append(ib.nodal_dofs[:, v[k]])
            radii.append(float(np.hypot(*mesh.p[:, v[k]])))
            if k + 1 < len(v):
                f = fac_of[tuple(sorted((v[k], v[k + 1])))]
                dofs.append(ib.facet_dofs[:, f])
                mid = 0.5 * (mesh.p[:, v[k]] + mesh.p[:, v[k + 1]])
                radii.append(float(np.hypot(*mid)))
        start = len(node_dofs)
        node_dofs.extend(dofs)
        node_index[j] = np.arange(start, start + len(dofs))
        node_radii[j] = np.array(radii)
        vertex_radii[j] = np.array(radii[0::2])
    dofs = np.concatenate(node_dofs)  # (2N,) x, y per node
    pos = np.full(ib.N, -1)
    pos[free] = np.arange(len(free))
    F = np.zeros((len(free), len(dofs)))
    F[pos[dofs], np.arange(len(dofs))] = 1.0
    U = fac.solve(F)
    G = U[pos[dofs], :]
    G = 0.5 * (G + G.T)
    return Body(
        geometry=g,
        form=form,
        teeth=z,
        size=size,
        rim_radius=rim,
        n_dofs=int(ib.N),
        n_elements=int(mesh.nelements),
        node_radii=node_radii,
        node_index=node_index,
        vertex_radii=vertex_radii,
        G=G,
        split_radius=float(sm.split_radius),
        seconds=time.perf_counter() - t0,
    )


# ------------------------------------------------------------------------------------------
# the pair in its rigid positions


@dataclass
class ContactState:
    """One solved position: ``theta`` (rad, nominal pinion rotation from the theoretical start),
    ``dtheta`` (rad, the pinion's extra rigid rotation: the TE), per candidate: ``pair`` (tooth
    pair k), ``p`` (N/m), ``gap`` (m, rigid), ``deformed_gap`` (m), ``x1``/``x2`` (m, world
    points on pinion / gear), ``corner`` (1: the slave node is a tip corner), ``arm`` (m)."""

    theta: float
    dtheta: float
    pair: np.ndarray
    p: np.ndarray
    gap: np.ndarray
    deformed_gap: np.ndarray
    x1: np.ndarray
    x2: np.ndarray
    corner: np.ndarray
    arm: np.ndarray

    def loads(self, pairs=(-1, 0, 1)) -> np.ndarray:
        """Normal load per tooth pair (N/m)."""
        return np.array([self.p[self.pair == k].sum() for k in pairs])


class PairModel:
    """An external spur pair of two condensed bodies in rigid kinematic positions.

    World frame: pinion centre at the origin, gear centre at (0, a_w); the pinion turns
    clockwise and drives with its right flank; the line of action has the direction
    d = (cos α_w, sin α_w) through the pitch point.  Tooth pair k: pinion tooth k (local index
    k), gear tooth −k; pair 0 is at the theoretical start of contact A at θ = 0."""

    def __init__(self, pair, pinion: Body, gear: Body, *, gap_cut: float = 1e-4, n_sub: int = 8):
        self.pair = pair
        self.b1, self.b2 = pinion, gear
        self.z1, self.z2 = pinion.teeth, gear.teeth
        self.a = float(pair.center_distance)
        rb1, rb2 = pair.base_radii
        self.rb1, self.rb2 = rb1, rb2
        aw = pair.operating_pressure_angle
        self.alpha_w = aw
        self.rw1 = self.a * rb1 / (rb1 + rb2)
        self.rw2 = self.a * rb2 / (rb1 + rb2)
        self.d = np.array([math.cos(aw), math.sin(aw)])
        self.o2 = np.array([0.0, self.a])
        t1 = rb1 * np.array([-math.sin(aw), math.cos(aw)])
        self.A = t1 + pair.start_roll * self.d  # theoretical start of contact
        self.g_alpha = float(pair.path_of_contact)
        self.p_b = float(pair.base_pitch)
        self.gap_cut = gap_cut
        self.n_sub = n_sub
        # phases: pinion tooth 0's right flank and gear tooth 0's right flank through A
        rA1 = float(np.hypot(*self.A))
        self.phi1_0 = math.atan2(self.A[0], self.A[1]) - float(
            math.atan2(*pinion.surface_point(rA1))
        )
        v = self.A - self.o2
        rA2 = float(np.hypot(*v))
        psi2 = float(math.atan2(*gear.surface_point(rA2)))
        self.phi2_0 = (psi2 - math.atan2(v[0], v[1]) - math.pi + math.pi) % (2 * math.pi) - math.pi
        # dense master flanks (local) per body: radii from r_P to the tip corner
        self.master = {}
        for tag, b in (("pinion", pinion), ("gear", gear)):
            r = np.linspace(b.split_radius, b.form.tip_radius, N_MASTER)
            pts = b.surface_point(r)
            self.master[tag] = (r, pts, cKDTree(pts))

    # rigid placements -------------------------------------------------------------------
    def frames(self, theta: float, dtheta: float = 0.0):
        """(R1, R2): local → world rotations of pinion and gear at nominal angle θ."""
        R1 = _rot(-(self.phi1_0 + theta + dtheta))
        R2 = _rot(math.pi + self.phi2_0 + theta * self.z1 / self.z2)
        return R1, R2

    def candidates(self, theta: float, pairs=(-1, 0, 1)):
        """Rigid gaps and compliance of every candidate contact at θ (pinion at Δθ = 0)."""
        R1, R2 = self.frames(theta)
        rows = {k: [] for k in ("pair", "gap", "n", "x1", "x2", "corner", "B1", "B2", "arm")}
        N1, N2 = self.b1.G.shape[0] // 2, self.b2.G.shape[0] // 2
        for k in pairs:
            j1, j2 = k, -k
            for slave_is_gear in (True, False):
                if slave_is_gear:
                    sb, s_j, Rs, os_, mb, m_j, Rm, om, mtag, r_pitch = (
                        self.b2, j2, R2, self.o2, self.b1, j1, R1, np.zeros(2), "pinion", self.rw2
                    )
                else:
                    sb, s_j, Rs, os_, mb, m_j, Rm, om, mtag, r_pitch = (
                        self.b1, j1, R1, np.zeros(2), self.b2, j2, R2, self.o2, "gear", self.rw1
                    )
                rn = sb.slave_radii(s_j, self.n_sub)
                sel = np.nonzero(rn >= r_pitch)[0]
                if len(sel) == 0:
                    continue
                S = sb.surface_point(rn[sel], s_j) @ Rs.T + os_
                mr, mloc, mtree = self.master[mtag]
                Rf = Rm @ _rot(-2 * math.pi * m_j / mb.teeth)  # master tooth local → world
                Sl = (S - om) @ Rf  # the slave points in the master tooth's frame
                # node-to-segment: every segment within 4 vertices of the nearest vertex
                # (the polyline's spacing is ~1.5 µm; the closest segment is among them)
                _, iv = mtree.query(Sl)
                cand = np.clip(iv[:, None] + np.arange(-4, 4)[None, :], 0, len(mr) - 2)
                P0, P1 = mloc[cand], mloc[cand + 1]
                seg = P1 - P0
                L2 = np.sum(seg * seg, -1)
                t = np.clip(np.sum((Sl[:, None, :] - P0) * seg, -1) / L2, 0.0, 1.0)
                foot = P0 + t[..., None] * seg
                dist = np.linalg.norm(Sl[:, None, :] - foot, axis=-1)
                best = np.argmin(dist, 1)
                ii = np.arange(len(sel))
                s = cand[ii, best]
                ts = t[ii, best]
                tang = seg[ii, best] / np.sqrt(L2[ii, best])[:, None]
                nl_out = np.stack([tang[:, 1], -tang[:, 0]], -1)  # master's outward normal
                gap = np.sum((Sl - foot[ii, best]) * nl_out, 1)
                nout = nl_out @ Rf.T
                Q = foot[ii, best] @ Rf.T + om
                inside = (ts > 0) | (s > 0)  # the foot point not beyond the polyline's ends
                inside &= (ts < 1) | (s < len(mr) - 2)
                keep = inside & (gap < self.gap_cut)
                if not np.any(keep):
                    continue
                rQ = mr[s] + ts * (mr[s + 1] - mr[s])
                n = nout if slave_is_gear else -nout
                for q in np.nonzero(keep)[0]:
                    srow = np.zeros(2 * (N2 if slave_is_gear else N1))
                    nl = Rs.T @ n[q]
                    srows, sw = sb.shape(rn[sel[q]], s_j)
                    for nd, w in zip(srows, sw):
                        srow[2 * nd : 2 * nd + 2] += w * nl
                    mrow = np.zeros(2 * (N1 if slave_is_gear else N2))
                    mrows, mw = mb.shape(rQ[q], m_j)
                    nlm = Rm.T @ n[q]
                    for nd, w in zip(mrows, mw):
                        mrow[2 * nd : 2 * nd + 2] += w * nlm
                    X1, X2 = (Q[q], S[q]) if slave_is_gear else (S[q], Q[q])
                    rows["pair"].append(k)
                    rows["gap"].append(gap[q])
                    rows["n"].append(n[q])
                    rows["x1"].append(X1)
                    rows["x2"].append(X2)
                    rows["corner"].append(int(sel[q] == len(rn) - 1))
                    rows["B1"].append(mrow if slave_is_gear else srow)
                    rows["B2"].append(srow if slave_is_gear else mrow)
                    rows["arm"].append(float(np.dot(n[q], [X1[1], -X1[0]])))
        out = {k: np.array(v) for k, v in rows.items()}
        if len(out["gap"]):
            B1, B2 = out["B1"], out["B2"]
            out["W"] = B1 @ self.b1.G @ B1.T + B2 @ self.b2.G @ B2.T
        return out

    # contact solve ------------------------------------------------------------------------
    @staticmethod
    def _factor(W):
        """Cholesky factor of W (singular where there are more contact points than nodes: 1e-9
        of its mean diagonal is added, a contact compliance that moves the gaps by ~1e-14 m)."""
        return sla.cholesky(W + 1e-9 * np.mean(np.diag(W)) * np.eye(len(W)), lower=True)

    @staticmethod
    def _lcp(L, q):
        """min ½pᵀWp + qᵀp, p >= 0, W = L Lᵀ: exact, by NNLS on ||Lᵀp + L⁻¹q||²."""
        rhs = -sla.solve_triangular(L, q, lower=True)
        p, _ = nnls(L.T, rhs, maxiter=50 * len(q))
        return p

    def solve(self, theta: float, torque: float, pairs=(-1, 0, 1), cand=None) -> ContactState:
        """Exact unilateral contact at θ under the torque T' (N·m per m face width)."""
        c = self.candidates(theta, pairs) if cand is None else cand
        g, a, W = c["gap"], c["arm"], c["W"]
        if torque <= 0:
            dth, p = 0.0, np.zeros_like(g)
        else:
            lo = float(np.min(g / a))
            L = self._factor(W)

            def excess(dt):
                return float(a @ self._lcp(L, g - dt * a)) - torque

            hi = lo + 1e-5
            while excess(hi) < 0:
                hi = lo + 2 * (hi - lo)
            dth = brentq(excess, lo, hi, xtol=1e-17, rtol=1e-13, maxiter=200)
            p = self._lcp(L, g - dth * a)
        return ContactState(
            theta=theta,
            dtheta=dth,
            pair=c["pair"],
            p=p,
            gap=g,
            deformed_gap=g + W @ p - dth * a,
            x1=c["x1"],
            x2=c["x2"],
            corner=c["corner"],
            arm=a,
        )

    def onset_gap(self, theta: float, torque: float, pair: int, others=(-1, 0, 1)) -> float:
        """The smallest deformed gap (m) of tooth pair ``pair`` under the load carried by the
        other pairs alone (< 0: it would penetrate, i.e. it carries load)."""
        c = self.candidates(theta, tuple(others))
        m = c["pair"] == pair
        if not np.any(m):
            return self.gap_cut
        o = ~m
        sub = {k: (v[o] if k != "W" else v[np.ix_(o, o)]) for k, v in c.items()}
        st = self.solve(theta, torque, cand=sub)
        W_mo = c["W"][np.ix_(m, o)]
        dg = c["gap"][m] + W_mo @ st.p - st.dtheta * c["arm"][m]
        return float(np.min(dg))

    def s(self, theta):
        return self.rb1 * theta

    def theta(self, s):
        return s / self.rb1


def build_pair(pair, *, size, n_teeth=5, rim_radius=None, youngs_modulus=210e9,
               poisson_ratio=0.3) -> PairModel:
    """Both bodies of a :class:`jaxgear.GearPair` (spur) at element size ``size`` (m)."""
    bodies = []
    for m in (pair.pinion, pair.gear):
        g = ToothGeometry(
            m.teeth,
            pair.normal_module,
            pair.normal_pressure_angle,
            0.0,
            m.profile_shift,
            m.addendum_coeff,
            m.dedendum_coeff,
            m.fillet_radius_coeff,
        )
        bodies.append(
            build_body(g, size=size, rim_radius=rim_radius, n_teeth=n_teeth,
                       youngs_modulus=youngs_modulus, poisson_ratio=poisson_ratio)
        )
    return PairModel(pair, *bodies)


# ------------------------------------------------------------------------------------------
# start / end of contact, scans


def accessory_spur_pair():
    """The embedded case ``accessory-spur``'s pair and torque (N·m): its tooth modifications
    are never applied here (the FE bodies are the unmodified generated forms)."""
    from jaxgear.io import load_case

    case = load_case("accessory-spur")
    return case.pair, float(case.torque), float(case.youngs_modulus), float(case.poisson_ratio)


def start_of_contact(pm: PairModel, torque: float, *, span: float = 1.5e-3) -> float:
    """Loaded start of contact s_start (m, from the theoretical start A; < 0: premature) under
    the torque T' (N·m/m): the root of tooth pair 0's smallest deformed gap under the load of
    the other pairs (Brent, 1e-10 m).  ``torque`` 0: the rigid (zero-load) start, the position
    near A where the rigid gap of the gear's tip corner (tooth pair 0) is least: it touches the
    pinion's flank there and lies beyond the conjugate contact point on either side (a minimum,
    not a root)."""
    if torque <= 0:
        return _touch(pm, 0.0, span)
    f = lambda s: pm.onset_gap(pm.theta(s), torque, 0)
    return float(brentq(f, -span, 0.0, xtol=1e-10))


def end_of_contact(pm: PairModel, torque: float, *, span: float = 1.5e-3) -> float:
    """Loaded end of contact s_end (m, from A; > g_α: late disengagement): where tooth pair 0
    (leaving) stops carrying load (its deformed gap under the other pairs' load crosses 0).
    ``torque`` 0: the rigid end (where the pinion's tip corner's rigid gap is least near g_α)."""
    if torque <= 0:
        return _touch(pm, pm.g_alpha, span)
    f = lambda s: pm.onset_gap(pm.theta(s), torque, 0)
    return float(brentq(f, pm.g_alpha, pm.g_alpha + span, xtol=1e-10))


def _touch(pm: PairModel, near: float, span: float) -> float:
    """Where pair 0's tip-corner rigid gap is least within ``near`` ± span/10 (m)."""
    from scipy.optimize import minimize_scalar

    w = 0.1 * span
    res = minimize_scalar(lambda s: _rigid_corner_gap(pm, s, 0), bounds=(near - w, near + w),
                          method="bounded", options={"xatol": 1e-10})
    return float(res.x)


def _rigid_corner_gap(pm: PairModel, s: float, pair: int) -> float:
    """The smallest rigid gap (m) of a tip corner of tooth pair ``pair`` at s."""
    c = pm.candidates(pm.theta(s))
    m = (c["pair"] == pair) & (c["corner"] == 1)
    return float(np.min(c["gap"][m])) if np.any(m) else pm.gap_cut


def contact_point(pm: PairModel, st: ContactState, pair: int) -> dict:
    """Load-weighted contact point of tooth pair ``pair``: radius on the pinion and on the gear
    (mm), distance off the line of action (µm, > 0: on the gear's side), the share of the
    pair's load carried by a tip-corner node, and the tip corner's owner."""
    m = (st.pair == pair) & (st.p > 0)
    if not np.any(m):
        return {"loaded": False}
    w = st.p[m] / st.p[m].sum()
    x1 = w @ st.x1[m]
    x2 = w @ st.x2[m]
    nperp = np.array([-pm.d[1], pm.d[0]])
    p_pitch = np.array([0.0, pm.rw1])
    corner = float(w @ st.corner[m])
    r1, r2 = float(np.hypot(*x1)), float(np.hypot(*(x2 - pm.o2)))
    return {
        "loaded": True,
        "r_pinion_mm": r1 * 1e3,
        "r_gear_mm": r2 * 1e3,
        "off_line_um": float((x1 - p_pitch) @ nperp) * 1e6,
        "tip_corner_share": corner,
        "at_tip_corner": bool(corner >= 0.5),
    }


def scan(pm: PairModel, torque: float, s_values, focus: int = 0) -> list[dict]:
    """Solve at each roll distance s (m): TE, loads per tooth pair (-1 behind, 0, +1 ahead),
    the share and contact point of pair ``focus``."""
    rows = []
    for s in s_values:
        st = pm.solve(pm.theta(float(s)), torque)
        L = st.loads()
        rows.append(
            {
                "s_mm": float(s) * 1e3,
                "dtheta_rad": st.dtheta,
                "te_um": pm.rb1 * st.dtheta * 1e6,
                "load_N_per_m": {"-1": L[0], "0": L[1], "+1": L[2]},
                "share": float(L[1] / L.sum()),
                "contact": contact_point(pm, st, focus),
            }
        )
    return rows


def onset_breakdown(pm: PairModel, s: float, torque: float) -> dict:
    """At a loaded start (or end) of contact s (m): tooth pair 0's tip-corner rigid gap, the
    loaded pinion's rigid approach there (Δθ times the corner's lever), and their difference:
    the entering (leaving) teeth's own displacement under the other pairs' load (µm)."""
    c = pm.candidates(pm.theta(s))
    m = (c["pair"] == 0) & (c["corner"] == 1)
    i = np.nonzero(m)[0][np.argmin(c["gap"][m])]
    o = c["pair"] != 0
    sub = {k: (v[o] if k != "W" else v[np.ix_(o, o)]) for k, v in c.items()}
    st = pm.solve(pm.theta(s), torque, cand=sub)
    approach = st.dtheta * c["arm"][i]
    return {
        "corner_rigid_gap_um": float(c["gap"][i]) * 1e6,
        "rigid_approach_um": float(approach) * 1e6,
        "carried_along_um": float(approach - c["gap"][i]) * 1e6,
        "te_um": pm.rb1 * st.dtheta * 1e6,
    }


def single_pair_stiffness(pm: PairModel, torque: float, s: float | None = None) -> float:
    """Mesh stiffness (N/m per m face width) of the single pair in contact at roll distance s
    (default: the middle of the path, g_α/2, where tooth pair 0 is alone in contact): the
    normal load T'/r_b1 over the approach r_b1 Δθ."""
    s = 0.5 * pm.g_alpha if s is None else s
    st = pm.solve(pm.theta(s), torque)
    L = st.loads()
    if L[0] > 0 or L[2] > 0:
        raise RuntimeError("single_pair_stiffness: more than one pair in contact")
    return (torque / pm.rb1) / (pm.rb1 * st.dtheta)


def main(argv=None) -> int:
    """Run the reference and write the JSON (default docs/bench/extended_contact_fe.json).

    Keys: ``what``, ``method``; ``inputs`` {case, teeth [z1, z2], normal_module_m,
    normal_pressure_angle_deg, profile_shift [x1, x2], addendum_coeff, dedendum_coeff,
    fillet_radius_coeff, face_width_m, center_distance_m, youngs_modulus_Pa, poisson_ratio,
    torque_Nm (the case's), rim_radius_m [pinion, gear], n_teeth_meshed, loaded_teeth,
    element: "P2"}; ``geometry`` {base_radii_m, base_pitch_m, path_of_contact_m (g_α),
    start_roll_m (pinion roll at A), operating_pressure_angle_deg, operating_pitch_radii_m};
    ``convention`` (text);
    ``mesh`` {size_m (the production mesh), size_over_module, n_dofs [pinion, gear],
    n_elements}; ``torques`` list, one per torque: {torque_Nm, torque_per_width_Nm_per_m,
    normal_load_N_per_m (T'/r_b1), s_start_mm, s_end_mm (from A), s_end_minus_g_alpha_mm,
    s_start_over_g_alpha, late_end_over_g_alpha, single_pair_stiffness_N_per_mm_um (pair 0
    alone at g_α/2), onset_start / onset_end {corner_rigid_gap_um, rigid_approach_um,
    carried_along_um, te_um} (at s_start / s_end: the tip corner's rigid gap = the pinion's
    rigid approach less what the other pairs' load carries the entering/leaving teeth along),
    approach [rows] (31 s from −0.3 p_b to +0.3 p_b), recess [rows] (31 s from g_α − 0.3 p_b
    to g_α + 0.3 p_b), period [rows] (33 s over one base pitch from 0)}; each row {s_mm,
    dtheta_rad, te_um, load_N_per_m {"-1", "0", "+1"}, share (pair 0's share of the total
    normal load: the entering pair in ``approach``, the leaving pair in ``recess``), contact
    of pair 0 {loaded; where loaded: r_pinion_mm, r_gear_mm (load-weighted contact point),
    off_line_um (from the line of action, > 0 towards the gear), tip_corner_share,
    at_tip_corner}};
    ``zero_load`` {s_start_mm, s_end_mm, s_end_minus_g_alpha_mm} (rigid teeth: where the tip
    corners touch) and ``small_load`` [{torque_Nm, s_start_mm, s_end_minus_g_alpha_mm}] at 1e-4
    and 1e-2 of the torque (s ∝ √T down to the ~0.02 mm left by the contact points' spacing);
    ``harris`` [{torque_Nm, s_start_mm, s_end_minus_g_alpha_mm}] at 5 … 160 N·m (the start
    and end of contact over the torque, production mesh); ``convergence`` list per mesh
    {size_over_module, size_m, n_dofs [pinion, gear], build_s,
    torques [{torque_Nm, s_start_mm, s_end_minus_g_alpha_mm, share_at {s_mm: pair 0's share}
    at s = −0.1 p_b, 0, +0.2 p_b, te_at_um {s_mm: TE}, single_pair_stiffness_N_per_mm_um}]};
    ``n_teeth_check`` {n_teeth_meshed 3, torque_Nm, s_start_mm, s_end_minus_g_alpha_mm,
    share_at_0} (3 teeth meshed instead of 5, production mesh);
    ``wall_s``.
    """
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="coarse meshes only (development)")
    ap.add_argument("--out", default="docs/bench/extended_contact_fe.json")
    args = ap.parse_args(argv)
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):  # small dense ops: threads only cost
        return _run(args)


def _run(args) -> int:
    t_start = time.perf_counter()
    pair, torque, E, nu = accessory_spur_pair()
    b = float(pair.face_width)
    prod_div = 4.0 if args.quick else 8.0
    conv_divs = (3.0, 4.0) if args.quick else (4.0, 6.0, 8.0, 12.0)
    torques = (torque, 0.5 * torque)
    models = {}

    def model(div, n_teeth=5):
        key = (div, n_teeth)
        if key not in models:
            models[key] = build_pair(pair, size=pair.normal_module / div, n_teeth=n_teeth,
                                     youngs_modulus=E, poisson_ratio=nu)
        return models[key]

    pm = model(prod_div)
    pb, ga = pm.p_b, pm.g_alpha
    approach_s = np.linspace(-0.3 * pb, 0.3 * pb, 31)
    recess_s = np.linspace(ga - 0.3 * pb, ga + 0.3 * pb, 31)
    period_s = np.linspace(0.0, pb, 33)
    results = []
    for T in torques:
        Tp = T / b
        s0 = start_of_contact(pm, Tp)
        s1 = end_of_contact(pm, Tp)
        k1 = single_pair_stiffness(pm, Tp)
        results.append(
            {
                "torque_Nm": T,
                "torque_per_width_Nm_per_m": Tp,
                "normal_load_N_per_m": Tp / pm.rb1,
                "s_start_mm": s0 * 1e3,
                "s_end_mm": s1 * 1e3,
                "s_end_minus_g_alpha_mm": (s1 - ga) * 1e3,
                "s_start_over_g_alpha": s0 / ga,
                "late_end_over_g_alpha": (s1 - ga) / ga,
                "single_pair_stiffness_N_per_mm_um": k1 * 1e-9,
                "onset_start": onset_breakdown(pm, s0, Tp),
                "onset_end": onset_breakdown(pm, s1, Tp),
                "approach": scan(pm, Tp, approach_s),
                "recess": scan(pm, Tp, recess_s),
                "period": scan(pm, Tp, period_s),
            }
        )
        print(f"T = {T:g} N·m: s_start {s0 * 1e3:.4f} mm ({s0 / ga:+.4f} g_α), s_end − g_α "
              f"{(s1 - ga) * 1e3:.4f} mm, single-pair stiffness {k1 * 1e-9:.3f} N/(mm·µm)",
              flush=True)
    zero = {
        "s_start_mm": start_of_contact(pm, 0.0) * 1e3,
        "s_end_mm": end_of_contact(pm, 0.0) * 1e3,
    }
    zero["s_end_minus_g_alpha_mm"] = zero["s_end_mm"] - ga * 1e3
    small = []
    for T in (1e-4 * torque, 1e-2 * torque):
        small.append({"torque_Nm": T,
                      "s_start_mm": start_of_contact(pm, T / b) * 1e3,
                      "s_end_minus_g_alpha_mm": (end_of_contact(pm, T / b) - ga) * 1e3})
    print("zero load:", zero, "small loads:", small, flush=True)
    harris = []
    for T in HARRIS_TORQUES:
        s0, s1 = start_of_contact(pm, T / b), end_of_contact(pm, T / b)
        harris.append({"torque_Nm": T, "s_start_mm": s0 * 1e3,
                       "s_end_minus_g_alpha_mm": (s1 - ga) * 1e3})
    print("start/end over torque:", [(h["torque_Nm"], round(h["s_start_mm"], 4),
                                      round(h["s_end_minus_g_alpha_mm"], 4)) for h in harris],
          flush=True)
    probe = (-0.1 * pb, 0.0, 0.2 * pb)
    convergence = []
    for div in conv_divs:
        m = model(div)
        row = {"size_over_module": 1 / div, "size_m": pair.normal_module / div,
               "n_dofs": [m.b1.n_dofs, m.b2.n_dofs], "build_s": m.b1.seconds + m.b2.seconds,
               "torques": []}
        for T in torques:
            Tp = T / b
            s0, s1 = start_of_contact(m, Tp), end_of_contact(m, Tp)
            sts = [m.solve(m.theta(s), Tp) for s in probe]
            row["torques"].append({
                "torque_Nm": T,
                "s_start_mm": s0 * 1e3,
                "s_end_minus_g_alpha_mm": (s1 - ga) * 1e3,
                "share_at": {f"{s * 1e3:.4f}": float(st.loads()[1] / st.loads().sum())
                             for s, st in zip(probe, sts)},
                "te_at_um": {f"{s * 1e3:.4f}": m.rb1 * st.dtheta * 1e6
                             for s, st in zip(probe, sts)},
                "single_pair_stiffness_N_per_mm_um": single_pair_stiffness(m, Tp) * 1e-9,
            })
        convergence.append(row)
        print(f"h = m/{div:g}: " + "; ".join(
            f"T {r['torque_Nm']:g}: s_start {r['s_start_mm']:.4f} "
            f"s_end-g {r['s_end_minus_g_alpha_mm']:.4f} "
            f"shares {[round(v, 4) for v in r['share_at'].values()]}" for r in row["torques"]),
            flush=True)
        if div != prod_div:
            models.pop((div, 5), None)
    m3 = model(prod_div, 3)
    n3 = {"n_teeth_meshed": 3, "torque_Nm": torque,
          "s_start_mm": start_of_contact(m3, torque / b) * 1e3,
          "s_end_minus_g_alpha_mm": (end_of_contact(m3, torque / b) - ga) * 1e3,
          "share_at_0": float(m3.solve(0.0, torque / b).loads()[1]
                              / m3.solve(0.0, torque / b).loads().sum())}
    print("3 teeth meshed:", n3, flush=True)
    p1, p2 = pair.pinion, pair.gear
    data = {
        "what": "independent 2-D plane-strain FE contact reference of the unmodified "
                "accessory-spur pair (benchmarks/extended_contact_fe.py): loaded start and end "
                "of contact beyond the theoretical path, load shares and TE",
        "method": "scikit-fem P2 triangles on fem_prep.mesh_sector (5 teeth per member, the "
                  "middle 3 loadable, full rim ring, bore clamped), stiffness condensed on the "
                  "drive-flank nodes by solves; node-to-segment gaps by brute force against 3000-"
                  "point exact flank polylines in the rigid positions; exact frictionless "
                  "unilateral contact (NNLS) with the pinion's rigid rotation solved for the "
                  "torque (Brent)",
        "inputs": {
            "case": "accessory-spur (tooth modifications removed)",
            "teeth": [p1.teeth, p2.teeth],
            "normal_module_m": pair.normal_module,
            "normal_pressure_angle_deg": math.degrees(pair.normal_pressure_angle),
            "profile_shift": [p1.profile_shift, p2.profile_shift],
            "addendum_coeff": [p1.addendum_coeff, p2.addendum_coeff],
            "dedendum_coeff": [p1.dedendum_coeff, p2.dedendum_coeff],
            "fillet_radius_coeff": [p1.fillet_radius_coeff, p2.fillet_radius_coeff],
            "face_width_m": b,
            "center_distance_m": pm.a,
            "youngs_modulus_Pa": E,
            "poisson_ratio": nu,
            "torque_Nm": torque,
            "rim_radius_m": [pm.b1.rim_radius, pm.b2.rim_radius],
            "n_teeth_meshed": 5,
            "loaded_teeth": [-1, 0, 1],
            "element": "P2 (quadratic triangles, straight edges), plane strain",
        },
        "geometry": {
            "base_radii_m": [pm.rb1, pm.rb2],
            "base_pitch_m": pb,
            "path_of_contact_m": ga,
            "start_roll_m": float(pair.start_roll),
            "operating_pressure_angle_deg": math.degrees(pm.alpha_w),
            "operating_pitch_radii_m": [pm.rw1, pm.rw2],
        },
        "convention": "s = r_b1 θ (m, reported in mm): roll distance along the line of action "
                      "from the theoretical start of contact A, by the gear's position (gear "
                      "held at its kinematic angle θ z1/z2 from A); tooth pair 0 enters at s = 0 "
                      "and leaves at s = g_α with rigid teeth; pair +1 is one base pitch ahead "
                      "(s + p_b), pair -1 one behind; te_um = r_b1 Δθ (µm), Δθ the pinion's "
                      "extra rotation under load (> 0: ahead of the kinematic position); loads "
                      "are normal contact forces per m of face width (T' = T / b)",
        "mesh": {"size_m": pm.b1.size, "size_over_module": 1 / prod_div,
                 "n_dofs": [pm.b1.n_dofs, pm.b2.n_dofs],
                 "n_elements": [pm.b1.n_elements, pm.b2.n_elements]},
        "torques": results,
        "zero_load": zero,
        "small_load": small,
        "harris": harris,
        "convergence": convergence,
        "n_teeth_check": n3,
        "wall_s": time.perf_counter() - t_start,
    }
    out = pathlib.Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(data, indent=1) + "\n", encoding="utf-8")
    print(f"wrote {out} ({data['wall_s']:.0f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
