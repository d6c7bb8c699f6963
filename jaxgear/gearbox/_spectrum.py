"""What a gearbox NVH engineer reads off the coupled model (docs/gearbox.md, "Campbell diagram
and housing spectrum"): every stage's mesh orders against the input speed with the coupled
modes they cross (the coupled Campbell diagram), and the spectrum of the force transmitted to
the housing at a ring mount of a planetary stage and at a parallel stage's bearing, from one
coupled time-domain run (:func:`~jaxgear.gearbox.gearbox_dynamics`' Newmark run) at one input
speed.

Mesh orders. Stage k's mesh frequency is f_k = z |omega_member - omega_c| / 2 pi (Hz), z a
member's tooth count, its speed taken relative to the carrier's frame (a parallel pair: the
fixed frame, omega_c = 0); in the model's terms f_k = v_k / p_b,k, the mesh travel speed over
the base pitch. Every stage's speeds are proportional to the input speed (Willis for a
planetary stage), so each order is a line f = h f_k(1) Omega_in through the origin.

The ring-mount point (McFadden & Smith 1985, "An explanation for the asymmetry of the modulation
sidebands about the tooth meshing frequency in epicyclic gear vibration", Proc. IMechE C
199(1); Inalpolat & Kahraman 2009, "A theoretical and experimental investigation of modulation
sidebands of planetary gear sets", J. Sound Vib. 323): a sensor fixed on the ring at angle
theta_s sees each planet's ring-mesh force through a transmission path whose gain falls with
the planet's angular distance from it,

    s(t) = sum_n w(psi_n + theta_c(t) - theta_s) F_rn(t) + a R(t),

with psi_n the planet's angle in the carrier, theta_c(t) = omega_c t the carrier's nominal
angle (rad, fixed frame, positive in the stages' common sense), w the planet-pass window of
:func:`jaxgear.planetary.ring_transducer_signal` (the one home of the windowed sum),
w(phi) = ((1 + cos phi) / 2)^p, whose Fourier coefficients are c_k = C(2p, p + k) / 4^p for
|k| <= p and 0 beyond, and R(t) = k_t theta_r(t) / r_br the ring's torsional support reaction
as a tangential force at its base circle (the torsional model's ring hold k_t), shared by the
sensor in the window's proportion a = (1 / 2 pi) integral of w = c_0 = C(2p, p) / 4^p. For
identical,
equally spaced planets with z_r the ring's teeth and N planets, the ring-held stage's part of
s holds lines only at p f_c with p = 0 mod N (f_c = omega_c / 2 pi): around the mesh harmonic
h z_r f_c only at h z_r + k with k = -h z_r (mod N) and |k| <= p; the mesh frequency itself is
absent unless z_r = 0 (mod N).

A parallel pair's bearing: its gears' centres are held (the torsional pair), so each gear's
bearing carries the mesh force; its component along the line of action equals the pair's
transverse mesh force F(t) (N; a helical pair's axial component is not modelled). A pair in
lumped 3D form (:class:`~jaxgear.gearbox.LumpedPairGearboxStage`) has its bearings: the signal
is the elastic force its output shaft's bearings carry (the scene's bearing force rows,
:attr:`~jaxgear.scenes.Structure.reaction`: k u, on a housing k d with d the shaft node's
displacement relative to its seat), summed over that shaft's bearings, in the plane normal to
the shaft, along the direction of its mean over the record (for a spur pair the line of action,
the sense of the mesh force: quasi-statically it is F(t)).
"""

from __future__ import annotations

import math

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._contact import AbstractContactLaw, ExactContact
from .._util import as_float, check_instance, check_integer, check_real
from ..dynamics import DynamicModel
from ..planetary import Central, PlanetaryModel, ring_transducer_signal
from ..scenes import LumpedPair
from ._chain import GearboxTorsional, PairGearboxStage
from ._coupled import (
    CoupledModes,
    GearboxDynamics,
    GearboxRun,
    _check,
    _kinematics,
    _layout,
    _run,
    coupled_mode_table,
    mesh_names,
)

