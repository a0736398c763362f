"""``symvi reproduce --quick`` end to end (issue 6)."""
import os
import subprocess
import sys

import pytest

PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def quick_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("report")
    p = subprocess.run([sys.executable, "-m", "symvi", "reproduce", "--out", str(out), "--quick"],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    return out, p


@pytest.mark.slow
def test_quick_report_lists_every_row_and_valid_pngs(quick_report):
    import matplotlib.image as mpimg

    from symvi.reporting.scenes import paper_scenes
    out, _ = quick_report
    text = (out / "report.md").read_text(encoding="utf-8")
    scenes = {s.name: s for s in paper_scenes()}
    from symvi.reporting.report import _cell, _text
    for row in scenes["numbers"].outputs[0].spec["row"]:
        assert "| " + _cell(_text(row["label"])) + " |" in text
    for eq in ("(11)", "(12)", "(16)", "(21)–(24)", "(37)", "(38)", "(46)", "(54)", "(60)",
               "(A2)", "(A3)", "(A4)", "(A10)", "(A13)", "(A16)", "(A17)"):
        assert eq in text, eq
    assert "eq. (3)" in text and "eq. (6)" in text
    # the high-precision validation: two independent chains agree far beyond float64
    import re
    rows = re.findall(r"^\| (omega_c|dmod_domega|l1) \| \S+ \| \S+ \| ([\d.]+) \| ([\d.]+) \|$",
                      text, flags=re.M)
    assert len(rows) == 6, rows
    assert all(float(ab) >= 25 and float(fa) >= 11 for _, ab, fa in rows), rows
    assert "not available" not in text
    assert "quick mode" in text
    # issue 26, item 5: each normalisation said once, in Conventions; every scene's result
    # in the summary; no Python dict in prose
    head, _, rest = text.partition("## Conventions")
    conv, _, body = rest.partition("\n## ")
    assert "||q||_2 = 1" in conv and "||q||_2 = 1" not in body
    summary = head.partition("## Summary")[2]
    assert "Hopf point at ω_c" in summary and "attractor:" in summary
    assert "{'" not in text and "{\"" not in text
    # one symbol per quantity: the forcing frequency is ω (omega in ASCII), never v
    assert "- ω: the forcing frequency" in conv
    assert not re.search(r"\bv_c\b|\bv = \d|/dv\b|\bv in \[", body), \
        re.findall(r".{30}(?:\bv_c\b|\bv = \d|/dv\b|\bv in \[).{30}", body)[:5]
    pngs = sorted(f for f in os.listdir(out) if f.endswith(".png"))
    assert len(pngs) >= 14
    for f in pngs:
        assert f"]({f})" in text
        data = (out / f).read_bytes()
        assert data[:8] == PNG
        img = mpimg.imread(out / f)
        assert img.ndim == 3 and img.shape[0] > 100
        assert (out / (f[:-4] + ".pdf")).read_bytes()[:5] == b"%PDF-"


@pytest.mark.slow
def test_quick_rerun_comes_from_cache(quick_report):
    out, _ = quick_report
    p = subprocess.run([sys.executable, "-m", "symvi", "reproduce", "--out", str(out), "--quick"],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert "0 computed" in (out / "report.md").read_text() or "from the cache" in p.stdout
    n = int(p.stdout.split("parts, ")[1].split(" from")[0])
    total = int(p.stdout.split("; ")[1].split(" parts")[0])
    assert n == total
