"""Sphinx configuration of the multicrank documentation site.

Built by ``scripts/docs`` (and by ``scripts/test``, with warnings as errors) against the
installed package: the API reference is generated from the docstrings of what ``pip install``
put on the path, the CLI reference from the click commands, and the gallery by running the
scripts in ``docs/gallery``.
"""

from __future__ import annotations

import os
import re
from fractions import Fraction

from docutils import nodes
from sphinx.util import logging
from sphinx.util.docutils import SphinxDirective

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
    # MathJax served from the site itself (_static/mathjax), so that the maths renders offline:
    # the package (the docs extra) ships MathJax 3 and copies it into the build.
    "sphinx-mathjax-offline",
    "numpydoc",
    "sphinx_click",
    "sphinx_gallery.gen_gallery",
    "matplotlib.sphinxext.plot_directive",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
# Quotes and ellipses only: "--option" in the help texts stays two hyphens, not an en dash.
smartquotes_action = "qe"
root_doc = "index"
# docs/machines is data the pages link to, not pages; the gallery's sources are rendered by
# sphinx-gallery into auto_examples/.
exclude_patterns = ["_build", "machines", "gallery", "**/README.md"]

# -- maths: MathJax from the site's own _static (set by sphinx-mathjax-offline; said here, so
# that no page ever names a CDN): tests/docs/test_pages.py checks the built site for it.
mathjax_path = "mathjax/tex-chtml.js"

# -- MyST: the pages are Markdown with $…$ / $$…$$ maths and anchors on headings -------------
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3

# -- API reference -----------------------------------------------------------------------
# docs/api.rst groups the public names; autosummary writes one page per name into
# docs/generated (gitignored), from the templates in docs/_templates/autosummary.
templates_path = ["_templates"]
autosummary_generate = True


def _inherited_from_the_package() -> dict[str, list[str]]:
    """For each public class, the public methods it inherits from a class of multicrank's own
    (DesignGrid's and MachineGrid's frame, to_frame, … from their ProductGrid): documented on
    the class's page like its own, unlike what it inherits from Python's builtins."""
    import inspect

    found = {}
    for name in multicrank.__all__:
        value = getattr(multicrank, name)
        if not inspect.isclass(value):
            continue
        own = set(vars(value))
        methods = {
            member
            for base in value.__mro__[1:]
            if base.__module__.startswith("multicrank")
            for member, attribute in vars(base).items()
            if not member.startswith("_") and member not in own and inspect.isfunction(attribute)
        }
        if methods:
            found[f"multicrank.{name}"] = sorted(methods)
    return found


autosummary_context = {"package_inherited": _inherited_from_the_package()}
autodoc_typehints = "none"  # the numpydoc "Parameters" sections carry the types and units
autodoc_member_order = "bysource"
add_module_names = False
numpydoc_show_class_members = False
numpydoc_xref_param_type = False
# Checked on every docstring the reference shows, so that a parameter added without its
# documentation (or documented under a wrong name) fails the build: PR01 undocumented
# parameter, PR02 documented parameter the signature lacks, PR04 a parameter without a type,
# PR07 without a description, PR10 "name: type" without the space, RT01 a function that
# returns something without a Returns section, GL08 no docstring at all.
numpydoc_validation_checks = {"PR01", "PR02", "PR04", "PR07", "PR10", "RT01", "GL08"}
# The result classes are made by the library, not by users: their docstrings list
# attributes, not the fields of a constructor nobody calls (their methods are checked).
RESULT_CLASSES = (
    "EnergyExtrema",
    "SteadyState",
    "FlywheelInertia",
    "Transient",
    "SymbolicGravity",
    "SymbolicInertia",
    "CounterweightOptimum",
    "ShakingForces",
    "BearingLoads",
    "TorsionalModel",
)
numpydoc_validation_exclude = {rf"^multicrank\.(symbolic\.)?{name}$" for name in RESULT_CLASSES}

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
html_static_path = ["_static"]
html_css_files = ["multicrank.css"]


# -- hooks ----------------------------------------------------------------------------------
def _hide_result_signatures(app, what, name, obj, options, signature, return_annotation):
    """No constructor signature for the result classes (see RESULT_CLASSES)."""
    if what == "class" and name.split(".")[-1] in RESULT_CLASSES:
        return "", None
    return None


