"""The README's worked example (a damped 3-mass chain from a model file) runs as printed."""
import os
import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def test_readme_model_example_runs(tmp_path):
    text = README.read_text(encoding="utf-8")
    sec = text[text.index("## Your own model"):]
    toml = re.search(r"```toml\n(.*?)```", sec, re.S).group(1)
    code = re.search(r"```python\n(.*?)```", sec, re.S).group(1)
    (tmp_path / "chain3.toml").write_text(toml)
    cwd = os.getcwd()
    try:
        os.chdir(tmp_path)
        ns = {}
        exec(compile(code, "README.md", "exec"), ns)
    finally:
        os.chdir(cwd)
    o, j, d = ns["o"], ns["j"], ns["d"]
    assert o.names == ("v2+", "x1", "x3", "v1", "v3", "tau") and o.admissible
    assert j.d3.shape == (6, 6, 6, 6) and d.dJ_branch.shape == (6, 6)
    assert ns["m2"].value("forcing[1]") == 0.3
