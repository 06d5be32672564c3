"""Sphinx configuration of forcenet's documentation site.

Build (warnings are errors, the tutorials executed):
``python -m pip install '.[docs]' && python -m sphinx -W --keep-going -b html docs docs/_build/html``.

The site loads nothing from the network: math is rendered by a local copy of
MathJax 3 (the ``sphinx-mathjax-offline`` package copies it into ``_static``),
the theme ships its own assets, and no inventory is fetched (no intersphinx).
``tests/test_docs.py`` builds the site and checks it in headless Chromium.
"""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import forcenet

sys.path.insert(0, str(Path(__file__).resolve().parent / "_ext"))  # the site's own extensions
from performance_data import performance_substitutions

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
    "cli_reference",  # docs/_ext: the command-line reference, generated from forcenet.cli.build_parser
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
# Every public name passes them (tests/test_api_examples.py checks the same without Sphinx); only dunder
# methods and private names are not validated.
numpydoc_validation_exclude = {
    r"\.__\w+__$",  # dunder methods
    r"\._\w+$",  # private names
}

# ------------------------------------------------------------------ MyST and the executed notebooks
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist", "substitution"]
# Measured costs in prose are substitutions from docs/_data/performance.json, the performance page's file:
# {{ pfaffian_table_seconds_64 }} is its pfaffian table's table_seconds at N = 64, as the pages write a time.
myst_substitutions = performance_substitutions(json.loads((Path(__file__).resolve().parent / "_data"
                                                           / "performance.json").read_text(encoding="utf-8")))
myst_heading_anchors = 3
nb_execution_mode = "force"  # every build runs every notebook: the pages show what today's code does
nb_execution_timeout = 300
nb_execution_raise_on_error = True  # a notebook that fails fails the build
nb_execution_show_tb = True
nb_merge_streams = True
nb_render_image_options = {"width": "100%"}
nb_render_markdown_format = "myst"  # a cell's Markdown output may be a table (the performance page's)

# ------------------------------------------------------------------ HTML
html_theme = "furo"
html_title = f"forcenet {release}"

html_show_sourcelink = False
html_copy_source = False
html_last_updated_fmt = None
html_theme_options = {"navigation_with_keys": True}


# Abbreviations after which a period does not end a sentence ("the maps of Sec. 4.6", "Eq. (4.1)").
_ABBREVIATIONS = ("Eq", "Eqs", "Sec", "Secs", "Fig", "Figs", "Ref", "Refs", "Ch", "Chap", "Thm", "Prop", "cf", "e.g",
                  "i.e", "vs", "resp", "approx", "No", "al")
_SENTENCE_END = re.compile(r"(?<!\b" + r")(?<!\b".join(re.escape(a) for a in _ABBREVIATIONS) + r")\.(?=\s|$)")


def first_sentence(doc: list[str]) -> str:
    """The first sentence of a docstring's first paragraph: ends at a period that follows no abbreviation
    (``Eq.``, ``Sec.``, ``e.g.``), outside inline literals; the whole paragraph if none.

    >>> first_sentence(["The maps of Sec. 4.6 per bottom row, Eq. (4.88).", "", "More."])
    'The maps of Sec. 4.6 per bottom row, Eq. (4.88).'
    >>> first_sentence(["A sum ``W_1 + ... + W_j``. Then more."])
    'A sum ``W_1 + ... + W_j``.'
    """
    paragraph = []
    for line in doc:
        if not line.strip():
            if paragraph:
                break
            continue
        paragraph.append(line.strip())
    text = " ".join(paragraph)
    for match in _SENTENCE_END.finditer(text):
        head = text[: match.end()]
        if head.count("``") % 2 == 0 and head.count("(") <= head.count(")"):
            return head
    return text


