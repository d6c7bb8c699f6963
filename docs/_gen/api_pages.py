"""The API reference pages: one page per public package, one mkdocstrings entry per public
name (the names its ``__init__`` re-exports, ``from ._x import A as A``), so that a new public
name gets its entry without editing a page; on each page the names are grouped by task
(:data:`SECTIONS`: geometry, mesh stiffness, quasi-statics, planetary stages, rating, …), a
section per task, not in the order of the private modules."""

from __future__ import annotations

import importlib
import inspect
import types

#: the documented packages: (module, page file, one-line summary)
PACKAGES = (
    (
        "jaxgear",
        "jaxgear.md",
        "the gear pair's model: geometry, mesh stiffness, modifications, contact, quasi-statics, "
        "deviations (each subpackage's names on its own page)",
    ),
    ("jaxgear.scenes", "jaxgear.scenes.md", "the structures the contact acts on"),
    ("jaxgear.dynamics", "jaxgear.dynamics.md", "time integration, modal analysis, speed sweeps"),
    (
        "jaxgear.planetary",
        "jaxgear.planetary.md",
        "planetary stages: model kinds, meshes, ring, deviations, modes, dynamics",
    ),
    ("jaxgear.rating", "jaxgear.rating.md", "load capacity: ISO 6336 ratings, load factors, root stress"),
    ("jaxgear.gearbox", "jaxgear.gearbox.md", "stages joined by shafts: the chain, the coupled model, its Campbell diagram and housing spectrum"),
    ("jaxgear.tribology", "jaxgear.tribology.md", "lubricant film along the path of contact, tooth friction, mesh power loss and efficiency"),
    ("jaxgear.acoustics", "jaxgear.acoustics.md", "the housing's surface vibration, its equivalent radiated power (ERP) and radiated sound power from a cached radiation resistance, levels, A weighting"),
    ("jaxgear.sizing", "jaxgear.sizing.md", "gear sizing: every (module, z1, z2) of a spec's ranges, its geometry, validity and ISO 6336 rating at once; the objectives and the Pareto front"),
    ("jaxgear.bearings", "jaxgear.bearings.md", "rolling bearings from their geometry: load distribution, stiffness at an operating point, ISO 281 and ISO/TS 16281 life, bearing tones"),
    ("jaxgear.io", "jaxgear.io.md", "case files: names to objects, cases to models"),
    ("optimise", "optimise.md", "objectives, problems and minimisers"),
    ("fem_prep", "fem_prep.md", "meshing and condensation of gear bodies"),
    (
        "fem_prep.housing",
        "fem_prep.housing.md",
        "the gearbox housing: box and file meshes, seats and feet, condensation at the seats",
    ),
    (
        "fem_prep.acoustics",
        "fem_prep.acoustics.md",
        "sound radiation: exterior BEM (bempp-cl), Rayleigh integral, cached radiation resistance",
    ),
)


