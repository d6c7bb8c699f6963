"""The API reference pages: one page per public package, one mkdocstrings entry per public
name (the names its ``__init__`` re-exports, ``from ._x import A as A``), so that a new public
name gets its entry without editing a page."""

from __future__ import annotations

import importlib
import inspect
import types

#: the documented packages: (module, page file, one-line summary)
PACKAGES = (
    (
        "jaxgear",
        "jaxgear.md",
        "the model: geometry, mesh stiffness, modifications, contact, quasi-statics",
    ),
    ("jaxgear.scenes", "jaxgear.scenes.md", "the structures the contact acts on"),
    ("jaxgear.dynamics", "jaxgear.dynamics.md", "time integration, modal analysis, speed sweeps"),
    ("jaxgear.io", "jaxgear.io.md", "case files: names to objects, cases to models"),
    ("optimise", "optimise.md", "objectives, problems and minimisers"),
    ("fem_prep", "fem_prep.md", "meshing and condensation of gear bodies"),
)


def public_names(module_name: str) -> tuple[list[str], list[str]]:
    """(classes and functions, other values) that ``module_name`` exports: names not starting
    with ``_``, defined in its package, not submodules."""
    module = importlib.import_module(module_name)
    root = module_name.split(".")[0]
    callables, values = [], []
    for name, obj in vars(module).items():
        if name.startswith("_") or isinstance(obj, types.ModuleType):
            continue
        owner = getattr(obj, "__module__", None) or ""
        if inspect.isclass(obj) or inspect.isfunction(obj):
            if owner.split(".")[0] == root:
                callables.append(name)
        elif not callable(obj) and name.isupper():
            values.append(name)
    return callables, values


def page(module_name: str, summary: str) -> str:
    callables, values = public_names(module_name)
    out = [
        f"# `{module_name}`",
        "",
        f"{summary.capitalize()}.",
        "",
        f"::: {module_name}",
        "    options:",
        "      members: false",
        "      show_root_heading: false",
        "",
    ]
    if values:
        out += [
            "Tables of names (case-file and command-line names mapped to objects): "
            + ", ".join(f"`{v}`" for v in values)
            + ".",
            "",
        ]
    for name in callables:
        out += [f"::: {module_name}.{name}", ""]
    return "\n".join(out)


def pages() -> dict[str, str]:
    return {f"api/{file}": page(mod, summary) for mod, file, summary in PACKAGES}
