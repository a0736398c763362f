"""The documentation site (issue 26): built as the README says, warnings as errors, every
gallery example executed; then opened in a real headless browser.

``tests/docs`` has no ``__init__.py``: it tests ``docs/``, not a package of ``symvi``
(``tests/test_layers.py::test_test_folders_mirror_the_package_tree`` counts only folders
that are packages), so this module's name is unique in the suite.

The build runs ``python -m sphinx -W -b html docs OUT`` in a subprocess with a fresh
execution cache in a temporary folder, so every example runs (no cached output is reused).
It needs the ``docs`` dependencies, which the ``test`` extra includes; where they are not
installed the tests skip, saying so.
"""
import html.parser
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path
from urllib.parse import unquote, urlsplit

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"

#: every page the site must have (paths under the output folder)
PAGES = [
    "index.html", "getting-started.html",
    "theory/map.html", "theory/jets.html", "theory/normal-forms.html", "theory/errata.html",
    "theory/grazing.html",
    "howto/model-files.html", "howto/continuation.html", "howto/curves.html",
    "howto/planes.html", "howto/scenes.html", "howto/validation.html",
    "gallery/index.html", "gallery/paper_examples.html", "gallery/chain3.html",
    "gallery/contact_two_stops.html", "gallery/contact_elastic.html",
    "gallery/contact_impact_damper.html", "gallery/contact_chain_stops.html",
    "gallery/plane_dask.html", "gallery/coco_15_2.html", "gallery/budd_dux.html",
    "gallery/duffing.html", "gallery/absorber.html",
    "api/index.html", "api/symvi.html", "api/continuation.html",
    "limitations.html", "comparison.html", "changelog.html", "citation.html",
]
#: (page, text its executed output must show): numbers the README and the examples'
#: README state, so a page that ran nothing, or ran something else, fails
OUTPUTS = {
    "gallery/duffing.html": ["at omega = 2.5003319202", "at omega = 2.7473542619",
                             "at omega = 2.8998114432", "c = 6.95455", "2-2 orbits: ",
                             "(past the flip): 2 distinct V"],
    "gallery/absorber.html": ["at omega = 1.2989631938", "at omega = 1.4390800002",
                              "at omega = 1.9765518613", "at omega = 2.0949537364",
                              "at omega = 3.1593133866"],
    "getting-started.html": ["flip at omega = 2.656177", "2-2 orbits from omega", "completed"],
    "gallery/paper_examples.html": ["omega_c = 0.736877", "omega_c = 0.490520"],
    "gallery/chain3.html": ["omega_c = 0.9997114225", "omega_c = 1.0459583390"],
    "gallery/contact_two_stops.html": ["symmetry-breaking", "omega = 1.0082739",
                                       "omega = 1.5745409"],
    "gallery/contact_elastic.html": ["stop2:entry", "omega = 1.3028444", "omega = 0.8803619"],
    "gallery/contact_impact_damper.html": ["omega = 0.9664823", "omega = 0.8487275",
                                           "omega = 1.0852260"],
    "gallery/contact_chain_stops.html": ["flip"],
    "gallery/plane_dask.html": ["blocks computed on 1 worker", "0 blocks computed the second"],
    "theory/normal-forms.html": ["||q||_2 = 1.000000000000000",
                                 "c1) = -0.097200709118  (this page)",
                                 "= -0.097200709118  (symvi.hopf_points)"],
    "theory/grazing.html": ["gap* = 0.1490711985 (|X| = 0.1490711985)",
                            "period-adding cascade with chaotic windows",
                            "1.0e-06  1.092047e-03  1.092048e-03  0.999998  period-6"],
    "howto/curves.html": ["CH   omega = 0.8164887222", "R3   omega = 0.7628671598"],
    "gallery/coco_15_2.html": ["omega = 0.30: grazing at A = 0.9104943712",
                               "omega = 1.00: grazing at A = 0.1000000000",
                               "omega = 1.20: grazing at A = 0.4560701700",
                               "fold below A_GR located: True", "grazing curve: ",
                               "RG at omega = 0.998749217772",
                               "RG omega = 1.997498436: kappa_fold = -101.847",
                               "fold curve ends: reached grazing at the resonant grazing "
                               "point omega = 0.998749217772"],
    "gallery/budd_dux.html": ["omega = 3.3531782", "omega = 4.6418368", "omega = 3.9265536",
                              "omega = 5.7820246", "closed form 3.1460730"],
}
#: gallery pages that draw at least one figure
FIGURES = ["theory/normal-forms.html", "howto/curves.html", "gallery/paper_examples.html",
           "gallery/chain3.html", "gallery/contact_two_stops.html", "gallery/contact_elastic.html",
           "gallery/contact_impact_damper.html", "gallery/contact_chain_stops.html",
           "gallery/coco_15_2.html", "gallery/budd_dux.html", "gallery/duffing.html", "gallery/absorber.html"]


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """(output folder, build seconds) of a fresh -W build of docs/."""
    for mod in ("sphinx", "myst_nb", "furo"):
        pytest.importorskip(mod, reason=f"{mod} is not installed: pip install -e \".[docs]\"")
    tmp = tmp_path_factory.mktemp("site")
    out = tmp / "html"
    env = dict(os.environ, SYMVI_PROGRESS="0")
    t0 = time.perf_counter()
    run = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "-q", "-b", "html",
         "-d", str(tmp / "doctrees"), "-D", f"nb_execution_cache_path={tmp / 'cache'}",
         str(DOCS), str(out)],
        cwd=ROOT, env=env, capture_output=True, text=True, timeout=900)
    seconds = time.perf_counter() - t0
    assert run.returncode == 0, f"sphinx -W failed:\n{run.stdout[-3000:]}\n{run.stderr[-6000:]}"
    print(f"docs build: {seconds:.1f} s")
    return out, seconds