__all__ = [
    "HousingSignals",
    "HousingSpectrum",
    "amplitude_spectrum",
    "campbell_crossings",
    "carrier_frequencies",
    "housing_lines",
    "housing_signals",
    "housing_spectrum",
    "line_amplitudes",
    "mesh_frequencies",
    "window_share",
]

#: a crossing whose mode holds at least this share of its strain energy in the exciting stage's
#: meshes is marked (the engine's excited-mode share, :data:`jaxgear.dynamics.MESH_ENERGY_MIN`)
CROSSING_SHARE = 0.05


def mesh_frequencies(chain: GearboxTorsional, input_speed) -> Float[Array, " s"]:
    """Each stage's mesh frequency (Hz, (n_stages,)) at the first stage's input speed
    (rad/s): f_k = v_k / p_b,k = z |omega_member - omega_c| / 2 pi, the member's speed relative
    to the stage's carrier (a pair: the fixed frame); the speeds carried stage by stage through
    the shafts (Willis for a planetary stage). Linear in ``input_speed``'s magnitude."""
    kin = _kinematics(chain, as_float(input_speed), 1.0)
    return jnp.stack([v / s.mesh_period() for s, (_, v, _) in zip(chain.stages, kin,
                                                                     strict=True)])


def carrier_frequencies(chain: GearboxTorsional, input_speed) -> Float[Array, " s"]:
    """Each stage's carrier rotation frequency omega_c / 2 pi (Hz, signed: positive in the
    stages' common sense, (n_stages,)) at the input speed (rad/s); 0 for a parallel pair."""
    kin = _kinematics(chain, as_float(input_speed), 1.0)
    out = []
    for s, (w, _, _) in zip(chain.stages, kin, strict=True):
        out.append(s.carrier_speed(w) / (2.0 * math.pi))
    return jnp.stack(out)


def _stage_meshes(chain, k):
    """The columns of stage k's meshes in :func:`mesh_names`."""
    names = mesh_names(chain)
    return [j for j, n in enumerate(names) if n.startswith(f"{k + 1}:")]


def _stage_index(chain, k, name):
    n = len(chain.stages)
    if not isinstance(k, int) or isinstance(k, bool) or not -n <= k < n:
        raise ValueError(f"{name} = {k!r} is out of range: allowed a stage index -{n}..{n - 1}")
    return k % n


def campbell_crossings(chain: GearboxTorsional, modes, max_speed: float,
                       harmonics=(1, 2, 3)) -> list[dict]:
    """Where each stage's mesh orders cross the coupled modes (host side): for every stage k,
    harmonic h and elastic mode j, the input speed Omega (rad/s, 0 < Omega <= ``max_speed``)
    at which h f_k(Omega) (:func:`mesh_frequencies`) equals the mode's frequency.

    Args:
        chain: the gearbox.
        modes: :class:`~jaxgear.gearbox.CoupledModes` (:func:`gearbox_coupled_modes`: the modes
            at rest).
        max_speed: the highest input speed (rad/s, > 0).
        harmonics: the mesh harmonics h (positive integers).

    Returns:
        One dict per crossing, by speed: ``speed_rad_s``, ``frequency_Hz``, ``stage`` (from 1),
        ``harmonic``, ``mode`` (its index in the modes), ``type`` and ``mesh`` (the mode's, as
        :func:`coupled_mode_table` names them), ``stage_mesh_energy`` (the share of the mode's
        strain energy in stage k's meshes: how strongly its orders excite it) and ``marked``
        (that share >= :data:`CROSSING_SHARE`).

    Raises:
        ValueError: ``max_speed`` not positive, ``modes`` not a CoupledModes, a harmonic not a
            positive integer (one line).
    """
    check_real("max_speed", max_speed, "rad/s", lo=0.0, lo_open=True, shape=(),
               where="campbell_crossings")
    check_instance("modes", modes, CoupledModes, "a jaxgear.gearbox.CoupledModes",
                   "campbell_crossings")
    for h in harmonics:
        check_integer("harmonics", h, 1)
    slope = np.asarray(mesh_frequencies(chain, 1.0))  # Hz per rad/s
    table = coupled_mode_table(chain, modes)
    me = np.asarray(modes.mesh_energy)
    out = []
    for k in range(len(chain.stages)):
        share = me[_stage_meshes(chain, k)].sum(axis=0)
        for h in harmonics:
            for j, row in enumerate(table):
                if row["type"] == "rigid body" or slope[k] <= 0.0:
                    continue
                speed = row["frequency_Hz"] / (h * slope[k])
                if 0.0 < speed <= float(max_speed):
                    out.append({
                        "speed_rad_s": float(speed),
                        "frequency_Hz": row["frequency_Hz"],
                        "stage": k + 1,
                        "harmonic": int(h),
                        "mode": j,
                        "type": row["type"],
                        "mesh": row["mesh"],
                        "stage_mesh_energy": float(share[j]),
                        "marked": bool(share[j] >= CROSSING_SHARE),
                    })
    return sorted(out, key=lambda c: c["speed_rad_s"])


