"""The rating's modification inputs in ``jaxgear run``'s outputs: the ``rating`` section's
``modification_inputs`` (ISO 6336-1's tip relief C_a and crowning C_β the mesh was rated with,
and their source) and its line in ``rating.md``."""

from __future__ import annotations

from ..io import RatingCase

__all__ = ["modification_inputs", "modification_line"]


def modification_inputs(rc: RatingCase, rating) -> dict | None:
    """The ``rating`` section's ``modification_inputs``: ISO 6336-1's tip relief C_a (K_v) and
    crowning C_β (K_Hβ) the mesh was rated with, in µm (C_a: the running-in C_ay where the
    case gives none), each with its source (``rc.modification_inputs``: the case's
    ``[modifications]`` or ``[rating] tip_relief_um``), and K_Hβ's B₂ (0.5 with the crowning,
    1 without); None for a standard whose load factors have no tip relief C_a (not ISO 6336's)."""
    if "C_a_m" not in rating.factors.details:  # a standard without ISO's inputs
        return None
    m = rc.modification_inputs
    cb = m.get("crowning_m")
    return {
        "tip_relief_um": float(rating.factors.details["C_a_m"]) * 1e6,
        "tip_relief_source": m.get("tip_relief_source", "[rating] settings"),
        "crowning_um": 0.0 if cb is None else float(cb) * 1e6,
        "crowning_source": m.get("crowning_source", "[rating] settings"),
        "B_2": float(rating.factors.details["B_2"]),
    }


def modification_line(section: dict) -> list[str]:
    """rating.md's lines after its units line: a blank line, then the line of ISO's
    modification inputs and a blank line (just the blank line for a section without them)."""
    m = section.get("modification_inputs")
    if m is None:
        return [""]
    line = (
        f"ISO 6336-1 modification inputs: tip relief C_a = {m['tip_relief_um']:.4g} µm of K_v "
        f"({m['tip_relief_source']}); crowning C_β = {m['crowning_um']:.4g} µm of K_Hβ "
        f"({m['crowning_source']}; B₂ = {m['B_2']:.4g})."
    )
    return ["", line, ""]
