"""Gear trains: their one description (:class:`TrainSpec`), their layout in the plane and their
phasing (:func:`train_layout`), and what every train scene shares (:class:`GearTrain`: the rigid
rotation, the shaft speeds and torques of the meshes and the span of first-mesh periods after
which every mesh repeats; docs/trains.md).

A train is described once, as a :class:`TrainSpec` (its meshes and gears, their layout and
phases, the shafts, the gear bodies, the loads and the material), and each scene kind is built
from that one description: the torsional train (:meth:`~jaxgear.scenes.TorsionalTrain.of`, one
rotation per shaft), the lumped 3D train (:meth:`~jaxgear.scenes.LumpedTrain.of`, 6-DOF shaft
nodes on bearings) and the hybrid train (:meth:`~jaxgear.scenes.HybridScene.train`, the lumped
train with condensed FE gear bodies). Another kind of train (a planetary stage) is one more
builder on the same description.
"""

from __future__ import annotations

import fractions
import math
from typing import NamedTuple

import equinox as eqx
import numpy as np
from jaxtyping import Array, Float

from .._geometry import GearPair, involute
from ._gear_mesh import line_of_action
from ._scene import DynamicScene
from ._structure import AssembledScene

__all__ = [
    "MAX_SCENE_PERIODS",
    "GearTrain",
    "TrainLayout",
    "TrainSpec",
    "half_base_angle",
    "mesh_period_ratios",
    "mesh_teeth",
    "scene_span",
    "shaft_speeds",
    "shaft_torques",
    "train_hands",
    "train_layout",
    "train_phases",
]


def half_base_angle(pair: GearPair, member: int) -> float:
    """ψ_b: half the angular tooth thickness of ``member`` (0 the pair's pinion, 1 its gear) at
    its base circle (rad), s_t/(2 r) + inv α_t (ISO 21771: the involute function carries the
    reference thickness s_t at radius r down to the base circle)."""
    at = pair.transverse_pressure_angle
    return pair.reference_thickness[member] / (2 * pair.pitch_radii[member]) + involute(at)


