"""Sphinx configuration of forcenet's documentation site.

Build (warnings are errors, the tutorials executed):
``python -m pip install '.[docs]' && python -m sphinx -W --keep-going -b html docs docs/_build/html``.

The site loads nothing from the network: math is rendered by a local copy of
MathJax 3 (the ``sphinx-mathjax-offline`` package copies it into ``_static``),
the theme ships its own assets, and no inventory is fetched (no intersphinx).
``tests/test_docs.py`` builds the site and checks it in headless Chromium.
"""

from __future__ import annotations

import re

import forcenet

project = "forcenet"
author = "The forcenet developers"
copyright = "2026, The forcenet developers"
release = forcenet.__version__
version = ".".join(release.split(".")[:2])

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx-mathjax-offline",  # MathJax 3 from a package, copied into _static/mathjax: no CDN
    "numpydoc",
    "myst_nb",
]

exclude_patterns = ["_build", "jupyter_execute", "**.ipynb_checkpoints", "Thumbs.db", ".DS_Store"]
templates_path = ["_templates"]
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb"}
root_doc = "index"
nitpicky = False

# ------------------------------------------------------------------ the API reference: autosummary + numpydoc
autosummary_generate = True
autosummary_imported_members = False
autodoc_default_options = {"members": False}
autodoc_typehints = "none"  # the signatures show them; numpydoc's Parameters say them in words
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
# Validation of the public surface (every object the reference renders). The checks kept are those a reader
# of the reference relies on: a docstring exists, its parameters are the function's, it says what it returns,
# and it has an example. Style checks (punctuation, the summary's length and mood, See Also sections) are off.
numpydoc_validation_checks = {
    "GL08",  # the object has a docstring
    "PR01",  # every parameter is documented
    "PR02",  # no documented parameter the signature lacks
    "RT01",  # a Returns section
    "EX01",  # an Examples section
}
# Docstrings that need work before they pass these checks (each listed, so the list can only shrink; the
# others are validated). The exceptions' shared example is on the family's page (api/errors.rst).
NEEDS_WORK = [
    "forcenet.ForcenetError", "forcenet.ArgumentError", "forcenet.ArgumentTypeError", "forcenet.ConvergenceError",
    "forcenet.numeric.autocorr.AutocorrError",
    "forcenet.testing.DisagreementError", "forcenet.testing.CannotJudgeError",
    "forcenet.testing.TableAgreement", "forcenet.testing.TableAgreement.*", "forcenet.testing.compare",
    "forcenet.testing.strategies.*",
    "forcenet.numeric.packing.PackingMetropolis.*", "forcenet.numeric.packing.Scene.name",
    "forcenet.numeric.packing.Scene.top_load",
    "forcenet.numeric.triangle.force_distribution.*",
]
numpydoc_validation_exclude = {
    r"\.__\w+__$",  # dunder methods
    r"\._\w+$",  # private names
    *("^" + re.escape(name).replace(r"\*", r"\w+") + "$" for name in NEEDS_WORK),
}

# ------------------------------------------------------------------ MyST and the executed notebooks
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
nb_execution_mode = "force"  # every build runs every notebook: the pages show what today's code does
nb_execution_timeout = 300
nb_execution_raise_on_error = True  # a notebook that fails fails the build
nb_execution_show_tb = True
nb_merge_streams = True
nb_render_image_options = {"width": "100%"}

# ------------------------------------------------------------------ HTML
html_theme = "furo"
html_title = f"forcenet {release}"

html_show_sourcelink = False
html_copy_source = False
html_last_updated_fmt = None
html_theme_options = {"navigation_with_keys": True}


def _summary_keeps_literals(extract_summary):
    """Autosummary's one-line summary, never cut inside an inline literal (``W_1 + ... + W_j``)."""

    def extract(doc, settings):
        summary = extract_summary(doc, settings)
        if summary.count("``") % 2:  # cut at a ". " inside a literal: keep the docstring's first line whole
            return doc[0].strip() if doc else summary
        return summary

    return extract


def setup(app):  # Sphinx calls it with the application
    import sphinx.ext.autosummary as autosummary

    autosummary.extract_summary = _summary_keeps_literals(autosummary.extract_summary)
