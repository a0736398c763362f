"""Scene files: strict validation, lazy imports, cache (issue 6)."""
import json
import subprocess
import sys
import textwrap

import pytest

from symvi.errors import ParameterError, SymviError
from symvi.reporting.scenes import SceneError, load_scene, paper_scenes, parse_scene, run_scene

GOOD = """
[scene]
name = "mult"
title = "multipliers only"

[params]
mu_m = 2.0
mu_k = 5.0
f2 = 0.0
b = 1.5
r = 0.8

[[output]]
kind = "multipliers"
omega_min = 0.7219
omega_max = 0.7396
steps = 20
"""


def test_paper_scenes_parse():
    names = [s.name for s in paper_scenes()]
    assert names[:2] == ["example1", "example2"]
    assert {f"fig{k}" for k in range(4, 13)} <= set(names)
    assert {"numbers", "formula_audit", "circle_check"} <= set(names)


@pytest.mark.parametrize("edit, key", [
    (("steps = 20", "stepz = 20"), "output[1].stepz"),                      # unknown key
    (("[scene]", "[scene]\ncolour = 'red'"), "scene.colour"),               # unknown key
    (("omega_max = 0.7396", "omega_max = 0.70"), "output[1].omega_max"),     # bad range
    (("omega_min = 0.7219", "omega_min = -1.0"), "output[1].omega_min"),     # out of range
    (("r = 0.8", "r = 1.5"), "params.r"),                                   # parameter out of range
    (("mu_m = 2.0", "mu_m = -2.0"), "params.mu_m"),
    (("steps = 20", "steps = 1"), "output[1].steps"),
    (("steps = 20", "steps = 'many'"), "output[1].steps"),
    (("kind = \"multipliers\"", "kind = \"multiplier\""), "output[1].kind"),
    (("omega_min = 0.7219\n", ""), "output[1].omega_min"),                 # missing key
])
def test_bad_scene_names_the_key(edit, key, tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text(GOOD.replace(*edit))
    with pytest.raises((SceneError, ParameterError)) as exc:
        load_scene(f)
    assert isinstance(exc.value, SymviError)
    assert key in str(exc.value) and "bad.toml" in str(exc.value)


def test_bad_scene_cli_one_line_nothing_lost(tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text(GOOD.replace("r = 0.8", "r = 1.5"))
    out = tmp_path / "out"
    out.mkdir()
    (out / "report.md").write_text("keep me")
    p = subprocess.run([sys.executable, "-m", "symvi", "run", str(f), "--out", str(out)],
                       capture_output=True, text=True)
    assert p.returncode == 2
    assert p.stderr.count("\n") == 1 and "params.r" in p.stderr
    assert (out / "report.md").read_text() == "keep me"


def test_not_toml():
    with pytest.raises(SceneError, match="not valid TOML"):
        parse_scene("[scene\nname=", "x.toml")


def test_multipliers_scene_imports_no_order2_or_3(tmp_path):
    """A multiplier-only scene loads no generated module above order 1 (its multipliers come
    from the compiled monodromy, eq. (30)), and no normal form."""
    f = tmp_path / "mult.toml"
    f.write_text(GOOD)
    code = textwrap.dedent(f"""
        import json, sys
        from symvi.reporting.scenes import load_scene, run_scene
        parts = run_scene(load_scene({str(f)!r}), {str(tmp_path / 'c')!r})
        assert parts[0].result["admissible"] == 20
        print(json.dumps(sorted(m for m in sys.modules if m.startswith("symvi"))))
    """)
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    mods = set(json.loads(p.stdout.strip().splitlines()[-1]))
    gen = {m for m in mods if m.startswith("symvi._generated.")}
    assert not {m for m in gen if not m.endswith("order1")}, gen
    assert not {"symvi.normal_forms.normal_form", "symvi.analysis.hopf",
                "symvi.simulations.simulation"} & mods


@pytest.mark.slow
def test_section_scene_computes_no_normal_form(tmp_path):
    f = tmp_path / "sec.toml"
    f.write_text(GOOD.replace('kind = "multipliers"\nomega_min = 0.7219\nomega_max = 0.7396\n'
                              'steps = 20', 'kind = "section"\nomega = 0.744\nimpacts = 300\n'
                              'transient = 1000'))
    code = textwrap.dedent(f"""
        import json, sys
        from symvi.reporting.scenes import load_scene, run_scene
        parts = run_scene(load_scene({str(f)!r}), {str(tmp_path / 'c')!r})
        assert parts[0].result["stored"] == 300
        print(json.dumps(sorted(m for m in sys.modules if m.startswith("symvi"))))
    """)
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    mods = set(json.loads(p.stdout.strip().splitlines()[-1]))
    assert not {"symvi.normal_forms.normal_form", "symvi.analysis.hopf", "symvi._generated.order2",
                "symvi._generated.order3"} & mods


def test_cache_hit_on_second_run(tmp_path):
    s = parse_scene(GOOD, "mult.toml")
    first = run_scene(s, tmp_path)
    second = run_scene(s, tmp_path)
    assert [p.source for p in first] == ["computed"]
    assert [p.source for p in second] == ["cache"]
    assert first[0].result["crossings"] == second[0].result["crossings"]
    assert (second[0].arrays["multipliers"] == first[0].arrays["multipliers"]).all()
    # a changed input is a different key: computed again
    s2 = parse_scene(GOOD.replace("steps = 20", "steps = 21"), "mult.toml")
    assert run_scene(s2, tmp_path)[0].source == "computed"
    # presentation keys do not change the result's key
    s3 = parse_scene(GOOD.replace("steps = 20", "steps = 20\ntitle = 'x'"), "mult.toml")
    assert run_scene(s3, tmp_path)[0].source == "cache"


def test_cache_keys_hash_every_module_an_output_imports():
    """Issue 11: precision.py, the compiled flow and the paper's reduction (issue 24) enter
    the keys of the Hopf scene."""
    from symvi.reporting import scenes as sc
    hopf = sc.module_closure(sc.ENTRY["hopf"])
    for m in ("analysis.precision", "analysis.hopf", "flow.linear", "flow.compiled",
              "codegen.jets", "normal_forms.normal_form", "paper.reduction"):
        assert m in hopf, m
    sec = sc.module_closure(sc.ENTRY["section"])
    assert "flow.compiled" in sec and "flow.linear" in sec
    assert "simulations.diagnostics" in sec
    assert "paper.audit" not in hopf        # only what is imported


def test_no_import_cycles_between_symvi_modules():
    """Issue 11: orbit <-> jets and audit <-> scenes are broken; none may come back.
    (The package's own __init__, which re-exports, is left out of the graph.)"""
    import os

    import symvi
    from symvi.reporting import scenes as sc
    pkg = os.path.dirname(symvi.__file__)
    mods = []
    for root, _, files in os.walk(pkg):
        for f in files:
            if f.endswith(".py"):
                rel = os.path.relpath(os.path.join(root, f), pkg)[:-3].replace(os.sep, ".")
                rel = rel[:-len(".__init__")] if rel.endswith(".__init__") else rel
                if rel != "__init__":
                    mods.append(rel)
    graph = {m: [t for t in sc.module_imports(m) if t and not m.startswith(t + ".")]
             for m in mods}
    state, stack = {}, []

    def visit(m):
        state[m] = 1
        stack.append(m)
        for t in graph.get(m, ()):
            if state.get(t) == 1:
                raise AssertionError("import cycle: " + " -> ".join(stack[stack.index(t):] + [t]))
            if t not in state:
                visit(t)
        stack.pop()
        state[m] = 2
    for m in mods:
        if m not in state:
            visit(m)
