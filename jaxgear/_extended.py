"""Contact beyond the theoretical path: the gap between a tooth's tip corner and the mating flank
ahead of the theoretical start of contact and after its end (docs/extended-contact.md).

Loaded teeth deflect: the transmission error advances the driving gear on the driven one, so the
next pair touches before the theoretical start of contact, the driven tooth's tip corner on the
driving flank below its start of active profile (premature engagement), and the leaving pair
keeps touching after the theoretical end, the driving tooth's tip corner on the driven flank
(late disengagement). The seed models contact on the line of action only (its §III names the
off-line contact its FE comparison finds); Munro, Morrish & Palmer (1999) measured the
transmission error it causes outside the normal path of contact.

Geometry (transverse plane, the pair's frame of :mod:`jaxgear.scenes._gear_mesh`: the pinion
centre O1 at the origin, t = (sin α_wt, cos α_wt), T1 = r_b1 (cos α_wt, −sin α_wt)). At the
base-plane coordinate s of rigid conjugate motion both drive flanks pass through the point
Q(s) = T1 + (ρ_A + s) t, each an involute of its base circle. Gear g's involute through Q has
the polar angle (about its centre O_g, counter-clockwise)

    Φ_g(r) = ang(T_g − O_g) + ρ_g/r_bg − inv(arccos(r_bg/r)),

ρ_g the roll distance of Q on gear g (:meth:`~jaxgear.GearPair.roll_distance`), so the tip
owner's corner sits at P = O_T + r_aT (cos Φ_T(r_aT), sin Φ_T(r_aT)). Turning the flank owner F
by an angle Δ about its centre moves its involute along its own normals by r_bF Δ everywhere
(the involute's defining property), so the flank owner's rotation that brings its flank onto P,
with the tip owner held, is exact:

    gap = κ_F r_bF [ang(P − O_F) − Φ_F(|P − O_F|)],

κ_F = +1 for the pinion and an external gear, −1 for an internal gear (whose involute point
moves away from the pinion as its angle grows). Before the start of contact (s < 0) the tip
owner is the driven gear and the flank owner the pinion; after the end (s > g_α) the other way
round. The gap vanishes at the path's ends and grows as the square of the distance from them
(the corner's velocity relative to the flank is tangent to it on the line of action: conjugate
action).
"""

from __future__ import annotations

import math

import numpy as np

from ._geometry import AbstractGearPair, involute

__all__ = ["CornerContact", "corner_table", "extension_table", "line_range"]


def _inv(r, rb):
    """inv of the pressure angle at radius ``r`` on a base circle ``rb`` (m)."""
    return involute(np.arccos(np.clip(rb / r, -1.0, 1.0)))


