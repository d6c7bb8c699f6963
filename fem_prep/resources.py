"""The work a computation may ask of this machine, checked before it starts: one bound on
memory (half the machine's physical memory, :data:`MEMORY_SHARE`) and the one-line refusal that
names the setting to change, shared by fem_prep's housing (the mesher, the condensation) and by
jaxgear's runs (a pair's or a stage's sweep records, ``jaxgear robust``'s realisations, the
whine's grid). JAX-free.

A computation estimates the bytes it will hold at its peak from its sizes (cells, DOFs, modes,
grid points: each caller's docstring says how) and calls :func:`check_memory` before the work;
the estimate is an order of magnitude, so the bound leaves the other half of the machine for
what the estimate leaves out.
"""

from __future__ import annotations

import os

__all__ = ["MEMORY_SHARE", "check_memory", "memory_allowed", "memory_bytes"]

#: the share of the machine's physical memory one computation may plan to hold
MEMORY_SHARE = 0.5


def memory_bytes() -> float:
    """The machine's physical memory (bytes); inf where the platform does not tell."""
    try:
        return float(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):  # pragma: no cover - non-POSIX
        return float("inf")


def memory_allowed() -> float:
    """The bytes one computation may plan to hold: :data:`MEMORY_SHARE` of
    :func:`memory_bytes`."""
    return MEMORY_SHARE * memory_bytes()


def check_memory(subject: str, need: float, what: str, fix: str) -> None:
    """Refuse, before the work, a computation whose estimated peak ``need`` (bytes) exceeds
    :func:`memory_allowed`: one-line ``ValueError``
    ``"<subject>: out of range: <what> need about X GB, allowed <= Y GB (half this machine's
    memory): <fix>"``. ``subject`` names the setting and its value (``"mesh_size_mm = 0.5"``),
    ``what`` the estimate's sizes, ``fix`` what to change."""
    have = memory_allowed()
    if need > have:
        raise ValueError(
            f"{subject}: out of range: {what} need about {need / 1e9:.3g} GB, allowed <= "
            f"{have / 1e9:.3g} GB (half this machine's memory): {fix}"
        )
