"""Sphinx configuration of the multicrank documentation site.

Built by ``scripts/docs`` (and by ``scripts/test``, with warnings as errors) against the
installed package: the API reference is generated from the docstrings of what ``pip install``
put on the path, the CLI reference from the click commands, and the gallery by running the
scripts in ``docs/gallery``.
"""

from __future__ import annotations

import os

import multicrank

project = "multicrank"
author = "the multicrank developers"
copyright = "2026, the multicrank developers"
release = multicrank.__version__
version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "sphinx_click",
    "sphinx_gallery.gen_gallery",
    "matplotlib.sphinxext.plot_directive",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
# docs/machines is data the pages link to, not pages; the gallery's sources are rendered by
# sphinx-gallery into auto_examples/.
exclude_patterns = ["_build", "machines", "gallery", "**/README.md"]

# -- MyST: the pages are Markdown with $…$ / $$…$$ maths and anchors on headings -------------
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3

# -- API reference -----------------------------------------------------------------------
autosummary_generate = True
autodoc_typehints = "none"  # the numpydoc "Parameters" sections carry the types and units
numpydoc_show_class_members = False
numpydoc_xref_param_type = False

# -- the gallery: every script in docs/gallery runs at build time and its figures are kept -
# MULTICRANK_DOCS_FAST=1 (set by scripts/test) asks the examples for their short settings.
sphinx_gallery_conf = {
    "examples_dirs": "gallery",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "abort_on_example_error": True,
    "write_computation_times": False,
    "show_signature": False,
}
os.environ.setdefault("MPLBACKEND", "Agg")

# -- figures drawn in the pages (plot directive) ------------------------------------------
plot_include_source = False
plot_html_show_source_link = False
plot_html_show_formats = False
plot_formats = [("png", 110)]

# -- HTML ----------------------------------------------------------------------------------
html_theme = "furo"
html_title = f"multicrank {release}"
html_static_path: list[str] = []
