"""The ``jaxgear`` command line (the application: commands, plots, terminal tables).

Imports flow one way: the CLI uses the model (:mod:`jaxgear`), :mod:`jaxgear.io`, :mod:`optimise`
and :mod:`fem_prep`; none of them imports the CLI.

The names below are imported on first use (PEP 562 ``__getattr__``): the console script
(``jaxgear = "jaxgear.cli:entry"``) imports this package for every command, and a command
imports only its own module (:func:`jaxgear.cli._main._command`), not every command's with its
figures (matplotlib), so that ``jaxgear --help``, ``jaxgear cases`` and ``jaxgear prep`` start
without them.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # the same names, for type checkers and editors
    from . import _plots as plots
    from ._case_line import case_line as case_line
    from ._main import main as main, runtime_message as runtime_message
    from ._optimise import (
        check_settings as check_settings,
        optimise_case as optimise_case,
        settings_from_case as settings_from_case,
    )
    from ._options import range_values as range_values
    from ._progress import progress as progress
    from ._paths import (
        GEARBOX_FILES as GEARBOX_FILES,
        OUTPUT_FILES as OUTPUT_FILES,
        PLANETARY_FILES as PLANETARY_FILES,
        TRAIN_FILES as TRAIN_FILES,
        clear_outputs as clear_outputs,
    )
    from ._rating_report import (
        ModelLoads as ModelLoads,
        at_speed_sections as at_speed_sections,
        measured_dynamic_factor as measured_dynamic_factor,
        measured_factors as measured_factors,
        rating_lines as rating_lines,
        rating_table_lines as rating_table_lines,
        rating_outputs as rating_outputs,
        root_stress_at_speed as root_stress_at_speed,
        root_stress_outputs as root_stress_outputs,
        scene_loads as scene_loads,
        train_loads as train_loads,
        train_mesh_results as train_mesh_results,
        write_rating_table as write_rating_table,
    )
    from ._start import entry as entry
    from ._stress_outputs import (
        body_stress_outputs as body_stress_outputs,
        fillet_table as fillet_table,
    )
    from ._summary import result_summary as result_summary
    from ._tribology_run import (
        efficiency_run_line as efficiency_run_line,
        gearbox_tribology as gearbox_tribology,
        planetary_tribology_outputs as planetary_tribology_outputs,
        train_tribology_outputs as train_tribology_outputs,
        tribology_outputs as tribology_outputs,
        tribology_rating_lines as tribology_rating_lines,
    )
    from .run import (
        format_table as format_table,
        rating_run_line as rating_run_line,
        run_case as run_case,
        train_rating_run_line as train_rating_run_line,
    )
    from .scene import scene_outputs as scene_outputs
    from .train import format_train_table as format_train_table, run_train as run_train

#: the public submodules, by their public name
_MODULES = {"plots": "._plots"}

#: every other public name of the package: the module that defines it
_EXPORTS = {
    "case_line": "._case_line",
    "entry": "._start",
    "main": "._main",
    "runtime_message": "._main",
    "check_settings": "._optimise",
    "optimise_case": "._optimise",
    "settings_from_case": "._optimise",
    "range_values": "._options",
    "OUTPUT_FILES": "._paths",
    "GEARBOX_FILES": "._paths",
    "progress": "._progress",
    "PLANETARY_FILES": "._paths",
    "TRAIN_FILES": "._paths",
    "clear_outputs": "._paths",
    "ModelLoads": "._rating_report",
    "at_speed_sections": "._rating_report",
    "body_stress_outputs": "._stress_outputs",
    "measured_dynamic_factor": "._rating_report",
    "measured_factors": "._rating_report",
    "rating_lines": "._rating_report",
    "rating_table_lines": "._rating_report",
    "scene_loads": "._rating_report",
    "train_loads": "._rating_report",
    "rating_outputs": "._rating_report",
    "rating_run_line": ".run",
    "train_rating_run_line": ".run",
    "root_stress_outputs": "._rating_report",
    "root_stress_at_speed": "._rating_report",
    "fillet_table": "._stress_outputs",
    "train_mesh_results": "._rating_report",
    "write_rating_table": "._rating_report",
    "tribology_outputs": "._tribology_run",
    "tribology_rating_lines": "._tribology_run",
    "result_summary": "._summary",
    "efficiency_run_line": "._tribology_run",
    "gearbox_tribology": "._tribology_run",
    "planetary_tribology_outputs": "._tribology_run",
    "train_tribology_outputs": "._tribology_run",
    "format_table": ".run",
    "run_case": ".run",
    "scene_outputs": ".scene",
    "format_train_table": ".train",
    "run_train": ".train",
}

__all__ = sorted({*_MODULES, *_EXPORTS})


def __getattr__(name: str):
    """The public ``name``, its module imported on first use (then kept as an attribute)."""
    if name in _MODULES:
        value = importlib.import_module(_MODULES[name], __name__)
    elif name in _EXPORTS:
        value = getattr(importlib.import_module(_EXPORTS[name], __name__), name)
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})
