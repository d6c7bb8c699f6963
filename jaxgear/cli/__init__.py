"""The ``jaxgear`` command line (the application: commands, plots, terminal tables).

Imports flow one way: the CLI uses the model (:mod:`jaxgear`), :mod:`jaxgear.io`, :mod:`optimise`
and :mod:`fem_prep`; none of them imports the CLI.
"""

from ._main import entry as entry, main as main
from ._run import run_case as run_case
