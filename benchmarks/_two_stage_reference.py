"""An independent continuous-time reference for the two-stage coupled example (a planetary stage,
ring held, carrier in, sun out, then a parallel spur pair on the sun's shaft), written with NumPy
and SciPy only (no jaxgear import), for the comparison of per-mesh dynamic factors with jaxgear's
coupled model (the shared specification of session 42; docs/bench/two_stage_reference.json).

Everything is derived here from first principles; the sources are cited where used.

Geometry (ISO 21771:2007, 5.3-5.4 and 6; F. L. Litvin & A. Fuentes, "Gear Geometry and Applied
Theory", 2nd ed., ch. 10 and 11). Standard spur gears (no profile shift, centre distance
a = m (z2 +- z1) / 2, operating pressure angle = alpha): pitch radius r = m z / 2, base radius
r_b = r cos alpha, tip radius r_a = r + m for an external gear and r_a = r - m for the internal
ring (its tip circle lies inside its pitch circle), base pitch p_b = pi m cos alpha. Path of
contact (the segment of the line of action between the two tip circles) and transverse contact
ratio eps = g / p_b:

    external: g = sqrt(r_a1^2 - r_b1^2) + sqrt(r_a2^2 - r_b2^2) - a sin alpha
    internal: g = sqrt(r_a1^2 - r_b1^2) - sqrt(r_a2^2 - r_b2^2) + a sin alpha   (2: the ring)

(ISO 21771 eq. (141)/(142) with alpha_wt = alpha). For the specification's gears: sun-planet
eps = 1.6052, ring-planet 1.9380, gear-pinion 1.6348.

Contact length. With a constant stiffness k_u per unit contact length the mesh force is
F = max(0, k_u L(s) delta), L = b n(s), s (m) the travel of the contact lines along the line of
action measured from the engagement point (the start of the active path) modulo p_b: the line
at s and the one at s + p_b are both on the path when s <= g - p_b, so that for 1 < eps < 2

    n(s) = 2 for 0 <= s mod p_b < g - p_b,  1 otherwise,

a rectangular wave of period p_b (one mesh period = one base pitch of travel) between floor(eps)
and ceil(eps) pairs with mean eps. The pair count changes at the travel, so L jumps in time: as
the mesh deflection delta is continuous, the force of a mesh jumps by the ratio of its pair
counts (F(t+) = 2 F(t-) where a pair enters), at any speed, even the slowest. The maximum force
of a period, and so the dynamic factor, therefore tends to ceil(eps)/floor(eps) = 2 (not 1) as
the speed tends to zero, while the quasi-static force (the limit between the jumps) and the
period mean of every force equal the static force (below).

Kinematics (Willis, ring held): sun speed omega_s = (1 + z_r/z_s) Omega_c; the sun turns relative
to the carrier at (z_r/z_s) Omega_c, so the stage-1 contact lines travel at v1 = r_bs (z_r/z_s)
Omega_c (= r_bp times the planet's spin relative to the carrier = r_br Omega_c), mesh frequency
z_r Omega_c / 2 pi; the pair's at v2 = r_bg omega_s, mesh frequency 32 * 5 Omega_c / 2 pi, twice
stage 1's, so that the coupled steady state repeats every stage-1 mesh period T1 = p_b / v1.

Lines of action and phasing. Angles counter-clockwise (CCW), planet 1 on the carrier's x axis,
the carrier input torque CCW. In the carrier frame the sun turns CCW and is driven (the planet
pushes it CCW), the ring turns CW and drives the planet: the sun-planet line of action touches
the sun's base circle at the angle +alpha (from the sun's centre) and the planet's at
pi + alpha (from the planet's centre); the ring-planet line touches the planet's base circle
at -alpha and the ring's at -alpha. Writing
a flank's contact point as its roll distance from the planet's tangent point (the involute's
unwound string, Litvin & Fuentes ch. 10), with tau a planet tooth's centre angle, theta_p the
planet's rotation relative to the carrier, psi_b = pi/z_p + 2 inv(alpha) the base thickness
angle (standard tooth, zero backlash):

    sun line:  sigma_s = r_bp (pi + alpha + psi_b/2 - tau - theta_p)   (engages at the sun's tip,
               sigma_s = a sin alpha - sqrt(r_as^2 - r_bs^2), and runs to the planet's tip)
    ring line: sigma_r = r_bp (tau + psi_b/2 + theta_p + alpha)        (engages at the planet's
               tip, sigma_r = sqrt(r_ap^2 - r_bp^2), and runs to the ring's tip)

so that, measured from each engagement point, the ring mesh of a planet runs ahead of its sun
mesh by

    Delta_rs = sqrt(r_ap^2 - r_bp^2) + a sin alpha - sqrt(r_as^2 - r_bs^2)
               - r_bp (pi + 2 alpha) - s_bp     (mod p_b),   s_bp = r_bp psi_b,

independent of tau and theta_p (pi r_bp = z_p p_b / 2: zero for an even z_p, half a pitch for an
odd one). For the specification: Delta_rs = 6.4751 mm = 0.5483 p_b (Parker & Lin's sun-ring
phase gamma_rs, R. G. Parker and J. Lin, "Mesh phasing relationships in planetary and epicyclic
gears", J. Mech. Des. 126 (2004) 365-370, there derived for the sun-driving direction). Check:
the sun-driving load direction (the sun pushes the planet) is this one mirrored and run
backwards in time, which maps each s to g - s: its offset is g_r - g_s - Delta_rs = 9.2638 mm
(mod p_b; tests/test_two_stage_reference.py derives Delta_rs this second way); this file's
Delta_rs belongs to the carrier-in, sun-out direction of the specification (the planet pushes
the sun) and differs from it.

Planet n at psi_n: turning the whole picture by psi_n shows that its sun mesh is planet 1's
with the sun turned back by psi_n, s_sn = s_s1 - (z_s psi_n / 2 pi) p_b, and its ring mesh planet
1's with the ring turned back by psi_n, s_rn = s_r1 + (z_r psi_n / 2 pi) p_b (the ring turns CW
relative to the carrier): Parker & Lin's (2004) relative phases gamma_sn = z_s psi_n / 2 pi and
gamma_rn = -z_r psi_n / 2 pi (mod 1, fractions of a mesh period; their signs follow the sense of
rotation). Here z_s psi_n / 2 pi = 5 (n-1) and
z_r psi_n / 2 pi = 20 (n-1) are integers: all four planets mesh in phase. The pair's travel at
the instant planet 1's sun mesh engages is a free choice of assembly (``pair_offset``, default 0:
both engage at t = 0).

Model (torsional, absolute rotations theta (rad, CCW, deviations from the nominal rigid motion);
Kahraman, J. Sound Vib. 173 (1994) 125-130; Lin & Parker, J. Vib. Acoust. 121 (1999) 316-321, eqs.
(1)-(4) without translations). Coordinates: carrier, ring, sun, planets 1-4, pair gear, pair
pinion (9). Mesh deflections along each line of action, compression positive (from the contact
points' tangential displacements projected on the line of action; r_cb = a cos alpha =
r_bs + r_bp = r_br - r_bp):

    sun mesh n:  delta_sn = r_cb theta_c - r_bs theta_s - r_bp theta_n
    ring mesh n: delta_rn = r_cb theta_c + r_bp theta_n - r_br theta_r
    pair:        delta_p  = r_bg theta_g + r_bpin theta_pin

(a rigid rotation of the whole stage gives delta_sn = delta_rn = 0). Mass: the planets' masses
ride on the carrier (J_c,eff = J_c + N m_p a^2), each planet's own inertia on its absolute
rotation. Structure: the ring hold k_r theta_r, the shaft k_sh (theta_s - theta_g), the output
hold k_o theta_pin. Equations of motion

    M theta'' + C theta' + K_s theta + sum_m g_m^T F_m = f,   F_m = max(0, k_u b n_m(t) g_m theta),

f the carrier torque on the carrier. Statics: F_sn = F_rn = T_c / (2 N r_cb) = T_sun / (N r_bs)
(T_sun = T_c / (1 + z_r/z_s)), F_p = T_sun / r_bg, whatever the stiffness (each planet's torque
balance sets F_sn = F_rn, the carrier's their sum, the shaft's the pair's), and the period
means of the forces in a periodic steady state equal these values at any speed (the same
balances averaged over a period, where the inertia and damping terms average to zero).

Damping: modal, C = M Phi diag(2 zeta omega) Phi^T M on the modes of (M, K_s + K_mesh_mean),
Phi^T M Phi = I, K_mesh_mean = sum_m k_u b eps_m g_m^T g_m (the pair count's mean is eps).

Integration: scipy.integrate.solve_ivp (DOP853, rtol 1e-10) in segments between the instants
where a pair count changes (known in advance from the nominal travel), so that the right-hand
side is smooth in every segment but for a loss of contact (the max(0, .) kink, which the step
control resolves); from the static equilibrium at t = 0 at rest, period after period until
the per-mesh maximum forces and the state at the period's end change by less than ``tol``
(relative) from one period to the next. The dynamic factor of a mesh is its maximum force over
the last period (continuous time: both one-sided limits at every jump, a dense grid of every
segment, refined by a bounded scalar search) over its static force.
"""