def _wrap(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


class CornerContact:
    """Tip-corner contact of ``pair`` at base-plane coordinates ``s`` outside the theoretical
    path (NumPy, SI; the module docstring's geometry).

    Attributes (arrays shaped like ``s``; NaN inside [0, g_α]):
        gap: the transverse gap (m) along the flank owner's normal, expressed
            as the base-plane approach that closes it (r_bF times the flank owner's rotation).
        flank_radius: radius of the contact point on the flank owner (m).
        flank_roll: its roll distance from the flank owner's tangent point (m).
        normal_angle: ε (rad), the angle from the line of action to the flank owner's normal
            at the contact point (its base-circle tangent point turned by ε).
        tip_lever: the tip owner's lever arm of that normal over its base radius, d_T/r_bT (-).
        on_flank: True where the contact point lies on the flank owner's involute (above its
            form circle, below its tip; an internal gear's within its root circle).
        offset: the contact point P (the tip owner's corner) from the line-of-action point Q(s),
            shape ``s.shape + (2,)`` (m): its components along t and along v = (T1 − O1)/r_b1
            (the unit vector from the pinion's centre to its tangent point), P = Q + o_t t +
            o_v v.

    ``rotation`` and ``shift`` displace the gears from their rigid conjugate positions at s
    (what the structure vector of a corner cell differentiates; docs/extended-contact.md):
    ``rotation`` (φ1, φ2) (rad), each gear's rotation in its direction of motion (the pinion
    counter-clockwise, an external gear clockwise, an internal gear counter-clockwise);
    ``shift`` (2, 2) (m), each centre's translation in the pair's frame. The tip owner's corner
    moves with its gear; ``gap`` is then the flank owner's rotation (times r_bF) that closes
    it, so that a positive ``gap`` is open and the approach V·X closes it.
    """

    def __init__(self, pair: AbstractGearPair, s, rotation=(0.0, 0.0), shift=((0, 0), (0, 0))):
        s = np.asarray(s, float)
        shape, s = s.shape, np.atleast_1d(s).ravel()
        alpha = pair.operating_pressure_angle
        rb, ra = pair.base_radii, pair.tip_radii
        sigma, L = pair._gear_sign, pair.line_length
        t = np.array([math.sin(alpha), math.cos(alpha)])
        nv = np.array([math.cos(alpha), -math.sin(alpha)])
        T1 = rb[0] * nv
        if sigma > 0:  # external: T2 beyond the pitch point, O2 on the far side of the line
            T2 = T1 + L * t
            O2 = T2 + rb[1] * nv
        else:  # internal: both tangent points on the same side, O2 on the pinion's side
            T2 = T1 - L * t
            O2 = T2 - rb[1] * nv
        centres, tangents = (np.zeros(2), O2), (T1, T2)
        start = [math.atan2(*(tangents[g] - centres[g])[::-1]) for g in (0, 1)]
        kappa = (1.0, float(sigma))
        # the displacement: each gear's polar rotation (counter-clockwise) and its centre's shift
        psi = (float(rotation[0]), -float(sigma) * float(rotation[1]))
        shift = np.asarray(shift, float).reshape(2, 2)
        # the flank owner's involute must exist at the contact: above its form circle and
        # below its tip (an internal gear's: between its tip circle and its root circle)
        bounds = (
            (_form_radius(pair, 0), ra[0]),
            (_form_radius(pair, 1), ra[1]) if sigma > 0 else (ra[1], pair.root_radii[1]),
        )
        fields = {k: np.full(s.shape, np.nan) for k in ("gap", "radius", "roll", "eps", "lever")}
        offset = np.full(s.shape + (2,), np.nan)
        on = np.zeros(s.shape, bool)
        for tip, flank, where in ((1, 0, s < 0.0), (0, 1, s > pair.path_of_contact)):
            if not np.any(where):
                continue
            rho1 = pair.start_roll + s[where]
            rolls = (rho1, L - sigma * rho1)
            # the tip owner's corner P: its involute through Q(s) at its tip radius
            ang = start[tip] + rolls[tip] / rb[tip] - _inv(ra[tip], rb[tip]) + psi[tip]
            tip_centre = centres[tip] + shift[tip]
            P = tip_centre[:, None] + ra[tip] * np.stack([np.cos(ang), np.sin(ang)])
            flank_centre = centres[flank] + shift[flank]
            d = P - flank_centre[:, None]
            r = np.hypot(d[0], d[1])
            rr = np.maximum(r, rb[flank])
            polar = np.arctan2(d[1], d[0])
            phi_f = start[flank] + rolls[flank] / rb[flank] - _inv(rr, rb[flank]) + psi[flank]
            rho = np.sqrt(rr**2 - rb[flank] ** 2)
            # the normal at the contact point: tangent to the flank owner's base circle at
            # χ = ang(P − O_F) − atan(ρ/r_b); ε from the line of action's tangent point
            chi = polar - np.arctan2(rho, rb[flank])
            e = np.stack([-np.sin(chi), np.cos(chi)])
            arm = P - tip_centre[:, None]
            Q = T1[:, None] + rho1 * t[:, None]
            offset[where] = np.stack([t @ (P - Q), (nv @ (P - Q))], axis=-1)
            fields["gap"][where] = kappa[flank] * rb[flank] * _wrap(polar - phi_f)
            fields["radius"][where] = r
            fields["roll"][where] = rho
            fields["eps"][where] = _wrap(chi - start[flank])
            fields["lever"][where] = np.abs(arm[0] * e[1] - arm[1] * e[0]) / rb[tip]
            lo, hi = bounds[flank]
            on[where] = (r >= lo * (1 - 1e-12)) & (r <= hi * (1 + 1e-12))
        self.gap = fields["gap"].reshape(shape)
        self.flank_radius = fields["radius"].reshape(shape)
        self.flank_roll = fields["roll"].reshape(shape)
        self.normal_angle = fields["eps"].reshape(shape)
        self.tip_lever = fields["lever"].reshape(shape)
        self.on_flank = on.reshape(shape)
        self.offset = offset.reshape(shape + (2,))


def _form_radius(pair: AbstractGearPair, member: int) -> float:
    """The radius where member ``member``'s involute starts (its form circle; the base circle
    where the form is not known, an internal gear's involute running out to its root)."""
    rb = pair.base_radii[member]
    rho = pair.form_roll[member]
    if rho is None:
        return rb
    return math.hypot(rb, rho)


#: the largest tip-corner gap the extended cells reach: the extension stops where the gap
#: exceeds EXTENSION_GAP × m_n or EXTENSION_GAP_MIN (m), the larger (a working gear's deflection,
#: dynamic overloads and thin rims included, closes neither), or where the contact point leaves
#: the mating involute, whichever comes first; a quasi-static solve whose approach would close
#: the gap at the extension's end fails loudly (ContactResult.beyond_extension)
EXTENSION_GAP = 0.03
EXTENSION_GAP_MIN = 100e-6
#: points of each side's gap table (equally spaced over the extension)
EXTENSION_POINTS = 65


def extension_table(pair: AbstractGearPair, points: int = EXTENSION_POINTS) -> tuple:
    """How far contact can reach beyond the theoretical path of ``pair`` and the tip-corner gaps
    there: ``((S_a, S_r), gap)`` with S_a, S_r (m) the extensions before the start of contact
    and after its end, and ``gap`` (2, ``points``) (m, transverse) at s = −S_a u (row 0) and
    s = g_α + S_r u (row 1), u = linspace(0, 1, points) (:class:`CornerContact`).

    Each side stops where the gap reaches max(:data:`EXTENSION_GAP` m_n,
    :data:`EXTENSION_GAP_MIN`) or where the contact point leaves the mating flank's involute
    (below its form circle), whichever comes first; at most one base pitch."""
    g, pb = pair.path_of_contact, pair.base_pitch
    cap = max(EXTENSION_GAP * pair.normal_module, EXTENSION_GAP_MIN)
    u = np.linspace(0.0, 1.0, 2001)[1:]
    spans = []
    for side in (-1.0, 1.0):
        s = (0.0 if side < 0 else g) + side * pb * u
        c = CornerContact(pair, s)
        stop = (c.gap >= cap) | ~c.on_flank
        k = int(np.argmax(stop)) if np.any(stop) else u.size - 1
        spans.append(pb * u[max(k, 1)] if c.on_flank[k] else pb * u[max(k - 1, 1)])
    grid = np.linspace(0.0, 1.0, points)
    gap = np.stack(
        [
            np.concatenate([[0.0], CornerContact(pair, -spans[0] * grid[1:]).gap]),
            np.concatenate([[0.0], CornerContact(pair, g + spans[1] * grid[1:]).gap]),
        ]
    )
    return (float(spans[0]), float(spans[1])), gap


def corner_table(pair: AbstractGearPair, span, points: int = EXTENSION_POINTS) -> np.ndarray:
    """Where a corner cell's force acts (:class:`CornerContact`), tabulated on the grid of
    :func:`extension_table` (row 0 at s = −S_a u, row 1 at s = g_α + S_r u, u =
    linspace(0, 1, ``points``); ``span`` = (S_a, S_r), m): shape (2, 4, ``points``), for each
    side the tip owner's lever ratio λ = d_T/r_bT (-), the normal's angle ε from the line of
    action (rad) and the contact point's offset (o_t, o_v) from the line-of-action point (m)
    (:attr:`CornerContact.offset`). At u = 0 (the path's ends) λ = 1 and ε = o = 0."""
    grid = np.linspace(0.0, 1.0, points)
    out = np.zeros((2, 4, points))
    out[:, 0] = 1.0
    g = pair.path_of_contact
    for k, s in enumerate((-span[0] * grid[1:], g + span[1] * grid[1:])):
        if span[k] <= 0.0:
            continue
        c = CornerContact(pair, s)
        out[k, 0, 1:], out[k, 1, 1:] = c.tip_lever, c.normal_angle
        out[k, 2, 1:], out[k, 3, 1:] = c.offset[:, 0], c.offset[:, 1]
    return out


def line_range(path_of_contact, base_pitch, lead, span=(0.0, 0.0)) -> tuple[int, int]:
    """(first, last): the tooth-pair indices i of the contact lines s = roll + i p_bt − z tan β_b
    (roll ∈ [0, p_bt)) that can reach the cells' range [−S_a, g_α + S_r] (g_α
    ``path_of_contact``, p_bt ``base_pitch``, ``lead`` b tan β_b, ``span`` = (S_a, S_r), all
    m): line i spans [i p_bt − b tan β_b, (i + 1) p_bt)."""
    pb = float(base_pitch)
    first = -int(math.ceil(span[0] / pb * (1 - 1e-12))) if span[0] > 0 else 0
    last = int(math.floor((float(path_of_contact) + span[1] + float(lead)) / pb * (1 + 1e-12)))
    return first, last
