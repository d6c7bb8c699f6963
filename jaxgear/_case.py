"""A gear-pair case in SI units: geometry, modifications, material, operating point, mesh model
settings, and optionally a dynamic scene and optimisation settings.

Cases are read from TOML files (units in key names) by :func:`jaxgear.io.load_case`, which
validates the whole file first; this module holds only the validated, SI-unit result.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from ._baseplane import MeshModel
from ._contact import ContactLaw, contact_law_from_name
from ._geometry import GearPair
from ._modifications import Modifications
from ._stiffness import stiffness_table

__all__ = ["Case"]


@dataclasses.dataclass(frozen=True)
class Case:
    """A validated case (SI units).

    Attributes:
        name: case name. pair: :class:`GearPair`. modifications: :class:`Modifications`.
        youngs_modulus (Pa), poisson_ratio (-), density (kg/m³).
        torque: pinion torque (N·m). speed: pinion speed Ω (rad/s) of the quasi-static
            centrifugal load of condensed bodies (each body at its own speed); 0: at rest.
        stiffness_model: "weber" | "uniform" | "iso6336" | "fe2d"; uniform_k0: N/m² (uniform
            only); fe2d_size: element size (m) of the ``fe2d`` model, ``None`` for m_n / 6.
        slices: slices per contact line; positions_per_pitch: positions per mesh period.
        smooth_width: smoothing width of the smooth contact law (m).
        foundation: the foundation (gear-body) term of the ``weber`` model: "weber" | "sainsot"
            | "none" (``True``/``False`` are accepted as aliases of "weber"/"none").
        scene: the validated ``[scene]`` table (:class:`jaxgear.dynamics.SceneSpec`) or None.
        optimise: the validated ``[optimise]`` table (a dict in case-file units) or None.
        raw: the parsed TOML, as read (for reference; the fields above are what the code uses).
    """

    name: str
    pair: GearPair
    modifications: Modifications
    youngs_modulus: float = 210e9
    poisson_ratio: float = 0.3
    density: float = 7800.0
    torque: float = 100.0
    speed: float = 0.0
    stiffness_model: str = "fe2d"
    uniform_k0: float | None = None
    slices: int = 40
    positions_per_pitch: int = 64
    smooth_width: float = 1e-7
    foundation: str = "weber"
    fe2d_size: float | None = None
    scene: Any = None
    optimise: dict | None = None
    raw: dict = dataclasses.field(default_factory=dict, repr=False, compare=False)

    def contact_law(self, mode: str) -> ContactLaw:
        """The contact law a case file names: ``"exact"`` → :class:`~jaxgear.ExactContact`,
        ``"smooth"`` → :class:`~jaxgear.SmoothContact` of the case's ``smooth_width`` (m).

        Raises:
            ValueError: another name.
        """
        return contact_law_from_name(mode, self.smooth_width)

    def __post_init__(self) -> None:
        if isinstance(self.foundation, bool):  # the old boolean
            object.__setattr__(self, "foundation", "weber" if self.foundation else "none")

    @property
    def normal_load(self) -> float:
        """Flank-normal mesh force F_n = T/(r_b1 cos β_b) (N)."""
        return self.torque / (self.pair.base_radii[0] * math.cos(self.pair.base_helix_angle))

    def nominal_line_load(self, torque: float | None = None) -> float:
        """Mean transverse load per unit face width, F_bt/(ε_α b) (N/m), for the Hertz term."""
        t = self.torque if torque is None else torque
        return (
            t
            / self.pair.base_radii[0]
            / (self.pair.transverse_contact_ratio * self.pair.face_width)
        )

    def specific_load(self, torque: float | None = None) -> float:
        """Nominal tangential load at the reference circle per unit face width, F_t / b =
        T / (r_1 b) (N/m), K_A = 1: the load of the ISO 6336-1 low-load factor (``iso6336``)."""
        t = self.torque if torque is None else torque
        return t / self.pair.pitch_radii[0] / self.pair.face_width

    def mesh_model(
        self,
        slices: int | None = None,
        torque: float | None = None,
        flexible: tuple[bool, bool] = (False, False),
    ) -> MeshModel:
        """Build the :class:`MeshModel` (stiffness table evaluated at the nominal line load; the
        ``iso6336`` table at the case's E and :meth:`specific_load` of ``torque``).

        ``flexible``: members that are condensed FE bodies (pinion, gear): their tooth stiffness
        leaves out the foundation term, which the FE rim replaces (seed remark after (2.31)).
        """
        foundation = self.foundation
        if any(flexible):
            foundation = tuple("none" if f else self.foundation for f in flexible)
        s, k = stiffness_table(
            self.pair,
            self.stiffness_model,
            youngs_modulus=self.youngs_modulus,
            poisson_ratio=self.poisson_ratio,
            line_load=self.nominal_line_load(torque),
            uniform_k0=self.uniform_k0,
            foundation=foundation,
            fe2d_size=self.fe2d_size,
            specific_load=self.specific_load(torque),
        )
        return MeshModel.from_pair(self.pair, s, k, self.slices if slices is None else slices)

    def replace(self, **changes) -> Case:
        return dataclasses.replace(self, **changes)