from __future__ import annotations

import dataclasses
import itertools
import json
import math
import pathlib
import sys

import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg import eigh
from scipy.optimize import minimize_scalar

__all__ = [
    "DEFAULT_CARRIER_SPEEDS",
    "SpurPair",
    "SteadyState",
    "TwoStageReference",
    "harmonic_steady_state",
    "reference_dynamic_factors",
    "spur_pair",
    "steady_state",
]

DOF_NAMES = ("carrier", "ring", "sun", "planet1", "planet2", "planet3", "planet4", "gear",
             "pinion")


def involute(alpha: float) -> float:
    """inv(alpha) = tan(alpha) - alpha (ISO 21771 eq. (23))."""
    return math.tan(alpha) - alpha


@dataclasses.dataclass(frozen=True)
class SpurPair:
    """A standard spur pair at the standard centre distance (SI: m, rad).

    Attributes:
        z1, z2: tooth numbers (member 1 external; member 2 the internal ring if ``internal``).
        module: m (m). pressure_angle: alpha (rad). face_width: b (m). internal: bool.
    """

    z1: int
    z2: int
    module: float
    pressure_angle: float
    face_width: float
    internal: bool = False

    @property
    def pitch_radii(self) -> tuple[float, float]:
        return self.module * self.z1 / 2, self.module * self.z2 / 2

    @property
    def base_radii(self) -> tuple[float, float]:
        c = math.cos(self.pressure_angle)
        return tuple(r * c for r in self.pitch_radii)

    @property
    def tip_radii(self) -> tuple[float, float]:
        """r + m (external), r - m (the internal ring's, inside its pitch circle)."""
        r1, r2 = self.pitch_radii
        return r1 + self.module, (r2 - self.module if self.internal else r2 + self.module)

    @property
    def centre_distance(self) -> float:
        r1, r2 = self.pitch_radii
        return r2 - r1 if self.internal else r1 + r2

    @property
    def base_pitch(self) -> float:
        """p_b = pi m cos alpha (m)."""
        return math.pi * self.module * math.cos(self.pressure_angle)

    @property
    def tip_rolls(self) -> tuple[float, float]:
        """sqrt(r_a^2 - r_b^2) of each member (m): the tip point's distance from the member's
        tangent point on the line of action."""
        return tuple(math.sqrt(ra**2 - rb**2) for ra, rb in zip(self.tip_radii, self.base_radii))

    @property
    def path_length(self) -> float:
        """g (m), ISO 21771 eqs. (141) (external) / (142) (internal) at alpha_w = alpha."""
        t1, t2 = self.tip_rolls
        asa = self.centre_distance * math.sin(self.pressure_angle)
        return t1 - t2 + asa if self.internal else t1 + t2 - asa

    @property
    def contact_ratio(self) -> float:
        """Transverse contact ratio eps = g / p_b (-)."""
        return self.path_length / self.base_pitch

    @property
    def base_thickness_1(self) -> float:
        """Base tooth thickness of member 1 (m): r_b1 (pi / z1 + 2 inv alpha) (standard tooth,
        s = pi m / 2 on the pitch circle; ISO 21771 eq. (44) with x = 0)."""
        return self.base_radii[0] * (math.pi / self.z1 + 2 * involute(self.pressure_angle))

    def check(self) -> None:
        """ValueError where the path leaves the involutes (interference) or 1 < eps < 2 fails."""
        t1, t2 = self.tip_rolls
        asa = self.centre_distance * math.sin(self.pressure_angle)
        # external: each tip point short of the other member's tangent point; internal: the
        # ring's tip point beyond the planet's tangent point (Litvin & Fuentes ch. 10)
        ok = t2 >= asa if self.internal else (t1 <= asa and t2 <= asa)
        if not ok or not 1.0 < self.contact_ratio < 2.0:
            raise ValueError(f"SpurPair: z = ({self.z1}, {self.z2}): path outside the involutes "
                             f"or eps = {self.contact_ratio:.4f} outside (1, 2)")

    def pairs(self, s):
        """n(s): pairs in contact at the travel s (m) from the engagement point (1 < eps < 2)."""
        return np.where(np.mod(s, self.base_pitch) < self.path_length - self.base_pitch, 2, 1)