class HousingSignals(eqx.Module):
    """The forces a housing-fixed point sees (:func:`housing_signals`).

    Attributes:
        time: s, (t,).
        ring_point: the ring-mount sensor's signal s(t) (N, (t,)): the windowed ring-planet
            mesh forces plus the window's share of the ring's support reaction.
        ring_meshes: the windowed ring-planet mesh forces alone (N, (t,)).
        ring_support: the ring's torsional support reaction R = k_t theta_r / r_br (N, (t,),
            sign: its mean that of the ring meshes' forces); a ring on a housing's seat (the
            stage's ``mount()`` joins it): k_t (theta_r − theta_seat) / r_br.
        bearing: the parallel stage's bearing force along its line of action (N, (t,)): a
            torsional pair's mesh force; a lumped 3D pair's output-shaft bearings' in-plane
            elastic force along its mean's direction (module docstring).
    """

    time: Float[Array, " t"]
    ring_point: Float[Array, " t"]
    ring_meshes: Float[Array, " t"]
    ring_support: Float[Array, " t"]
    bearing: Float[Array, " t"]


def window_share(window_power: int) -> float:
    """a = (1 / 2 pi) integral of ((1 + cos phi) / 2)^p over the circle = C(2p, p) / 4^p (-):
    the share of the ring's support reaction the ring-mount sensor takes (the window's mean)."""
    check_integer("window_power", window_power, 1)
    return math.comb(2 * window_power, window_power) / 4.0**window_power


#: the stage kinds whose bearing the housing signals read (a torsional pair's is its mesh
#: force; a lumped 3D pair's its output shaft's bearings): the torsional pair stage and a
#: pair's dynamic model (:class:`~jaxgear.gearbox.LumpedPairGearboxStage` builds one)
BEARING_STAGES = (PairGearboxStage, DynamicModel)


def lumped_pair_stage(stage) -> bool:
    """Whether ``stage`` is a pair's dynamic model on a lumped 3D scene (its bearings)."""
    return isinstance(stage, DynamicModel) and isinstance(stage.scene, LumpedPair)


def _defaults(chain, ring_stage, bearing_stage, where):
    planetary = [k for k, s in enumerate(chain.stages) if isinstance(s, PlanetaryModel)]
    pairs = [k for k, s in enumerate(chain.stages) if isinstance(s, BEARING_STAGES)]
    if ring_stage is None:
        if not planetary:
            raise ValueError(f"{where}: chain has no planetary stage: allowed a chain with one "
                             "(the ring mount)")
        ring_stage = planetary[0]
    if bearing_stage is None:
        if not pairs:
            raise ValueError(f"{where}: chain has no parallel stage: allowed a chain with one "
                             "(the bearing: a PairGearboxStage or a LumpedPairGearboxStage)")
        bearing_stage = pairs[-1]
    ring_stage = _stage_index(chain, ring_stage, "ring_stage")
    bearing_stage = _stage_index(chain, bearing_stage, "bearing_stage")
    s = chain.stages[ring_stage]
    if not isinstance(s, PlanetaryModel):
        raise TypeError(f"{where}: ring_stage = {ring_stage} is a {type(s).__name__}: allowed "
                         "a planetary stage")
    if Central.RING in (s.input, s.output):
        raise ValueError(f"{where}: ring_stage = {ring_stage}: its ring turns (input or output)"
                         ": allowed a stage whose ring is held (the housing mount)")
    b = chain.stages[bearing_stage]
    if not isinstance(b, BEARING_STAGES):
        raise TypeError(f"{where}: bearing_stage = {bearing_stage} is a {type(b).__name__}: "
                         "allowed a parallel pair stage (PairGearboxStage, "
                         "LumpedPairGearboxStage)")
    return ring_stage, bearing_stage


