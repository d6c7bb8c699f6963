"""The one place where the names of a case file (or a command line) become model objects: the
mesh-stiffness models, the foundations, the contact laws and the contact geometry.

A new model is one class in the model (:class:`jaxgear.AbstractStiffness`,
:class:`jaxgear.AbstractFoundation`) plus its name here.
"""

from __future__ import annotations

import functools

from .._contact import ContactLaw, ExactContact, SmoothContact
from .._contact_geometry import AbstractContactGeometry, BeyondPath, TheoreticalPath
from .._stiffness import (
    AbstractFoundation,
    MemberFoundations,
    NoFoundation,
    SainsotFoundation,
    WeberFoundation,
)
from .._stiffness_models import FE2D, ISO6336, AbstractStiffness, Uniform, Weber

__all__ = [
    "FOUNDATIONS",
    "STIFFNESS_MODELS",
    "contact_geometry_from_key",
    "contact_law_from_name",
    "foundation_from_name",
    "stiffness_from_name",
]

#: ``[mesh] foundation`` names (``true``/``false`` alias "weber"/"none")
FOUNDATIONS = {"weber": WeberFoundation(), "sainsot": SainsotFoundation(), "none": NoFoundation()}
#: ``[mesh] stiffness`` names
STIFFNESS_MODELS = ("weber", "uniform", "iso6336", "fe2d")


def contact_geometry_from_key(extended: bool) -> AbstractContactGeometry:
    """``[mesh] extended_contact``'s value → the mesh model's contact geometry: true
    :class:`~jaxgear.BeyondPath` (contact beyond the theoretical path too), false
    :class:`~jaxgear.TheoreticalPath`."""
    return BeyondPath() if extended else TheoreticalPath()


def _one_foundation(name) -> AbstractFoundation:
    if name is True:
        return FOUNDATIONS["weber"]
    if name is False or name is None:
        return FOUNDATIONS["none"]
    if name not in FOUNDATIONS:
        raise ValueError(
            f"mesh.foundation = {name!r} is unknown: allowed 'weber', 'sainsot', 'none'"
        )
    return FOUNDATIONS[name]


@functools.singledispatch
def foundation_from_name(foundation) -> AbstractFoundation:
    """The foundation a name gives: "weber" → :class:`~jaxgear.WeberFoundation`, "sainsot" →
    :class:`~jaxgear.SainsotFoundation`, "none" → :class:`~jaxgear.NoFoundation` (``True``/
    ``False``/``None``, the old boolean: "weber"/"none"); a 2-tuple/list of them, (pinion, gear):
    a :class:`~jaxgear.MemberFoundations`.

    Raises:
        ValueError: an unknown name, or a sequence that is not of length 2.
    """
    return _one_foundation(foundation)


@foundation_from_name.register(tuple)
@foundation_from_name.register(list)
def _member_foundations(foundation) -> MemberFoundations:
    """(pinion, gear) names: each member's foundation."""
    if len(foundation) != 2:
        raise ValueError(
            f"mesh.foundation = {foundation!r} has {len(foundation)} entries: allowed one "
            "name for both members or a (pinion, gear) pair of 'weber', 'sainsot', 'none'"
        )
    return MemberFoundations(*(_one_foundation(f) for f in foundation))


def stiffness_from_name(
    model: str, *, uniform_k0: float | None = None, foundation="weber", fe2d_size=None
) -> AbstractStiffness:
    """The mesh-stiffness model a case file's ``[mesh] stiffness`` names, with its settings:
    "uniform" → :class:`~jaxgear.Uniform` (``uniform_k0``, N/m²), "iso6336" →
    :class:`~jaxgear.ISO6336`, "weber" → :class:`~jaxgear.Weber` (``foundation``, a name for
    :func:`foundation_from_name`), "fe2d" → :class:`~jaxgear.FE2D` (``fe2d_size`` (m) or None,
    ``foundation``).

    Raises:
        ValueError: an unknown model or foundation name; "uniform" without a positive k0.
    """
    if model == "uniform":
        return Uniform(uniform_k0)
    if model == "iso6336":
        return ISO6336()
    if model == "weber":
        return Weber(foundation_from_name(foundation))
    if model == "fe2d":
        return FE2D(fe2d_size, foundation_from_name(foundation))
    raise ValueError(
        f"mesh.stiffness = {model!r} is unknown: allowed 'weber', 'uniform', 'iso6336', 'fe2d'"
    )


def contact_law_from_name(mode: str, width=1e-7, max_iterations: int = 100) -> ContactLaw:
    """The contact law a case file or a command line names: ``"exact"`` →
    :class:`~jaxgear.ExactContact`, ``"smooth"`` → :class:`~jaxgear.SmoothContact` of ``width``
    (m), each with
    ``max_iterations``.

    Raises:
        ValueError: another name (one line).
    """
    if mode == "exact":
        return ExactContact(max_iterations)
    if mode == "smooth":
        return SmoothContact(width, max_iterations)
    raise ValueError(f"contact = {mode!r}: allowed 'exact', 'smooth'")