def train_phases(pairs, lines, gears, spins, n_gears: int, shafts=None, clockings=None):
    """Mesh phasing of a gear train from its layout and tooth counts (NumPy): the phase of each
    mesh's angle θ_k = ratio_k θ + phase_k (:attr:`GearMesh.phase`) and the angle of a tooth
    centre of each gear at θ = 0.

    Angles about a gear's axis are measured in its direction of motion. A gear's tooth has its
    centre line at c, its leading flank's involute starting on the base circle at c + ψ_b and its
    trailing flank's at c − ψ_b (:func:`half_base_angle`). A contact point at roll distance ρ from
    a base-circle tangent point at angle τ lies on a driving gear's leading flank when
    c + ψ_b = τ + ρ/r_b and on a driven gear's trailing flank when c − ψ_b = τ − ρ/r_b (the
    involute's origin is ρ/r_b behind or ahead of the tangent point). A mesh's angle is 0 when a
    contact line, at the face end z = 0, is at its engagement point (ρ_1 = ρ_A, as
    :meth:`MeshModel.cells`), and the first mesh's driving gear (the input) sets θ: its phase
    is 0. Each later mesh's driving gear must already be placed by an earlier mesh; its phase
    then follows from that gear's teeth (Parker & Lin, J. Mech. Des. 126 (2004), for planetary
    stages, read here in the base plane), and its driven gear's teeth from the contact.

    Args:
        pairs: the :class:`~jaxgear.GearPair` of each mesh (its pinion the driving gear).
        lines: each mesh's :func:`line_of_action` as placed in the train.
        gears: each mesh's (driving, driven) gear indices. spins: each gear's sense of rotation
            about z (+1 or −1), (n_gears,). n_gears: the number of gears.
        shafts: each gear's shaft (n_gears,) (default: a shaft each): gears on one shaft turn
            together (a compound gear), their teeth set by ``clockings``: each gear's tooth
            angle less its shaft's reference (rad, in the direction of motion; default 0: a
            tooth centre of every gear of a shaft on one radial line at θ = 0).

    Returns:
        (phases (m,) in rad of each mesh's driving gear, in [0, 2π/z_driving); tooth angles
        (n_gears,) in rad, each in its gear's direction of motion from the fixed +x axis).

    Raises:
        ValueError: a mesh whose driving gear no earlier mesh places (one line).
    """
    shafts = list(range(n_gears)) if shafts is None else list(shafts)
    clockings = [0.0] * n_gears if clockings is None else [float(c) for c in clockings]
    centre = [None] * n_gears
    c0 = [None] * n_gears
    ref = {}  # each placed shaft's reference angle: c0 = ref + clocking
    phases = []
    for k, (pair, line, (g, h)) in enumerate(zip(pairs, lines, gears, strict=True)):
        if c0[g] is None and shafts[g] in ref:  # a shaft-mate's teeth place the shaft
            c0[g] = ref[shafts[g]] + clockings[g]
        T1 = np.asarray(line["tangent_point"], float)
        T2 = T1 + (pair.center_distance * math.sin(pair.operating_pressure_angle)) * np.asarray(
            line["direction"], float
        )
        centre[g], centre[h] = line["centres"][0], line["centres"][1]
        rb1, rb2 = pair.base_radii
        z1 = pair.pinion.teeth
        tau1 = spins[g] * math.atan2(T1[1] - centre[g][1], T1[0] - centre[g][0])
        tau2 = spins[h] * math.atan2(T2[1] - centre[h][1], T2[0] - centre[h][0])
        rho_a = pair.start_roll
        if c0[g] is None:
            if k:
                raise ValueError(
                    f"mesh {k}: its driving gear {g} is not placed by an earlier mesh (list the "
                    "meshes from the input outwards)"
                )
            c0[g] = tau1 + rho_a / rb1 - half_base_angle(pair, 0)
            ref[shafts[g]] = c0[g] - clockings[g]
        phase = (c0[g] + half_base_angle(pair, 0) - tau1 - rho_a / rb1) % (2 * math.pi / z1)
        phases.append(phase)
        if c0[h] is None:
            length = pair.center_distance * math.sin(pair.operating_pressure_angle)
            c0[h] = tau2 + half_base_angle(pair, 1) - (length - rho_a - rb1 * phase) / rb2
            ref[shafts[h]] = c0[h] - clockings[h]
    c0 = [
        ref[shafts[i]] + clockings[i] if c is None and shafts[i] in ref else c
        for i, c in enumerate(c0)
    ]
    return np.array(phases), np.array([np.nan if c is None else c for c in c0])


def train_hands(gears, shafts, hands=None) -> tuple[list, int | None]:
    """Each gear's helix hand (+1 right, −1 left) in a train: as given (``hands``, 0 for none),
    else the input left-handed (a pair's pinion), a driven gear the other hand than its mate
    (external gears) and a later gear of a shaft its shaft's first placed gear's hand.

    Args:
        gears: each mesh's (driving, driven) gear indices, from the input outwards.
        shafts: each gear's shaft. hands: each gear's given hand or 0, (n,) (default none).

    Returns:
        (hands (n,), the first mesh whose two gears have the same hand, or None).
    """
    n = len(shafts)
    given = [0] * n if hands is None else [int(np.sign(h)) for h in hands]
    hand = [0] * n

    def place(gear, h):  # the gear and its shaft-mates without a hand yet
        hand[gear] = given[gear] or h
        for i in range(n):
            if shafts[i] == shafts[gear] and not hand[i]:
                hand[i] = given[i] or hand[gear]

    place(0, -1)
    clash = None
    for k, (g, h) in enumerate(gears):
        if not hand[h]:
            place(h, -hand[g])
        if hand[h] == hand[g] and clash is None:
            clash = k
    return hand, clash


