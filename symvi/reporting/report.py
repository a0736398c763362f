"""The report of ``symvi run`` / ``symvi reproduce``: ``DIR/report.md`` and its PNG figures.

Runs scenes (:mod:`symvi.reporting.scenes`, cached in ``DIR/.cache``), draws each figure
with :mod:`symvi.reporting.figures` unless the cached one for the same result is already
in place, and writes the Markdown report.  Every file is written to a
temporary name and renamed into place (:mod:`symvi._io`), so a failed run
loses nothing already written.
"""
import datetime
import hashlib
import json
import os
import re
import time
from dataclasses import dataclass

from . import scenes as sc
from .._io import write_text
from ..errors import SymviError
from ..paper.audit import NOTES, fmt

_FIG_KINDS = ("multipliers", "section", "bifurcation", "circle_check", "curve",
              "codim2_evidence")


@dataclass
class Report:
    """What a report run produced."""

    path: str
    figures: list
    parts: list
    seconds: float

    @property
    def from_cache(self):
        return [p for p in self.parts if p.source == "cache"]


def build_report(scene_list, out_dir, *, quick=False, use_cache=True, command="",
                 progress=None, title=None):
    """Run ``scene_list`` into ``out_dir``: report.md, figures, cache.  Returns a :class:`Report`.

    Checked before any work: every scene has its parameters, and ``out_dir`` (flag ``--out``)
    is a writable folder whose ``report.md`` can be written.  A cached part that cannot be
    shown (written by something else) is computed again.
    """
    from .._io import check_output
    from ..progress import Progress
    t0 = time.perf_counter()
    for s in scene_list:
        s.check_params()
    out_dir = check_output(os.fspath(out_dir), flag="--out", folder=True)
    path = os.path.join(out_dir, "report.md")
    check_output(path, flag="--out", suffixes=(".md",))
    cache_dir = os.path.join(out_dir, ".cache")
    if os.path.lexists(cache_dir):
        check_output(cache_dir, flag="--out", folder=True)
    os.makedirs(out_dir, exist_ok=True)
    cache = sc.Cache(cache_dir)
    total = sum(len(s.outputs) for s in scene_list)
    parts, figures = [], []
    with Progress(total, "symvi", enabled=progress) as bar:
        for s in scene_list:
            for out in s.outputs:
                p = sc.run_output(s, out, cache_dir, quick=quick, use_cache=use_cache)
                try:
                    f = _figure(p, out_dir, cache, use_cache)
                    _part(p)
                except SymviError:     # an unwritable figure: the same after recomputing
                    raise
                except Exception:      # noqa: BLE001 - a cached result that cannot be shown
                    if p.source != "cache":
                        raise
                    p = sc.run_output(s, out, cache_dir, quick=quick, use_cache=False)
                    f = _figure(p, out_dir, cache, False)
                if f:
                    figures.append(f)
                    p.result["_figure"] = os.path.basename(f[0])
                    p.result["_figure_source"] = f[1]
                bar.update()
                parts.append(p)
    seconds = time.perf_counter() - t0
    md = render(scene_list, parts, quick=quick, command=command, seconds=seconds, title=title)
    write_text(path, md)
    return Report(path, [f[0] for f in figures], parts, seconds)


# --------------------------------------------------------------------------- figures
def _fig_title(p):
    t = p.output.spec.get("title") or p.scene.title
    note = p.result.get("quick_note")
    return f"{t}\n{note}" if note else t


def _figure(p, out_dir, cache, use_cache):
    """Draw the figure of part ``p`` (if its kind has one): (path, "drawn" | "cache") or None."""
    if p.output.kind not in _FIG_KINDS or not p.available:
        return None
    if p.output.kind == "section" and not len(p.arrays.get("section", [])):
        return None
    stem = os.path.join(out_dir, f"{p.scene.name}-{p.output.id}")
    path = stem + ".png"
    rkey = hashlib.sha256(json.dumps([p.key, _fig_title(p), p.output.spec.get("highlight"),
                                      sc.source_hash(("figures", "report"))],
                                     default=str).encode()).hexdigest()[:24]
    if use_cache and cache.figure_ok(p.key, path, rkey) and os.path.exists(stem + ".pdf"):
        return path, "cache"
    from . import figures
    fig = _draw(figures, p)
    figures.save_all(fig, stem)          # PNG for the report, PDF for print
    cache.record_figure(p.key, path, rkey)
    return path, "drawn"


