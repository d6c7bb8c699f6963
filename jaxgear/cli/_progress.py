"""The command line's progress bars: tqdm's on a terminal (or in a notebook); on a stderr that
is not a terminal (a log file, a pipe, ``2> log``) plain lines instead, one per change, with
no carriage returns, cursor moves or blank lines (tqdm's nested bars would fill a log with
escape codes and empty lines): ``jaxgear run case: 43%|| 3/7 [00:01<00:02, 1.2s/it, stage]``.
"""

from __future__ import annotations

import sys

from tqdm import tqdm as _tqdm

__all__ = ["PLAIN_INTERVAL_S", "PlainProgress", "inner_bars", "progress"]

#: the least time (s) between two plain lines of one bar (a stage change always prints)
PLAIN_INTERVAL_S = 1.0


class PlainProgress(_tqdm):
    """A tqdm bar that prints each state as its own line (no bar drawing, no cursor control):
    the state when it changes (a step after :data:`PLAIN_INTERVAL_S`, a new postfix, the close
    of a bar that is left), never the same line twice, nothing when a bar that is not left
    closes."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("bar_format", "{l_bar}{r_bar}")
        kwargs.setdefault("mininterval", PLAIN_INTERVAL_S)
        kwargs.setdefault("ascii", True)
        self._plain_last = None
        super().__init__(*args, **kwargs)

    def display(self, msg=None, pos=None):
        text = self.__str__() if msg is None else msg
        if text and text != self._plain_last:
            self._plain_last = text
            self.fp.write(text + "\n")
            self.fp.flush()
        return True

    def close(self):
        if not self.__dict__.get("disable", True) and self.leave is not False:
            self.display()  # the final state, once
        self.sp = None  # tqdm's close: nothing more to clear or to end with a newline
        super().close()


def _terminal(file) -> bool:
    if sys.modules.get("ipykernel") is not None:  # a notebook: tqdm.auto's widget
        return True
    try:
        return bool(file.isatty())
    except (AttributeError, ValueError):
        return False


def progress(*args, **kwargs) -> _tqdm:
    """A progress bar with tqdm's arguments: :mod:`tqdm.auto`'s where its file (default
    stderr) is a terminal or the session a notebook, else a :class:`PlainProgress`."""
    if _terminal(kwargs.get("file") or sys.stderr):
        from tqdm.auto import tqdm

        return tqdm(*args, **kwargs)
    return PlainProgress(*args, **kwargs)


def inner_bars(show: bool) -> bool:
    """Whether fem-prep's and the optimiser's own tqdm bars (nested under the command's, drawn
    with cursor moves) are shown: ``show`` on a terminal or in a notebook, never on a redirected
    stderr, where the command's bar prints its plain lines alone."""
    return bool(show) and _terminal(sys.stderr)
