"""The quadratic hexahedra of the body mesh: the kinds of :class:`fem_prep._kinds.Element`.

:class:`Hex20` is the 20-node serendipity hexahedron (scikit-fem's ``ElementHexS2``, quadrature
order 4), :class:`Hex27` the 27-node Lagrange hexahedron (``ElementHex2``, order 5); both on
the 27-node quadratic geometry of ``_mesh`` (circles exact at the nodes).
"""

from __future__ import annotations

from typing import ClassVar, final

import skfem

from ._kinds import Element

__all__ = ["Hex20", "Hex27"]


@final
class Hex20(Element):
    """The 20-node serendipity hexahedron (``[mesh] element = "hex20"``, the default)."""

    name: ClassVar[str] = "hex20"
    intorder: ClassVar[int] = 4

    def skfem_element(self) -> skfem.Element:
        return skfem.ElementHexS2()

    def inner_nodes(self, faces: float, cells: float) -> float:
        return 0


@final
class Hex27(Element):
    """The 27-node Lagrange hexahedron (``[mesh] element = "hex27"``): face and centre nodes."""

    name: ClassVar[str] = "hex27"
    intorder: ClassVar[int] = 5

    def skfem_element(self) -> skfem.Element:
        return skfem.ElementHex2()

    def inner_nodes(self, faces: float, cells: float) -> float:
        return faces + cells
