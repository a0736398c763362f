"""Maths as MathML, written at build time (latex2mathml): the pages need no script and no
network to show their formulas (MathJax would load from a CDN, so an offline reader, or
the headless browser of ``tests/docs``, would see raw TeX).  Browsers render MathML Core
natively (Chromium from 109, Firefox, Safari)."""
from docutils import nodes
from latex2mathml.converter import convert


def _mathml(tex, display):
    return convert(tex.strip(), display="block" if display else "inline")


def visit_inline(self, node):
    self.body.append(f'<span class="math notranslate">{_mathml(node.astext(), False)}</span>')
    raise nodes.SkipNode


def visit_block(self, node):
    label = ""
    if node.get("number"):
        label = f'<span class="eqno">({node["number"]})</span>'
    self.body.append(f'<div class="math notranslate" id="{node["ids"][0]}">'
                     if node.get("ids") else '<div class="math notranslate">')
    self.body.append(label + _mathml(node.astext(), True) + "</div>\n")
    raise nodes.SkipNode


def setup(app):
    app.add_html_math_renderer("mathml", (visit_inline, None), (visit_block, None))
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
