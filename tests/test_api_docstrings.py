"""The docstrings of the API pages (issue 26): numpy-style sections, and examples that run.

The names are read from the pages themselves (``docs/api/symvi.rst``,
``docs/api/continuation.rst``: each ``auto*`` directive and its ``:members:``), so a name
added to a page is held to the same rules.  Each ``>>>`` example of those docstrings
runs as a doctest (only those: the other docstrings of the package are not doctests).
"""
import dataclasses
import doctest
import importlib
import inspect
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "docs" / "api" / "symvi.rst", ROOT / "docs" / "api" / "continuation.rst"]
#: an autodoc directive: the name (an explicit signature after it is skipped), its options
_DIRECTIVE = re.compile(r"^\.\. auto(?:function|class|exception):: ([\w.]+).*\n((?:   :\w+:.*\n)*)",
                        re.MULTILINE)
#: result classes, built by the library: an ``Attributes`` section, not ``Parameters``
RESULTS = {"symvi.Orbit", "symvi.Jet", "symvi.continuation.Result",
           "symvi.continuation.Branch", "symvi.continuation.BranchPoint",
           "symvi.continuation.SpecialPoint"}
#: documented names without an example, and why (every other one has one)
NO_EXAMPLE = {
    "symvi.NearSingularWarning": "a warning class: nothing to call",
    "symvi.continuation.switch_at_branch_point": "needs a located pitchfork: a long run",
    "symvi.continuation.ns_scan": "runs and continues attractors: a long run",
    "symvi.continuation.BranchPoint": "shown in Branch's example",
    "symvi.continuation.SpecialPoint": "shown in Branch's example",
}
_SECTION = re.compile(r"^([A-Z][a-z]+)\n-+\n", re.MULTILINE)


def _resolve(name):
    """The object called ``name`` (``symvi.continuation.Branch``), through its module."""
    parts = name.split(".")
    for k in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:k]))
        except ModuleNotFoundError:
            continue
        for attr in parts[k:]:
            obj = getattr(obj, attr)
        return obj
    raise LookupError(name)


def documented():
    """[(name, object)] of every name the API pages document, members included."""
    out = []
    for page in PAGES:
        for name, options in _DIRECTIVE.findall(page.read_text(encoding="utf-8")):
            obj = _resolve(name)
            out.append((name, obj))
            members = re.search(r":members: (.*)", options)
            for member in members.group(1).split(",") if members else ():
                out.append((f"{name}.{member.strip()}", getattr(obj, member.strip())))
    return out


DOCUMENTED = documented()
NAMES = [name for name, _ in DOCUMENTED]


def sections(doc):
    """{section title: its text} of a numpy-style docstring (the summary under ``""``)."""
    doc = inspect.cleandoc(doc or "")
    heads = list(_SECTION.finditer(doc))
    out = {"": doc[:heads[0].start()] if heads else doc}
    for h, nxt in zip(heads, heads[1:] + [None]):
        out[h.group(1)] = doc[h.end():nxt.start() if nxt else len(doc)]
    return out


def entries(text):
    """The names a Parameters or Attributes section lists (``a, b : type`` gives both)."""
    names = []
    for line in text.splitlines():
        if line and not line[0].isspace():
            names += [n.strip().lstrip("*") for n in line.split(" : ")[0].split(",")]
    return names


def parameters(name, obj):
    """The names of the arguments a user passes to ``obj`` (none for a class whose
    ``__init__`` is not symvi's own, e.g. an exception that takes Exception's)."""
    if inspect.isclass(obj):
        own = any("__init__" in vars(k) for k in inspect.getmro(obj)
                  if k.__module__.startswith("symvi"))
        if not own:
            return []
    sig = inspect.signature(obj)
    return [p.name for p in sig.parameters.values()
            if not p.name.startswith("_") and p.name not in ("self", "cls")]


def test_the_pages_name_the_public_api():
    """The reader of the pages finds every directive (a change of their layout must not
    leave this module testing nothing)."""
    for name in ("symvi.Model", "symvi.Model.luo_xie", "symvi.Model.with_", "symvi.Stop",
                 "symvi.load_model", "symvi.period1_orbits", "symvi.Orbit", "symvi.jet",
                 "symvi.Jet", "symvi.hopf_points", "symvi.simulate", "symvi.Params.as_model",
                 "symvi.modal", "symvi.SingularCaseError",
                 "symvi.continuation.continue_orbits", "symvi.continuation.ns_scan",
                 "symvi.continuation.Branch.curve", "symvi.continuation.SpecialPoint"):
        assert name in NAMES, name
    assert len(NAMES) == len(set(NAMES)) >= 35
    assert set(RESULTS) | set(NO_EXAMPLE) <= set(NAMES)


@pytest.mark.parametrize("name", NAMES)
def test_docstring_has_the_numpy_sections(name):
    """A one-line summary; every argument of a callable in its ``Parameters`` (and nothing
    else there); a result class lists its fields under ``Attributes``."""
    obj = dict(DOCUMENTED)[name]
    doc = inspect.getdoc(obj)
    assert doc, f"{name} has no docstring"
    sec = sections(doc)
    summary = sec[""].strip().split("\n\n")[0]
    assert "\n" not in summary, f"{name}: the summary is not one line: {summary!r}"
    if name in RESULTS:
        assert "Attributes" in sec, f"{name}: no Attributes section"
        listed = set(entries(sec["Attributes"]))
        fields = {f.name for f in dataclasses.fields(obj)} if dataclasses.is_dataclass(obj) \
            else set()
        assert fields <= listed, f"{name}: fields not under Attributes: {fields - listed}"
        return
    args = parameters(name, obj)
    if not args:
        assert "Parameters" not in sec, f"{name} takes no arguments"
        return
    assert "Parameters" in sec, f"{name} takes {args} but has no Parameters section"
    listed = entries(sec["Parameters"])
    assert set(args) <= set(listed), f"{name}: not documented: {set(args) - set(listed)}"
    assert set(listed) <= set(args), f"{name}: not arguments: {set(listed) - set(args)}"


@pytest.mark.parametrize("name", NAMES)
def test_examples_run(name):
    """The ``>>>`` lines of the docstring give what it says they give."""
    obj = dict(DOCUMENTED)[name]
    doc = inspect.getdoc(obj) or ""
    test = doctest.DocTestParser().get_doctest(doc, {}, name, None, 0)
    if not test.examples:
        assert name in NO_EXAMPLE, f"{name}: no example (or say why in NO_EXAMPLE)"
        return
    assert "Examples" in sections(doc), f"{name}: examples outside an Examples section"
    report = []
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    runner.run(test, out=report.append)
    assert runner.failures == 0, "".join(report)


def test_a_wrong_example_fails():
    """The runner above reports a wrong output (it is not a test that always passes)."""
    test = doctest.DocTestParser().get_doctest(">>> 1 + 1\n3\n", {}, "wrong", None, 0)
    runner = doctest.DocTestRunner()
    runner.run(test, out=lambda s: None)
    assert runner.failures == 1
    assert entries("a, b : int\n    meaning\n**fixed : float\n") == ["a", "b", "fixed"]
