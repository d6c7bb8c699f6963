"""A griffe extension for the API pages: the docstrings' Sphinx roles (``:class:`~jaxgear.Weber```,
``:func:`quasi_static```, ``:meth:``, ``:attr:``, ``:mod:``, ``:data:``, ``:exc:``) shown as
code, the ``~`` form by its last component, as Sphinx shows them. The docstrings stay as they
are (they read well in ``help()`` and in an editor)."""

from __future__ import annotations

import re

import griffe

ROLE = re.compile(r":(?:class|func|meth|attr|mod|data|exc|obj):`(~?)([^`]+)`")


def plain(text: str) -> str:
    """``:class:`~a.B``` → ```B```, ``:func:`a.f``` → ```a.f```."""
    return ROLE.sub(
        lambda m: f"`{m.group(2).rsplit('.', 1)[-1] if m.group(1) else m.group(2)}`", text
    )


class SphinxRoles(griffe.Extension):
    def on_object(self, *, obj, **kwargs) -> None:
        if obj.docstring is not None:
            obj.docstring.value = plain(obj.docstring.value)

    def on_module_instance(self, *, mod, **kwargs) -> None:
        # a package's own docstring (the API pages' introductions), which on_object leaves
        self.on_object(obj=mod)
