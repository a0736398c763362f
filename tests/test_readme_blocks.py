"""Every code block of README.md runs as printed (issue 23), in order, in one temporary folder.

* ```toml blocks are written to the file their first comment names (``# chain3.toml: ...``);
* ```python blocks run in order, one namespace per ``##`` section (so each section pastes on
  its own, given the files written above it);
* shell blocks: each ``symvi ...`` line runs in this process through ``symvi.cli.main``, its
  optional parts (``[--flag ...]``) dropped, once (a line repeated later is not run again);
  ``symvi plane`` without ``--workers``/``--scheduler`` runs with ``--workers 0``, the
  in-process engine (the local Dask cluster gives the identical store: tests/plane).  The
  lines of :data:`SKIP` are not run; any other line fails the test.

Beyond "runs": the numbers the README quotes next to a block are checked against its output.
"""
import contextlib
import io
import math
import re
import shlex
from pathlib import Path

import numpy as np
import pytest

from .fuzz._cli import cli

README = Path(__file__).resolve().parents[1] / "README.md"

#: shell lines not run (after their optional parts are dropped), with the reason
SKIP = {
    'pip install -e . && symvi reproduce --out report': "installs; the full report takes minutes "
                                                        "(tests/reporting runs reproduce --quick)",
    'pip install -e ".[test]" && python -m pytest -q': "installs; runs this very suite",
    'symvi reproduce --out DIR': "the full report takes minutes (tests/reporting: --quick)",
    'symvi regenerate': "writes symvi's own generated/ (tests/codegen runs it into a "
                        "temporary folder)",
}


def blocks(text):
    """[(section, lang, first line number, body)] of every fenced block, in order."""
    out, section, lines, i = [], "", text.splitlines(), 0
    while i < len(lines):
        ln = lines[i]
        if ln.startswith("## "):
            section = ln[3:].strip()
        m = re.match(r"^```(\w*)\s*$", ln)
        if m:
            j = i + 1
            while not lines[j].startswith("```"):
                j += 1
            out.append((section, m.group(1), i + 1, "\n".join(lines[i + 1:j]) + "\n"))
            i = j
        i += 1
    return out


def _drop_optional(cmd):
    """``cmd`` without its optional parts: ``[--flag ...]`` groups (brackets nest)."""
    out, i = [], 0
    while i < len(cmd):
        if cmd[i] == "[" and (i == 0 or cmd[i - 1] == " ") and cmd[i + 1:i + 2] == "-":
            depth = 0
            for j in range(i, len(cmd)):
                depth += {"[": 1, "]": -1}.get(cmd[j], 0)
                if depth == 0:
                    break
            i = j + 1
            continue
        out.append(cmd[i])
        i += 1
    return re.sub(r"\s+", " ", "".join(out)).strip()


def shell_lines(body):
    """The commands of a shell block: continuation lines joined, comments dropped."""
    cmds, cur = [], ""
    for ln in body.splitlines():
        cur += ln.rstrip()
        if cur.endswith("\\"):
            cur = cur[:-1] + " "
            continue
        cmd = re.split(r"\s+#\s", cur, maxsplit=1)[0].strip()
        cur = ""
        if cmd and not cmd.startswith("#"):
            cmds.append(cmd)
    return cmds


def toml_name(body):
    m = re.match(r"#\s*([\w.-]+\.toml)\s*:", body)
    assert m, f"a toml block must name its file in its first comment: {body[:60]!r}"
    return m.group(1)


def commands(body):
    """(line as printed, line as run) of a shell block."""
    return [(c, _drop_optional(c)) for c in shell_lines(body)]


def test_readme_blocks_are_runnable_as_written():
    """Quick form check: every block is python, toml (naming its file) or shell; every shell
    line is a symvi command or skipped with a reason; the two commands stay as they are."""
    text = README.read_text(encoding="utf-8")
    assert "pip install -e \".[test]\" && python -m pytest -q\n" in text
    assert "pip install -e . && symvi reproduce --out report\n" in text
    seen_skip = set()
    for section, lang, line, body in blocks(text):
        assert lang in ("", "python", "toml"), (line, lang)
        if lang == "toml":
            toml_name(body)
        elif lang == "":
            for printed, run in commands(body):
                if run in SKIP:
                    seen_skip.add(run)
                    continue
                assert run.startswith("symvi "), f"README.md:{line}: not a symvi command: {printed}"
                assert not re.search(r"\.\.\.|\b(FILE|DIR|SCENE|W|N)\b", run), \
                    f"README.md:{line}: a placeholder left in {run!r}"
    assert seen_skip == set(SKIP), set(SKIP) - seen_skip       # no stale allow-list entry


def _run_python(body, ns, where):
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(body, where, "exec"), ns)
    return out.getvalue()


