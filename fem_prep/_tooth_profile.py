"""The transverse tooth form of one member as a polar half-angle table, for the plane-strain FE
tooth model (:mod:`fem_prep._tooth_fe`).

The fillet is a kind passed as an object: :class:`TrochoidFillet` (the rack-generated trochoid of
:func:`fem_prep.tooth_form.generate_tooth`, the default) or :class:`CircularFillet` (a circular arc
tangent to the root circle, the approximation ``weber`` used before: kept for comparison, 1.6 %
more compliant on ROSS's gear).  NumPy only (never JAX); a constant for jaxgear.
"""

from __future__ import annotations

import abc
import functools
import math
from dataclasses import dataclass
from typing import ClassVar, final

import numpy as np

from ._kinds import Kind
from .tooth_form import InternalToothGeometry, ToothGeometry, generate_tooth, involute

__all__ = [
    "CircularFillet",
    "FilletForm",
    "InternalCircularFillet",
    "InternalToothProfile",
    "ToothProfile",
    "TrochoidFillet",
    "tooth_profile",
]


# ------------------------------------------------------------------------------------------
# the tooth form as a polar half-angle table


@dataclass(frozen=True)
class ToothProfile:
    """One member's transverse tooth form as a polar table (SI units, angles in rad).

    The tooth centre line is the +y axis, the gear centre the origin; the right flank is
    ``x = r sin ψ(r), y = r cos ψ(r)`` for ``root_radius <= r <= tip_radius``.

    Attributes:
        teeth: z. root_radius, tip_radius, base_radius, form_radius: r_f, r_a, r_b, r_F (m).
        root_half_angle: ψ_f (rad), the polar half angle of the fillet/root-circle tangency
            point (at most π/z).
        r_tab: radii (m), shape (n,), increasing from r_f to r_a.
        psi_tab: half angles ψ(r) (rad), shape (n,), decreasing.
        source: the fillet's name: ``"tooth_form"`` (:class:`TrochoidFillet`) or
            ``"circular_fillet"`` (:class:`CircularFillet`).
    """

    teeth: int
    root_radius: float
    tip_radius: float
    base_radius: float
    form_radius: float
    root_half_angle: float
    r_tab: np.ndarray
    psi_tab: np.ndarray
    source: str

    def psi(self, r):
        """Half angle ψ(r) (rad) of the tooth at radius r (m); any shape."""
        return np.interp(r, self.r_tab, self.psi_tab)

    def r_of_psi(self, psi):
        """Radius (m) of the flank/fillet at half angle ψ (rad), ψ in [ψ(r_a), ψ_f]."""
        return np.interp(psi, self.psi_tab[::-1], self.r_tab[::-1])

    @property
    def form_roll(self) -> float:
        """Roll distance ρ_F (m) of the form circle (start of the involute)."""
        return math.sqrt(max(self.form_radius**2 - self.base_radius**2, 0.0))

    @property
    def tip_roll(self) -> float:
        """Roll distance ρ_a (m) of the tip."""
        return math.sqrt(self.tip_radius**2 - self.base_radius**2)