def _section_view(params):
    """Labels and projections of a model's section (the paper's defaults otherwise)."""
    from ..model import Model
    if not isinstance(params, Model):
        return {}
    from ..maps.section import Section
    names = Section.of(params).names
    d = len(names)
    proj = ((1, 0), (d - 1, 0), (d // 2 + 1, 1)) if d >= 4 else ((1, 0),)
    return {"labels": names, "projections": proj}


def _draw(figures, p):
    import numpy as np
    a, kind, title = p.arrays, p.output.kind, _fig_title(p)
    if kind == "multipliers":
        lam = np.asarray(a["multipliers"])
        ok = np.isfinite(lam[:, 0].real)
        return figures.multiplier_paths(np.asarray(a["omega"])[ok], lam[ok], title=title)
    view = _section_view(p.scene.params_for(p.output))
    if kind == "section":
        hl = p.output.spec.get("highlight")
        fp = p.result.get("fixed_point")
        return figures.sections(a["section"], title=title, fixed_point=fp,
                                highlight=None if hl is None else (int(hl[0]), int(hl[1])),
                                **view)
    if kind == "bifurcation":
        return figures.bifurcation_diagram(a["omega"], a["section"], a["counts"],
                                           component=p.output.spec["component"], title=title,
                                           curves=p.result.get("curves"),
                                           **({"labels": view["labels"]} if view else {}))
    if kind == "curve":
        return figures.two_parameter([p.result["plot"]], p.result["names"], title=title)
    if kind == "codim2_evidence":
        return figures.codim2_evidence(p.result, a, title=title)
    if kind == "circle_check":
        return figures.circle_loglog(a["mu"], a["measured"], a["predicted"], title=title,
                                     **({"names": view["labels"]} if view else {}))
    raise ValueError(kind)


# --------------------------------------------------------------------------- markdown
#: Markdown and HTML specials in user-provided text, made literal: entities for & < > (no raw
#: HTML, no autolink), backslash escapes for [ ] (no link, image or link definition), ` (no
#: code span) and the backslash itself (so an escape cannot be cancelled)
_LITERAL = str.maketrans({"\\": "\\\\", "`": "\\`", "[": "\\[", "]": "\\]", "&": "&amp;",
                          "<": "&lt;", ">": "&gt;"})


def _text(x, lines=False):
    """User-provided text (a scene's title, description, names, a row's label) as inert
    Markdown: it reads the same, but cannot put HTML, a link or an image into report.md.
    One line unless ``lines``."""
    s = str(x)
    if not lines:
        s = re.sub(r"[\r\n]+", " ", s)
    return s.translate(_LITERAL)


def _code(x):
    """``x`` as one inline code span (nothing inside one is HTML or Markdown): a fence of
    more backticks than any run in ``x``."""
    s = re.sub(r"[\r\n]+", " ", str(x))
    fence = "`" * (max((len(r) for r in re.findall(r"`+", s)), default=0) + 1)
    pad = " " if s[:1] == "`" or s[-1:] == "`" else ""
    return f"{fence}{pad}{s}{pad}{fence}"


def _cell(x):
    return str(x).replace("|", "\\|").replace("\n", " ")


def _e(x, digits=2):
    return "—" if x is None else f"{x:.{digits}e}"


def _status(s):
    return {"agrees": "agrees", "differs": "**differs**", "not checkable": "*not checkable*",
            "not available": "**not available**"}.get(s, s)


def render(scene_list, parts, *, quick=False, command="", seconds=0.0, title=None):
    """The Markdown text of the report."""
    by_kind = {}
    for p in parts:
        by_kind.setdefault(p.output.kind, []).append(p)
    stamp = sc.version_stamp()
    n_cache = sum(p.source == "cache" for p in parts)
    L = [f"# {_text(title) if title else 'symvi reproduce: Luo & Xie (1998) cross-checked'}", ""]
    L += [f"- command: {_code(command)}" if command else "- command: (library call)",
          f"- written: {datetime.datetime.now().isoformat(timespec='seconds')}, in {seconds:.1f} s",
          f"- symvi {stamp['symvi']} (source {stamp['source']}, generated/ {stamp['generated']})",
          f"- parts: {len(parts)}, of which {n_cache} from the cache (`.cache/`, keyed by the "
          f"hash of their inputs) and {len(parts) - n_cache} computed",
          ("- **quick mode**: fewer impacts, frequencies and values of μ; every affected figure "
           "and row says so" if quick else "- full run"), ""]
    L += _summary(by_kind, parts)
    L += _conventions(by_kind)
    if "numbers" in by_kind:
        L += _numbers(by_kind["numbers"])
    if "audit" in by_kind:
        L += _audit(by_kind["audit"])
    L += ["## Scenes", ""]
    for s in scene_list:
        ps = [p for p in parts if p.scene is s]
        if all(p.output.kind in ("numbers", "audit") for p in ps):
            continue
        L += [f"### {_text(s.title)}", ""]
        if s.paper:
            L += [f"Reproduces: {_text(s.paper)}. Scene {_code(s.source)}.", ""]
        if s.description:
            L += [_text(s.description, lines=True), ""]
        for p in ps:
            L += _part(p)
    L += ["## Where each part came from", "",
          "| scene | output | kind | source | time (s) |", "|---|---|---|---|---|"]
    for p in parts:
        fig = p.result.get("_figure_source")
        src = p.source + (f", figure {fig}" if fig else "")
        L.append(f"| {p.scene.name} | {p.output.id} | {p.output.kind} | {src} | {p.seconds:.2f} |")
    L.append("")
    return "\n".join(L)


def _summary(by_kind, parts=()):
    L = ["## Summary", ""]
    for p in by_kind.get("numbers", []):
        if not p.available:
            continue
        rows = p.result["rows"]
        cnt = {}
        for r in rows:
            cnt[r["status"]] = cnt.get(r["status"], 0) + 1
        L.append(f"- Numbers table: {len(rows)} printed numbers; "
                 + ", ".join(f"{v} {k}" for k, v in sorted(cnt.items())) + ".")
    for p in by_kind.get("audit", []):
        if not p.available:
            continue
        rows = p.result["rows"]
        bad = sorted({r["eq"] for r in rows if r["status"] == "differs"})
        L.append(f"- Formula audit at {_code(p.output.params_name)} (ω_c = "
                 f"{fmt(p.result.get('omega_c'), 10)}): {len(rows)} checks, "
                 f"{sum(r['status'] == 'agrees' for r in rows)} agree; differ: "
                 + (", ".join(bad) if bad else "none") + ".")
    for p in parts:                        # each scene's result in a line
        line = _result_line(p) if p.available else "not available"
        if line:
            L.append(f"- {_text(p.output.spec.get('title') or p.output.id)} "
                     f"({_code(p.scene.name)}): {line}.")
    L.append("")
    return L


def _result_line(p):
    """What a scene part found, in one line (None for the numbers and the audit, which
    have their own lines)."""
    r, k = p.result, p.output.kind
    if k == "hopf":
        pts = r.get("points", [])
        if not pts:
            return "no Hopf point" + (" (not certified everywhere)" if r.get("uncertified")
                                      else "")
        return "; ".join(f"Hopf point at ω_c = {_num(q['omega_c'], '.10g')}, l1 = "
                         f"{_num(q['l1'], '.4g')} ({q['kind']})" for q in pts)
    if k == "curve":
        kinds = sorted({s["kind"] for s in r["special"]})
        return (f"{r['curve'].upper()} curve of {r['points']} points; codimension-two points: "
                + (", ".join(kinds) if kinds else "none"))
    if k == "codim2_evidence":
        ok = r["coexist"] if r["kind"] == "CH" else r["agrees"]
        return f"{r['kind']} normal form {'confirmed' if ok else 'NOT confirmed'} by simulation"
    if k == "circle_check":
        return (f"circle half-widths against the normal form, error slope "
                f"{r['error_slope']:.2f} (1 expected)")
    if k == "mpcheck":
        ag = r["agreement_digits"]
        return ("digits of agreement of two independent chains: "
                + ", ".join(f"{q} {ag[q]['A-B']}" for q in ag))
    if k == "nordmark":
        m = r["map"]
        return (f"grazing ({m['kind']}) at ω = {m['value']:.10g}; first new impact against "
                f"c√μ: ratio {_num(r['rows'][-1]['v1_ratio'], '.4f')} at the smallest μ")
    if k == "section":
        att = r.get("attractor")
        return f"attractor: {att['kind']}" if att else f"{r['stored']} impacts ({r['stop']})"
    if k == "bifurcation":
        return f"{r['steps']} frequencies; run stops: {_counts(r['stops'])}"
    if k == "multipliers":
        return (f"{len(r['crossings'])} crossing(s) of the unit circle on "
                f"[{r['omega'][0]}, {r['omega'][1]}]")
    return None


def _counts(d):
    """{"completed": 240} as "completed 240": never a Python dict in prose."""
    return ", ".join(f"{k} {v}" for k, v in d.items()) if isinstance(d, dict) else str(d)


def _point(d):
    """{"omega": 0.785, "r": 0.276} as "omega = 0.7852013525, r = 0.2761921527"."""
    if not isinstance(d, dict):
        return str(d)
    return ", ".join(f"{k} = {v:.10g}" if isinstance(v, float) else f"{k} = {v}"
                     for k, v in d.items())


#: how the coefficients of curves and codimension-two points are normalised (said once)
_CURVE_CONVENTIONS = ("Curves: solid where supercritical (l1 < 0) or the fold is simple, "
                      "dashed where subcritical, dotted on neutral-saddle stretches, grey "
                      "where the orbit is not admissible; ticks point to the side where the "
                      "orbit is stable. Every coefficient of a curve point and of a "
                      "codimension-two point is computed with ||q||_2 = 1, <p,q> = 1.")


def _conventions(by_kind):
    """Every normalisation the report's numbers use, said once (the parts refer here)."""
    L = ["## Conventions", ""]
    if by_kind.get("numbers") or by_kind.get("audit"):
        L.append("- ω: the forcing frequency, ω_c at a Neimark-Sacker point (the paper's "
                 "Section 4 writes v and v_c; its eq. (41) uses ω for Im λ1)")
    for p in by_kind.get("hopf", []):
        pts = p.result.get("points", []) if p.available else []
        if pts and pts[0].get("normalisation"):
            L += [f"- {k}: {v}" for k, v in pts[0]["normalisation"].items()]
            break
    if by_kind.get("curve"):
        L.append(f"- {_CURVE_CONVENTIONS}")
    kinds = {}                            # one line per normalisation, with its kinds
    for p in by_kind.get("codim2_evidence", []):
        nm = p.result.get("normalisation") if p.available else None
        if nm and p.result["kind"] not in kinds.setdefault(nm, []):
            kinds[nm].append(p.result["kind"])
    L += [f"- {', '.join(ks)} evidence: {nm}" for nm, ks in kinds.items()]
    return L + [""] if len(L) > 2 else []


def _unavailable(p):
    """The lines of a part that could not be computed: why."""
    return [f"**not available**: {_text(p.result.get('why'))}", ""]


def _section(heading, intro, parts, body, head=lambda p: []):
    """A section of the report: its heading and intro, then for each part its ``head``
    lines and its ``body`` (or why it is not available)."""
    L = [heading, "", intro, ""]
    for p in parts:
        L += head(p)
        L += body(p) if p.available else _unavailable(p)
    return L


def _numbers(parts):
    return _section("## Numbers table",
                    "Each number the paper prints beside symvi's own value. *agrees*: within "
                    "one unit of the last printed digit (or the grid step of the check), or the "
                    "same qualitative finding; *not checkable*: the paper does not give what "
                    "the number depends on.", parts, _numbers_rows)


def _numbers_rows(p):
    L = []
    if p.result.get("quick"):
        L += ["*Quick mode: simulation rows use fewer impacts and coarser grids (see each "
              "reason).*", ""]
    L += ["| # | printed claim | where | paper | symvi | status | reason and evidence |",
          "|---|---|---|---|---|---|---|"]
    for i, r in enumerate(p.result["rows"], start=1):
        L.append(f"| {i} | {_cell(_text(r['label']))} | {_cell(_text(r['where']))} | "
                 f"{_cell(_text(r['printed']))} "
                 f"| {_cell(fmt(r['symvi']) if r['symvi'] is not None else '—')} | "
                 f"{_status(r['status'])} | {_cell(r['reason'])} |")
    L.append("")
    return L


def _audit(parts):
    L = _section("## Formula audit",
                 "Each printed formula evaluated exactly as printed, beside an independent route "
                 "to the same quantity (column *symvi*; the route is in the details). abs/rel: "
                 "2-norm of the difference, and relative to symvi's value.", parts, _audit_rows,
                 head=lambda p: [f"### At {_code(p.output.params_name)}: " + ", ".join(
                     f"{k} = {v:g}" for k, v in p.scene.params_for(p.output).as_dict().items()),
                     ""])
    L += ["### Typos and conventions (no number to compare)", ""]
    for n in NOTES:
        L.append(f"- eq. {n['eq']} — {n['status']}: {n['text']}")
    L.append("")
    return L


def _audit_rows(p):
    r0 = p.result
    L = [f"Orbit formulas at ω = {fmt(r0['omega_orbit'], 10)}; normal form at the Hopf "
         f"point ω_c = {fmt(r0['omega_c'], 12)} (branch {r0['branch']}).", "",
         "| eq. | quantity | as printed | symvi | abs | rel | status |",
         "|---|---|---|---|---|---|---|"]
    for r in r0["rows"]:
        L.append(f"| {r['eq']} | {_cell(r['what'])} | {_cell(r['printed'])} | "
                 f"{_cell(r['symvi'])} | {_e(r['abs'])} | {_e(r['rel'])} | "
                 f"{_status(r['status'])} |")
    L += ["", "Details:", ""]
    for r in r0["rows"]:
        line = f"- **{r['eq']} {r['what']}** — {r['status']}. Matters: {r['matters'] or '—'}. " \
               f"Evidence: {r['evidence']}."
        L.append(line)
        if r.get("corrected"):
            L.append(f"  Corrected: $${r['corrected']}$$")
    L.append("")
    return L


def _part(p):
    L = [f"#### {_text(p.output.spec.get('title') or p.output.id)} "
         f"({'from the cache' if p.source == 'cache' else f'computed in {p.seconds:.2f} s'})", ""]
    r = p.result
    if not p.available:
        return L + _unavailable(p)
    k = p.output.kind
    if r.get("quick_note"):
        L += [f"*{r['quick_note']}*", ""]
    if k == "hopf":
        L += _hopf_table(r)
    elif k == "multipliers":
        cr = "; ".join(f"{c['type']} between ω = {c['between'][0]:.6f} and {c['between'][1]:.6f}"
                       for c in r["crossings"]) or "none"
        L += [f"{r['steps']} frequencies on [{r['omega'][0]}, {r['omega'][1]}], admissible orbit at "
              f"{r['admissible']}; |λ| = 1 crossings: {cr}.", ""]
    elif k == "section":
        att = r.get("attractor")
        desc = (f"{r['stored']} impacts after a transient of {r['transient']} "
                f"(stop: {r['stop']}) from y0 = {fmt(r['y0'])}")
        if att:
            lya = att.get("lyapunov")
            desc += (f"; attractor: **{att['kind']}**"
                     + (f", Lyapunov exponents {fmt(lya)} per impact" if lya else "")
                     + (f", rotation number {att['rotation']:.4f}" if att.get("rotation") else ""))
        L += [desc + ".", ""]
    elif k == "bifurcation":
        L += [f"{r['steps']} frequencies, {r['impacts']} points each after {r['transient']}; run "
              f"stops: {_counts(r['stops'])}.", ""]
        if r.get("special") is not None:
            L += ["Continued branches (stable solid, unstable dashed, inadmissible dotted) and "
                  "their special points, located by `symvi continue`:", "",
                  "| orbit | kind | omega | coefficients | admissible |", "|---|---|---|---|---|"]
            L += [f"| {s['orbit']} | {s['kind']} | {s['value']:.12g} | "
                  + ", ".join(f"{k} = {v:.6g}" for k, v in s["coefficients"].items()
                              if k in ("l1", "c", "a", "theta"))
                  + f" | {'yes' if s['admissible'] else 'no'} |" for s in r["special"]]
            L += [""]
    elif k == "circle_check":
        L += _circle_table(r)
    elif k == "mpcheck":
        L += _mpcheck_table(r)
    elif k == "curve":
        L += _curve_table(r)
    elif k == "codim2_evidence":
        L += _evidence_text(r)
    elif k == "nordmark":
        L += _nordmark_text(r)
    if r.get("_figure"):
        L += [f"![{p.output.id}]({r['_figure']})", ""]
    if r.get("warnings"):
        L += ["Warnings: " + _text("; ".join(r["warnings"])), ""]
    return L


def _curve_table(r):
    a, b = r["names"]
    L = [f"{r['curve'].upper()} curve in ({a}, {b}) from the {r['curve']} point at ω = "
         f"{r['start']['omega']:.12g} ({r['start']['orbit']} orbit), {r['points']} points; "
         f"it ends: (1) {r['ends'][0]}; (2) {r['ends'][-1]}.", ""]
    L += [f"Note: {n}" for n in r.get("notes", [])]
    if not r["special"]:
        return L + ["No codimension-two point on the curve.", ""]
    L += ["Line styles and normalisations: see [Conventions](#conventions).", "",
          f"| kind | {a} | {b} | coefficients | admissible | what |", "|---|---|---|---|---|---|"]
    keep = ("l2", "l1", "c1", "c2", "re", "im", "a", "b", "s", "C", "D", "c", "coef", "theta")
    for s in r["special"]:
        co = ", ".join(f"{k} = {_short(v)}" for k, v in s["coefficients"].items() if k in keep)
        L.append(f"| {s['kind']} | {s['params'][a]:.12g} | {s['params'][b]:.12g} | {co or '—'} | "
                 f"{'yes' if s['admissible'] else 'no'} | {_cell(s['detail'])} |")
    return L + [""]


def _evidence_text(r):
    where = ", ".join(f"{k} = {v:.9g}" for k, v in r["params"].items())
    if r["kind"] == "CH":
        w = r["wedge"]
        L = [f"Next to the Chenciner point ({_point(r['ch_point'])}; l2 = "
             f"{r['l2_at_ch']:.4g}), at {where}: "
             f"l1 = {r['l1']:.4g}, l2 = {r['l2']:.4g}, d mu = |λ| − 1 = {r['dmu']:.4g} (the "
             f"bistable wedge is {w['condition']}: d mu > {w['dmu_min']:.4g}); predicted "
             f"circles ρ₋ = {w['rho_inner']:.4g} (repelling), ρ₊ = {w['rho_outer']:.4g} "
             f"(attracting; normalisation: see [Conventions](#conventions)).", "",
             f"**{'Coexistence observed' if r['coexist'] else 'Coexistence not shown'}.** "
             + r["verdict"] + ".", ""]
        return L
    return [f"Next to the {r['kind']} point ({_point(r['r_point'])}), at {where} (d mu = "
            f"{r['dmu']:.3g}): "
            f"**{'the normal form is confirmed' if r['agrees'] else 'the normal form is NOT confirmed'}**"
            f" — {r['verdict']}. Checked: {r['checked']}; not checked: {r['not_checked']} "
            "(normalisation: see [Conventions](#conventions)).", ""]


def _short(v):
    if isinstance(v, list) and len(v) == 2:
        return f"{v[0]:.6g}{v[1]:+.6g}i"
    if isinstance(v, float):
        return f"{v:.6g}"
    return str(v)


def _uncertified(r):
    """The spans the scan could not certify, in words (none: [])."""
    spans = r.get("uncertified") or []
    if not spans:
        return []
    from ..analysis.hopf import spans_text
    why = "; ".join(r.get("uncertified_reasons") or [])
    return ["**Not certified** (a crossing there may have been missed): "
            + spans_text(spans)
            + (f" ({_text(why)})" if why else "") + ".", ""]


def _hopf_table(r):
    pts = r.get("points", [])
    head = [_text(r["conservative"]) + ".", ""] if r.get("conservative") else []
    if not pts:
        if r.get("uncertified"):
            return head + ["No Hopf point found where the scan is certified.", ""] + _uncertified(r)
        return head + ["No Hopf point in the interval.", ""]
    L = head + ["| ω_c | branch | λ1 | θ/2π | d\\|λ1\\|/dω (A1–A3) | along branch | l1 | f1 (60) as printed "
         "| f1 (60) corrected | kind | H1 | H2 | H3 |", "|" + "---|" * 13]
    for q in pts:
        L.append(f"| {_num(q['omega_c'], '.12f')} | {q['branch']} | "
                 f"{fmt(complex(*q['multiplier']))} | "
                 f"{q['theta_over_2pi']:.6f} | {_num(q['dmod_domega'], '.8g')} | "
                 f"{_num(q['dmod_domega_branch'], '.8g')} | {_num(q['l1'], '.6g')} | {_na(q['f1_paper'])} | "
                 f"{_na(q['f1_wan'])} | {q['kind']} | {q['h1']} | {q['h2']} | {q.get('h3')} |")
    L += ["", "Normalisations: see [Conventions](#conventions).", ""]
    for q in pts:       # what a number in the table does not mean as stated
        for key in ("dmod_domega_branch_caveat", "circle_caveat"):
            if q.get(key):
                L += [f"Caution at ω_c = {_num(q['omega_c'], '.10g')}: {_text(q[key])}.", ""]
    L += _uncertified(r)
    if r.get("events"):
        L += ["Events: " + "; ".join(f"{e.get('kind')} at ω = {e.get('omega'):.10g} "
                                     f"({e.get('detail', '')})" for e in r["events"]), ""]
    return L


def _mpcheck_table(r):
    a, b = r["chain_a"], r["chain_b"]
    L = [f"Chain A: symvi's own chain on the mpmath backend at {a['digits']} digits. Chain B: "
         "Newton on the numeric map P and Richardson finite differences at higher precision, "
         "fed into an independent Kuznetsov formula (shares no derivation code with A).", "",
         "| quantity | chain A | chain B | digits A–B | digits float64–A |", "|---|---|---|---|---|"]
    for q in ("omega_c", "dmod_domega", "l1"):
        ag = r["agreement_digits"][q]
        L.append(f"| {q} | {a[q]} | {b[q]} | {ag['A-B']} | {ag['float-A']} |")
    return L + [""]


def _na(x, spec=".6g"):
    # eq. (60) belongs to the paper's model: "—" for any other model
    return "—" if x is None else format(x, spec)


def _num(x, spec):
    # automatic precision reports an untrustworthy quantity as None: never print a number
    return "UNTRUSTED" if x is None else format(x, spec)


def _nordmark_text(r):
    """Nordmark's map at a grazing point and its check by simulation
    (:mod:`symvi.studies.nordmark_check`)."""
    m = r["map"]
    names = m["names"]
    vec = lambda v: "(" + ", ".join(f"{x:.6g}" for x in v) + ")"      # noqa: E731
    mult = ", ".join(f"{complex(a, b):.4g}".strip("()") for a, b in m["multipliers"])
    past = {1.0: "increasing", -1.0: "decreasing"}.get(m["past_direction"], "—")
    how = "a touch inside a flight" if m["kind"] == "flight" else "an impact of zero velocity"
    L = [f"Grazing ({how}) of stop {m['stop']} at {m['param']} = {m['value']:.12g}, phase "
         f"{m['phase']:.6f}; acceleration at the tangency a = h'' = {m['acceleration']:.6g}, "
         f"r = {m['restitution']:g}.", "",
         "Normalisation: " + _text(m["normalisation"]) + ".", "",
         "| quantity | value |", "|---|---|",
         f"| section coordinates ξ | {', '.join(names)} |",
         "| smooth part N (rows) | " + "; ".join(vec(row) for row in m["N"]) + " |",
         f"| multipliers of N | {mult} |",
         f"| E0 (discontinuity map on Π) | {vec(m['E0'])} |",
         f"| E = N E0 (√h term of P_N) | {vec(m['E'])} |",
         f"| m = dP/d{m['param']} | {vec(m['m']) if m['m'] else '—'} |",
         f"| δ' (depth per unit {m['param']}) | {_num(m['delta_rate'], '.6g')}; past grazing: "
         f"{m['param']} {past} |",
         f"| c_first (v1 = c_first √μ) | {_num(m['c_first'], '.6g')} |",
         f"| c_attractor (1-D bound) | {_na(m['c_attractor'])} |", "",
         f"Predicted scenario past grazing: {_text(m['scenario'])}.", "",
         f"Simulation past grazing (the run starts on the smooth orbit where it leaves the "
         f"stop; v1 is its first new impact):", "",
         f"| μ | {m['param']} | δ | v1 predicted | v1 measured | ratio | attractor | "
         "new-impact max / bound |", "|---|---|---|---|---|---|---|---|"]
    for row in r["rows"]:
        L.append(f"| {row['mu']:.3e} | {row['value']:.10g} | {row['delta']:.2e} | "
                 f"{row['v1_predicted']:.6g} | {_num(row['v1_measured'], '.6g')} | "
                 f"{_num(row['v1_ratio'], '.5f')} | {_text(row['attractor'])} | "
                 f"{_na(row['v_new_ratio'], '.4f')} |")
    L += ["", "The ratio tends to 1 with an error O(√δ): v1 = √(2|a|δ)(1 + O(√δ)). "
          "The attractor's bound applies only inside the 1-D reduction (a real, dominant "
          "0 < λ1 < 1).", ""]
    return L


def _circle_table(r):
    names = r.get("variables", ["x1dot+", "x2", "x2dot", "tau"])
    L = [f"ω_c = {r['omega_c']:.12f}; d|λ1|/dω = {r['dmod_domega']:.6g}, l1 = {r['l1']:.6g} "
         f"(‖q‖₂ = 1); predicted half-width = k·√μ.", "",
         "| μ | " + " | ".join(f"{n} sim | {n} nf | rel. err" for n in names) + " |",
         "|---|" + "---|---|---|" * len(names)]
    for i, mu in enumerate(r["mu"]):
        L.append(f"| {mu:.2e} | " + " | ".join(
            f"{r['measured'][i][k]:.5g} | {r['predicted'][i][k]:.5g} | {r['rel_error'][i][k]:+.2e}"
            for k in range(len(names))) + " |")
    L += ["", f"Log-log slope of max |rel. error| against μ: {r['error_slope']:.2f} (1 expected for "
              "the O(μ) error of a leading-order prediction). Coefficients k: predicted "
          f"{fmt(r['predicted_coefficients'])}, measured (extrapolated to μ → 0) "
          f"{fmt(r['measured_coefficients'])}."]
    if r.get("lost"):
        L.append("Lost (the run stopped before the circle was measured; left out above): "
                 + "; ".join(f"μ = {x['mu']:.2e} ({_text(x['why'])})" for x in r["lost"]) + ".")
    if r.get("printed_eq60_factor"):
        L.append(f"With eq. (60) as printed (f1 = {r['f1_paper']:.6g} instead of "
                 f"{r['f1_wan']:.6g}) every predicted half-width would be "
                 f"{r['printed_eq60_factor']:.3g}× the values in the *nf* columns.")
    L.append("")
    return L