_ALPHA_20 = math.radians(20.0)


def spur_pair(z1, z2, module=4e-3, pressure_angle=_ALPHA_20, face_width=0.05,
              internal=False) -> SpurPair:
    """A checked :class:`SpurPair` (ValueError: interference or eps outside (1, 2))."""
    p = SpurPair(int(z1), int(z2), float(module), float(pressure_angle), float(face_width),
                 bool(internal))
    p.check()
    return p


@dataclasses.dataclass(frozen=True)
class TwoStageReference:
    """The specification's system (SI). Defaults: the shared spec of session 42."""

    module: float = 4e-3
    pressure_angle: float = math.radians(20.0)
    z_sun: int = 20
    z_planet: int = 30
    z_ring: int = 80
    planet_angles_deg: tuple = (0.0, 90.0, 180.0, 270.0)
    face_width_1: float = 0.050
    z_gear: int = 32
    z_pinion: int = 24
    face_width_2: float = 0.080
    j_sun: float = 1.6e-3
    j_planet: float = 8.0e-3
    j_carrier: float = 0.5
    j_ring: float = 2.0
    m_planet: float = 4.44
    j_gear: float = 0.0165
    j_pinion: float = 5.2e-3
    k_ring_hold: float = 1e9
    k_shaft: float = 5e5
    k_output_hold: float = 5e5
    k_u: float = 1.4e10
    carrier_torque: float = 5000.0
    damping_ratio: float = 0.05
    pair_offset: float = 0.0  # the pair's travel (m) when planet 1's sun mesh engages
    sun_ring_offset: float | None = None  # Delta_rs (m); None: derived (module docstring)

    # -- geometry -----------------------------------------------------------------------------
    @property
    def sun_planet(self) -> SpurPair:
        return spur_pair(self.z_sun, self.z_planet, self.module, self.pressure_angle,
                         self.face_width_1)

    @property
    def planet_ring(self) -> SpurPair:
        return spur_pair(self.z_planet, self.z_ring, self.module, self.pressure_angle,
                         self.face_width_1, internal=True)

    @property
    def gear_pinion(self) -> SpurPair:
        return spur_pair(self.z_gear, self.z_pinion, self.module, self.pressure_angle,
                         self.face_width_2)

    @property
    def planet_angles(self) -> np.ndarray:
        return np.radians(np.asarray(self.planet_angles_deg, float))

    @property
    def n_planets(self) -> int:
        return len(self.planet_angles_deg)

    @property
    def derived_sun_ring_offset(self) -> float:
        """Delta_rs (m, in [0, p_b)) for the carrier-in, sun-out load direction (module
        docstring)."""
        sp, pr = self.sun_planet, self.planet_ring
        a, al = sp.centre_distance, self.pressure_angle
        r_bp = sp.base_radii[1]
        s_bp = r_bp * (math.pi / self.z_planet + 2 * involute(al))
        d = (pr.tip_rolls[0] + a * math.sin(al) - sp.tip_rolls[0]
             - r_bp * (math.pi + 2 * al) - s_bp)
        return float(np.mod(d, sp.base_pitch))

    @property
    def offsets(self) -> np.ndarray:
        """Each mesh's travel from its engagement point at t = 0 (m), shape (2N + 1,): sun
        meshes, ring meshes, pair (module docstring)."""
        pb = self.sun_planet.base_pitch
        psi = self.planet_angles
        d_rs = self.derived_sun_ring_offset if self.sun_ring_offset is None else (
            self.sun_ring_offset)
        g_s = self.z_sun * psi / (2 * np.pi)
        g_r = self.z_ring * psi / (2 * np.pi)
        off = np.concatenate([-g_s * pb, d_rs + g_r * pb, [self.pair_offset]])
        frac = np.mod(off / pb, 1.0)
        frac[(frac < 1e-9) | (frac > 1 - 1e-9)] = 0.0  # whole pitches (round-off) to 0
        return frac * pb

    # -- matrices -----------------------------------------------------------------------------
    @property
    def mass_matrix(self) -> np.ndarray:
        n = self.n_planets
        a = self.sun_planet.centre_distance
        j = [self.j_carrier + n * self.m_planet * a**2, self.j_ring, self.j_sun,
             *([self.j_planet] * n), self.j_gear, self.j_pinion]
        return np.diag(j)

    @property
    def structure_stiffness(self) -> np.ndarray:
        n = self.n_planets
        K = np.zeros((n + 5, n + 5))
        K[1, 1] += self.k_ring_hold
        s, g = 2, n + 3
        K[np.ix_([s, g], [s, g])] += self.k_shaft * np.array([[1.0, -1.0], [-1.0, 1.0]])
        K[n + 4, n + 4] += self.k_output_hold
        return K

    @property
    def mesh_rows(self) -> np.ndarray:
        """G (2N + 1, N + 5): delta = G theta (m), compression positive (module docstring)."""
        n = self.n_planets
        sp, pr, gp = self.sun_planet, self.planet_ring, self.gear_pinion
        r_bs, r_bp = sp.base_radii
        r_br = pr.base_radii[1]
        G = np.zeros((2 * n + 1, n + 5))
        for i in range(n):
            G[i, 0] = r_bs + r_bp
            G[i, 2] = -r_bs
            G[i, 3 + i] = -r_bp
            G[n + i, 0] = r_br - r_bp
            G[n + i, 3 + i] = r_bp
            G[n + i, 1] = -r_br
        G[2 * n, n + 3], G[2 * n, n + 4] = gp.base_radii
        return G

    @property
    def load(self) -> np.ndarray:
        f = np.zeros(self.n_planets + 5)
        f[0] = self.carrier_torque
        return f

    @property
    def pair_stiffness(self) -> np.ndarray:
        """k_u b per mesh (N/m per pair in contact), (2N + 1,)."""
        n = self.n_planets
        return self.k_u * np.array([self.face_width_1] * 2 * n + [self.face_width_2])

    @property
    def pairs_list(self) -> list[SpurPair]:
        n = self.n_planets
        return [self.sun_planet] * n + [self.planet_ring] * n + [self.gear_pinion]

    @property
    def mean_mesh_stiffness(self) -> np.ndarray:
        """k_u b eps per mesh (N/m), (2N + 1,)."""
        return self.pair_stiffness * np.array([p.contact_ratio for p in self.pairs_list])

    def stiffness_matrix(self, k_mesh) -> np.ndarray:
        G = self.mesh_rows
        return self.structure_stiffness + G.T @ (np.asarray(k_mesh)[:, None] * G)

    def modes(self):
        """(omega (rad/s), Phi mass-normalised) of (M, K_s + K_mesh_mean)."""
        w2, phi = eigh(self.stiffness_matrix(self.mean_mesh_stiffness), self.mass_matrix)
        return np.sqrt(w2), phi

    @property
    def modes_hz(self) -> np.ndarray:
        return self.modes()[0] / (2 * np.pi)

    def mesh_energy_fractions(self) -> np.ndarray:
        """Per mode, the share of the strain energy stored in the meshes (-), (n_dof,)."""
        _, phi = self.modes()
        G, k = self.mesh_rows, self.mean_mesh_stiffness
        mesh = np.sum(k[:, None] * (G @ phi) ** 2, axis=0)
        total = np.einsum("im,ij,jm->m", phi, self.stiffness_matrix(k), phi)
        return mesh / total

    @property
    def damping_matrix(self) -> np.ndarray:
        w, phi = self.modes()
        M = self.mass_matrix
        return M @ phi @ np.diag(2 * self.damping_ratio * w) @ phi.T @ M

    # -- statics and kinematics ---------------------------------------------------------------
    @property
    def static_forces(self) -> np.ndarray:
        """The torque-ratio transverse forces (N), (2N + 1,): T_sun / (N r_bs) on every stage-1
        mesh, T_sun / r_bg on the pair, T_sun = T_c / (1 + z_r / z_s)."""
        n = self.n_planets
        t_sun = self.carrier_torque / (1 + self.z_ring / self.z_sun)
        f1 = t_sun / (n * self.sun_planet.base_radii[0])
        return np.array([f1] * 2 * n + [t_sun / self.gear_pinion.base_radii[0]])

    def travel_speeds(self, carrier_speed: float) -> np.ndarray:
        """Contact-line travel speed of every mesh (m/s), (2N + 1,)."""
        n = self.n_planets
        v1 = self.sun_planet.base_radii[0] * self.z_ring / self.z_sun * carrier_speed
        v2 = self.gear_pinion.base_radii[0] * (1 + self.z_ring / self.z_sun) * carrier_speed
        return np.array([v1] * 2 * n + [v2])

    def mesh_period(self, carrier_speed: float) -> float:
        """T1 = p_b / v1 (s): stage 1's mesh period, the coupled steady state's period."""
        return self.sun_planet.base_pitch / self.travel_speeds(carrier_speed)[0]

    def mesh_stiffness(self, t, carrier_speed: float) -> np.ndarray:
        """k_u b n_m(s_m(t)) (N/m), (2N + 1,) at one time t (s)."""
        s = self.offsets + self.travel_speeds(carrier_speed) * t
        n = np.array([p.pairs(si) for p, si in zip(self.pairs_list, s)], float)
        return self.pair_stiffness * n

    def switch_times(self, carrier_speed: float) -> np.ndarray:
        """Instants in [0, T1) where a pair count changes (s), sorted, with 0 and T1 added."""
        T = self.mesh_period(carrier_speed)
        v = self.travel_speeds(carrier_speed)
        times = {0.0, T}
        for p, s0, vi in zip(self.pairs_list, self.offsets, v):
            pb = p.base_pitch
            for edge in (0.0, p.path_length - pb):
                t = np.mod(edge - s0, pb) / vi
                while t < T * (1 - 1e-12):
                    times.add(float(t))
                    t += pb / vi
        ts = np.array(sorted(times))
        keep = np.concatenate([[True], np.diff(ts) > 1e-12 * T])
        return ts[keep]

    def static_solution(self, t: float = 0.0, carrier_speed: float = 1.0) -> np.ndarray:
        """theta (rad) at rest under the carrier torque with the stiffness at t (right limit)."""
        T = self.mesh_period(carrier_speed)
        k = self.mesh_stiffness(t + 1e-9 * T, carrier_speed)
        return np.linalg.solve(self.stiffness_matrix(k), self.load)