# The docstrings cite the theory as `docs/theory.md, "Section"` (readable in help()); on the
# site that becomes a link to the section, and a section that no longer exists fails the build.
_THEORY = re.compile(r'docs/theory\.md(?:,\s+"([^"]+)")?')
_cited: set[tuple[str, str]] = set()


def _link_theory(app, what, name, obj, options, lines):
    text = "\n".join(lines)
    if "docs/theory.md" not in text:
        return
    page = app.builder.get_relative_uri(app.env.docname, "theory")

    def link(match: re.Match) -> str:
        section = match[1]
        if section is None:
            return f"`docs/theory.md <{page}>`__"
        _cited.add((name, section))
        return f'`docs/theory.md, "{section}" <{page}#{nodes.make_id(section)}>`__'

    lines[:] = _THEORY.sub(link, text).split("\n")


def _check_theory_sections(app, env):
    if "theory" not in env.found_docs:
        return
    titles = {section[0].astext() for section in env.get_doctree("theory").findall(nodes.section)}
    for name, section in sorted(_cited):
        if section not in titles:
            logging.getLogger(__name__).warning(
                f'{name} cites docs/theory.md, "{section}", which has no such section', type="multicrank"
            )


def _check_public_names(app, env):
    """Every public name (multicrank.__all__, multicrank.presets.__all__) is in the reference."""
    documented = set(env.get_domain("py").objects)
    names = [f"multicrank.{name}" for name in multicrank.__all__]
    names += [f"multicrank.presets.{name}" for name in multicrank.presets.__all__]
    for name in names:
        if name not in documented and name.replace(".presets.", ".") not in documented:
            logging.getLogger(__name__).warning(f"{name} is public but not in docs/api.rst", type="multicrank")


def _list_table(header: list[str], rows: list[list[str]], widths: str) -> str:
    lines = [".. list-table::", "   :header-rows: 1", f"   :widths: {widths}", "   :class: multicrank-presets", ""]
    for row in [header, *rows]:
        lines += [f"   * - {row[0]}", *(f"     - {cell}" for cell in row[1:])]
    return "\n".join(lines)


class _BuiltInMachines(SphinxDirective):
    """A table of multicrank.presets.MACHINES, made from the machines themselves."""

    def run(self) -> list[nodes.Node]:
        from multicrank.presets import MACHINES

        rows = []
        for name, machine in MACHINES.items():
            low, high = machine.rpm_range or (machine.rpm, machine.rpm)
            rows.append(
                [
                    f"``{name}``",
                    f"{len(machine)}, {machine.strokes}-stroke",
                    f"{machine.rpm:g} ({low:g} … {high:g})",
                    f"{machine.shaft_inertia:,.0f}" if machine.shaft_inertia >= 1e4 else f"{machine.shaft_inertia:g}",
                    machine.note,
                ]
            )
        header = ["name", "cylinders", "speed [1/min] (range)", "I_w [kg·m²]", "what it is"]
        return self.parse_text_to_nodes(_list_table(header, rows, "17 10 13 10 50"))


class _SpeedFluctuationClasses(SphinxDirective):
    """A table of multicrank.presets.SPEED_FLUCTUATION, as fractions."""

    def run(self) -> list[nodes.Node]:
        from multicrank.presets import MACHINE_CLASSES, SPEED_FLUCTUATION

        def fraction(value: float) -> str:
            return "0" if value == 0 else str(Fraction(value).limit_denominator(10_000))

        rows = [
            [
                name,
                fraction(low),
                fraction(high),
                ", ".join(f"``{m}``" for m, c in MACHINE_CLASSES.items() if c == name),
            ]
            for name, (low, high) in SPEED_FLUCTUATION.items()
        ]
        return self.parse_text_to_nodes(
            _list_table(["class", "δ from", "δ to", "built-in machines"], rows, "25 12 12 51")
        )


def setup(app):
    app.add_directive("multicrank-machines", _BuiltInMachines)
    app.add_directive("multicrank-speed-classes", _SpeedFluctuationClasses)
    app.connect("autodoc-process-signature", _hide_result_signatures, priority=400)
    app.connect("autodoc-process-docstring", _link_theory)
    app.connect("env-check-consistency", _check_theory_sections)
    app.connect("env-check-consistency", _check_public_names)