@dataclass(frozen=True)
class InternalToothProfile(ToothProfile):
    """An internal gear's (a ring's) transverse tooth form as a polar table: the tooth points
    inwards, its tip circle inside its root circle (SI units, angles in rad).

    The fields are :class:`ToothProfile`'s with the internal tooth's contract
    (:class:`~fem_prep.InternalToothGeometry`): ``teeth`` |z|; ``tip_radius`` r_a <
    ``form_radius`` r_F < ``root_radius`` r_f; ``r_tab`` increasing from r_a to r_f and
    ``psi_tab`` the half angle ψ(r), increasing with r (the tooth widens towards its root);
    ``root_half_angle`` ψ_f = ψ(r_f) <= π/|z|, where the fillet meets the root circle.  The
    concave right flank is ``x = r sin ψ(r), y = r cos ψ(r)``, the ring's centre at the origin;
    its roll distances grow from the tip (:attr:`tip_roll`) to the form circle
    (:attr:`form_roll`).
    """

    def r_of_psi(self, psi):
        """Radius (m) of the flank/fillet at half angle ψ (rad), ψ in [ψ(r_a), ψ_f]."""
        return np.interp(psi, self.psi_tab, self.r_tab)

    def mirrored(self, radius: float) -> ToothProfile:
        """The external tooth of the radial mirror r' = ``radius`` − r (``radius`` > r_f): the
        same half angles at the mirrored radii, root r' = radius − r_f, tip r' = radius − r_a
        (the plane mesh of an internal tooth is the mesh of this one, its vertices mapped back;
        :func:`fem_prep.mesh_sector`).  ``base_radius`` is 0 (no involute of its own)."""
        c = float(radius)
        return ToothProfile(
            teeth=self.teeth,
            root_radius=c - self.root_radius,
            tip_radius=c - self.tip_radius,
            base_radius=0.0,
            form_radius=c - self.form_radius,
            root_half_angle=self.root_half_angle,
            r_tab=c - self.r_tab[::-1],
            psi_tab=self.psi_tab[::-1],
            source=self.source,
        )


def _internal_circular_table(g: InternalToothGeometry) -> dict:
    """ψ(r) table of an internal tooth: the exact involute (ISO 21771: ψ(r) = s_t/(2|r|) −
    inv α_t + inv α_r, the ring's tooth thickness s_t = m_t (π/2 + 2 x tan α_n)) and a circular
    arc of radius ρ_fP tangent to it and to the root circle (inside it, in the tooth space);
    ρ_fP is reduced to the full round of the space bottom where it does not fit."""
    z = abs(g.teeth)
    mn, an, x = g.normal_module, g.normal_pressure_angle, g.profile_shift
    _mt, at, r, rb, st = _transverse(z, mn, an, g.helix_angle, x)
    ra, rf = g.tip_radius, g.root_radius
    if not ra > rb:
        raise ValueError(
            f"addendum_coeff = {g.addendum_coeff!r} is out of range: the tip radius "
            f"{ra * 1e3:.6g} mm must exceed the base radius {rb * 1e3:.6g} mm"
        )
    k = st / (2 * r) - float(involute(at))

    def psi_inv(rr):
        return k + involute(np.arccos(np.clip(rb / rr, -1.0, 1.0)))

    def arc(rho):
        """Tangency radius r_q on the involute, arc centre P, root tangency angle ψ_f."""
        from scipy.optimize import brentq  # lazy: only the internal tooth needs it

        def centre(rq):
            psi = float(psi_inv(rq))
            al = math.acos(rb / rq)
            q = rq * np.array([math.sin(psi), math.cos(psi)])
            t = rb * np.array([math.sin(psi + al), math.cos(psi + al)])
            return q, q + rho * (t - q) / np.linalg.norm(t - q)

        rq = brentq(lambda v: np.linalg.norm(centre(v)[1]) - (rf - rho), ra, rf, xtol=1e-15)
        q, p = centre(rq)
        return rq, q, p, math.atan2(p[0], p[1])

    rho = g.fillet_radius_coeff * mn
    if rho > 0 and arc(rho)[3] > math.pi / z:  # the full round: ψ_f = π/|z|
        lo, hi = 0.0, rho
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if arc(mid)[3] <= math.pi / z else (lo, mid)
        rho = lo
    if rho > 0:
        r_form, q, p, _psi_f = arc(rho)
        a0 = math.atan2(*(q - p)[::-1])
        turn = (math.atan2(p[1], p[0]) - a0 + math.pi) % (2 * math.pi) - math.pi
        th = a0 + turn * np.linspace(0.0, 1.0, 400)  # dense in r at the root tangency
        pts = p[None, :] + rho * np.stack([np.cos(th), np.sin(th)], -1)
        r_arc = np.hypot(pts[:, 0], pts[:, 1])[1:]
        psi_arc = np.arctan2(pts[:, 0], pts[:, 1])[1:]
        r_arc[-1] = rf
    else:
        r_form, r_arc, psi_arc = rf, np.zeros(0), np.zeros(0)
    r_inv = np.linspace(ra, r_form, 400)
    r_tab = np.concatenate([r_inv, r_arc])
    psi_tab = np.concatenate([psi_inv(r_inv), psi_arc])
    ok = np.concatenate([[True], np.diff(r_tab) > 1e-12 * rf])
    return {
        "root_radius": rf,
        "tip_radius": ra,
        "base_radius": rb,
        "form_radius": float(r_form),
        "r_tab": r_tab[ok],
        "psi_tab": np.minimum(np.maximum.accumulate(psi_tab[ok]), math.pi / z),
    }


