"""What ``jaxgear sweep`` computes and reports by the kind of dynamic model it sweeps: a lumped
model (:class:`jaxgear.dynamics.DynamicModel`: torsional, 1-DOF relative, lumped 3D scenes and
their trains) or a model with condensed FE bodies (:class:`jaxgear.dynamics.HybridModel`).

:func:`sweep_kind` dispatches on the model's type to a :class:`SweepKind`, whose methods give
``sweep.json``'s sections of that kind (in the order the file has them); a new kind of model
registers its own.

:func:`check_model_options` asks a model kind's contract which of ``jaxgear sweep``'s options it
cannot run (every form's sweep, at load: from the class, before any model is built)."""

from __future__ import annotations

import abc
import functools
import warnings

import numpy as np

from ..dynamics import (
    DIRECTIONS,
    DynamicModel,
    HybridModel,
    mesh_energy_shares,
    mesh_stiffness_means,
    modes_at_speed,
)
from ..io import SceneSpec, dynamic_model_kind, spec_integrator
from ._case_kinds import pair_teeth
from ._parser import CONTACT_NAMES, SOLVER_NAMES
from ._sweep_json import (
    at_speed_keys,
    clean,
    flexible_gears,
    hybrid_static_pressures,
    lumped_static_pressures,
    nodal_diameter_resonances,
    passing_rate,
    rim_content,
    vtu_series,
)

__all__ = [
    "CAMPBELL_GRID",
    "STIFFENING_WARN",
    "HybridSweep",
    "LumpedSweep",
    "SweepKind",
    "check_model_options",
    "exports_bodies",
    "sweep_kind",
]

# a hybrid run without the rotating-frame terms warns when the modes move more than this by the
# top speed (the critical speeds at rest are then off by about as much)
STIFFENING_WARN = 0.05
# pinion speeds (0 to 1.05 x the top speed) at which a hybrid sweep follows the modes
CAMPBELL_GRID = 43

_HYBRID_NOTES = (
    "hybrid model (condensed bodies): Newmark in the cell space, centrifugal loads on, "
    "damping on the mesh-averaged system ([scene.damping]); steps_per_period_used per "
    "speed (automatic unless [scene.integration] sets it; with several, the kept records "
    "are subsampled to the smallest); rim_waves: each condensed gear's largest rim wave "
    "above half the mesh frequency per nodal diameter (its body frame, direction +1 "
    "forward, with its rotation); nodal_diameter_resonances: (3.9) for each condensed "
    "gear at its teeth and speed (gear, teeth, speed_ratio); bearing "
    "forces in the fixed frame, the static ones at the first speed (its centrifugal load)"
)


class SweepKind(abc.ABC):
    """The parts of a speed sweep that depend on the kind of dynamic model.

    ``n_modes``: the lowest modes ``sweep.json`` reports (None: every one)."""

    n_modes: int | None = None

    @abc.abstractmethod
    def chunk_size(self, n_speeds: int) -> int:
        """Speeds per compiled call of :func:`jaxgear.dynamics.speed_sweep`."""

    @abc.abstractmethod
    def model_name(self, spec) -> str:
        """``sweep.json``'s ``model``."""

    @abc.abstractmethod
    def flexible_gears(self, case, model) -> list[dict]:
        """The condensed gears whose nodal diameters and rim waves are reported
        (:func:`jaxgear.cli._sweep_json.flexible_gears`)."""

    @abc.abstractmethod
    def structure_keys(self, case, model, spec, n_meshes: int, flexible: list) -> dict:
        """The keys that describe the model after the static mesh force: its damping and
        condensed gears, or its mean mesh stiffness."""

    @abc.abstractmethod
    def modal_keys(self, model, spec, modes, n_meshes: int) -> dict:
        """The keys of the modes after their frequencies and mesh energy shares."""

    @abc.abstractmethod
    def campbell_modes(self, model, modes, speeds, omega):
        """``(keys, grid, omega, at)``: ``sweep.json``'s keys of the modes at speed, the speed
        grid the critical speeds follow the modes on (None: at rest), the modes' frequencies
        (rad/s) on it (or ``omega`` at rest) and the modes at speed (None without)."""

    @abc.abstractmethod
    def resonance_keys(self, model, modes, speeds, flexible: list, at) -> dict:
        """The keys of the condensed gears' nodal-diameter resonances (3.9)."""

    @abc.abstractmethod
    def static_pressures(self, model, r, law, hertz) -> list[float]:
        """Each mesh's largest quasi-static Hertzian pressure at rest (Pa)."""

    @abc.abstractmethod
    def rim_keys(self, r, flexible: list, z1: float) -> dict:
        """The keys of the condensed gears' rim waves per speed."""

    @abc.abstractmethod
    def closing_keys(self, model, bodies, spec, law, modes, vtu_speed, out_dir, flexible):
        """The last keys before the timing: the VTU series and the notes."""