def _summary_survives_abbreviations(extract_summary):
    """Autosummary's one-line summary, never cut after "Eq." or "Sec." nor inside an inline literal."""

    def extract(doc, settings):
        summary = extract_summary(doc, settings)
        sentence = first_sentence(doc)
        if sentence and (summary.count("``") % 2 or len(sentence) > len(summary.rstrip("."))
                         or re.search(r"\b(?:" + "|".join(map(re.escape, _ABBREVIATIONS)) + r")\.$", summary)):
            return sentence
        return summary

    return extract


# ------------------------------------------------------------------ the derivations of notes/, rendered on the site
# Each page docs/derivations/NAME.md is a one-line stub; its source is notes/NAME.md, read when the page is read
# (so the notes stay where the code and the tests cite them, and the site shows the proofs). The project's issue
# numbers are dropped (they mean nothing to a reader of the site); figures are found in notes/figures.
NOTES = Path(__file__).resolve().parent.parent / "notes"
_ISSUE_REFERENCE = re.compile(
    r"\s*\((?:issues?|Issues?)\s+#?\d+[^()]*\)"  # a parenthetical "(issue 43)", "(issues 45 items 1, 3 and 46)"
    r"|\b(?:[Ii]ssues?)\s+#?\d+(?:\s+items?\s+[\d, -]+)?(?:(?:,|\s+and)\s+\d+(?:\s+items?\s+[\d, -]+)?)*")


def note_as_page(text: str) -> str:
    """A note's Markdown as a page of the site: issue numbers out, figure paths from docs/derivations/.

    >>> note_as_page("# Fluctuations (issue 27)\\n\\nAs in issue 6, see ![a](figures/x.png).")
    '# Fluctuations\\n\\nAs in a project issue, see ![a](../../notes/figures/x.png).'
    """
    text = _ISSUE_REFERENCE.sub(lambda m: "" if m.group(0).lstrip().startswith("(") else "a project issue", text)
    return re.sub(r"\]\((?:\./)?figures/", "](../../notes/figures/", text)


def _render_note(app, docname, source):  # Sphinx's "source-read" event
    if docname.startswith("derivations/") and docname != "derivations/index":
        note = NOTES / (docname.split("/", 1)[1] + ".md")
        app.env.note_dependency(str(note))
        source[0] = note_as_page(note.read_text(encoding="utf-8"))


# ------------------------------------------------------------------ the tutorials as downloadable notebooks
# myst-nb writes each executed page to OUTDIR/../jupyter_execute; when the build has finished the tutorials' are
# copied to OUTDIR/notebooks, and each tutorial links its own (with the outputs the page shows).
_DOWNLOAD = """

```{raw} html
<p class="download-notebook"><a href="../notebooks/NAME.ipynb" download>Download this tutorial as a Jupyter
notebook</a> (with the outputs shown here; it runs where forcenet is installed).</p>
```
"""


def _link_notebook(app, docname, source):  # Sphinx's "source-read" event
    if docname.startswith("tutorials/") and docname != "tutorials/index":
        lines = source[0].split("\n")
        title = next(k for k, line in enumerate(lines) if line.startswith("# "))
        name = docname.split("/", 1)[1]
        source[0] = "\n".join([*lines[: title + 1], *_DOWNLOAD.replace("NAME", name).split("\n"), *lines[title + 1:]])


def _copy_notebooks(app, exception):  # Sphinx's "build-finished" event
    import shutil

    executed = Path(app.outdir).parent / "jupyter_execute" / "tutorials"
    if exception is None and app.builder.format == "html" and executed.is_dir():
        target = Path(app.outdir) / "notebooks"
        target.mkdir(exist_ok=True)
        for notebook in executed.glob("*.ipynb"):
            shutil.copyfile(notebook, target / notebook.name)


def setup(app):  # Sphinx calls it with the application
    import sphinx.ext.autosummary as autosummary

    autosummary.extract_summary = _summary_survives_abbreviations(autosummary.extract_summary)
    app.connect("source-read", _render_note)
    app.connect("source-read", _link_notebook)
    app.connect("build-finished", _copy_notebooks)