class TrainLayout(NamedTuple):
    """A train of external gears laid out in the plane (:func:`train_layout`; NumPy, SI).

    Attributes:
        centres: each gear's centre (m), (n, 3), the input at the origin.
        spins: each gear's sense of rotation about +z (+1 or −1), (n,).
        lines: each mesh's :func:`line_of_action` as placed in the train.
        phases: each mesh's phase (rad of its driving gear), (m,) (:func:`train_phases`).
        tooth_angles: a tooth centre of each gear at θ = 0 (rad, in its direction of motion
            from the fixed +x axis), (n,).
        ratios: each gear's angle per unit input angle (z_in / z_g through the train), (n,).
        hands: each gear's helix hand (+1 right, −1 left), (n,).
    """

    centres: np.ndarray
    spins: np.ndarray
    lines: tuple
    phases: np.ndarray
    tooth_angles: np.ndarray
    ratios: np.ndarray
    hands: np.ndarray


def train_layout(
    pairs, gears, angles, n_gears: int, shafts=None, clockings=None, hands=None
) -> TrainLayout:
    """Lay out a train of external gears from its meshes (NumPy, SI).

    The input (gear 0, the driving gear of mesh 0) sits at the origin turning about +z; each
    mesh's driven gear sits at its driving gear's centre plus the pair's operating centre
    distance a_w in the direction ``angles[k]`` and turns the other way (an external mesh);
    then each mesh's line of action (:func:`line_of_action`, with its driving gear's hand) and
    the phasing (:func:`train_phases`).

    Args:
        pairs: the :class:`~jaxgear.GearPair` of each mesh, its pinion the driving gear.
        gears: each mesh's (driving, driven) gear indices, listed from the input outwards.
        angles: each mesh's direction of the driven gear's centre seen from the driving one (rad,
            fixed frame), (m,).
        n_gears: the number of gears.
        shafts, clockings: gears on one shaft (a compound gear: one centre, one rotation) and
            their teeth's angles on it (:func:`train_phases`); default a shaft each.
        hands: each gear's helix hand, +1 right, −1 left or 0 (default), (n,): by default the
            input is left-handed (a pair's pinion), a driven gear takes the other hand than its
            mate (external gears) and a later gear of a shaft its shaft's first gear's hand (a
            compound gear's two axial forces then oppose).

    Raises:
        ValueError: a mesh whose driving gear no earlier mesh places, a gear placed twice
            (a closed loop of meshes), or two gears in mesh given the same hand, in one line.
    """
    shafts = list(range(n_gears)) if shafts is None else list(shafts)
    hand, clash = train_hands(gears, shafts, hands)
    if clash is not None:
        g, h = gears[clash]
        raise ValueError(
            f"meshes[{clash}]: gears {g} and {h} have the same helix hand (allowed: external "
            "gears in mesh have opposite hands)"
        )
    centres = [None] * n_gears
    spins = [None] * n_gears
    ratios = [None] * n_gears

    def place(gear, centre, spin, ratio):  # the gear and its shaft-mates
        for i in range(n_gears):
            if shafts[i] == shafts[gear]:
                centres[i], spins[i], ratios[i] = centre, spin, ratio

    place(0, np.zeros(3), 1.0, 1.0)
    lines = []
    for k, (pair, (g, h), angle) in enumerate(zip(pairs, gears, angles, strict=True)):
        if centres[g] is None:
            raise ValueError(
                f"meshes[{k}]: its driving gear {g} is not placed by an earlier mesh (list the "
                "meshes from the input outwards)"
            )
        if centres[h] is not None:
            raise ValueError(f"meshes[{k}]: gear {h} is placed twice (allowed: once)")
        line = line_of_action(pair, centres[g], angle, spins[g], hand[g])
        place(h, line["centres"][1], -spins[g], ratios[g] * pair.pinion.teeth / pair.gear.teeth)
        lines.append(line)
    if any(c is None for c in centres):
        missing = [i for i, c in enumerate(centres) if c is None]
        raise ValueError(f"gears {missing} mesh with none")
    phases, tooth = train_phases(pairs, lines, gears, spins, n_gears, shafts, clockings)
    return TrainLayout(
        np.array(centres),
        np.array(spins),
        tuple(lines),
        phases,
        tooth,
        np.array(ratios),
        np.array(hand, dtype=float),
    )