# -- integration --------------------------------------------------------------------------------


@dataclasses.dataclass
class SteadyState:
    """The last period of a run: segments (t0, t1, k_mesh, dense solution), the period T (s),
    the periods run and the last relative change; ``forces(t)`` gives the mesh forces."""

    model: TwoStageReference
    period: float
    segments: list
    periods: int
    change: float
    rows: np.ndarray
    f_max: float = 0.0  # the highest natural frequency (Hz): sets the grids

    def _grid(self, t0, t1, at_least):
        return max(at_least, math.ceil(24 * (t1 - t0) * self.f_max))

    def forces_in_segment(self, seg, t) -> np.ndarray:
        """Mesh forces (N), (2N + 1, len(t)), with the segment's stiffness."""
        t0, t1, k, sol = seg
        theta = sol(np.clip(t, t0, t1))[: self.rows.shape[1]]
        return np.maximum(0.0, k[:, None] * (self.rows @ theta))

    def max_forces(self, grid: int = 64, refine: bool = True) -> np.ndarray:
        """Each mesh's maximum force over the period (N), (2N + 1,): both one-sided limits at
        the segment ends, a grid of at least ``grid`` points per segment and 24 per period of
        the highest mode, refined by a bounded scalar search around the grid's maximum."""
        best = np.zeros(self.rows.shape[0])
        for seg in self.segments:
            t0, t1 = seg[0], seg[1]
            n = self._grid(t0, t1, grid)
            ts = np.linspace(t0, t1, n + 1)
            F = self.forces_in_segment(seg, ts)
            for m in range(F.shape[0]):
                i = int(np.argmax(F[m]))
                fm = F[m, i]
                if refine and 0 < i < n:
                    r = minimize_scalar(
                        lambda t, seg=seg, m=m: -self.forces_in_segment(
                            seg, np.array([t]))[m, 0],
                        bounds=(ts[i - 1], ts[i + 1]), method="bounded",
                        options={"xatol": 1e-12 * self.period})
                    fm = max(fm, -r.fun)
                best[m] = max(best[m], fm)
        return best

    def min_forces(self, grid: int = 64) -> np.ndarray:
        """Each mesh's minimum force over the period on the grid of :meth:`max_forces` (N),
        (2N + 1,): 0 where the mesh loses contact."""
        low = np.full(self.rows.shape[0], np.inf)
        for seg in self.segments:
            ts = np.linspace(seg[0], seg[1], self._grid(seg[0], seg[1], grid) + 1)
            low = np.minimum(low, self.forces_in_segment(seg, ts).min(axis=1))
        return low

    def mean_forces(self, grid: int = 256) -> np.ndarray:
        """Each mesh's period-mean force (N), (2N + 1,) (Simpson's rule per segment, at least
        24 points per period of the highest mode)."""
        from scipy.integrate import simpson

        tot = np.zeros(self.rows.shape[0])
        for seg in self.segments:
            n = self._grid(seg[0], seg[1], grid)
            ts = np.linspace(seg[0], seg[1], 2 * n + 1)
            tot += simpson(self.forces_in_segment(seg, ts), x=ts, axis=1)
        return tot / self.period

    def sample(self, times) -> tuple[np.ndarray, np.ndarray]:
        """(theta (n_dof, t), forces (2N + 1, t)) at times in [0, T] (right-continuous)."""
        out_th, out_f = [], []
        for t in np.atleast_1d(times):
            seg = next((g for g in self.segments if g[0] <= t < g[1]), self.segments[-1])
            th = seg[3](np.clip(t, seg[0], seg[1]))[: self.rows.shape[1]]
            out_th.append(th)
            out_f.append(np.maximum(0.0, seg[2] * (self.rows @ th)))
        return np.array(out_th).T, np.array(out_f).T


