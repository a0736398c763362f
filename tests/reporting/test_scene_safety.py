"""Scene files as untrusted input (issue 23, items 13 and 14): what a model path may name,
what user text may put into report.md, a corrupt or forged cache, a scene without
[params] for ``symvi run --model``, and circle_check on a model."""
import hashlib
import json
import os
import re

import numpy as np
import pytest

from symvi.errors import OutputError, SingularCaseError, SymviError
from symvi.model import dumps
from symvi.reporting import report
from symvi.reporting.scenes import parse_scene, run_scene

from ..fuzz._cli import assert_bad_input, cli, snapshot
from tests.zoo import THREE_STOP2_GAP05

HEAD = """[scene]
name = "safe"
title = "safe"
"""
PAPER = """
[params]
mu_m = 2
mu_k = 5
f2 = 0
b = 1.5
r = 0.8
"""
OUT = """
[[output]]
kind = "multipliers"
omega_min = 0.72
omega_max = 0.74
steps = 3
"""
#: an output with no figure (a report without matplotlib's cost)
HOPF = """
[[output]]
kind = "hopf"
omega_min = 0.736
omega_max = 0.738
"""


def _model_scene(folder, value):
    f = folder / "s.toml"
    f.write_text(HEAD + f"\n[params]\nmodel = {json.dumps(value)}\n" + OUT)
    return f


# --------------------------------------------------------------------------- model paths
def _specials(tmp_path):
    (tmp_path / "dir.toml").mkdir()
    os.mkfifo(tmp_path / "fifo.toml")
    (tmp_path / "passwd").write_text("root:x:0:0:root:/root:/bin/bash\n")
    os.symlink(tmp_path / "passwd", tmp_path / "link.toml")
    return {"/etc/passwd": "not a .toml file", "passwd": "not a .toml file",
            "dir.toml": "folder", "fifo.toml": "not a regular file",
            "link.toml": "symlink", "missing.toml": "no such file", "": "not a file name"}


def test_model_path_must_be_a_regular_toml_file(tmp_path):
    """Nothing but a regular .toml file is opened as a model (a FIFO would block, a device
    or /etc/passwd would be read): one line naming the scene file and the key."""
    for value, why in _specials(tmp_path).items():
        f = _model_scene(tmp_path, value)
        with pytest.raises(SymviError) as exc:
            parse_scene(f.read_text(), str(f))
        msg = str(exc.value)
        assert "\n" not in msg and "s.toml: params.model" in msg and why in msg, msg


def test_bad_model_path_through_the_cli_writes_nothing(tmp_path):
    _specials(tmp_path)
    out = tmp_path / "out"
    out.mkdir()
    (out / "keep.txt").write_text("precious")
    before = snapshot(out)
    for value in ("/etc/passwd", "fifo.toml", "dir.toml"):
        f = _model_scene(tmp_path, value)
        assert_bad_input(cli("run", f, "--out", out), "params.model", ".toml")
    assert snapshot(out) == before


def test_relative_model_path_is_read_from_the_scene_folder(tmp_path):
    sub = tmp_path / "study"
    sub.mkdir()
    (sub / "m.toml").write_text(dumps(THREE_STOP2_GAP05))
    f = _model_scene(sub, "m.toml")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    old = os.getcwd()
    try:
        os.chdir(elsewhere)
        scene = parse_scene(f.read_text(), str(f))
    finally:
        os.chdir(old)
    assert scene.params_for(scene.outputs[0]) == THREE_STOP2_GAP05
    # a model file that is not a valid model: the key and the model's own reason, one line
    (sub / "m.toml").write_text("[model]\nmass = [1.0]\n")
    with pytest.raises(SymviError, match=r"s\.toml: params\.model: .*m\.toml") as exc:
        parse_scene(f.read_text(), str(f))
    assert "\n" not in str(exc.value)


# --------------------------------------------------------------------------- report.md
HOSTILE = {
    "title": 'x <script>alert(1)</script> & [a](http://e.x) ![i](http://e.x/p.png)',
    "description": "<img src=x onerror=alert(1)>\n[r]: javascript:alert(1)\n\\[b](http://e.x)",
    "paper": "<b>bold</b> `code`",
}


