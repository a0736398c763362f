"""Parameters as objects (issue 24, item 2): below the command line, no code asks whether a
parameter's name is the string "omega"; it asks the parameter object
(``par.is_forcing_frequency``), parsed once at the entry (:mod:`symvi.model.parameters`)."""
import re
from pathlib import Path

import symvi

ROOT = Path(symvi.__file__).parent
#: ``name == "omega"`` / ``name != "omega"`` (either side)
COMPARE = re.compile(r"""(==|!=)\s*["']omega["']|["']omega["']\s*(==|!=)""")
#: where such a comparison stays, and why
ALLOWED = {
    # the one parser of names: "omega" becomes the Omega parameter there
    "model/parameters.py",
    # presentation: the axis label of what the user typed (the string itself, not a parameter)
    "reporting/figures.py",
}


def test_no_omega_string_comparisons_below_the_cli():
    found = []
    for path in sorted(ROOT.rglob("*.py")):
        rel = path.relative_to(ROOT).as_posix()
        if rel.startswith("cli/") or rel in ALLOWED:
            continue
        for k, line in enumerate(path.read_text().splitlines(), 1):
            if COMPARE.search(line.split("#")[0]):
                found.append(f"{rel}:{k}: {line.strip()}")
    assert found == [], "compare the parameter object, not the name:\n" + "\n".join(found)


def test_the_pattern_finds_a_comparison():
    """The check can fail: it sees both spellings and both sides."""
    for line in ('if name == "omega":', "x = a if 'omega' != p else b", 'w if nm!="omega"'):
        assert COMPARE.search(line)
    assert not COMPARE.search('fixed.pop("omega", None)')