class TrainSpec(eqx.Module):
    """The description of a gear train that every train scene kind is built from (the module
    docstring): gears 0 … n−1 (gear 0 the input) on shafts, the meshes between them, their
    layout and phasing, the gear bodies, the loads and the shaft material. A build-time
    description (Python numbers, NumPy arrays and mesh models); the scenes built from it hold
    the JAX arrays.

    Attributes:
        meshes: ((mesh model, (driving gear, driven gear)), ...), listed from the input
            outwards (a mesh's driving gear is the input or driven by an earlier mesh), each
            :class:`~jaxgear.MeshModel` with its driving gear as pinion.
        layout: the train laid out in the plane (:class:`TrainLayout`: centres, spins, lines of
            action with their hands, phases, speed ratios), or None: a train without a place
            in space (torsional), its phases :attr:`phases`.
        shafts: each shaft's :class:`~jaxgear.scenes.ShaftSpec` (shaft 0 the input's), its
            ``gear_z`` the positions of its gears in gear order; None without shafts
            (torsional).
        gear_shafts: each gear's shaft, (n,); None: a shaft each. Gears on one shaft turn
            together (a compound gear: one rotation of the torsional train).
        masses: each gear body's mass (kg), (n,), or None (torsional).
        inertias: each gear body's (I_diametral, I_polar) (kg·m²), (n,) (a torsional train
            reads I_polar alone; its I_diametral may be None).
        shares: ``{shaft: share of the input power}`` (:func:`shaft_torques`), or None.
        wrenches: :class:`~jaxgear.scenes.Wrench` loads per unit input torque (shaft nodes).
        shaft_names: each shaft's name (bearing force names, stiffness parts); default
            ``shaft<i>``.
        youngs_modulus, poisson_ratio, density: the shafts' material (Pa, -, kg/m³); the
            density also gives the teeth's mass on a condensed body.
        phases: each mesh's phase (rad, :attr:`~jaxgear.scenes.GearMesh.phase`) of a train
            without a layout (default 0); with a layout, its phases.
        pairs: each mesh's :class:`~jaxgear.GearPair` (its pinion the driving gear), for the
            teeth of condensed gears (a hybrid train), or None.
        bodies: each gear's condensed body (``fem_prep.CondensedBody``) or None (a rigid gear
            node), (n,); None: every gear rigid.
        rims: each gear's rim on its body (0 the wheel's rim, 1 the ``[pinion_rim]``), (n,);
            default 0 for every gear.
        gear_names: each gear's name, for the messages (default ``gear<g>``).
    """

    meshes: tuple
    layout: TrainLayout | None = None
    shafts: tuple | None = None
    gear_shafts: tuple | None = None
    masses: tuple | list | None = None
    inertias: tuple | list = ()
    shares: dict | None = None
    wrenches: tuple = ()
    shaft_names: tuple | None = None
    youngs_modulus: float = 210e9
    poisson_ratio: float = 0.3
    density: float = 7800.0
    phases: tuple | None = None
    pairs: tuple | None = None
    bodies: tuple | None = None
    rims: tuple | None = None
    gear_names: tuple | None = None

    @property
    def n_gears(self) -> int:
        """The number n of gears."""
        return len(self.inertias)

    @property
    def shaft_of(self) -> tuple:
        """Each gear's shaft, (n,)."""
        if self.gear_shafts is None:
            return tuple(range(self.n_gears))
        return tuple(self.gear_shafts)

    @property
    def n_shafts(self) -> int:
        """The number of shafts (of rotations of the torsional train)."""
        if self.shafts is None:
            return max(self.shaft_of) + 1
        return len(self.shafts)

    @property
    def shaft_gears(self) -> list:
        """Each shaft's gears, in gear order."""
        return [[g for g, s in enumerate(self.shaft_of) if s == i] for i in range(self.n_shafts)]

    @property
    def links(self) -> list:
        """Each mesh's (driving, driven) shafts."""
        shaft = self.shaft_of
        return [(shaft[g], shaft[h]) for _, (g, h) in self.meshes]

    @property
    def wrench_z(self) -> tuple:
        """Each shaft's wrench positions (m from its start), the nodes the wrenches add to it
        (:func:`~jaxgear.scenes.bearing_dofs`' ``extra_z`` of a lumped train), one tuple per
        shaft."""
        return tuple(tuple(w.z for w in self.wrenches if w.shaft == i)
                     for i in range(self.n_shafts))

    @property
    def names(self) -> tuple:
        """Each shaft's name (:attr:`shaft_names`, default ``shaft<i>``)."""
        return self.shaft_names or tuple(f"shaft{i}" for i in range(self.n_shafts))

    @property
    def gear_labels(self) -> tuple:
        """Each gear's name (:attr:`gear_names`, default ``gear<g>``)."""
        return self.gear_names or tuple(f"gear{g}" for g in range(self.n_gears))

    @property
    def mesh_phases(self) -> list:
        """Each mesh's phase (rad): the layout's, else :attr:`phases`, else 0."""
        if self.layout is not None:
            return [float(p) for p in self.layout.phases]
        return [0.0] * len(self.meshes) if self.phases is None else list(self.phases)

    @property
    def gear_bodies(self) -> tuple:
        """Each gear's condensed body or None, (n,)."""
        return (None,) * self.n_gears if self.bodies is None else tuple(self.bodies)

    @property
    def gear_rims(self) -> tuple:
        """Each gear's rim on its body, (n,) (:attr:`rims`, default 0)."""
        return (0,) * self.n_gears if self.rims is None else tuple(self.rims)

    @property
    def material(self) -> tuple[float, float, float]:
        """(E (Pa), ν, ρ (kg/m³)) of the shafts (a :class:`~jaxgear.scenes.Material`'s
        order)."""
        return (self.youngs_modulus, self.poisson_ratio, self.density)