def test_user_text_cannot_put_html_links_or_images_into_the_report(tmp_path):
    text = (HEAD.replace('title = "safe"', "\n".join(f"{k} = {json.dumps(v)}"
                                                     for k, v in HOSTILE.items()))
            + "\n[params.'<i>set</i>`x']\nmu_m = 2\nmu_k = 5\nf2 = 0\nb = 1.5\nr = 0.8\n"
            + OUT + 'title = "<iframe src=http://e.x>"\n')
    scene = parse_scene(text, "s.toml")
    parts = run_scene(scene, tmp_path / "c")
    md = report.render([scene], parts, command="symvi run s`<b>`.toml", title=scene.title)
    assert "- command: ``symvi run s`<b>`.toml``\n" in md          # a code span, fenced
    prose = md.replace("``symvi run s`<b>`.toml``", "")
    assert not re.search(r"<\s*[a-z/!?]", prose, re.I), md       # no raw HTML at all
    assert "](" not in md.replace("\\](", "") and "]:" not in md.replace("\\]:", "")
    assert "&lt;script&gt;alert(1)&lt;/script&gt; &amp; \\[a\\](http://e.x)" in md
    # text that escapes nothing reads as written
    assert report._text("Fig. 4: multipliers, v = 0.7369") == "Fig. 4: multipliers, v = 0.7369"


def test_escaped_text_round_trips():
    """Each escape is undone by a Markdown reader: the reader sees exactly the user's text."""
    import html
    s = "a\\[b](c) <d> & `e` \\\\ ]:"
    t = report._text(s)
    unescaped = html.unescape(re.sub(r"\\(.)", r"\1", t))
    assert unescaped == s


# --------------------------------------------------------------------------- cache
def _entry(folder):
    [f] = [p for p in folder.iterdir() if p.suffix == ".json" and not p.name.endswith("figs.json")]
    return f