def housing_signals(
    chain: GearboxTorsional,
    dynamics: GearboxDynamics,
    input_speed,
    window_power: int = 4,
    sensor_angle: float = 0.0,
    ring_stage: int | None = None,
    bearing_stage: int | None = None,
) -> HousingSignals:
    """The forces transmitted to the housing (module docstring) from a coupled run.

    Args:
        chain: the gearbox the run was made on.
        dynamics: a :func:`~jaxgear.gearbox.gearbox_dynamics` result (one speed: ``time``
            (t,), ``mesh_forces`` (t, m), ``displacement`` (t, n)).
        input_speed: its input speed (rad/s).
        window_power: p (>= 1), the planet-pass window's sharpness
            (:func:`jaxgear.planetary.ring_transducer_signal`).
        sensor_angle: theta_s (rad), the sensor's angle on the ring in the fixed frame, from
            the carrier's angle 0 at t = 0.
        ring_stage: the planetary stage with the ring mount (index; None: the first planetary
            stage); its ring must be held.
        bearing_stage: the parallel stage with the bearing (index; None: the last pair, a
            :class:`PairGearboxStage` or a :class:`~jaxgear.gearbox.LumpedPairGearboxStage`).

    Returns:
        :class:`HousingSignals`.

    Raises:
        ValueError: a stage index out of range, a ring that turns, ``window_power`` not a
            positive integer (one line).
        TypeError: a stage of the wrong kind (one line).
    """
    where = "housing_signals"
    ring_stage, bearing_stage = _defaults(chain, ring_stage, bearing_stage, where)
    share = window_share(window_power)
    check_real("sensor_angle", sensor_angle, "rad", shape=(), where=where)
    s = chain.stages[ring_stage]
    st = s.stage
    n = st.n_planets
    t = dynamics.time
    omega_c = 2.0 * jnp.pi * carrier_frequencies(chain, input_speed)[ring_stage]
    cols = _stage_meshes(chain, ring_stage)[n:]  # the ring-planet meshes
    f_ring = dynamics.mesh_forces[:, cols]  # (t, N)
    meshes = ring_transducer_signal(f_ring, omega_c * t, st.planet_angles, sensor_angle,
                                    window_power)
    support = (st.ring.torsional_stiffness * _ring_twist(chain, dynamics, ring_stage)
               / st.ring.base_radius)
    support = support * jnp.sign(jnp.mean(support)) * jnp.sign(jnp.mean(jnp.sum(f_ring, 1)))
    if lumped_pair_stage(chain.stages[bearing_stage]):
        bearing = _shaft_bearings(chain, dynamics, bearing_stage)
    else:
        bearing = dynamics.mesh_forces[:, _stage_meshes(chain, bearing_stage)[0]]
    return HousingSignals(t, meshes + share * support, meshes, support, bearing)


def _ring_twist(chain, dynamics, k):
    """The ring's turn on its torsional support (rad, (t,)): θ_r, or on a housing's seat
    (a stage whose :meth:`~jaxgear.dynamics.AbstractStage.mount` joins its ring) θ_r −
    θ_seat, θ_seat the seat's rotation about the stage axis at the joint's point, the stage
    centre (the last row of :meth:`~jaxgear.scenes.Housing.seat_transform` on the seat's
    coordinates)."""
    stage = chain.stages[k]
    x = dynamics.displacement[:, _layout(chain.stages, chain.housing)[0][k]]
    names = stage.coordinates()
    twist = x[:, names.index("theta_r")]
    mount = stage.mount()
    if mount is not None:
        n = len(names) - mount.size
        for j, joint in enumerate(mount.joints):
            if joint.member == "ring":
                seat = mount.seat_index(j)
                g = jnp.asarray(mount.housing.seat_transform(seat, joint.point)[5], x.dtype)
                twist = twist - x[:, n + 6 * seat:n + 6 * seat + 6] @ g
    return twist


