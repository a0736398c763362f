"""Sphinx configuration of symvi's documentation site (issue 26).

Build: ``pip install -e ".[docs]" && python -m sphinx -W -b html docs docs/_build/html``.
The gallery pages are MyST-NB text notebooks, executed at build time; their outputs are
cached in ``docs/_build/.jupyter_cache`` (jupyter-cache), so a rebuild with unchanged
cells runs nothing.  ``tests/docs`` builds into a fresh folder, so every example runs.
"""
import os
import sys
from pathlib import Path

import symvi

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))
# the gallery's kernels inherit this: no compile messages or progress bars in the pages
os.environ.setdefault("SYMVI_PROGRESS", "0")

project = "symvi"
author = "the symvi authors"
copyright = "2026, the symvi authors"
version = release = symvi.__version__

extensions = [
    "myst_nb",                      # Markdown pages and executed notebooks
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",          # numpy-style docstring sections
    "mathml",                       # maths as MathML at build time (docs/_ext/mathml.py)
]
html_math_renderer = "mathml"

exclude_patterns = ["_build", "_generated", "Thumbs.db", ".DS_Store", "**.ipynb_checkpoints"]
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb"}

# MyST: $...$ maths, definition lists, anchors for ## headings (links like page.md#anchor)
myst_enable_extensions = ["dollarmath", "amsmath", "deflist", "colon_fence"]
myst_heading_anchors = 3

# MyST-NB: execute every gallery page, cache the outputs, fail the build on an error
nb_execution_mode = "cache"
nb_execution_cache_path = str(HERE / "_build" / ".jupyter_cache")
nb_execution_timeout = 300
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_merge_streams = True

# API pages: the public names only, in source order, numpy-style sections
autodoc_member_order = "bysource"
autodoc_typehints = "none"
napoleon_google_docstring = False
napoleon_numpy_docstring = True

html_theme = "furo"
html_title = f"symvi {release}"
html_static_path = ["_static"]
html_show_sourcelink = False


def _event_kinds():
    """docs/_generated/event_kinds.rst: the table of EVENT_KINDS, written from the code at
    each build (its ``#:`` comment lives in continuation/result.py, so autodoc would show
    dict's own docstring instead)."""
    from symvi.continuation import EVENT_KINDS
    rows = [(f"``{k}``", v.replace("|", "\\|").replace("*", "\\*")) for k, v in EVENT_KINDS.items()]
    w0 = max(len(a) for a, _ in rows)
    w1 = max(len(b) for _, b in rows)
    line = "=" * w0 + " " + "=" * w1
    text = [line, f"{'kind':<{w0}} meaning", line]
    text += [f"{a:<{w0}} {b}" for a, b in rows] + [line, ""]
    out = HERE / "_generated" / "event_kinds.rst"
    out.parent.mkdir(exist_ok=True)
    new = "\n".join(text)
    if not out.exists() or out.read_text(encoding="utf-8") != new:
        out.write_text(new, encoding="utf-8")


_event_kinds()