class GearTrain(AssembledScene, DynamicScene):
    """A gear train of rigid gears, the base of its scene kinds: a structure (one rotation per
    shaft: :class:`~jaxgear.scenes.TorsionalTrain`; or 6-DOF shaft nodes:
    :class:`~jaxgear.scenes.LumpedTrain`) with one mesh per pair of gears in contact, each kind
    built from the train's one :class:`TrainSpec` (its ``of``). The input torque T acts on the
    input shaft, each loaded shaft takes its share of the input power and the balancing output
    the rest (:func:`shaft_torques`); the chain turns freely (its rigid rotation
    :attr:`rigid`).

    Attributes:
        rigid: the rigid rotation (n,): each shaft's rotation per unit base-plane advance of the
            input (ω_s / r_b,0 on every rotation of shaft s, in the sense it turns).
        periods: static, the periods of the first mesh after which the cells of every mesh
            repeat together (:func:`scene_span`): 1 for an idler train; 37 for 23-37 then 29-41
            on the 37's shaft (one turn of that shaft).
        period_ratios: static, each mesh's period in periods of the first, exact
            (:func:`mesh_period_ratios`; 37/29 for the second mesh there); None: 1 for every
            mesh.
    """

    rigid: Float[Array, " n"]
    periods: int = eqx.field(static=True, default=1)
    period_ratios: tuple | None = eqx.field(static=True, default=None)

    def rigid_modes(self):
        return self.rigid[:, None]

    def scene_periods(self) -> int:
        """:attr:`periods`: first-mesh periods after which every mesh's cells repeat."""
        return self.periods

    def mesh_periods(self):
        """:attr:`period_ratios` (each mesh's period in periods of the first)."""
        if self.period_ratios is None:
            return super().mesh_periods()
        return self.period_ratios


def mesh_teeth(plane) -> tuple[int, int]:
    """A mesh's (driving, driven) tooth counts, 2π r_b / p_bt rounded (exact whatever the float
    width of the base plane: the spans and speed ratios of a train are ratios of these)."""
    p = float(plane.base_pitch)
    return tuple(
        round(2.0 * math.pi * float(r) / p)
        for r in (plane.base_radius_pinion, plane.base_radius_gear)
    )