def _shaft_bearings(chain, dynamics, k):
    """A lumped 3D pair stage's output-shaft bearings' force (N, (t,)): the scene's bearing
    force rows (k u, on a housing k d) of that shaft's bearings on the stage's coordinates of
    the run, summed per in-plane direction (x, y), along the direction of their mean."""
    stage = chain.stages[k]
    st = stage.scene.structure
    shaft = 1 - stage.input
    x = dynamics.displacement[:, _layout(chain.stages, chain.housing)[0][k]]
    F = x @ jnp.asarray(st.reaction).T  # (t, r)
    xy = [[i for i, (name, m) in enumerate(zip(st.reaction_names, st.reaction_member,
                                                strict=True)) if m == shaft and name.endswith(c)]
          for c in ("Fx", "Fy")]
    plane = jnp.stack([F[:, rows].sum(axis=1) for rows in xy], axis=1)  # (t, 2)
    mean = plane.mean(axis=0)
    norm = jnp.linalg.norm(mean)
    # no mean load (none carried): the scene's x direction
    unit = jnp.where(norm > 0.0, mean / jnp.where(norm > 0.0, norm, 1.0),
                     jnp.array([1.0, 0.0], plane.dtype))
    return plane @ unit


def _window(n, window):
    if window == "hann":
        return 0.5 - 0.5 * np.cos(2.0 * np.pi * np.arange(n) / n)
    if window == "rect":
        return np.ones(n)
    raise ValueError(f"window = {window!r} is out of range: allowed 'hann', 'rect'")


def line_amplitudes(time, signal, frequencies, window: str = "hann") -> np.ndarray:
    """The single-sided amplitude (the signal's unit, peak) of ``signal`` (t,) sampled at the
    uniform ``time`` (s, (t,)) at each of ``frequencies`` (Hz, (f,)): 2 |sum_i w_i x_i
    exp(-2 pi i f t_i)| / sum_i w_i (the DC line: without the 2), w the periodic Hann window
    over the record (``"hann"``) or 1 (``"rect"``). A record of R whole periods of a line
    spacing f_0 (R >= 2 with Hann) gives every line on that grid exactly, without leakage from
    the others; a line off the grid is read at its own frequency (no scalloping), with the
    Hann window's sidelobes from its neighbours. Host side (NumPy), (f,)."""
    t = np.asarray(time, dtype=float)
    x = np.asarray(signal, dtype=float)
    f = np.atleast_1d(np.asarray(frequencies, dtype=float))
    w = _window(t.size, window)
    e = np.exp(-2j * np.pi * f[:, None] * (t - t[0])[None, :])
    a = np.abs(e @ (w * x)) / w.sum()
    return np.where(f == 0.0, a, 2.0 * a)


def amplitude_spectrum(time, signal, window: str = "hann") -> tuple[np.ndarray, np.ndarray]:
    """(frequencies (Hz, (k,)), single-sided amplitudes (peak, the signal's unit, (k,))) of
    ``signal`` sampled at the uniform ``time`` (s): the FFT with the window's coherent gain
    taken out (:func:`line_amplitudes` on the FFT's bins, 1 / (t dt) apart). Host side."""
    t = np.asarray(time, dtype=float)
    x = np.asarray(signal, dtype=float)
    dt = (t[-1] - t[0]) / (t.size - 1)
    w = _window(t.size, window)
    a = np.abs(np.fft.rfft(w * x)) / w.sum()
    a[1:] *= 2.0
    return np.fft.rfftfreq(t.size, dt), a