class LumpedSweep(SweepKind):
    """A lumped model: every mode reported with its energy per part, about ten chunks of
    speeds, no condensed gear."""

    def chunk_size(self, n_speeds: int) -> int:
        return max(1, min(32, -(-n_speeds // 10)))

    def model_name(self, spec) -> str:
        return spec.model

    def flexible_gears(self, case, model) -> list[dict]:
        return []

    def structure_keys(self, case, model, spec, n_meshes: int, flexible: list) -> dict:
        if n_meshes == 1:
            return {"mesh_stiffness_mean_N_per_m": float(model.mesh_stiffness_mean)}
        ppp = spec.steps_per_period or 64  # each mesh's time-averaged loaded stiffness
        means = np.asarray(mesh_stiffness_means(model, positions_per_pitch=ppp))
        return {"mesh_stiffness_mean_N_per_m": [float(k) for k in means]}

    def modal_keys(self, model, spec, modes, n_meshes: int) -> dict:
        out = {}
        if n_meshes > 1:  # each mesh's share of each mode's strain energy
            shares = np.asarray(
                mesh_energy_shares(model, positions_per_pitch=spec.steps_per_period or 64)
            )
            out["mesh_energy_share_mesh"] = [clean(row) for row in shares.T[: self.n_modes]]
        out["modal_energy_parts"] = list(modes.parts)
        out["modal_energy"] = [clean(row) for row in np.asarray(modes.energy)]
        return out

    def campbell_modes(self, model, modes, speeds, omega):
        return {}, None, omega, None

    def resonance_keys(self, model, modes, speeds, flexible: list, at) -> dict:
        return {}

    def static_pressures(self, model, r, law, hertz) -> list[float]:
        return lumped_static_pressures(r)

    def rim_keys(self, r, flexible: list, z1: float) -> dict:
        return {}

    def closing_keys(self, model, bodies, spec, law, modes, vtu_speed, out_dir, flexible):
        return {}


class HybridSweep(SweepKind):
    """A model with condensed FE bodies: the 20 lowest modes (of thousands of coordinates),
    one speed per call (a speed takes seconds: the bar moves per speed and Ctrl-C stops the
    sweep after the speed in progress), the modes at speed, each condensed gear's
    nodal-diameter resonances and rim waves, a VTU series on request."""

    n_modes = 20

    def chunk_size(self, n_speeds: int) -> int:
        return 1

    def model_name(self, spec) -> str:
        return "hybrid"

    def flexible_gears(self, case, model) -> list[dict]:
        return flexible_gears(case, model.scene)

    def structure_keys(self, case, model, spec, n_meshes: int, flexible: list) -> dict:
        return {
            "rayleigh_alpha_per_s": spec.rayleigh_alpha,
            "rayleigh_beta_s": spec.rayleigh_beta,
            "damping_ratio_mesh_structure": [spec.mesh_ratio, spec.structure_ratio],
            "rotating_frame": spec.rotating_frame,
            **pair_teeth(case),
            "flexible_gears": [g["name"] for g in flexible],
            "flexible_gear_teeth": [g["teeth"] for g in flexible],
            "flexible_gear_speed_ratio": [g["speed_ratio"] for g in flexible],
            "flexible_gear_meshes": [g["meshes"] for g in flexible],
        }

    def modal_keys(self, model, spec, modes, n_meshes: int) -> dict:
        return {}

    def campbell_modes(self, model, modes, speeds, omega):
        # the modes at speed (spin softening and stress stiffening, checked at the top speed):
        # the Campbell diagram and the critical speeds follow them when the run has the
        # rotating-frame terms
        at = modes_at_speed(
            model.scene, modes, np.linspace(0.0, 1.05 * speeds.max(), CAMPBELL_GRID)
        )
        keys = at_speed_keys(at, self.n_modes, model.rotating_frame)
        if model.rotating_frame:
            return keys, np.asarray(at.speeds), np.asarray(at.omega)[:, : self.n_modes], at
        if at.shift > STIFFENING_WARN:
            warnings.warn(
                f"the structure's modes move by up to {at.shift:.1%} at "
                f"{float(at.speeds[-1]):.6g} rad/s (spin softening, stress stiffening), which "
                "this run leaves out: [scene."
                "integration] rotating_frame = true adds them (the critical speeds and the "
                "Campbell diagram then follow the modes at speed)",
                stacklevel=3,
            )
        return keys, None, omega, None

    def resonance_keys(self, model, modes, speeds, flexible: list, at) -> dict:
        rows = [
            row
            for g in flexible
            for row in nodal_diameter_resonances(model.scene, modes, speeds, g, at)
        ]
        return {"nodal_diameter_resonances": rows}

    def static_pressures(self, model, r, law, hertz) -> list[float]:
        return hybrid_static_pressures(model, law, hertz)

    def rim_keys(self, r, flexible: list, z1: float) -> dict:
        # each condensed gear's, per speed, above half its own tooth-passing frequency
        return {
            "rim_waves": {
                g["name"]: [
                    rim_content(r, i, float(f) * passing_rate(g, z1), g["stations"], g["spin"])
                    for i, f in enumerate(np.asarray(r.mesh_frequency))
                ]
                for g in flexible
            }
        }

    def closing_keys(self, model, bodies, spec, law, modes, vtu_speed, out_dir, flexible):
        vtu = vtu_series(model, bodies, spec, law, modes, vtu_speed, out_dir, flexible)
        return {
            "vtu_series": {"speed_rad_s": vtu_speed, "files": vtu} if vtu else None,
            "notes": _HYBRID_NOTES,
        }


@functools.singledispatch
def sweep_kind(model) -> SweepKind:
    """The :class:`SweepKind` of a dynamic model, by its type."""
    raise TypeError(f"jaxgear sweep: no sweep of a {type(model).__name__}")


@sweep_kind.register
def _(model: DynamicModel) -> SweepKind:
    return LumpedSweep()


@sweep_kind.register
def _(model: HybridModel) -> SweepKind:
    return HybridSweep()


def exports_bodies(kind) -> bool:
    """Whether a sweep of a model of ``kind`` (its class) can write its condensed bodies' VTU
    series (``--vtu-speed``): a model with condensed FE bodies
    (:class:`~jaxgear.dynamics.HybridModel`)."""
    return issubclass(kind, HybridModel)


def named_integrator(name: str):
    """The integrator a ``--solver`` name (a case file's ``[scene.integration] solver``)
    names, of its type (:func:`jaxgear.io.spec_integrator`: Newmark, else a diffrax solver)."""
    return spec_integrator(SceneSpec(solver=name))


def check_case_options(case, **options) -> None:
    """:func:`check_model_options` for the kind of a case's dynamic model
    (:func:`jaxgear.io.dynamic_model_kind`: nothing is built), its ``--contact`` names read as
    the case reads them (:meth:`jaxgear.io.Case.contact_law`); nothing for a case without a
    dynamic model (an internal mesh: its sweep refuses it)."""
    kind = dynamic_model_kind(case.form, case)
    if kind is not None:
        check_model_options(kind, law_of=case.contact_law, **options)


def check_model_options(kind, *, direction="independent", solver=None, contact=None,
                        vtu_speed=None, integrator_of=named_integrator, law_of=None,
                        **_) -> None:
    """Refuse in one line, before any model is built, an option of ``jaxgear sweep`` that a
    dynamic model of ``kind`` (an :class:`~jaxgear.dynamics.AbstractDynamicModel` class)
    cannot run, by asking its contract's declarations: ``--direction`` other than independent
    where the kind does not continue (:attr:`~jaxgear.dynamics.AbstractDynamicModel.continues`),
    ``--solver`` and ``--contact`` whose integrator (``integrator_of(name)``) or contact law
    (``law_of(name)``) is not of a type it declares
    (:attr:`~jaxgear.dynamics.AbstractDynamicModel.integrators`,
    :attr:`~jaxgear.dynamics.AbstractDynamicModel.contact_laws`; the allowed names are those
    of its types), ``--vtu-speed`` without condensed bodies (:func:`exports_bodies`).

    Raises:
        ValueError: the option, its value, what the model is and the allowed values."""
    what = kind.__name__
    if DIRECTIONS[direction].continues and not kind.continues:
        raise ValueError(
            f"--direction = {direction}: a {what} sweeps independent speeds only (allowed: "
            "independent)"
        )
    if solver is not None and not kind.runs(integrator_of(solver)):
        allowed = [name for name in SOLVER_NAMES if kind.runs(integrator_of(name))]
        raise ValueError(
            f"--solver = {solver}: a {what} does not run it (allowed: {', '.join(allowed)})"
        )
    if contact is not None and law_of is not None and not kind.runs(law_of(contact)):
        allowed = [name for name in CONTACT_NAMES if kind.runs(law_of(name))]
        raise ValueError(
            f"--contact = {contact}: a {what} does not run it (allowed: {', '.join(allowed)})"
        )
    if vtu_speed is not None and not exports_bodies(kind):
        raise ValueError(
            f"--vtu-speed = {vtu_speed}: a {what} has no condensed body to export (allowed: "
            "leave it out; a scene with condensed bodies writes them)"
        )
