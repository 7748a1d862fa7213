"""Matplotlib figures drawn off screen without touching pyplot's global backend or figure
registry."""

from __future__ import annotations

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure


def agg_figure(width_in: float, height_in: float, dpi: float = 100) -> Figure:
    """A figure of the given size (inches) with its own Agg canvas: `savefig` and
    `canvas.buffer_rgba()` work, and it is freed with its last reference (no `plt.close`)."""
    figure = Figure(figsize=(width_in, height_in), dpi=dpi)
    FigureCanvasAgg(figure)
    return figure