def housing_lines(chain: GearboxTorsional, input_speed, harmonics=(1, 2, 3), sidebands: int = 2,
                  ring_stage: int | None = None) -> list[dict]:
    """The lines a housing point's spectrum is read at (host side): each stage's mesh harmonics
    h f_k (``kind`` "mesh"), around each the ring stage's planet-pass sidebands
    h f_k + j N f_c, 0 < |j| <= ``sidebands`` ("planet pass"), and around the ring stage's own
    harmonics the lines McFadden & Smith's analysis keeps for a ring-fixed sensor, the
    multiples p N f_c of the planet-pass frequency next to h z_r f_c (below and above,
    "McFadden-Smith"; h z_r f_c itself when z_r = 0 mod N).

    Returns: dicts ``frequency_Hz``, ``stage`` (the order's, from 1), ``harmonic``,
    ``sideband`` (j, or the offset p N - h z_r in carrier orders for "McFadden-Smith"),
    ``kind``, ``label``; by frequency (a frequency two rows share is listed under each)."""
    if ring_stage is None:
        ring_stage = next((k for k, s in enumerate(chain.stages)
                           if isinstance(s, PlanetaryModel)), None)
        if ring_stage is None:
            raise ValueError("housing_lines: chain has no planetary stage: allowed a chain with "
                             "one (the ring mount)")
    ring_stage = _stage_index(chain, ring_stage, "ring_stage")
    if not isinstance(chain.stages[ring_stage], PlanetaryModel):
        raise TypeError(f"housing_lines: ring_stage = {ring_stage} is a "
                        f"{type(chain.stages[ring_stage]).__name__}: allowed a planetary stage")
    f_m = np.asarray(mesh_frequencies(chain, input_speed))
    f_c = abs(float(carrier_frequencies(chain, input_speed)[ring_stage]))
    n = chain.stages[ring_stage].stage.n_planets
    pp = n * f_c
    out = []
    for k in range(len(chain.stages)):
        for h in harmonics:
            c = h * f_m[k]
            out.append({"frequency_Hz": c, "stage": k + 1, "harmonic": h, "sideband": 0,
                        "kind": "mesh", "label": f"{h}×f{k + 1}"})
            for j in range(-sidebands, sidebands + 1):
                if j:
                    out.append({"frequency_Hz": c + j * pp, "stage": k + 1, "harmonic": h,
                                "sideband": j, "kind": "planet pass",
                                "label": f"{h}×f{k + 1}{j:+d}×{n}fc{ring_stage + 1}"})
            if k == ring_stage and f_c > 0.0:
                order = c / f_c  # h z_r
                for p in sorted({math.floor(order / n + 1e-9), math.ceil(order / n - 1e-9)}):
                    off = round(p * n - order)
                    out.append({"frequency_Hz": p * pp, "stage": k + 1, "harmonic": h,
                                "sideband": off, "kind": "McFadden-Smith",
                                "label": f"{p}×{n}fc{k + 1}"})
    out = [r for r in out if r["frequency_Hz"] > 0.0]
    out.sort(key=lambda r: r["frequency_Hz"])
    return out


class HousingSpectrum(eqx.Module):
    """A housing-point spectrum from one coupled run (:func:`housing_spectrum`).

    Attributes:
        signals: :class:`HousingSignals` over the recorded revolutions.
        frequency: the spectra's frequencies (Hz, (k,)), 1 / (the record's length) apart.
        ring_point: the ring-mount sensor's amplitude spectrum (N, peak, (k,)).
        bearing: the parallel stage's bearing's (N, peak, (k,)).
        mesh_frequency: each stage's mesh frequency (Hz, (n_stages,)).
        carrier_frequency: each stage's carrier frequency (Hz, signed, (n_stages,)).
        dynamics: the run (:class:`GearboxDynamics`, the recorded revolutions).
        time_step: s.
        settle_time: the time integrated before the record (s).
    """

    signals: HousingSignals
    frequency: np.ndarray
    ring_point: np.ndarray
    bearing: np.ndarray
    mesh_frequency: np.ndarray
    carrier_frequency: np.ndarray
    dynamics: GearboxDynamics
    time_step: float
    settle_time: float


#: a revolution's steps come in this many blocks (the settling is a whole number of blocks)
BLOCKS_PER_REVOLUTION = 16


