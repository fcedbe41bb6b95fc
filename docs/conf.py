"""Sphinx configuration of the impactdyn documentation.

Build (warnings are errors, so a broken internal link or reference fails it):
``python -m sphinx -W --keep-going -b html docs docs/_build/html``.
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent / "_ext"))

project = "impactdyn"
author = "the impactdyn authors"
copyright = "the impactdyn authors, BSD-3-Clause"

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx_gallery.gen_gallery",
    "impactdyn_reference",
    "impactdyn_vv",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "tutorials/README.rst", "auto_tutorials/*.ipynb", "auto_tutorials/*.py",
                    "auto_tutorials/*.zip", "auto_tutorials/*.md5", "auto_tutorials/*.json",
                    "vv/_generated/*", "_static/mathjax/*"]
root_doc = "index"

# MyST: the pages are Markdown (readable on GitHub too); $...$ maths, numbered $$...$$ (label) equations.
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
math_number_all = False
math_numfig = False  # equations numbered per page, (1), (2), …: the docstrings cite them so
math_eqref_format = "({number})"
# MathJax served with the site (docs/_static/mathjax/README.md: version, licence, why SVG): the
# equations render offline.  A relative path is relative to the built _static folder.
mathjax_path = "mathjax/tex-svg.js"

# No smart quotes: they turned the command-line reference's "--vary" into an en dash ("–vary").
# The pages write their dashes and quotes as the characters themselves.
smartquotes = False

# API reference: each public package's __all__ (autodoc respects it), types as written in the signatures.
autodoc_default_options = {"members": True}
autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_typehints_format = "short"
napoleon_numpy_docstring = True
napoleon_google_docstring = False

sphinx_gallery_conf = {
    "examples_dirs": "tutorials",
    "gallery_dirs": "auto_tutorials",
    "filename_pattern": r"/plot_",  # every tutorial runs at build time
    "download_all_examples": False,
    "remove_config_comments": True,
    "min_reported_time": 1,
    "within_subsection_order": "FileNameSortKey",
    "show_signature": False,
}

html_theme = "pydata_sphinx_theme"
html_title = "impactdyn"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    # The generated references are wide tables: they take the room of the page's table of contents.
    "secondary_sidebar_items": {"**": ["page-toc"], "user-guide/case-files": [], "user-guide/cli": []},
    "footer_start": ["copyright"],
    "footer_end": [],
}
html_show_sourcelink = False
html_static_path = ["_static"]
html_css_files = ["impactdyn.css"]