@pytest.mark.parametrize("damage", ["truncate", "garbage", "list", "edited", "npz", "deep"])
def test_corrupt_cache_entry_is_computed_again(tmp_path, damage):
    scene = parse_scene(HEAD + PAPER + OUT, "s.toml")
    cache = tmp_path / "c"
    first = run_scene(scene, cache)[0]
    f = _entry(cache)
    raw = f.read_text()
    if damage == "truncate":
        f.write_text(raw[:len(raw) // 2])
    elif damage == "garbage":
        f.write_bytes(os.urandom(200))
    elif damage == "list":
        f.write_text("[1, 2]")
    elif damage == "edited":          # a number changed, the recorded hash not
        d = json.loads(raw)
        d["result"]["admissible"] = 99
        f.write_text(json.dumps(d))
    elif damage == "npz":
        f.with_suffix(".npz").write_bytes(b"PK\x03\x04 not a zip")
    elif damage == "deep":
        f.write_text("[" * 100000 + "]" * 100000)
    again = run_scene(scene, cache)[0]
    assert again.source == "computed" and again.result["admissible"] == first.result["admissible"]
    assert np.array_equal(again.arrays["multipliers"], first.arrays["multipliers"])
    assert run_scene(scene, cache)[0].source == "cache"           # and stored again


def test_cache_entry_replaced_by_a_fifo(tmp_path):
    """Never opened (it would block), never replaced (a special file): one line."""
    scene = parse_scene(HEAD + PAPER + HOPF, "s.toml")
    out = tmp_path / "out"
    report.build_report([scene], out)
    f = _entry(out / ".cache")
    f.unlink()
    os.mkfifo(f)
    with pytest.raises(OutputError, match="FIFO") as exc:
        report.build_report([scene], out)
    assert "\n" not in str(exc.value)


def test_cache_folder_replaced_by_a_fifo_is_refused_before_computing(tmp_path):
    from symvi.errors import ParameterError
    out = tmp_path / "out"
    out.mkdir()
    os.mkfifo(out / ".cache")
    scene = parse_scene(HEAD + PAPER + HOPF, "s.toml")
    with pytest.raises(ParameterError, match=r"--out = .*\.cache.*FIFO"):
        report.build_report([scene], out)
    assert sorted(os.listdir(out)) == [".cache"]


def test_forged_cache_entry_is_recomputed_by_the_report(tmp_path):
    """A cached result with the right hash but the wrong content cannot be shown: the
    report computes that part again instead of failing."""
    scene = parse_scene(HEAD + PAPER + HOPF, "s.toml")
    out = tmp_path / "out"
    report.build_report([scene], out)
    f = _entry(out / ".cache")
    d = json.loads(f.read_text())
    d["result"] = {"points": [{"omega_c": "x"}], "_arrays": False}
    d["sha256"] = hashlib.sha256(
        json.dumps(d["result"], sort_keys=True).encode()).hexdigest()
    f.write_text(json.dumps(d))
    rep = report.build_report([scene], out)
    assert [p.source for p in rep.parts] == ["computed"]
    assert "0.7368" in (out / "report.md").read_text()


# --------------------------------------------------------------------------- run --model
def test_run_model_needs_no_params(tmp_path):
    """``symvi run SCENE --model FILE`` takes a scene without [params] (or with an empty
    one); without --model such a scene is refused before anything is written."""
    (tmp_path / "m.toml").write_text(dumps(THREE_STOP2_GAP05))
    for i, params in enumerate(("", "\n[params]\n")):
        out = tmp_path / f"out{i}"
        f = tmp_path / "s.toml"
        f.write_text(HEAD + params + HOPF.replace("0.736", "0.9995").replace("0.738", "1.0"))
        assert_bad_input(cli("run", f, "--out", out), "params", "--model")
        assert not out.exists()
        rc, stdout, err = cli("run", f, "--out", out, "--model", tmp_path / "m.toml")
        assert rc == 0, err
        assert "wrote" in stdout and (out / "report.md").exists()


# --------------------------------------------------------------------------- circle_check
class _Circle:
    stable, side = True, -1

    @staticmethod
    def half_widths(mu):
        return 2.0 * np.sqrt(abs(mu)) * np.ones(6)


class _Point:
    omega_c, circle, normal_form = 1.0, _Circle(), None


def test_circle_check_lists_lost_mu_and_needs_two(monkeypatch):
    """A mu whose run stops (chatter, grazing) is left out with its reason; fewer than two
    measured values cannot give the error's slope: circle-lost, never a partial verdict."""
    from symvi.studies import circle_check as cc

    def fake(params, omega, **kw):
        mu = omega - 1.0
        if abs(mu) > 5e-5:
            raise SingularCaseError("circle-lost", f"run stopped (chatter) at omega = {omega}")
        hw = 2.0 * np.sqrt(abs(mu)) * (1 + abs(mu)) * np.ones(6)
        return cc.Measurement(omega, hw, hw * 0, 1000, True, (0.0,) * 6)
    monkeypatch.setattr(cc, "measure", fake)
    monkeypatch.setattr(cc, "names_of", lambda params: tuple("abcdef"))
    c, lost = cc._check(None, _Point(), [-1e-4, -4e-5, -2e-5, -1e-5], True)
    assert [x["mu"] for x in lost] == [-1e-4] and "chatter" in lost[0]["why"]
    assert list(c.mu) == [-4e-5, -2e-5, -1e-5]
    assert c.error_slope == pytest.approx(1.0, abs=1e-3)       # mu < 0: slope of |mu|
    with pytest.raises(SingularCaseError, match="circle-lost: 3 of 4"):
        cc._check(None, _Point(), [-1e-4, -4e-4, -2e-4, -1e-5], True)
    with pytest.raises(SingularCaseError, match="chatter"):   # check() still raises
        cc.check(None, _Point(), [-1e-4, -1e-5])


@pytest.mark.slow
def test_circle_check_scene_on_a_model(tmp_path):
    """The chain's second NS point has its circle below omega_c (mu < 0); mu = -1e-4 is
    lost (the run chatters), the others agree with the normal form to O(mu)."""
    (tmp_path / "m.toml").write_text(dumps(THREE_STOP2_GAP05))
    f = tmp_path / "s.toml"
    f.write_text(HEAD + '\n[params]\nmodel = "m.toml"\n\n[[output]]\nkind = "circle_check"\n'
                 "omega_min = 1.03\nomega_max = 1.06\nmu = [1e-4, 2e-5, 1e-5]\n")
    scene = parse_scene(f.read_text(), str(f))
    [p] = run_scene(scene, tmp_path / "c")
    r = p.result
    assert p.available and r["variables"][0] == "v2+"
    assert [x["mu"] for x in r["lost"]] == [-1e-4]
    assert r["mu"] == [-2e-5, -1e-5] and all(r["converged"])
    assert np.abs(r["rel_error"]).max() < 0.03
    md = "\n".join(report._part(p))
    assert "Lost" in md and "-1.00e-04" in md
    # every value lost: said in the report, not an error of the scene
    scene = parse_scene(f.read_text().replace("[1e-4, 2e-5, 1e-5]", "[4e-4, 2e-4]"), str(f))
    [p] = run_scene(scene, tmp_path / "c")
    assert not p.available and "circle-lost" in p.result["why"]


def test_circle_check_mu_validated():
    for bad in ("[1e-4]", "[0.0, 1e-4]", "[1.0, 1e-4]"):
        with pytest.raises(SymviError, match="output\\[1\\].mu"):
            parse_scene(HEAD + PAPER + '\n[[output]]\nkind = "circle_check"\nomega_min = 0.7\n'
                        f"omega_max = 0.76\nmu = {bad}\n", "s.toml")