class _Links(html.parser.HTMLParser):
    """Every href and src of a page, and the ids it defines."""

    def __init__(self):
        super().__init__()
        self.links, self.ids = [], set()

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "id" in a:
            self.ids.add(a["id"])
        for key in ("href", "src"):
            if a.get(key):
                self.links.append((tag, key, a[key]))


def _parse(text):
    p = _Links()
    p.feed(text)
    return p


def broken_links(page, text, root):
    """The local href/src targets of ``page`` (a file under ``root``) that do not exist:
    a missing file, or a #fragment no element of the target page has as its id."""
    bad = []
    for tag, key, url in _parse(text).links:
        parts = urlsplit(url)
        if parts.scheme or parts.netloc or url.startswith(("mailto:", "javascript:", "data:")):
            continue                                     # external: not checked here
        target = page if not parts.path else (page.parent / unquote(parts.path)).resolve()
        if target.is_dir():
            target = target / "index.html"
        if not target.exists() or root.resolve() not in target.resolve().parents:
            bad.append(f"{tag} {key}={url!r} (no {target})")
            continue
        if parts.fragment and target.suffix == ".html":
            ids = _parse(target.read_text(encoding="utf-8")).ids
            if unquote(parts.fragment) not in ids:
                bad.append(f"{tag} {key}={url!r} (no id {parts.fragment!r} in {target.name})")
    return bad


@pytest.mark.slow
def test_site_builds_with_every_page(site):
    out, seconds = site
    missing = [p for p in PAGES if not (out / p).is_file()]
    assert not missing, missing
    assert seconds > 0


@pytest.mark.slow
def test_gallery_pages_show_their_executed_output(site):
    out, _ = site
    for page, needles in OUTPUTS.items():
        text = (out / page).read_text(encoding="utf-8")
        assert "cell_output" in text, f"{page}: no executed output"
        for needle in needles:
            assert needle in text, f"{page}: {needle!r} not in its output"
        assert "Traceback" not in text, page
    for page in FIGURES:
        text = (out / page).read_text(encoding="utf-8")
        imgs = [u for t, k, u in _parse(text).links if t == "img" and "_images/" in u]
        assert imgs, f"{page}: no figure"


@pytest.mark.slow
def test_api_pages_document_the_public_names(site):
    out, _ = site
    top = (out / "api/symvi.html").read_text(encoding="utf-8")
    cont = (out / "api/continuation.html").read_text(encoding="utf-8")
    for name in ("symvi.Model", "symvi.Model.luo_xie", "symvi.Stop", "symvi.load_model",
                 "symvi.Params", "symvi.Params.as_model",
                 "symvi.period1_orbits", "symvi.hopf_points", "symvi.simulate", "symvi.jet",
                 "symvi.poincare_map"):
        assert f'id="{name}"' in top, name
    for name in ("continue_orbits", "continue_branch", "switch_at_flip", "Branch",
                 "SpecialPoint", "EVENT_KINDS"):
        assert f'id="symvi.continuation.{name}"' in cont, name
    assert "symmetry-breaking" in cont                    # the EVENT_KINDS table


#: TeX left as text (a formula the maths renderer did not turn into MathML)
RAW_TEX = re.compile(r"\$[^$<>]*\\[A-Za-z]+[^$<>]*\$|\\\(|\\\[")


