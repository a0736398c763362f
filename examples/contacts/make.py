"""Regenerate the worked examples' diagrams and JSON (run from anywhere):

    python examples/contacts/make.py

Each example is one ``symvi continue`` command; its JSON records the command (without
``--plot``) so that tests/cli/test_cli_itinerary.py can check that it is current."""
import json
import pathlib
import subprocess
import sys

HERE = pathlib.Path(__file__).resolve().parent

EXAMPLES = {
    "oscillator_two_stops": ["--range", "omega=1.0:2.5", "--switch"],
    "oscillator_elastic": ["--range", "omega=0.5:4.0", "--start-omega", "2.0", "--switch"],
    "chain3_two_stops": ["--range", "omega=1.0:2.0", "--start-omega", "1.5", "--switch"],
    "impact_damper": ["--range", "omega=0.8:1.2", "--start-omega", "1.0", "--switch"],
}


def main():
    for name, rest in EXAMPLES.items():
        args = ["continue", "--model", f"examples/contacts/{name}.toml", *rest, "--json"]
        out = subprocess.run([sys.executable, "-m", "symvi", *args, "--plot",
                              f"examples/contacts/{name}.png"], cwd=HERE.parents[1],
                             check=True, capture_output=True, text=True).stdout
        d = {"command": args, **json.loads(out)}
        d.pop("plot", None)
        (HERE / f"{name}.json").write_text(json.dumps(d, indent=1) + "\n")
        print(name, len(d["branches"]), "branches,", len(d["special"]), "special points")


if __name__ == "__main__":
    main()
