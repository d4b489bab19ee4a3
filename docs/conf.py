"""Sphinx configuration of slicelab's documentation (``make docs``: warnings are errors).

Generated when this file is read, all git-ignored (see ``docs/_ext/``): the API
page of every subpackage from its ``__all__`` (``api/slicelab.*.rst``), copies
of ``notebooks/*.ipynb`` for myst-nb to execute (``notebooks/``), and the
structure picture, its tables and the command-line help (``_generated/``).
"""
from __future__ import annotations

import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
sys.path.insert(0, str(DOCS / "_ext"))

import apipages  # noqa: E402
import clihelp  # noqa: E402
import notebookcopies  # noqa: E402
import structure  # noqa: E402

import slicelab  # noqa: E402

apipages.write_pages()
notebookcopies.copy_notebooks()
structure.write_structure()
clihelp.write_cli_help()

project = "slicelab"
author = "the slicelab authors"
copyright = "slicelab authors, MIT licence"
version = release = slicelab.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_nb",
    "apipages",
    "benchresults",
    "datadocs",
]

source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
root_doc = "index"
exclude_patterns = ["_build", "_generated", "performance/tables", "**.ipynb_checkpoints"]
templates_path = ["_templates"]

# Single backticks in the docstrings name objects (`Mesh`, `section`): links where Sphinx finds the
# name, plain code where it does not (not an error: nitpicky mode is off).
default_role = "py:obj"

# --- API reference -----------------------------------------------------------------------------
autosummary_generate = True
autosummary_ignore_module_all = False
autodoc_default_options = {"member-order": "bysource"}
autodoc_typehints = "none"                 # the numpy docstrings give the types
autodoc_preserve_defaults = True
numpydoc_show_class_members = False        # the class template lists members with autodoc
numpydoc_class_members_toctree = False
numpydoc_validation_checks: set[str] = set()
numpydoc_xref_param_type = False

# --- Notebooks: executed at every build, from notebooks/ (see _ext/notebookcopies.py) -------------
nb_execution_mode = "force"
nb_execution_timeout = 600
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_merge_streams = True
myst_enable_extensions = ["dollarmath"]

# --- HTML --------------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"slicelab {release}"
html_static_path: list[str] = []
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "navbar_align": "left",
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version", "theme-version"],
    "secondary_sidebar_items": ["page-toc"],
}
html_sidebars = {"index": []}
html_last_updated_fmt = None