def raw_tex(text):
    """The raw TeX fragments of a page's text, outside code (pre) blocks."""
    return RAW_TEX.findall(re.sub(r"<pre.*?</pre>", "", text, flags=re.S))


@pytest.mark.slow
def test_every_formula_is_rendered(site):
    out, _ = site
    pages = {p: p.read_text(encoding="utf-8") for p in out.rglob("*.html")}
    bad = {str(p.relative_to(out)): raw_tex(t)[:3] for p, t in pages.items() if raw_tex(t)}
    assert not bad, bad
    assert "<math" in pages[out / "theory" / "normal-forms.html"]
    assert raw_tex(r"<p>a $w \mapsto \lambda w$ b</p>") and not raw_tex("<p>$5 and $6</p>")


@pytest.mark.slow
def test_no_broken_image_or_internal_link(site):
    out, _ = site
    bad = {}
    for page in sorted(out.rglob("*.html")):
        b = broken_links(page, page.read_text(encoding="utf-8"), out)
        if b:
            bad[str(page.relative_to(out))] = b
    assert not bad, bad


def test_the_link_check_finds_a_broken_link(tmp_path):
    """The checker itself: a missing file, a missing image and a missing anchor are found;
    external links, existing files and ids are not."""
    (tmp_path / "a.html").write_text('<p id="x">a</p>', encoding="utf-8")
    page = tmp_path / "index.html"
    text = ('<a href="a.html#x">ok</a> <a href="https://example.org/n">ext</a>'
            '<a href="#top">self</a><span id="top"></span>'
            '<a href="b.html">missing</a> <img src="_images/none.png">'
            '<a href="a.html#y">no anchor</a>')
    page.write_text(text, encoding="utf-8")
    bad = broken_links(page, text, tmp_path)
    assert len(bad) == 3, bad
    assert any("b.html" in b for b in bad) and any("none.png" in b for b in bad)
    assert any("'y'" in b for b in bad)


# ------------------------------------------------------------------ a real headless browser
def chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


def _chromium(args, user_data, timeout=120):
    exe = chromium()
    cmd = [exe, "--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
           "--disable-component-update", "--disable-sync", "--no-first-run",
           "--disable-dev-shm-usage", "--hide-scrollbars", f"--user-data-dir={user_data}", *args]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)


def _png(path):
    import matplotlib.image
    return matplotlib.image.imread(str(path))


#: (page, text the rendered DOM must hold): the front page, one API page, one gallery page
BROWSED = [("index.html", "Symbolic-numeric bifurcation analysis"),
           ("api/continuation.html", "continue_orbits"),
           ("gallery/contact_two_stops.html", "symmetry-breaking")]


@pytest.mark.slow
@pytest.mark.skipif(chromium() is None, reason="no chromium on PATH (apt-get install chromium)")
def test_pages_render_in_a_headless_browser(site, tmp_path):
    """Chromium opens each page: its DOM (after scripts ran) holds the page's text and no
    broken local link or image, and its screenshot is a drawn page, not a blank one."""
    out, _ = site
    shots = Path(os.environ.get("SYMVI_DOCS_SCREENSHOTS", tmp_path))
    shots.mkdir(parents=True, exist_ok=True)
    for k, (page, needle) in enumerate(BROWSED):
        url = (out / page).as_uri()
        png = shots / (page.replace("/", "_").replace(".html", ".png"))
        run = _chromium([f"--screenshot={png}", "--window-size=1280,1600",
                         "--virtual-time-budget=5000", url], tmp_path / f"profile-s{k}")
        assert png.is_file(), f"no screenshot of {page}: {run.stderr[-2000:]}"
        img = _png(png)
        assert img.shape[0] == 1600 and img.shape[1] == 1280, img.shape
        rgb = img[..., :3]
        # a drawn page: not one colour, and some dark pixels (text) on it
        assert float(rgb.std()) > 0.02, f"{page}: blank screenshot {png}"
        assert float((rgb.mean(axis=2) < 0.35).mean()) > 0.002, f"{page}: no text in {png}"
        run = _chromium(["--dump-dom", "--virtual-time-budget=5000", url],
                        tmp_path / f"profile-d{k}")
        dom = run.stdout
        assert needle in dom, f"{page}: {needle!r} not in the rendered DOM"
        bad = broken_links(out / page, dom, out)
        assert not bad, (page, bad)
    if page.startswith("gallery"):
        assert "_images/" in dom                           # the figures are in the page
    print(f"screenshots: {sorted(str(p) for p in shots.glob('*.png'))}")
    assert np.isfinite(rgb).all()