def _integrate(model: TwoStageReference, period: float, breaks, k_of_t, forcing=None, *,
               tol=1e-6, rtol=1e-10, method="DOP853", min_periods=3, max_periods=4000,
               y0=None) -> SteadyState:
    """Period after period from y0 (default: the static state at rest) until the maximum forces
    (relative to the static forces) and the end state (relative to its largest rotation) change
    by less than ``tol`` over one period. The transient decays geometrically, by a factor rho
    per period, so the distance to the periodic state is about change / (1 - rho); the slowest
    mode (448 Hz at zeta = 0.05) gives 1 - rho >= 0.02 up to a mesh frequency of 7 kHz, so
    tol = 1e-6 leaves the dynamic factors within about 5e-5 of the periodic state's."""
    M = model.mass_matrix
    Minv = np.diag(1.0 / np.diag(M))
    C = model.damping_matrix
    Ks = model.structure_stiffness
    G = model.mesh_rows
    f0 = model.load
    nd = M.shape[0]
    if y0 is None:
        th0 = np.linalg.solve(model.stiffness_matrix(k_of_t(0.5 * (breaks[0] + breaks[1]))), f0)
        y0 = np.concatenate([th0, np.zeros(nd)])
    scale_th = max(np.max(np.abs(y0[:nd])), 1e-6)
    w_max = float(model.modes()[0].max())
    atol = np.concatenate([np.full(nd, 1e-3 * rtol * scale_th),
                           np.full(nd, 1e-3 * rtol * scale_th * w_max)])
    fscale = model.static_forces
    ks = [k_of_t(0.5 * (a + b)) for a, b in itertools.pairwise(breaks)]

    def rhs_factory(k, t_base):
        def rhs(t, y):
            th, v = y[:nd], y[nd:]
            F = np.maximum(0.0, k * (G @ th))
            acc = f0 - C @ v - Ks @ th - G.T @ F
            if forcing is not None:
                acc = acc + forcing(t + t_base)
            return np.concatenate([v, Minv @ acc])
        return rhs

    def jac_factory(k):
        # exact while every mesh is in contact (an implicit method's Newton matrix otherwise)
        A = np.zeros((2 * nd, 2 * nd))
        A[:nd, nd:] = np.eye(nd)
        A[nd:, :nd] = -Minv @ (Ks + G.T @ (k[:, None] * G))
        A[nd:, nd:] = -Minv @ C
        return A

    def one_period(y, dense):
        """(end state, forces at both ends of every segment (2 n_seg, 2N + 1), segments)."""
        segs, ends = [], []
        for (a, b), k in zip(itertools.pairwise(breaks), ks, strict=True):
            extra = {} if method in ("DOP853", "RK45") else {"jac": jac_factory(k)}
            sol = solve_ivp(rhs_factory(k, 0.0), (a, b), y, method=method, rtol=rtol,
                            atol=atol, dense_output=dense, **extra)
            if not sol.success:
                raise RuntimeError(f"solve_ivp failed: {sol.message}")
            ends.append(np.maximum(0.0, k * (G @ y[:nd])))
            y = sol.y[:, -1]
            ends.append(np.maximum(0.0, k * (G @ y[:nd])))
            segs.append((a, b, k, sol.sol))
        return y, np.array(ends), segs

    def change_of(y_a, y_b, f_a, f_b):
        return max(np.max(np.abs(f_b - f_a) / fscale),
                   np.max(np.abs(y_b[:nd] - y_a[:nd])) / scale_th)

    y = np.asarray(y0, float)
    f_prev, change = None, np.inf
    for p in range(1, max_periods + 1):
        y_start = y
        y, f_ends, _ = one_period(y, dense=False)
        if f_prev is not None:
            change = change_of(y_start, y, f_prev, f_ends)
            if p >= min_periods - 1 and change < tol:
                # one more period, with its dense output: the steady period
                y_last, f_last, segs = one_period(y, dense=True)
                return SteadyState(model, period, segs, p + 1,
                                   change_of(y, y_last, f_ends, f_last), G,
                                   w_max / (2 * np.pi))
        f_prev = f_ends
    raise RuntimeError(f"no periodic steady state in {max_periods} periods (change {change:.2e})")


