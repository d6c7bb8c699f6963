"""The ``jaxgear`` command line (the application: commands, plots, terminal tables).

Imports flow one way: the CLI uses the model (:mod:`jaxgear`), :mod:`jaxgear.io`, :mod:`optimise`
and :mod:`fem_prep`; none of them imports the CLI.
"""

from . import _plots as plots  # noqa: F401 (the figures: jaxgear.cli.plots)
from ._main import entry as entry, main as main, runtime_message as runtime_message
from ._optimise import (
    check_settings as check_settings,
    optimise_case as optimise_case,
    settings_from_case as settings_from_case,
)
from ._options import range_values as range_values
from ._paths import (
    OUTPUT_FILES as OUTPUT_FILES,
    TRAIN_FILES as TRAIN_FILES,
    clear_outputs as clear_outputs,
)
from ._summary import result_summary as result_summary
from .run import format_table as format_table, run_case as run_case
from .scene import scene_outputs as scene_outputs
from .train import format_train_table as format_train_table, run_train as run_train
