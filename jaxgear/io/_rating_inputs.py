"""ISO 6336-1's modification inputs of a case's rating, derived from its ``[modifications]``:
the tip relief C_a of K_v (clause 6) and the crowning C_β of K_Hβ (clause 7), each with where
it comes from (``[rating] tip_relief_um`` overrides C_a)."""

from __future__ import annotations

__all__ = [
    "CASE_CROWNING",
    "CASE_RELIEF",
    "GIVEN_RELIEF",
    "NO_CROWNING",
    "RUNNING_IN_RELIEF",
    "modification_inputs",
]

#: where ISO's modification inputs come from (:func:`modification_inputs`)
GIVEN_RELIEF = "[rating] tip_relief_um (given)"
CASE_RELIEF = "[modifications] tip_relief, the larger member's depth"
RUNNING_IN_RELIEF = "none in the case: the running-in C_ay (ISO 6336-1 clause 6)"
CASE_CROWNING = "[modifications] crowning, the larger member's depth"
NO_CROWNING = "none in the case"


def modification_inputs(given_tip_relief: float | None, modifications=None) -> dict:
    """ISO 6336-1's modification inputs of a rating and their sources: ``tip_relief_m`` (C_a
    of K_v, m, or None: the running-in C_ay) — ``[rating] tip_relief_um`` where given (an
    override), else the case's ``[modifications]`` tip relief (the larger member's depth,
    :meth:`jaxgear.Modifications.rating_inputs`), else None — and ``crowning_m`` (C_β of
    K_Hβ, m, or None), the case's crowning; with ``tip_relief_source`` and
    ``crowning_source`` in words.

    Args:
        given_tip_relief: ``[rating] tip_relief_um`` in m, or None.
        modifications: the case's :class:`jaxgear.Modifications` (of the rated mesh), or None.
    """
    ca, cb = (0.0, 0.0) if modifications is None else (
        float(v) for v in modifications.rating_inputs()
    )
    if given_tip_relief is not None:
        relief, relief_source = given_tip_relief, GIVEN_RELIEF
    elif ca > 0:
        relief, relief_source = ca, CASE_RELIEF
    else:
        relief, relief_source = None, RUNNING_IN_RELIEF
    crowning, crowning_source = (cb, CASE_CROWNING) if cb > 0 else (None, NO_CROWNING)
    return {
        "tip_relief_m": relief,
        "tip_relief_source": relief_source,
        "crowning_m": crowning,
        "crowning_source": crowning_source,
    }
