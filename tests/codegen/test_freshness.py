"""generated/ is fresh, deterministic and machine-written (compare hashes, never CSE text)."""
import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import symvi._generated as gen
from symvi._derivations import poincare_jets as pj

GEN = Path(gen.__file__).parent


@pytest.mark.slow
def test_regenerating_into_tmp_gives_identical_files(tmp_path):
    wrote, man = pj.generate(tmp_path, force=True)
    assert wrote
    committed = json.loads((GEN / "manifest.json").read_text())
    assert man["input_hash"] == committed["input_hash"]
    for f in committed["files"]:
        assert pj.file_hash(tmp_path / f) == pj.file_hash(GEN / f), f


def test_committed_generated_is_fresh():
    assert pj.check(GEN) == []


def test_header_says_do_not_edit():
    for k in (1, 2, 3):
        first = (GEN / f"order{k}.py").read_text().splitlines()[0]
        assert "derivations/poincare_jets.py" in first and "DO NOT EDIT" in first
    man = json.loads((GEN / "manifest.json").read_text())
    assert man["sympy"] and man["input_hash"]


def test_check_detects_hand_edit_and_skip_when_unchanged(tmp_path):
    out = tmp_path / "g"
    shutil.copytree(GEN, out)
    run = lambda *a: subprocess.run([sys.executable, "-m", "symvi", "regenerate", "--out",
                                     str(out), *a], capture_output=True, text=True)
    assert run("--check").returncode == 0
    r = run()
    assert r.returncode == 0 and "nothing written" in r.stdout
    p = out / "order2.py"
    p.write_text(p.read_text() + "\n# edited\n")
    r = run("--check")
    assert r.returncode == 1 and "order2.py" in r.stderr


def test_impact_structures_fresh_and_regenerate_identically(tmp_path):
    """generated/impact_n<N>_order<K>.py: fresh, and N = 1 regenerates bit for bit."""
    from symvi._derivations import impact_jets as ij
    assert ij.check(GEN) == []
    written, man = ij.generate(tmp_path, ns=(1,), force=True)
    committed = json.loads((GEN / ij.MANIFEST).read_text())
    for f in written:
        assert ij.file_hash(tmp_path / f) == committed["files"][f], f
    first = (GEN / "impact_n3_order2.py").read_text().splitlines()[0]
    assert "derivations/impact_jets.py" in first and "DO NOT EDIT" in first
