"""N > 4: the structure is generated on first use into the per-user cache (same hash,
header and atomic write), or by ``symvi regenerate --model FILE``."""
import json
import subprocess
import sys

from symvi.model import dumps
from tests.zoo import FIVE_CHAIN_STOP3


def test_five_masses_generated_on_first_use(tmp_path):
    f = tmp_path / "m5.toml"
    f.write_text(dumps(FIVE_CHAIN_STOP3))
    env = {"XDG_CACHE_HOME": str(tmp_path / "cache"), "PATH": ""}
    # det DP = r^2 exp(-tr(M^-1 C) T) at the period-1 solution: the generated code works
    # (period1_orbits itself no longer needs it: the multipliers from the generated jets)
    code = ("import math, symvi, numpy as np; from symvi.orbits import period1_orbits;"
            "from symvi.codegen.jets import multipliers_at;"
            f"m = symvi.load_model({str(f)!r}); o = period1_orbits(m, 1.0)[0];"
            "lam = multipliers_at(m, 1.0, o.y, 2 * math.pi);"
            "d = np.prod(lam).real; e = 0.64 * math.exp(-0.1 * 2 * math.pi);"
            "print(len(lam), abs(d / e - 1) < 1e-9)")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["10", "True"] and "generating" in r.stderr
    gen = tmp_path / "cache" / "symvi" / "generated"
    man = json.loads((gen / "impact_manifest.json").read_text())
    assert "impact_n5_order1.py" in man["files"]
    assert "DO NOT EDIT" in (gen / "impact_n5_order1.py").read_text().splitlines()[0]
    # second use: loaded, not generated again
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert r.returncode == 0 and "generating" not in r.stderr
    # symvi regenerate --model: fresh, nothing written
    r = subprocess.run([sys.executable, "-m", "symvi", "regenerate", "--model", str(f),
                        "--order", "1", "--check"], capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stderr
