"""The one matplotlib setup of the package: a non-interactive backend and atomic figure files.

Imported only where a plot is drawn, so ``import impactdyn`` never loads matplotlib.
"""

from __future__ import annotations

import os
from pathlib import Path

from impactdyn._runfolder import atomic_output


def pyplot():
    """``matplotlib.pyplot`` on the Agg backend (files only, no display needed)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save_figure(fig, path: str | os.PathLike, dpi: int = 110) -> Path:
    """Write ``fig`` to ``path`` atomically (format from the suffix) and close it."""
    path = Path(path)
    try:
        with atomic_output(path) as tmp:
            fig.savefig(tmp, dpi=dpi, format=path.suffix.lstrip(".") or None)
    finally:
        pyplot().close(fig)
    return path