#: the sections of a package's page, by task, in reading order: (title, the private modules
#: whose public names it holds, by their last dotted part; a prefix ends with ``*``; a pattern
#: with a dot, ``rating.*``, matches the last two parts and is tried before the plain ones, so
#: that ``jaxgear.rating._geometry`` is not taken for ``jaxgear._geometry``). A name whose
#: module no section names goes to "Other" (a new module shows up, never disappears).
SECTIONS = {
    "jaxgear": (
        ("Geometry", ("_geometry", "_internal", "_backlash", "_extended")),
        ("Contact and quasi-statics", ("_quasi_static", "_contact", "_contact_geometry",
                                       "_compiled", "_results", "_maps", "_pressure",
                                       "_spectrum")),
        ("Mesh stiffness", ("_stiffness", "_stiffness_models", "_baseplane", "_cell_factor",
                            "_weber_internal")),
        ("Modifications and deviations", ("_modifications", "_deviations")),
        ("Robustness (tolerances, Monte Carlo)", ("_robust",)),
        ("Numerics and batching", ("_util",)),
    ),
    "jaxgear.scenes": (
        ("Scenes", ("_scene", "_rigid", "_torsional", "_lumped3d", "_structure")),
        ("Shafts and meshes", ("_shaft", "_gear_mesh", "_window_compliance")),
        ("A flexible housing", ("_housing", "_mount")),
        ("Condensed bodies (hybrid)", ("_hybrid", "_interface")),
        ("Trains", ("_train",)),
    ),
    "jaxgear.dynamics": (
        ("Simulation", ("_simulate", "_model", "_build", "_lumped", "_settings", "_result",
                        "_newmark", "_damping", "_bearings")),
        ("Speed sweeps", ("_sweep", "_robust", "_settle")),
        ("Modes and Campbell diagrams", ("_modal", "_modal_basis", "_rim")),
        ("Gear whine in the frequency domain", ("_whine", "_whine_qp", "_whine_methods")),
        ("Condensed bodies (hybrid)", ("_hybrid*",)),
        ("The stage contract (the stages of a gearbox)", ("_stage",)),
    ),
    "jaxgear.planetary": (
        ("Stage and model kinds", ("_stage", "_spatial", "_runout")),
        ("Meshes and quasi-statics", ("_meshes", "_hunting")),
        ("Flexible ring", ("_ring",)),
        ("Modes, phasing and load sharing", ("_analysis",)),
        ("Dynamics and the engine model", ("_dynamics", "_model")),
        ("Gear whine in the frequency domain", ("_whine",)),
        ("Time plan of a sweep", ("_plan",)),
        ("On a housing", ("_housed",)),
    ),
    "jaxgear.rating": (
        ("Rating", ("_rate", "_settings", "_material")),
        ("Rating standards and the ISO 6336 editions", ("_standard", "_iso6336")),
        ("Geometry and tooth form", ("_geometry", "_internal", "_bending")),
        ("Load factors, measured factors", ("_factors", "_measured")),
        ("Root stress", ("_root_stress",)),
        ("Life under a load spectrum (ISO 6336-6)", ("_load_spectrum",)),
    ),
    "jaxgear.gearbox": (
        ("The stages and the torsional chain", ("_chain",)),
        ("The coupled dynamic model", ("_coupled",)),
        ("A stage kind: the compound planetary stage (stepped planets)", ("_compound",)),
        ("A stage kind: a parallel pair in lumped 3D form", ("_lumped",)),
        ("Campbell diagram and housing spectrum", ("_spectrum",)),
        ("Gear whine of the whole gearbox", ("_whine",)),
    ),
    "jaxgear.tribology": (
        ("Lubricant", ("_lubricant",)),
        ("Film thickness", ("_film",)),
        ("Friction and the tooth loss factor", ("_loss",)),
        ("Film and loss along the path of contact", ("_mesh",)),
        ("Efficiency of trains, planetary stages and gearboxes", ("_efficiency",)),
        ("Flash temperature and scuffing", ("_flash", "_ts_scuffing")),
        ("Micropitting", ("_micropitting",)),
    ),
    "jaxgear.acoustics": (
        ("Housing response and equivalent radiated power", ("_erp",)),
        ("Sound power and levels", ("_power",)),
        ("Power and microphone pressure across a band", ("_band",)),
        ("A surface's sound over speeds and orders", ("_sound",)),
        ("A weighting", ("_weighting",)),
    ),
    "jaxgear.bearings": (
        ("Bearing kinds and the catalogue", ("_kinds", "_catalogue")),
        ("Hertz contact", ("_hertz",)),
        ("Operating point: the inverse solve", ("_solve",)),
        ("Life (ISO 281, ISO/TS 16281) and tones", ("_life", "_reference", "_tones")),
    ),
    "fem_prep.acoustics": (
        ("Surfaces and fluid", ("_surface",)),
        ("Radiation resistance (cached)", ("_resistance",)),
        ("Boundary elements", ("_bem",)),
        ("Rayleigh integral", ("_rayleigh",)),
    ),
    "jaxgear.io": (
        ("Loading a case", ("_load", "_case_file", "_case", "_names", "_plausibility")),
        ("A sizing spec and its candidates' case files", ("_sizing_spec", "_sizing_sound")),
        ("From a case to models", ("_case_model", "_operating", "_scene_spec", "_scene_table",
                                   "_problem", "_acoustic_path", "_case_sound",
                                   "_planetary_spec", "_train_file", "_gearbox_file")),
        ("Tables of a case file", ("_sections", "_deviations_table", "_modifications_table",
                                   "_optimise_table", "_rating*", "_robust_table",
                                   "_lubricant_table", "_scuffing_table",
                                   "_micropitting_table", "_housing_table", "_whine_table",
                                   "_acoustics_table", "_bearings_table")),
        ("Writing files", ("_writers",)),
    ),
    "optimise": (
        ("Objectives", ("_objectives", "_safety", "_tribology", "_acoustics")),
        ("Problems and variables", ("_problem", "_variables", "_bearings")),
        ("Minimisers", ("_minimise", "_master_curve", "_robust")),
    ),
}


def _matches(module: str, patterns) -> bool:
    def one(p):
        tail = ".".join(module.split(".")[-(p.count(".") + 1):])
        return tail == p or (p.endswith("*") and tail.startswith(p[:-1]))

    return any(one(p) for p in patterns)


def sections(module_name: str, names: list[str]) -> list[tuple[str, list[str]]]:
    """``names`` (public names of ``module_name``, in their export order) grouped by task
    (:data:`SECTIONS`), each section's names in export order; empty sections left out."""
    module = importlib.import_module(module_name)
    owner = {n: getattr(getattr(module, n), "__module__", "") or "" for n in names}
    spec = SECTIONS.get(module_name, ())
    got: dict[str, list[str]] = {title: [] for title, _ in spec}
    placed = set()
    for dotted in (True, False):  # the dotted patterns first (see SECTIONS)
        for title, patterns in spec:
            mine = [p for p in patterns if ("." in p) == dotted]
            new = [n for n in names if n not in placed and _matches(owner[n], mine)]
            placed.update(new)
            got[title] += new
    out = [(t, sorted(got[t], key=names.index)) for t, _ in spec if got[t]]
    rest = [n for n in names if n not in placed]
    if rest:
        out.append(("Other" if out else "", rest))
    return out


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
    groups = sections(module_name, callables)
    if len(groups) > 1:  # a contents line, then a section per task
        out += ["Sections: " + ", ".join(f"[{t}](#{_anchor(t)})" for t, _ in groups) + ".", ""]
    for title, names in groups:
        if title and len(groups) > 1:
            out += [f"## {title}", ""]
        for name in names:
            out += [f"::: {module_name}.{name}"]
            if len(groups) > 1:
                out += ["    options:", "      heading_level: 3"]
            out += [""]
    return "\n".join(out)


def _anchor(title: str) -> str:
    """The id mkdocs' toc gives a heading (Python-Markdown's ``slugify``: punctuation dropped,
    lower case, runs of spaces and dashes one ``-``; "ISO/TS" → "isots")."""
    import re

    return re.sub(r"[-\s]+", "-", re.sub(r"[^\w\s-]", "", title).strip().lower())


def pages() -> dict[str, str]:
    return {f"api/{file}": page(mod, summary) for mod, file, summary in PACKAGES}