def steady_state(model: TwoStageReference, carrier_speed: float, **kw) -> SteadyState:
    """The periodic steady state at one carrier speed (rad/s) with the time-varying meshes."""
    if not (carrier_speed > 0 and math.isfinite(carrier_speed)):
        raise ValueError(f"steady_state: carrier_speed = {carrier_speed!r} rad/s is out of "
                         "range: allowed a finite value > 0")
    T = model.mesh_period(carrier_speed)
    breaks = model.switch_times(carrier_speed)
    return _integrate(model, T, breaks, lambda t: model.mesh_stiffness(t, carrier_speed), **kw)


def harmonic_steady_state(model: TwoStageReference, amplitude, omega: float, pieces: int = 8,
                          **kw) -> SteadyState:
    """The steady state with constant mean mesh stiffness and an added torque
    ``amplitude * sin(omega t)`` (N m, (n_dof,)) at omega (rad/s): a check of the integrator
    against the frequency response (K - omega^2 M + i omega C)^-1 (tests)."""
    T = 2 * np.pi / omega
    amp = np.asarray(amplitude, float)
    km = model.mean_mesh_stiffness
    return _integrate(model, T, np.linspace(0.0, T, pieces + 1), lambda t: km,
                      forcing=lambda t: amp * np.sin(omega * t), **kw)


