"""The Pareto front of a sizing: the feasible candidates sorted into non-dominated fronts over
several objectives, each a column of the table with a sense (:func:`pareto_front`), and the
design chosen on the first front (:data:`CHOICES`).

Non-dominated sorting is moocore's (``moocore.pareto_rank``: Jensen's O(n log n) algorithm for
two objectives, front by front for more; duplicates share a rank). Candidate A dominates B when
A is no worse in every objective and better in one; front 1 holds the candidates no other
dominates, front 2 those only front 1 dominates, and so on.

The chosen design, ``"knee"`` (the default): the candidate of front 1 nearest the ideal point
once each objective is scaled over front 1 to 0 at its best and 1 at its worst (Euclidean
distance; the lowest row on a tie). It is the balanced compromise a designer reads off a front's
bend: moving from it along the front buys little in one objective for much in another. Named by
an objective's column instead, the chosen design is the candidate of front 1 best in that
objective (``"mass_kg"``: the lightest feasible candidate, the one with the largest least margin
among equally light ones when the margin is an objective).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ._objectives import OBJECTIVES

__all__ = ["CHOICES", "DEFAULT_OBJECTIVES", "MOST_OBJECTIVES", "ParetoFront", "check_objectives",
           "pareto_front"]

#: the objectives of a sizing that names none: the lightest, with the largest margin
DEFAULT_OBJECTIVES = (("mass_kg", "min"), ("least_margin", "max"))
#: how the chosen design is picked: ``"knee"`` or an objective's column (the module docstring)
CHOICES = ("knee",)
#: the most objectives a front takes (its plots: one per pair)
MOST_OBJECTIVES = 6


def check_objectives(objectives, chosen: str, where: str = "pareto_front") -> None:
    """``objectives`` ((column, "min" | "max") pairs, 2 to :data:`MOST_OBJECTIVES`, columns of
    :data:`OBJECTIVES`, none twice) and ``chosen`` (``"knee"`` or one of the objectives' columns),
    or one line naming the argument, its value and what is allowed (ValueError)."""
    names = [o[0] if isinstance(o, tuple | list) and len(o) == 2 else o for o in objectives]
    bad = [o for o in objectives if not (isinstance(o, tuple | list) and len(o) == 2
                                         and o[0] in OBJECTIVES and o[1] in ("min", "max"))]
    if bad:
        raise ValueError(f"{where}: objectives entry {bad[0]!r} is out of range: allowed "
                         f"(column, 'min' or 'max'), the column one of {', '.join(OBJECTIVES)}")
    if not 2 <= len(names) <= MOST_OBJECTIVES or len(set(names)) != len(names):
        raise ValueError(f"{where}: objectives = {tuple(names)!r} is out of range: allowed 2 to "
                         f"{MOST_OBJECTIVES} columns, none twice")
    if chosen not in (*CHOICES, *names):
        raise ValueError(f"{where}: chosen = {chosen!r} is out of range: allowed "
                         f"{', '.join(map(repr, (*CHOICES, *names)))}")


@dataclasses.dataclass(frozen=True)
class ParetoFront:
    """The fronts of a sizing table over its objectives.

    Attributes:
        objectives: the (column, sense) pairs, sense ``"min"`` or ``"max"``.
        rank: (n,) integers, each candidate's front: 1 non-dominated, 2 dominated only by front
            1, …; 0 not ranked (infeasible, or an objective without a value).
        chosen: the row of the chosen design (front 1), or None when no candidate is ranked.
        rule: how it was chosen (``"knee"`` or an objective's column; the module docstring).
    """

    objectives: tuple
    rank: np.ndarray
    chosen: int | None
    rule: str

    @property
    def front(self) -> np.ndarray:
        """The rows of front 1, increasing."""
        return np.flatnonzero(self.rank == 1)


def _oriented(columns: dict, objectives, rows) -> np.ndarray:
    """(len(rows), k) the objectives of ``rows``, each negated where maximised (all minimised)."""
    return np.stack([columns[n][rows] * (1.0 if s == "min" else -1.0) for n, s in objectives],
                    axis=1).astype(float)


def pareto_front(table, objectives=DEFAULT_OBJECTIVES, chosen: str = "knee") -> ParetoFront:
    """Non-dominated sorting of ``table``'s feasible candidates over ``objectives`` and the
    chosen design (the module docstring).

    Args:
        table: a :class:`jaxgear.sizing.SizingTable` holding every objective's column.
        objectives: (column, sense) pairs, sense ``"min"`` or ``"max"``, 2 to 6, columns of
            :data:`jaxgear.sizing.OBJECTIVES`.
        chosen: ``"knee"`` or one of the objectives' columns.

    Returns:
        :class:`ParetoFront` (ranks 0 everywhere and no chosen design when no feasible
        candidate has every objective).

    Raises:
        ValueError: an objective or ``chosen`` out of range (:func:`check_objectives`), an
            objective's column missing from the table (a mesh loss without its inputs); one line.
    """
    import moocore  # the sort's library, loaded where a front is sorted

    objectives = tuple((str(n), str(s)) for n, s in objectives)
    check_objectives(objectives, chosen)
    missing = [n for n, _ in objectives if n not in table.columns]
    if missing:
        raise ValueError(f"pareto_front: objective {missing[0]!r} is not a column of the table "
                         "(the mesh loss's columns need the spec's lubricant)")
    n = len(table)
    rows = np.flatnonzero(table.feasible)
    values = _oriented(table.columns, objectives, rows)
    keep = np.all(np.isfinite(values), axis=1)
    rows, values = rows[keep], values[keep]
    rank = np.zeros(n, dtype=int)
    if rows.size == 0:
        return ParetoFront(objectives, rank, None, chosen)
    rank[rows] = np.asarray(moocore.pareto_rank(values), dtype=int) + 1
    first = rank[rows] == 1
    front, f = rows[first], values[first]
    if chosen == "knee":
        lo, hi = f.min(axis=0), f.max(axis=0)
        span = np.where(hi > lo, hi - lo, 1.0)
        pick = int(np.argmin(np.sqrt((((f - lo) / span) ** 2).sum(axis=1))))
    else:
        j = [name for name, _ in objectives].index(chosen)
        # the best in that objective; among equals, the best in the others in order
        others = [f[:, i] for i in range(f.shape[1]) if i != j]
        pick = int(np.lexsort([*others[::-1], f[:, j]])[0])
    return ParetoFront(objectives, rank, int(front[pick]), chosen)
