"""What every benchmark chart does before it is written: no tick label prints over another."""

from __future__ import annotations

__all__ = ["thin_tick_labels"]


def thin_tick_labels(fig, pad_px: float = 3.0) -> int:
    """Hide the tick labels that would overlap a neighbour on the same axis.

    Log axes with labelled minor ticks (``LogFormatter(labelOnlyBase=False)`` over about a
    decade prints 200, 300, ... 900, 1000 with 800 and 900 a few pixels apart) and ticks set at
    data values that lie close together overlap on some runs' data and not on others. The
    figure is laid out (drawn once); on each axis the major labels are kept first, left to right
    (bottom to top), then the minor ones, each only where it keeps ``pad_px`` pixels from every
    label kept before. Call it after everything is drawn, just before saving. Returns the number
    of labels hidden.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    if not hasattr(fig.canvas, "get_renderer"):
        FigureCanvasAgg(fig)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    hidden = 0
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            lo, hi = sorted(axis.get_view_interval())
            tol = 1e-9 * (abs(hi) + abs(lo))
            kept = []
            for minor in (False, True):
                locs = axis.get_minorticklocs() if minor else axis.get_majorticklocs()
                n = len(locs)
                ticks = axis.get_minor_ticks(n) if minor else axis.get_major_ticks(n)
                for tick, loc in sorted(zip(ticks, locs, strict=True), key=lambda t: t[1]):
                    if not lo - tol <= loc <= hi + tol:  # not drawn
                        continue
                    for label in (tick.label1, tick.label2):
                        if not label.get_visible() or not label.get_text():
                            continue
                        box = label.get_window_extent(renderer).padded(pad_px / 2)
                        if any(box.overlaps(k) for k in kept):
                            label.set_visible(False)
                            hidden += 1
                        else:
                            kept.append(box)
    return hidden