def reference_dynamic_factors(carrier_speeds, model: TwoStageReference | None = None,
                              samples_per_period: int | None = None, **kw) -> dict:
    """Per-mesh dynamic factors of the specification's system at the carrier speeds (rad/s).

    Args:
        carrier_speeds: Omega_c (rad/s), > 0, shape (S,) or ().
        model: the system (default: the specification's).
        samples_per_period: also give the factors from the forces sampled at the S_p instants
            (i + 1/2) T1 / S_p of the steady period (as a fixed-step integrator with S_p steps
            per stage-1 mesh period samples them): "sun_sampled", "ring_sampled",
            "pair_sampled".
        **kw: to the period-by-period integration (tol, rtol, method, min_periods, max_periods).

    Returns:
        a dict: "sun" (S, N) and "ring" (S, N): each planet's sun-planet and ring-planet mesh's
        maximum force over the steady period (continuous time, the jump instants included) /
        its static force; "pair" (S,); "static": the static forces (N) {"sun", "ring",
        "pair"}; "modes_Hz": the natural frequencies (Hz) of (M, K_s + K_mesh_mean), (n_dof,);
        "mesh_energy": each mode's share of strain energy in the meshes; "min_ratio"
        (S, 2N + 1): minimum force / static (0: the mesh loses contact); "mean_ratio"
        (S, 2N + 1): period-mean force / static force (1 in a periodic steady state: a check);
        "pre_entry_ratio" (S, 2N + 1): the largest force just before a pair enters / static
        (the factor is 2 x this where the entry jump sets the maximum); "periods" (S,);
        "change" (S,): the last period-to-period change; "carrier_speeds" (S,);
        "mesh_frequency_Hz" (S,): stage 1's, z_r Omega_c / 2 pi.

    Raises:
        ValueError: a speed not finite or <= 0.
    """
    model = model or TwoStageReference()
    speeds = np.atleast_1d(np.asarray(carrier_speeds, float))
    bad = [w for w in speeds if not (math.isfinite(w) and w > 0)]
    if bad:
        raise ValueError(f"reference_dynamic_factors: carrier_speeds = {bad[0]!r} rad/s is out "
                         "of range: allowed finite values > 0")
    n = model.n_planets
    F0 = model.static_forces
    out = {k: [] for k in ("df", "min", "mean", "pre", "periods", "change", "sampled")}
    for w in speeds:
        st = steady_state(model, float(w), **kw)
        out["df"].append(st.max_forces() / F0)
        out["min"].append(st.min_forces() / F0)
        out["mean"].append(st.mean_forces() / F0)
        out["pre"].append(_pre_entry(model, st, float(w)) / F0)
        out["periods"].append(st.periods)
        out["change"].append(st.change)
        if samples_per_period:
            ts = (np.arange(samples_per_period) + 0.5) * st.period / samples_per_period
            out["sampled"].append(st.sample(ts)[1].max(axis=1) / F0)
    df = np.array(out["df"])
    res = {
        "sun": df[:, :n],
        "ring": df[:, n:2 * n],
        "pair": df[:, 2 * n],
        "static": {"sun": float(F0[0]), "ring": float(F0[n]), "pair": float(F0[2 * n])},
        "modes_Hz": model.modes_hz,
        "mesh_energy": model.mesh_energy_fractions(),
        "min_ratio": np.array(out["min"]),
        "mean_ratio": np.array(out["mean"]),
        "pre_entry_ratio": np.array(out["pre"]),
        "periods": np.array(out["periods"]),
        "change": np.array(out["change"]),
        "carrier_speeds": speeds,
        "mesh_frequency_Hz": model.z_ring * speeds / (2 * np.pi),
    }
    if samples_per_period:
        sm = np.array(out["sampled"])
        res.update(sun_sampled=sm[:, :n], ring_sampled=sm[:, n:2 * n], pair_sampled=sm[:, 2 * n])
    return res


def _pre_entry(model: TwoStageReference, st: SteadyState, carrier_speed: float) -> np.ndarray:
    """Each mesh's largest force at the left limit of an instant where one of its pairs enters
    (N), (2N + 1,)."""
    v = model.travel_speeds(carrier_speed)
    out = np.zeros(len(v))
    for m, (p, s0, vi) in enumerate(zip(model.pairs_list, model.offsets, v)):
        t = np.mod(-s0, p.base_pitch) / vi
        while t < st.period * (1 - 1e-12):
            # the segment ending at t (the last one for an entry at t = 0: periodicity)
            seg = next((g for g in st.segments if abs(g[1] - t) <= 1e-12 * st.period),
                       st.segments[-1])
            out[m] = max(out[m], st.forces_in_segment(seg, np.array([seg[1]]))[m, 0])
            t += p.base_pitch / vi
    return out


