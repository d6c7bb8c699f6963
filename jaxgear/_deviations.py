"""Manufacturing deviations per tooth (ISO 1328-1:2013): tolerances of an accuracy grade, a
deviation model per gear, random draws for a grade, and their entry into the initial separation.

See docs/deviations.md (formulas with their clause numbers, distributions, how the deviations
enter δ0 = max e − e, evidence).

Conventions (docs/design.md, "Base plane and sign conventions"; SI units, metres):

* Every deviation is given as ISO 1328-1 measures it, in the transverse plane: the pitch
  deviations along the reference circle (the model carries them to the line of action with
  cos α_t), the profile and helix deviations along the base tangent, i.e. along the transverse line
  of action; the radial runout F_r radially. The model turns them into the flank-normal deviation
  e of the cells with cos β_b, as the TE goes the other way (TE = (u·X − max e)/cos β_b).
* Positive adds material on the working flank (moves it into the mate), as for the modifications.
* Teeth are numbered in the order they come into mesh: the contact line of tooth pair j is at
  s = r_b1 θ − j p_bt − z tan β_b (pinion angle θ, docs/design.md), so pair 0 enters (s = 0 at
  z = 0) at θ = 0; pinion tooth j mod z1 meshes there with gear tooth j mod z2.
* Tooth n's single pitch deviation f_pt,n is the deviation of the pitch from tooth n − 1 to tooth
  n (tooth −1 is tooth z − 1); they close around the gear (Σ f_pt,n = 0), and tooth n sits at the
  cumulative pitch deviation F_p,n = Σ_{m=1..n} f_pt,m from its nominal place (tooth 0 the
  reference, F_p,0 = 0). ISO's total cumulative pitch deviation F_p is max F_p,n − min F_p,n.
* Runout: an eccentricity e_r = F_r/2 of the toothing about the axis of rotation (a radial probe
  in the tooth spaces reads 2 e_r from maximum to minimum), turning with the gear at phase φ: the
  whole gear moves by e_r sin(θ_gear + φ) along the line of action (the component across the line
  slides each involute along itself and leaves the contact unchanged to first order).
"""

from __future__ import annotations

import dataclasses
import math
from decimal import ROUND_HALF_UP, Decimal, localcontext

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from ._util import as_float, check_instance, check_real

__all__ = [
    "Deviations",
    "GearDeviations",
    "ISO1328Tolerances",
    "hunting_revolutions",
    "iso1328_round",
    "iso1328_tolerances",
    "iso1328_tolerances_array",
    "sample_gear_deviations",
]

#: ISO 1328-1:2013, clause 1 (scope) and 5.2.1 (no extrapolation): the formulas hold for
#: 5 <= z <= 1000, 5 mm <= d <= 15000 mm, 0.5 mm <= m_n <= 70 mm, 4 mm <= b <= 1200 mm, β <= 45°
#: and the flank tolerance classes 1 to 11.
ISO1328_SCOPE = {
    "teeth": (5, 1000),
    "reference_diameter_mm": (5.0, 15000.0),
    "normal_module_mm": (0.5, 70.0),
    "face_width_mm": (4.0, 1200.0),
    "helix_angle_deg": (0.0, 45.0),
    "grade": (1, 11),
}
#: F_rT = 0.9 F_pT: the runout tolerance of ISO 1328-1:2013's informative annex as third-party
#: implementations give it (the annex's own text was not available; docs/deviations.md)
RUNOUT_FACTOR = 0.9


def iso1328_round(value_um: float) -> float:
    """ISO 1328-1:2013, 5.2.3: a tolerance (µm) above 10 µm is rounded to the nearest integer
    micrometre, from 5 µm to 10 µm to the nearest 0.5 µm, below 5 µm to the nearest 0.1 µm
    (halves up). The value is read as the decimal its float prints as (``repr``)."""
    return float(_round_5_2_3(Decimal(repr(float(value_um)))))