def _transverse(teeth, mn, an, beta, x):
    mt = mn / math.cos(beta)
    at = math.atan(math.tan(an) / math.cos(beta))
    r = teeth * mt / 2
    rb = r * math.cos(at)
    st = mt * (math.pi / 2 + 2 * x * math.tan(an))
    return mt, at, r, rb, st


def _circular_fillet_table(teeth, mn, an, beta, x, ha, hf, rho_c):
    """ψ(r) table of the involute with a circular-arc fillet of radius min(ρ_fP, r_F − r_f)
    tangent to the root circle (the approximation ``weber`` used before the generated form)."""
    _mt, at, r, rb, st = _transverse(teeth, mn, an, beta, x)
    ra = r + mn * (ha + x)
    rf = r - mn * (hf - x)
    h = mn * (hf - x - rho_c * (1 - math.sin(an)))
    rho_f = r * math.sin(at) - h / math.sin(at)
    r_form = max(math.hypot(rho_f, rb), rb)

    def psi_inv(rr):
        ar = np.arccos(np.clip(rb / rr, -1.0, 1.0))
        return st / (2 * r) + float(involute(at)) - involute(ar)

    half_form = r_form * math.sin(float(psi_inv(np.array(r_form))))
    rho = min(rho_c * mn, max(r_form - rf, 0.0))
    # involute from the form circle to the tip
    r_inv = np.linspace(r_form, ra, 400)
    parts_r = [r_inv]
    parts_half = [r_inv * np.sin(psi_inv(r_inv))]
    if r_form - rf > rho:  # constant chordal half thickness between the fillet and r_form
        rr = np.linspace(rf + rho, r_form, 50)[:-1]
        parts_r.insert(0, rr)
        parts_half.insert(0, np.full_like(rr, half_form))
    if rho > 0:
        th = np.linspace(0.0, math.pi / 2, 400)[:-1]  # fillet arc, dense at the tangency
        parts_r.insert(0, rf + rho * (1 - np.cos(th)))
        parts_half.insert(0, half_form + rho * (1 - np.sin(th)))
    r_tab = np.concatenate(parts_r)
    half = np.concatenate(parts_half)
    psi_tab = np.arcsin(np.clip(half / r_tab, -1.0, 1.0))
    psi_tab = np.minimum(psi_tab, math.pi / teeth)
    return {
        "root_radius": rf,
        "tip_radius": ra,
        "base_radius": rb,
        "form_radius": r_form,
        "r_tab": r_tab,
        "psi_tab": psi_tab,
    }


def _form_table(form) -> dict:
    """ψ(r) table of a ``fem_prep.tooth_form.ToothForm``: its right fillet points (root
    junction to form point) and the closed-form involute above the form circle."""
    fil = np.asarray(form.fillet, dtype=float)
    r_fil = np.hypot(fil[:, 0], fil[:, 1])
    psi_fil = np.arctan2(fil[:, 0], fil[:, 1])
    r_inv = np.linspace(float(form.form_radius), float(form.tip_radius), 400)[1:]
    r = np.concatenate([r_fil, r_inv])
    psi = np.concatenate([psi_fil, form.involute_half_angle(r_inv)])
    ok = np.concatenate([[True], np.diff(r) > 1e-12 * r[-1]])
    return form_table(form, r[ok], np.minimum.accumulate(psi[ok]))