def shaft_speeds(links, base_radii, n: int) -> list:
    """Each shaft's speed per unit input speed, ω_s (unsigned), from the meshes.

    Args:
        links: each mesh's (driving, driven) shafts, listed from the input (shaft 0) outwards.
        base_radii: each mesh's (driving, driven) base radii (m), or anything in their ratio:
            the trains pass the tooth counts (:func:`mesh_teeth`), exact in float32 too.
        n: the number of shafts.

    Raises:
        ValueError: a mesh whose driving shaft does not turn yet, a shaft driven twice or one
            that meshes with none (one line).
    """
    omega = [None] * n
    omega[0] = 1.0
    for k, ((g, h), (r1, r2)) in enumerate(zip(links, base_radii, strict=True)):
        if omega[g] is None:
            raise ValueError(
                f"meshes[{k}]: driving gear {g} does not turn yet (list the meshes from the input "
                "gear 0 outwards)"
            )
        if omega[h] is not None:
            raise ValueError(f"meshes[{k}]: gear {h} is driven twice (allowed: once)")
        omega[h] = omega[g] * float(r1) / float(r2)
    if any(w is None for w in omega):
        raise ValueError(f"gears {[i for i, w in enumerate(omega) if w is None]} mesh with none")
    return omega


def shaft_torques(links, omega, shares) -> tuple[dict, int]:
    """The external torque on each loaded shaft per unit input torque, in its direction of
    motion: +1 on the input (shaft 0), −share_s ω_0/ω_s on each shaft with a share of the input
    power, and −(1 − Σ shares) ω_0/ω_o on the balancing output o, the one shaft that drives no
    other and has no share (the torques balance the power: Σ T_s ω_s = 0).

    Args:
        links: each mesh's (driving, driven) shafts. omega: :func:`shaft_speeds`.
        shares: ``{shaft: share}``, 0 < share, their sum < 1 (``None``: no share).

    Returns:
        ({shaft: torque per unit input torque}, o).

    Raises:
        ValueError: no or several shafts left for the balancing output, shares out of range.
    """
    n = len(omega)
    shares = {} if shares is None else {int(g): float(v) for g, v in shares.items()}
    driving = {g for g, _ in links}
    free = [i for i in range(n) if i not in driving and i not in shares]
    if len(free) != 1:
        raise ValueError(
            f"the train has output gears {free} without a share of the input power (allowed: "
            "exactly one, the balancing output)"
        )
    o = free[0]
    if 0 in shares or any(not 0.0 < v < 1.0 for v in shares.values()):
        raise ValueError(f"shares = {shares}: allowed gears other than the input, each in (0, 1)")
    rest = 1.0 - sum(shares.values())
    if not rest > 0.0:
        raise ValueError(f"shares = {shares}: their sum {1.0 - rest:.6g} leaves the output none")
    torques = {0: 1.0, o: -rest / omega[o]}
    torques.update({g: -v / omega[g] for g, v in shares.items()})
    return torques, o


#: the longest span of first-mesh periods a train may repeat over (a table row per step of it)
MAX_SCENE_PERIODS = 1000


def mesh_period_ratios(periods) -> tuple[fractions.Fraction, ...]:
    """Each mesh's period T_k / T_0 in periods of the first mesh, exact, from the periods T_k
    (input rad, floats): the fraction of tooth counts of denominator <= 10⁶ within 1e-9 (127/35
    for the second stage of the embedded ``two-stage`` case: a 35-tooth pinion on the 127-tooth
    wheel's shaft).

    Raises:
        ValueError: a ratio that is no such fraction."""
    out = []
    for k, t in enumerate(periods):
        r = t / periods[0]
        f = fractions.Fraction(r).limit_denominator(10**6)
        if abs(float(f) - r) > 1e-9 * r:
            raise ValueError(
                f"meshes[{k}]: its period is {r:.12g} periods of mesh 0, not a ratio of tooth "
                "counts (allowed: the meshes repeat together)"
            )
        out.append(f)
    return tuple(out)


def scene_span(periods) -> int:
    """The least q such that q T_0 is a whole number of every mesh period T_k (input rad), from
    the exact ratios T_k / T_0 of tooth counts (:func:`mesh_period_ratios`): the least common
    multiple of their numerators.

    Raises:
        ValueError: a ratio that is no such fraction, or q above MAX_SCENE_PERIODS."""
    q = 1
    for f in mesh_period_ratios(periods):
        q = math.lcm(q, f.numerator)
    if q > MAX_SCENE_PERIODS:
        raise ValueError(
            f"the meshes repeat together every {q} periods of mesh 0 (allowed: at most "
            f"{MAX_SCENE_PERIODS}; choose tooth counts with common factors)"
        )
    return q