@pytest.mark.slow
def test_readme_blocks_run(tmp_path, monkeypatch):
    """Run every block in order (see the module docstring); then check what they printed
    and computed against the numbers the README states."""
    monkeypatch.chdir(tmp_path)
    text = README.read_text(encoding="utf-8")
    ran, spaces, section = {}, {}, None
    for section, lang, line, body in blocks(text):
        where = f"README.md:{line}"
        if lang == "toml":
            (tmp_path / toml_name(body)).write_text(body, encoding="utf-8")
        elif lang == "python":
            ns = spaces.setdefault(section, {"__name__": "__readme__"})
            _run_python(body, ns, where)
        else:
            for printed, run in commands(body):
                if run in SKIP or run in ran:
                    continue
                argv = shlex.split(run)[1:]
                if argv[0] == "plane" and not {"--workers", "--scheduler"} & set(argv):
                    argv += ["--workers", "0"]
                rc, out, err = cli(*argv, cwd=tmp_path)
                assert rc == 0, f"{where}: {printed}\n{err}"
                assert "Traceback" not in err, err
                # the README teaches the current flags: no deprecation notice (simulate's and
                # sweep's JSON-without---json notice is for scripts: this is not a terminal)
                assert "deprecated" not in err, f"{where}: {err}"
                ran[run] = out

    def out_of(prefix):
        [out] = [o for c, o in ran.items() if c.startswith(prefix)]
        return out

    # Using it from Python: the paper's v_c, and the compiled jet = symvi.jet
    py = spaces["Using it from Python"]
    assert py["res"].points[0].omega_c == pytest.approx(0.736877, abs=1e-6)
    assert np.abs(np.array(py["J"]) - np.array(py["j"].jacobian)).max() < 1e-12
    # Your own model: the chain's names, shapes, named parameters and its two NS points
    m = spaces["Your own model: N masses, damping, the stop on any mass"]
    o, j, d = m["o"], m["j"], m["d"]
    assert o.names == ("v2+", "x1", "x3", "v1", "v3", "tau") and o.admissible
    assert j.d3.shape == (6, 6, 6, 6) and d.dJ_branch.shape == (6, 6)
    assert m["m2"].value("forcing[1]") == 0.3
    # nonlinear forces: the Duffing oscillator's period-1 orbit and its branch's points
    assert m["run"].stop == "completed" and m["duffing"].value("beta") == 0.2
    assert m["orbit"].impact_velocities[0] == pytest.approx(0.6040666637, abs=1e-9)
    assert abs(m["orbit"].multipliers[0]) == pytest.approx(0.753099, abs=1e-6)
    got = sorted((s.value, s.kind) for s in m["branch"].special)
    assert [k for _, k in got] == ["fold", "flip", "fold"]
    assert [w for w, _ in got] == pytest.approx([2.50033192, 2.74735426, 2.89981144], abs=1e-8)
    c = {k: s.coefficients for s in m["branch"].special for k in [s.kind]}
    assert c["flip"]["c"] == pytest.approx(6.9546, abs=1e-4)
    assert "completed" in out_of("symvi simulate --model duffing.toml")
    assert "2.747354261" in out_of("symvi continue --model duffing.toml --range omega=2.2:3.2")
    orbits = out_of("symvi orbit --model duffing.toml --omega 2.6")
    assert "3 period-1 one-impact orbit(s)" in orbits and orbits.count("  stable;") == 2
    assert "flip curve in (omega, beta)" in out_of("symvi curve --model duffing.toml")
    hopf = out_of("symvi hopf --model chain3.toml --range omega=0.99:1.06")
    assert "0.99971142" in hopf and "1.0459583" in hopf
    # the study: a report from a scene file, then every part from the cache
    md = (tmp_path / "chain3-report" / "report.md").read_text(encoding="utf-8")
    assert "0.999711422" in md and "invariant circle" in md and "chain3-circle_check.png" in md
    assert "4 from the cache" in out_of("symvi run chain3-study.toml --out chain3-report --model")
    # branches: one.toml's flips, the doubled branch, the simulated 2-2 orbit
    br = spaces["Branches: n-p orbits continued in any parameter"]
    assert br["flip"].kind == "flip" and (br["doubled"].n, br["doubled"].p) == (2, 2)
    assert (br["orb"].n, br["orb"].p) == (2, 2) and br["orb"].residual < 1e-9
    assert sum(br["orb"].times) == pytest.approx(2 * 2 * math.pi / 2.69, rel=1e-12)
    # curves: the two Chenciner points of example 1 in (omega, r), a flip curve
    cu = spaces["Two-parameter curves and codimension-two points"]
    assert len(cu["ch"]) == 2 and len(cu["curve2"]) > 10
    # grazing: the resonant grazing points at 2 omega_d / m, kappa of the curves leaving one
    gz = spaces["Grazing: where an impact has zero velocity"]
    assert gz["g"].value == pytest.approx(abs(1 - 1.5 ** 2 + 0.15j), rel=1e-12)
    wd = math.sqrt(1 - 0.1 ** 2 / 4)
    assert [s.params["omega"] for s in gz["rg"]] == pytest.approx([2 * wd / 3, wd, 2 * wd],
                                                                   abs=1e-9)
    assert gz["kappas"]["kappa_fold"] == pytest.approx(-101.85, abs=0.01)
    assert gz["kappas"]["kappa_flip"] == pytest.approx(7.32, abs=0.01)
    # orbits with a sticking phase: the release phase's closed form, the branch's end
    assert str(gz["orb"].signature) == "1-0+stick"
    assert gz["orb"].tau_release == pytest.approx(math.pi - math.asin(0.2), abs=1e-12)
    assert round(gz["orb"].tau_release, 7) == 2.9402347
    end = re.search(r"held phase vanishes near omega = ([0-9.]+)", gz["stick"].end)
    assert float(end.group(1)) == pytest.approx(0.56424, abs=5e-6)
    # planes: the stored grid, labelled
    pl = spaces["Parameter planes on Dask"]
    assert dict(pl["ds"].attractor.sizes) in ({"b": 12, "omega": 16}, {"omega": 16, "b": 12})