def form_table(form, r: np.ndarray, psi: np.ndarray) -> dict:
    """The ψ(r) table dict of a generated tooth ``form`` (external or internal: its radii) with
    radii ``r`` (m, increasing) and half angles ``psi`` (rad), capped at π/|z|."""
    return {
        "root_radius": float(form.root_radius),
        "tip_radius": float(form.tip_radius),
        "base_radius": float(form.base_radius),
        "form_radius": float(form.form_radius),
        "r_tab": r,
        "psi_tab": np.minimum(psi, math.pi / abs(form.teeth)),
    }


class FilletForm(Kind):
    """Where the tooth form's fillet comes from; its :attr:`name` is the profile's ``source``
    (and part of the FE cache key)."""

    @abc.abstractmethod
    def table(self, geometry: ToothGeometry) -> dict:
        """The ψ(r) table of the member: ``root_radius``, ``tip_radius``, ``base_radius``,
        ``form_radius`` (m), ``r_tab`` (m) and ``psi_tab`` (rad)."""


@final
class TrochoidFillet(FilletForm):
    """The rack-generated trochoid fillet (:func:`fem_prep.tooth_form.generate_tooth`, 200
    fillet points), the default."""

    name: ClassVar[str] = "tooth_form"

    def table(self, geometry):
        return _form_table(generate_tooth(geometry, n_fillet=200))


@final
class CircularFillet(FilletForm):
    """A circular arc tangent to the root circle (the former ``weber`` approximation)."""

    name: ClassVar[str] = "circular_fillet"

    def table(self, geometry):
        g = geometry
        return _circular_fillet_table(
            g.teeth,
            g.normal_module,
            g.normal_pressure_angle,
            g.helix_angle,
            g.profile_shift,
            g.addendum_coeff,
            g.dedendum_coeff,
            g.fillet_radius_coeff,
        )


@final
class InternalCircularFillet(FilletForm):
    """An internal tooth's fillet as a circular arc of radius ρ_fP = ``fillet_radius_coeff`` ·
    m_n tangent to the involute and to the root circle (reduced to the full round of the space
    bottom where it does not fit): the internal analogue of :class:`CircularFillet`, a stand-in
    for the shaper-generated fillet. Its :meth:`table` takes an
    :class:`~fem_prep.InternalToothGeometry`."""

    name: ClassVar[str] = "internal_circular_fillet"

    def table(self, geometry):
        return _internal_circular_table(geometry)


@functools.singledispatch
def tooth_profile(geometry: ToothGeometry, *, form: FilletForm | None = None) -> ToothProfile:
    """The transverse tooth form of one member (ISO 21771 notation).

    Args:
        geometry: the member's :class:`fem_prep.ToothGeometry`.
        form: the fillet, :class:`TrochoidFillet` (``None``: the default; the generated trochoid
            fillet, :mod:`fem_prep.tooth_form`) or :class:`CircularFillet` (a circular arc
            tangent to the root circle: the former ``weber`` approximation, kept for
            comparison).

    Returns:
        The :class:`ToothProfile` (``source`` the fillet's name).

    Raises:
        ValueError: ``form`` is not a :class:`FilletForm`.
    """
    form = TrochoidFillet() if form is None else form
    if not isinstance(form, FilletForm):
        raise ValueError(
            f"form = {form!r}; use fem_prep.TrochoidFillet() or fem_prep.CircularFillet()"
        )
    g = geometry
    tab = form.table(g)
    return ToothProfile(
        teeth=g.teeth,
        root_half_angle=float(tab["psi_tab"][0]),
        source=str(form),
        **tab,
    )