# The stage-1 mesh frequency z_r Omega_c / 2 pi = 12.73 Omega_c Hz of each default speed, against
# the modes of the specification's system (448.5, 1199.2, 3137.5, 4389.8, 4996.4 x3, 5492.3,
# 11022.6 Hz; mesh-dominated, i.e. over half their strain energy in the meshes: 4389.8, the three
# planet modes at 4996.4 (orthogonal to the in-phase meshing: not excited), 5492.3, 11022.6):
#   3 rad/s   ->   38 Hz  slow (quasi-static: 1/115 of the lowest mode)
#   170       -> 2165 Hz  the pair's mesh frequency (2 x) 1.4 % below the 4389.8 Hz mode
#   260       -> 3310 Hz  between the 3137.5 and 4389.8 Hz modes
#   338       -> 4304 Hz  2.0 % below the 4389.8 Hz mode (within 5 % of a resonance)
#   370       -> 4711 Hz  between 4389.8 and 4996.4
#   392       -> 4991 Hz  on the planet modes (not excited: a check of the phasing)
#   431       -> 5487 Hz  0.1 % below the 5492.3 Hz mode
#   510       -> 6494 Hz  above the three
DEFAULT_CARRIER_SPEEDS = (3.0, 170.0, 260.0, 338.0, 370.0, 392.0, 431.0, 510.0)


def _jsonable(x):
    if isinstance(x, dict):
        return {k: _jsonable(v) for k, v in x.items()}
    if isinstance(x, np.ndarray):
        return x.tolist()
    if isinstance(x, (np.floating, np.integer)):
        return x.item()
    return x


def _lost(min_ratio) -> str:
    lost = [n for n, j in (("sun", 0), ("ring", 4), ("pair", 8)) if min_ratio[j] == 0]
    return ",".join(lost) or "-"


def _main(argv=None) -> int:
    """Print the table and write docs/bench/two_stage_reference.json (from the checkout root)."""
    import time

    model = TwoStageReference()
    t0 = time.perf_counter()
    res = reference_dynamic_factors(DEFAULT_CARRIER_SPEEDS, model, samples_per_period=64)
    wall = time.perf_counter() - t0
    geo = {name: {"contact_ratio": p.contact_ratio, "path_length_m": p.path_length,
                  "base_radii_m": p.base_radii, "tip_radii_m": p.tip_radii,
                  "centre_distance_m": p.centre_distance, "base_pitch_m": p.base_pitch}
           for name, p in (("sun_planet", model.sun_planet), ("planet_ring", model.planet_ring),
                           ("gear_pinion", model.gear_pinion))}
    print("modes (Hz):", " ".join(f"{f:.1f}" for f in res["modes_Hz"]))
    print("mesh energy share:", " ".join(f"{e:.2f}" for e in res["mesh_energy"]))
    print("contact ratios:", {k: round(v["contact_ratio"], 4) for k, v in geo.items()})
    print(f"sun-ring offset {model.derived_sun_ring_offset * 1e3:.4f} mm "
          f"({model.derived_sun_ring_offset / model.sun_planet.base_pitch:.4f} p_b)")
    print("static forces (N):", res["static"])
    print(f"{'Omega_c':>8} {'f_mesh1':>8} {'DF sun':>8} {'DF ring':>8} {'DF pair':>8} "
          f"{'sun@64':>8} {'ring@64':>8} {'pair@64':>8} {'periods':>7} {'contact loss':>12}")
    for i, w in enumerate(res["carrier_speeds"]):
        print(f"{w:8.1f} {res['mesh_frequency_Hz'][i]:8.1f} {res['sun'][i, 0]:8.4f} "
              f"{res['ring'][i, 0]:8.4f} {res['pair'][i]:8.4f} {res['sun_sampled'][i, 0]:8.4f} "
              f"{res['ring_sampled'][i, 0]:8.4f} {res['pair_sampled'][i]:8.4f} "
              f"{res['periods'][i]:7d} {_lost(res['min_ratio'][i]):>12}")
    data = {
        "what": "two-stage coupled example, independent numpy/scipy reference "
                "(benchmarks/_two_stage_reference.py): per-mesh dynamic factors",
        "spec": "session 42 shared spec (two_stage_spec.md)",
        "integrator": "scipy solve_ivp DOP853 rtol 1e-10, segmented at the stiffness jumps, "
                      "from the static state until the period-to-period change < 1e-6",
        "df_definition": "max over the steady stage-1 mesh period of the mesh force (continuous "
                         "time, jump instants included) / static force; *_sampled: the max of "
                         "the forces at (i + 1/2) T1 / 64",
        "sun_ring_offset_m": model.derived_sun_ring_offset,
        "pair_offset_m": model.pair_offset,
        "geometry": geo,
        "wall_s": wall,
        **_jsonable(res),
    }
    out = pathlib.Path("docs/bench/two_stage_reference.json")
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(data, indent=1) + "\n", encoding="utf-8")
    print(f"wrote {out} ({wall:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(_main())
