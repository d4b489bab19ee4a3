"""The notebooks of ``notebooks/``, copied into ``docs/notebooks/`` for myst-nb to execute and render.

Sphinx reads documents from its source folder only, so each notebook is copied
there (git-ignored) when ``conf.py`` is read; the copies are never edited by
hand and never committed. myst-nb runs a notebook in the folder that holds
it, while the notebooks read ``../data`` from ``notebooks/`` (as ``make test``
runs them), so each copy opens with one hidden cell (tagged ``remove-cell``)
that changes into ``notebooks/``. A copy is rewritten only when its notebook
changed, so an incremental build executes only what changed.
"""
from __future__ import annotations

import json
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SOURCE = ROOT / "notebooks"
COPIES = ROOT / "docs" / "notebooks"


def notebooks() -> list[Path]:
    """The notebooks of ``notebooks/``, in name order."""
    return sorted(SOURCE.glob("*.ipynb"))


def _chdir_cell() -> dict:
    return {"cell_type": "code", "execution_count": None, "id": "slicelab-docs-chdir",
            "metadata": {"tags": ["remove-cell"]}, "outputs": [],
            "source": [f"import os\n", f"os.chdir({str(SOURCE)!r})"]}


def copy_notebooks() -> list[str]:
    """Copy every notebook with its opening cell; drop copies whose notebook is gone.
    Returns the copies' names."""
    COPIES.mkdir(parents=True, exist_ok=True)
    names = []
    for path in notebooks():
        nb = json.loads(path.read_text())
        nb["cells"] = [_chdir_cell(), *nb["cells"]]
        text = json.dumps(nb, indent=1, ensure_ascii=False) + "\n"
        target = COPIES / path.name
        if not target.exists() or target.read_text() != text:
            target.write_text(text)
        names.append(path.name)
    for stale in COPIES.glob("*.ipynb"):
        if stale.name not in names:
            stale.unlink()
    return names