def _round_5_2_3(d: Decimal) -> Decimal:
    """:func:`iso1328_round` of an exact decimal (µm)."""
    if d > 10:
        return d.quantize(Decimal(1), rounding=ROUND_HALF_UP)
    if d >= 5:
        return (2 * d).quantize(Decimal(1), rounding=ROUND_HALF_UP) / 2
    return d.quantize(Decimal("0.1"), rounding=ROUND_HALF_UP)


#: significant digits to which a length in mm is read (a drawing's decimal; removes the binary
#: noise of m → mm and of d = z m_n / cos β)
_MM_DIGITS = 12


def _mm(value_m: float) -> Decimal:
    """A length in metres as a decimal in mm, to :data:`_MM_DIGITS` significant digits."""
    return Decimal(f"{float(value_m) * 1e3:.{_MM_DIGITS}g}")


def _class_step(grade: int) -> Decimal:
    """The step factor (√2)^(A − 5) between classes (5.2.2): an exact power of 2 for an even
    A − 5 (the classes 1, 3, 5, 7, 9, 11), 2^k √2 otherwise (irrational: no rounding tie)."""
    e = grade - 5
    two = Decimal(2)
    return two ** (e // 2) * (two.sqrt() if e % 2 else 1)


@dataclasses.dataclass(frozen=True)
class ISO1328Tolerances:
    """ISO 1328-1:2013 flank tolerances of one gear (m, rounded by 5.2.3 unless asked not to).

    Attributes:
        single_pitch: f_pT, formula (5). cumulative_pitch: F_pT, total cumulative pitch (6).
        profile_slope: f_HαT (7), a ± tolerance. profile_form: f_fαT (8). profile_total: F_αT (9).
        helix_slope: f_HβT (10), a ± tolerance. helix_form: f_fβT (11). helix_total: F_βT (12).
        runout: F_rT = 0.9 F_pT (the runout annex, see :data:`RUNOUT_FACTOR`).
        grade: the flank tolerance class A (1 to 11).
    """

    single_pitch: float
    cumulative_pitch: float
    profile_slope: float
    profile_form: float
    profile_total: float
    helix_slope: float
    helix_form: float
    helix_total: float
    runout: float
    grade: int

    def as_um(self) -> dict:
        """The tolerances in µm, keyed by their ISO symbols (f_pT, F_pT, …, F_rT)."""
        names = {
            "f_pT": "single_pitch",
            "F_pT": "cumulative_pitch",
            "f_HaT": "profile_slope",
            "f_faT": "profile_form",
            "F_aT": "profile_total",
            "f_HbT": "helix_slope",
            "f_fbT": "helix_form",
            "F_bT": "helix_total",
            "F_rT": "runout",
        }
        return {k: round(getattr(self, v) * 1e6, 6) for k, v in names.items()}


def _check_scope(name: str, value, unit: str = "") -> None:
    lo, hi = ISO1328_SCOPE[name]
    if not (lo <= value <= hi):
        raise ValueError(
            f"ISO 1328-1 {name} = {value:g}{unit} is out of range: allowed [{lo:g}, {hi:g}]{unit} "
            "(the standard's formulas are not extrapolated, 5.2.1)"
        )


def iso1328_tolerances(
    normal_module: float,
    reference_diameter: float,
    face_width: float,
    grade: int,
    *,
    rounded: bool = True,
) -> ISO1328Tolerances:
    """The ISO 1328-1:2013 flank tolerances of a gear of flank tolerance class ``grade``.

    With m_n, d, b in mm and the step factor (√2)^(A − 5) between classes (5.2.2), in µm:

    * (5)  f_pT = (0.001 d + 0.4 m_n + 5) (√2)^(A−5)
    * (6)  F_pT = (0.002 d + 0.55 √d + 0.7 m_n + 12) (√2)^(A−5)
    * (7)  f_HαT = (0.4 m_n + 0.001 d + 4) (√2)^(A−5)
    * (8)  f_fαT = (0.55 m_n + 5) (√2)^(A−5)
    * (9)  F_αT = √(f_HαT² + f_fαT²)
    * (10) f_HβT = (0.05 √d + 0.35 √b + 4) (√2)^(A−5)
    * (11) f_fβT = (0.07 √d + 0.45 √b + 4) (√2)^(A−5)
    * (12) F_βT = √(f_HβT² + f_fβT²)
    * F_rT = 0.9 F_pT (runout annex)

    The totals (9), (12) and F_rT are computed from the unrounded values, then each value is
    rounded by 5.2.3 (:func:`iso1328_round`) unless ``rounded`` is False. The arithmetic is
    decimal, m_n, d and b read in mm to 12 significant digits: an exact tie such as
    f_fαT = 9.4 · 0.25 = 2.35 µm (m_n 8 mm, class 1) rounds up to 2.4, as the standard's
    arithmetic gives (binary floats made it 2.3499… → 2.3 in classes 1, 3, …).

    Args:
        normal_module: m_n (m). reference_diameter: d = z m_n / cos β (m). face_width: b (m).
        grade: flank tolerance class A, an integer in [1, 11].
        rounded: apply the rounding rules of 5.2.3 (default).

    Returns:
        :class:`ISO1328Tolerances` in metres.

    Raises:
        ValueError: a grade that is not an integer in [1, 11], or m_n, d, b outside the
            standard's scope (clause 1; 5.2.1 forbids extrapolation), naming the value and range.
    """
    if isinstance(grade, bool) or int(grade) != grade:
        raise ValueError(f"ISO 1328-1 grade = {grade!r} is out of range: allowed an integer 1-11")
    grade = int(grade)
    _check_scope("grade", grade)
    m, d, b = normal_module * 1e3, reference_diameter * 1e3, face_width * 1e3
    _check_scope("normal_module_mm", m, " mm")
    _check_scope("reference_diameter_mm", d, " mm")
    _check_scope("face_width_mm", b, " mm")
    # in decimal arithmetic (50 digits; exact but for square roots of non-squares and odd
    # steps): a value that is a rounding tie of 5.2.3 is one exactly, rounded half up (binary
    # floats put (√2)^(A−5) a bit below a power of 2 and 0.001 d off its decimal)
    with localcontext() as ctx:
        ctx.prec = 50
        m, d, b = _mm(normal_module), _mm(reference_diameter), _mm(face_width)
        step, D = _class_step(grade), Decimal
        raw = {
            "single_pitch": (D("0.001") * d + D("0.4") * m + 5) * step,
            "cumulative_pitch": (D("0.002") * d + D("0.55") * d.sqrt() + D("0.7") * m + 12)
            * step,
            "profile_slope": (D("0.4") * m + D("0.001") * d + 4) * step,
            "profile_form": (D("0.55") * m + 5) * step,
            "helix_slope": (D("0.05") * d.sqrt() + D("0.35") * b.sqrt() + 4) * step,
            "helix_form": (D("0.07") * d.sqrt() + D("0.45") * b.sqrt() + 4) * step,
        }
        raw["profile_total"] = (raw["profile_slope"] ** 2 + raw["profile_form"] ** 2).sqrt()
        raw["helix_total"] = (raw["helix_slope"] ** 2 + raw["helix_form"] ** 2).sqrt()
        raw["runout"] = Decimal(repr(RUNOUT_FACTOR)) * raw["cumulative_pitch"]
        rnd = _round_5_2_3 if rounded else (lambda v: v)
        return ISO1328Tolerances(
            **{k: float(rnd(v)) * 1e-6 for k, v in raw.items()}, grade=grade
        )


#: the relative amount :func:`iso1328_tolerances_array` lifts a value before it rounds, so that
#: a decimal tie (2.35 µm read in binary as 2.3499…) rounds up as the standard's decimal
#: arithmetic does; far above float64's round-off of the formulas (1e-15) and far below any
#: step of the rounding (0.1 µm in 5 µm: 2e-2)
TIE_LIFT = 1e-11


def _round_5_2_3_array(um):
    """5.2.3's rounding (:func:`iso1328_round`) of an array of tolerances (µm), jnp: halves up
    after a lift of :data:`TIE_LIFT` (a decimal tie read in binary)."""
    v = um * (1 + TIE_LIFT)
    return jnp.where(
        v > 10, jnp.floor(v + 0.5), jnp.where(v >= 5, jnp.floor(2 * v + 0.5) / 2,
                                              jnp.floor(10 * v + 0.5) / 10)
    )


def iso1328_tolerances_array(normal_module, reference_diameter, face_width, grade: int):
    """The tolerances of ISO 1328-1:2013 the rating reads, as ``jax.numpy`` functions of the
    dimensions (traceable, broadcasting over gears or candidates): f_pT (5), f_fαT (8) and
    f_HβT (10) (m), rounded by 5.2.3, the formulas of :func:`iso1328_tolerances` in binary
    floats (a decimal tie lifted by :data:`TIE_LIFT` so that it rounds up as there). Equal to
    :func:`iso1328_tolerances` to the last bit or one ulp (the rounded µm value carried to m),
    but where a value lies within 1e-11 of a rounding step without being on it. The standard's scope (m_n, d, b) is not checked (values may be traced): check
    it where the dimensions are known (:data:`ISO1328_SCOPE`).

    Args:
        normal_module: m_n (m). reference_diameter: d (m). face_width: b (m); arrays that
            broadcast. grade: the flank tolerance class A, a Python integer in [1, 11]
            (static).

    Returns:
        (f_pT, f_fαT, f_HβT) in metres, each of the broadcast shape.

    Raises:
        ValueError: a grade that is not an integer in [1, 11].
    """
    if isinstance(grade, bool) or int(grade) != grade:
        raise ValueError(f"ISO 1328-1 grade = {grade!r} is out of range: allowed an integer 1-11")
    _check_scope("grade", int(grade))
    step = float(_class_step(int(grade)))
    m, d, b = normal_module * 1e3, reference_diameter * 1e3, face_width * 1e3
    f_pt = (0.001 * d + 0.4 * m + 5) * step
    f_fa = (0.55 * m + 5) * step
    f_hb = (0.05 * jnp.sqrt(d) + 0.35 * jnp.sqrt(b) + 4) * step
    return tuple(_round_5_2_3_array(v) * 1e-6 for v in (f_pt, f_fa, f_hb))


def hunting_revolutions(teeth_pinion: int, teeth_gear: int) -> int:
    """Pinion revolutions of the hunting-tooth period, z2 / gcd(z1, z2): after it every pinion
    tooth has met every gear tooth it ever meets, and both gears are back at their start."""
    return int(teeth_gear) // math.gcd(int(teeth_pinion), int(teeth_gear))


class GearDeviations(eqx.Module):
    """Manufacturing deviations of one gear, per tooth (m; ISO 1328-1 quantities, module
    docstring for the conventions). Arrays have one entry per tooth, shape (z,), tooth 0 first.

    Attributes:
        single_pitch: f_pt,n (m) on the reference circle, closing around the gear (Σ = 0; not
            checked here, where the values may be traced: the case file checks it).
        runout: radial runout F_r = 2 e_r (m), >= 0; runout_phase: φ (rad).
        profile_slope: f_Hα,n (m): e = f_Hα (u − ½) along the active profile (u the roll fraction,
            0 at the start of active profile, 1 at the tip): + adds material at the tip.
        profile_form: c_α,n (m), signed: e = c_α (2u − 1)², a profile form deviation |c_α|
            (+: hollow, material added at both ends; −: barrel).
        helix_slope: f_Hβ,n (m): e = f_Hβ (ζ − ½) across the face (ζ = z/b): + adds at z = b.
        helix_form: c_β,n (m), signed: e = c_β (2ζ − 1)², a helix form deviation |c_β|.
        reference_pressure_angle: α_t (rad) of the reference circle the pitch deviations are
            measured on: the line of action sees f_pt cos α_t (0: given on the line of action).

    Raises:
        ValueError: (one line) per-tooth arrays of another shape than (z,), and, on concrete
            values (a traced draw is not known here), a value that is not finite or a runout
            < 0.
    """

    single_pitch: Float[Array, " z"]
    runout: Float[Array, ""]
    runout_phase: Float[Array, ""]
    profile_slope: Float[Array, " z"]
    profile_form: Float[Array, " z"]
    helix_slope: Float[Array, " z"]
    helix_form: Float[Array, " z"]
    reference_pressure_angle: Float[Array, ""]

    def __init__(
        self,
        single_pitch,
        runout=0.0,
        runout_phase=0.0,
        profile_slope=0.0,
        profile_form=0.0,
        helix_slope=0.0,
        helix_form=0.0,
        reference_pressure_angle=0.0,
    ):
        self.single_pitch = as_float(single_pitch)
        z = self.single_pitch.shape[:1]
        self.runout = as_float(runout)
        self.runout_phase = as_float(runout_phase)
        for name, v in (
            ("profile_slope", profile_slope),
            ("profile_form", profile_form),
            ("helix_slope", helix_slope),
            ("helix_form", helix_form),
        ):
            v = as_float(v)
            setattr(self, name, jnp.broadcast_to(v, z) if v.ndim == 0 else v)
        self.reference_pressure_angle = as_float(reference_pressure_angle)

    def __check_init__(self):
        z = self.single_pitch.shape
        if self.single_pitch.ndim != 1 or z[0] < 1:
            raise ValueError(
                f"single_pitch: shape {z} is out of range: allowed one value per tooth, (z,)"
            )
        for name in ("profile_slope", "profile_form", "helix_slope", "helix_form"):
            if getattr(self, name).shape != z:
                raise ValueError(
                    f"{name}: shape {getattr(self, name).shape} is out of range: allowed one value "
                    f"per tooth, {z} (or a scalar for every tooth)"
                )
        # finite values, runout >= 0, on concrete values (a traced draw is not known here)
        for name in ("runout_phase", "reference_pressure_angle"):
            check_real(name, getattr(self, name), "rad", shape=(), where="GearDeviations")
        check_real("runout", self.runout, "m", lo=0.0, shape=(), where="GearDeviations")
        for name in ("single_pitch", "profile_slope", "profile_form", "helix_slope", "helix_form"):
            check_real(name, getattr(self, name), "m", where="GearDeviations")

    @property
    def teeth(self) -> int:
        """Number of teeth z (static: the length of the per-tooth arrays)."""
        return self.single_pitch.shape[0]

    @property
    def cumulative_pitch(self) -> Float[Array, " z"]:
        """F_p,n = Σ_{m=1..n} f_pt,m (m), tooth 0 the reference (F_p,0 = 0)."""
        return jnp.cumsum(self.single_pitch) - self.single_pitch[0]

    def line_deviation(self, tooth, angle, u, zeta):
        """Deviation of the working flank of tooth ``tooth`` (integer array) along the transverse
        line of action (m), the gear turned by ``angle`` (rad), at roll fraction ``u`` and lead
        fraction ``zeta`` (broadcast)."""
        pos = self.cumulative_pitch[tooth] * jnp.cos(self.reference_pressure_angle)
        ecc = 0.5 * self.runout * jnp.sin(angle + self.runout_phase)
        profile = (
            self.profile_slope[tooth] * (u - 0.5) + self.profile_form[tooth] * (2.0 * u - 1.0) ** 2
        )
        helix = (
            self.helix_slope[tooth] * (zeta - 0.5)
            + self.helix_form[tooth] * (2.0 * zeta - 1.0) ** 2
        )
        return pos + ecc + profile + helix

    def summary(self) -> dict:
        """The values (µm; the phase in degrees) as lists, per tooth from tooth 0, and ISO's
        totals over the gear: F_p (max − min of F_p,n), the largest |f_pt|, F_r."""
        um = lambda v: [round(float(x) * 1e6, 6) for x in np.asarray(v)]
        cum = np.asarray(self.cumulative_pitch)
        return {
            "teeth": self.teeth,
            "single_pitch_um": um(self.single_pitch),
            "cumulative_pitch_um": um(cum),
            "total_cumulative_pitch_um": round(float(cum.max() - cum.min()) * 1e6, 6),
            "max_single_pitch_um": round(float(np.abs(self.single_pitch).max()) * 1e6, 6),
            "runout_um": round(float(self.runout) * 1e6, 6),
            "runout_phase_deg": round(math.degrees(float(self.runout_phase)), 6),
            "profile_slope_um": um(self.profile_slope),
            "profile_form_um": um(self.profile_form),
            "helix_slope_um": um(self.helix_slope),
            "helix_form_um": um(self.helix_form),
        }


class Deviations(eqx.Module):
    """Manufacturing deviations of both members of a mesh (``None``: a perfect member). Carried by
    :class:`~jaxgear.Modifications` (``deviations=``), they enter the initial separation of the
    cells through :func:`~jaxgear.separation` (docs/deviations.md, "Initial separation")."""

    pinion: GearDeviations | None = None
    gear: GearDeviations | None = None

    def __check_init__(self):
        for tag in ("pinion", "gear"):
            g = getattr(self, tag)
            if g is not None:
                allowed = "a jaxgear.GearDeviations or None"
                check_instance(tag, g, GearDeviations, allowed, "Deviations")

    def teeth(self) -> tuple[int | None, int | None]:
        """(z1, z2) of the members that have deviations."""
        return tuple(None if g is None else g.teeth for g in (self.pinion, self.gear))

    def check(self, mesh) -> None:
        """Refuse, eagerly, per-tooth arrays whose lengths are not the mesh's tooth counts
        (z1 = 2π r_b1/p_bt, z2 = 2π r_b2/p_bt).

        Raises:
            ValueError: naming the member, the array length and the tooth count.
        """
        try:
            p = float(mesh.base_pitch)
            z = (
                round(2 * math.pi * float(mesh.base_radius_pinion) / p),
                round(2 * math.pi * float(mesh.base_radius_gear) / p),
            )
        except (TypeError, jax.errors.ConcretizationTypeError):  # traced: nothing to check
            return
        for tag, n, g in zip(("pinion", "gear"), z, (self.pinion, self.gear), strict=True):
            if g is not None and g.teeth != n:
                raise ValueError(
                    f"deviations.{tag}: {g.teeth} teeth is out of range: allowed one value per "
                    f"tooth of the {tag} ({n} teeth)"
                )

    def deviation(self, mesh, cells) -> Float[Array, "n_lines n_slices"]:
        """Flank-normal deviation e (m) of the cells ``cells`` of ``mesh`` (the pair's: pinion plus
        gear, each at the tooth of the cell's tooth pair), to add to the modifications' e.

        Tooth pair of line i at pinion angle θ: j = k − i with k = (r_b1 θ − (r_b1 θ mod p_bt))
        /p_bt the whole mesh periods turned; pinion tooth j mod z1, gear tooth j mod z2; the
        gear turned by θ z1/z2.
        """
        r1, pb = mesh.base_radius_pinion, mesh.base_pitch
        arc = r1 * cells.theta
        k = jnp.round((arc - jnp.mod(arc, pb)) / pb)
        pair = (k - cells.line).astype(jnp.int32)
        u = cells.s / mesh.path_of_contact
        zeta = cells.z / mesh.face_width
        e = jnp.zeros_like(cells.s)
        if self.pinion is not None:
            z1 = self.pinion.teeth
            e = e + self.pinion.line_deviation(jnp.mod(pair, z1), cells.theta, u, zeta)
        if self.gear is not None:
            z2 = self.gear.teeth
            angle = cells.theta * r1 / mesh.base_radius_gear  # θ2 = θ z1/z2
            e = e + self.gear.line_deviation(jnp.mod(pair, z2), angle, 1.0 - u, zeta)
        return e * jnp.cos(mesh.base_helix_angle)


# --------------------------------------------------------------------------------------------
# random draws for an accuracy grade


def sample_gear_deviations(
    rng: np.random.Generator,
    teeth: int,
    tolerances: ISO1328Tolerances,
    reference_pressure_angle: float = 0.0,
) -> GearDeviations:
    """Draw a gear of ISO 1328-1 flank tolerance class ``tolerances.grade`` (NumPy, eager).

    Distributions (docs/deviations.md, "Random draws"), all independent:

    * single pitch: u_n ~ U(−f_pT, f_pT) per tooth, closed around the gear (u_n − mean u), then
      scaled by s = min(1, f_pT / max|f_pt|, F_pT / (max F_p − min F_p)), so that the gear meets
      both f_pT and F_pT (s < 1 mostly for many teeth, where the closed random walk of the
      cumulative pitch outgrows F_pT);
    * runout: F_r ~ U(0, F_rT), phase φ ~ U(0, 2π);
    * per tooth, independently: profile slope f_Hα ~ U(−f_HαT, f_HαT), profile form
      c_α ~ U(−f_fαT, f_fαT), then both scaled down together where the tooth's total profile
      deviation (the range of f_Hα (u − ½) + c_α (2u − 1)² over u ∈ [0, 1]) exceeds F_αT;
      likewise the helix with f_HβT, f_fβT, F_βT.

    Args:
        rng: a NumPy ``Generator`` (``np.random.default_rng(seed)``: reproducible).
        teeth: z. tolerances: :func:`iso1328_tolerances` of the gear.
        reference_pressure_angle: α_t (rad) of the gear (the pitch deviations are on its reference
            circle).

    Returns:
        :class:`GearDeviations` (float64 arrays made with the current default dtype).
    """
    z = int(teeth)
    if z < 2:
        raise ValueError(f"teeth = {teeth!r} is out of range: allowed an integer >= 2")
    t = tolerances
    fpt = rng.uniform(-t.single_pitch, t.single_pitch, z)
    fpt = fpt - fpt.mean()
    cum = np.cumsum(fpt) - fpt[0]
    scale = min(
        1.0,
        t.single_pitch / max(np.abs(fpt).max(), 1e-300),
        t.cumulative_pitch / max(cum.max() - cum.min(), 1e-300),
    )
    fpt = fpt * scale
    fr = rng.uniform(0.0, t.runout)
    phase = rng.uniform(0.0, 2.0 * math.pi)
    p_slope, p_form = _slope_form(rng, z, t.profile_slope, t.profile_form, t.profile_total)
    h_slope, h_form = _slope_form(rng, z, t.helix_slope, t.helix_form, t.helix_total)
    return GearDeviations(
        single_pitch=fpt,
        runout=fr,
        runout_phase=phase,
        profile_slope=p_slope,
        profile_form=p_form,
        helix_slope=h_slope,
        helix_form=h_form,
        reference_pressure_angle=reference_pressure_angle,
    )


def total_range(slope, form):
    """Range (max − min) of slope·(x − ½) + form·(2x − 1)² over x ∈ [0, 1] (NumPy, per tooth):
    the total profile (helix) deviation F_α (F_β) of a trace of that slope and form."""
    x = np.linspace(0.0, 1.0, 201)[:, None]
    trace = np.asarray(slope)[None, :] * (x - 0.5) + np.asarray(form)[None, :] * (2 * x - 1) ** 2
    return trace.max(axis=0) - trace.min(axis=0)


def _slope_form(rng, z, slope_tol, form_tol, total_tol):
    slope = rng.uniform(-slope_tol, slope_tol, z)
    form = rng.uniform(-form_tol, form_tol, z)
    total = total_range(slope, form)
    s = np.minimum(1.0, total_tol / np.maximum(total, 1e-300))
    return slope * s, form * s