def housing_spectrum(
    chain: GearboxTorsional,
    run: GearboxRun,
    input_speed: float,
    law: AbstractContactLaw = ExactContact(),  # noqa: B008 - an immutable module
    *,
    revolutions: int = 2,
    steps_per_period: int = 8,
    window_power: int = 4,
    sensor_angle: float = 0.0,
    ring_stage: int | None = None,
    bearing_stage: int | None = None,
    window: str = "hann",
) -> HousingSpectrum:
    """One coupled run at ``input_speed`` long enough to resolve the ring stage's planet-pass
    sidebands, and the spectra of the housing signals (:func:`housing_signals`).

    The run's plan is its own (``run``'s torque, output hold, damping and mean positions are
    taken, its steps and blocks are not): the time step is 1 / (``steps_per_period`` f_max),
    f_max the fastest excited mesh frequency, rounded so that one revolution of the ring
    stage's carrier, T_c = 1 / |f_c|, is a whole number of steps (in
    :data:`BLOCKS_PER_REVOLUTION` blocks); from the quasi-static state at rest, the settling
    (:meth:`~jaxgear.gearbox.GearboxModel.settle_time`: the engine's settling time of the
    slowest decaying mode the meshes excite, :func:`jaxgear.dynamics.settling_time`, in
    whole blocks), then ``revolutions`` whole revolutions recorded. Over R whole revolutions
    with the Hann window (R >= 2) every line on the carrier's grid p f_c is read without
    leakage (:func:`line_amplitudes`); the spectra's resolution is f_c / R.

    Args:
        chain, run, law: as :func:`~jaxgear.gearbox.gearbox_dynamics`.
        input_speed: rad/s, nonzero.
        revolutions: R, recorded carrier revolutions (static, >= 1).
        steps_per_period: steps per period of the fastest excited mesh (static, >= 4; the orders'
            amplitudes' convergence with it is the caller's to check: docs/gearbox.md).
        window_power, sensor_angle, ring_stage, bearing_stage: :func:`housing_signals`.
        window: ``"hann"`` or ``"rect"`` (:func:`amplitude_spectrum`).

    Returns:
        :class:`HousingSpectrum` (host-side NumPy spectra).

    Raises:
        ValueError: an argument out of range or of another kind (one line), before any run.
        TypeError: ``ring_stage`` or ``bearing_stage`` a stage of the wrong kind (one line).
    """
    where = "housing_spectrum"
    _check(chain, run, law, where)
    check_real("input_speed", input_speed, "rad/s", shape=(), where=where)
    if float(input_speed) == 0.0:
        raise ValueError(f"{where}: input_speed = 0 rad/s: allowed a nonzero speed")
    check_integer("revolutions", revolutions, 1)
    check_integer("steps_per_period", steps_per_period, 4)
    _window(2, window)
    ring_stage, bearing_stage = _defaults(chain, ring_stage, bearing_stage, where)
    window_share(window_power)
    w = float(input_speed)
    f_m = np.asarray(mesh_frequencies(chain, w))
    f_c = np.asarray(carrier_frequencies(chain, w))
    excited = [f for s, f in zip(chain.stages, f_m, strict=True) if s.excited()]
    f_max = max(excited) if excited else float(f_m[0])
    t_rev = 1.0 / abs(float(f_c[ring_stage]))
    b = BLOCKS_PER_REVOLUTION
    block = math.ceil(steps_per_period * f_max * t_rev / b)
    dt = t_rev / (b * block)
    from ._model import GearboxModel

    settle = math.ceil(GearboxModel(chain, run).settle_time() / (block * dt))
    keep = b * revolutions
    plan = GearboxRun(run.input_torque, run.output_stiffness, steps_per_period=None,
                      periods=None, keep_periods=keep, damping_ratio=run.damping_ratio,
                      mean_positions=run.mean_positions)
    # _run's time step is fast / (S |omega|): S = 1 and fast = dt |omega| give dt exactly
    dyn = _run(chain, plan, as_float(w), law, 1, block, dt * abs(w), settle + keep)
    sig = housing_signals(chain, dyn, w, window_power, sensor_angle, ring_stage, bearing_stage)
    freq, ring = amplitude_spectrum(sig.time, sig.ring_point, window)
    _, bearing = amplitude_spectrum(sig.time, sig.bearing, window)
    return HousingSpectrum(sig, freq, ring, bearing, f_m, f_c, dyn, dt, settle * block * dt)
