"""The figure of every plot of the command line: built on the Agg canvas directly (no pyplot
state: a notebook keeps its inline figures), written atomically as PNG at 120 dpi; the legend
below the axes, sized to the figure."""

from __future__ import annotations

import os
import re
import sys
import textwrap

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ...io import atomic_open

__all__ = [
    "DPI",
    "FIGSIZE",
    "finish",
    "fit_legend_columns",
    "floats",
    "hz_text",
    "legend_below_and_save",
    "legend_columns",
    "new_figure",
    "savefig",
]


FIGSIZE = (8, 4.5)


DPI = 120


#: the environment variable that makes :func:`savefig` write no PNG (the test suite's switch for
#: tests that never read a figure: drawing and encoding a figure costs 0.1-0.5 CPU s, 10-25 %
#: of a small warm ``jaxgear run``); any value but empty or ``0`` sets it. Not for users: the
#: files a run lists then lack its figures.
NO_FIGURES_VARIABLE = "JAXGEAR_TEST_NO_FIGURES"


def figures_off() -> bool:
    """Whether :data:`NO_FIGURES_VARIABLE` is set (read at each figure: a test sets it for its
    own runs, in this process or in the subprocesses it starts)."""
    return os.environ.get(NO_FIGURES_VARIABLE, "") not in ("", "0")


def new_figure(figsize=FIGSIZE):
    """A figure on the Agg canvas (no pyplot state) with one axes, constrained layout."""
    fig = Figure(figsize=figsize, layout="constrained")
    FigureCanvasAgg(fig)
    return fig, fig.add_subplot()


#: (pattern, replacement) pairs that tie a unit to its number and a sign to what follows with a
#: no-break space before a title is wrapped (textwrap breaks at ASCII spaces only)
NO_BREAK = (
    (r"(?<=\d) (%|µm|mm|Hz|rad/s|N·m|N/µm|kN|MPa)(?=\W|$)", "\u00a0\\1"),
    (r"([≥≤<>=]) (?=\S)", "\\1\u00a0"),
)


def wrap_titles(fig) -> None:
    """Break each axes title, and the figure's suptitle, wider than its axes (the figure) into
    lines, each line of a title of several on its own (a long case name or model description
    would otherwise run past the figure's edges, which constrained layout does not prevent):
    about 0.55 em per character of the title's font. A unit or a sign keeps to its number
    (``5 %``, ``≥ 5``, ``20 µm``: no-break spaces, :data:`NO_BREAK`)."""
    width_pt = fig.get_figwidth() * 72.0
    titles = [(ax.title, ax.get_position().width) for ax in fig.axes]
    if fig._suptitle is not None:  # matplotlib keeps its Text there (no public getter)
        titles.append((fig._suptitle, 1.0))
    for title, width in titles:
        chars = int(width_pt * width / (0.55 * title.get_fontsize()))
        lines = title.get_text().splitlines()
        if chars > 20 and any(len(line) > chars for line in lines):
            wrapped = []
            for line in lines:
                for before, after in NO_BREAK:
                    line = re.sub(before, after, line)
                wrapped.append(textwrap.fill(line, chars))
            title.set_text("\n".join(wrapped))


def savefig(fig, path) -> None:
    """Write ``fig`` as PNG (120 dpi, Agg) to ``path`` atomically and close it; titles wider
    than their axes are broken into lines (:func:`wrap_titles`). With the test suite's switch
    (:func:`figures_off`) the figure is closed and nothing is written."""
    try:
        if figures_off():
            return
        wrap_titles(fig)
        FigureCanvasAgg(fig)  # an Agg canvas (a pyplot figure's is replaced: closed below)
        with atomic_open(path, "wb") as f:
            fig.savefig(f, format="png", dpi=DPI)
    finally:
        plt = sys.modules.get("matplotlib.pyplot")
        if plt is not None:  # a pyplot-managed figure: release it
            plt.close(fig)


def finish(
    fig, ax, path, *, xlabel: str, ylabel: str, title: str, legend: bool = True, grid: bool = True
):
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    if grid:
        ax.grid(alpha=0.3)
    labels = []
    if legend:
        labels = [t.get_text() for t in ax.legend().get_texts()]
    savefig(fig, path)
    return labels


def hz_text(f: float) -> str:
    """2345.6 -> '2 346' (a space between thousands, as engineering drawings write it)."""
    return f"{f:,.0f}".replace(",", "\u2009")


def floats(v) -> np.ndarray:
    return np.asarray([np.nan if x is None else x for x in v], dtype=float)


def legend_below_and_save(fig, ax, path, note: str | None) -> list[str]:
    """The legend below the axes (never on the curves; ``note`` as its title), the figure saved
    to ``path``; returns the legend's labels."""
    leg = fig.legend(
        loc="outside lower center",
        ncols=legend_columns(ax),
        fontsize=9,
        frameon=False,
        title=note,
        title_fontsize=8,
    )
    savefig(fig, path)
    return [t.get_text() for t in leg.get_texts()]


def legend_columns(ax, width: int = 48) -> int:
    """Legend columns below a FIGSIZE figure: two unless a label is too long for half of it."""
    labels = ax.get_legend_handles_labels()[1]
    return 1 if any(len(t) > width for t in labels) else 2


def fit_legend_columns(fig, ax, fontsize: float, most: int) -> int:
    """As many legend columns (at most ``most``) as fit the figure's width with its longest
    label: a legend below the axes never runs off either side."""
    labels = ax.get_legend_handles_labels()[1]
    if not labels:
        return 1
    char = 0.6 * fontsize  # points per character, a generous mean for DejaVu Sans
    entry = char * max(len(t) for t in labels) + 3.5 * fontsize  # handle and spacing
    width = fig.get_figwidth() * 72 * 0.97
    return int(max(1, min(most, len(labels), width // entry)))
