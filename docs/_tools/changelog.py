"""Write CHANGELOG.md from ``git log``, grouped by issue (run from the repository root):

    python docs/_tools/changelog.py > CHANGELOG.md

A commit belongs to the issue its message names ("issue 24", "Issue 13"), else to the issue
of the branch merged with it (a merge of ``i24-engine`` or ``i25a-model`` names issue 24 or
25 in its branch), else it is listed under its day with the issues open that day.
"""
import re
import subprocess
import sys
from collections import defaultdict

TITLES = {
    2: "Model, period-1 impacting orbit and the exact Poincaré map",
    3: "SymPy derivation of the map's derivatives, code-generated into generated/",
    4: "Neimark–Sacker (Hopf) analysis and the normal form",
    5: "Fast impact simulation, Poincaré sections, diagnostics, figures 4–12",
    6: "symvi reproduce: the paper's results cross-checked, one report built from scenes",
    7: "Benchmarks, stability under stress, automatic precision",
    11: "Any linear impact oscillator: N masses, damping, the stop on any mass",
    12: "n-p orbits continued in any parameter, with every bifurcation on the way",
    13: "Two-parameter curves and codimension-two points",
    14: "Parameter planes on Dask",
    23: "Reliability: defects found by an outside test, the scan's certificate, README examples",
    24: "Core: one hybrid core, the paper on top, one engine per job",
    25: "Contacts: several stops, two-sided stops, impacts between masses, elastic stops",
    26: "Docs: a documentation site and a command line with one set of conventions",
    27: "Grazing: grazing, chatter and sticking, what happens where an impact has zero velocity",
}


def git(*args):
    return subprocess.run(["git", *args], check=True, capture_output=True, text=True).stdout


def named_issue(text):
    m = re.search(r"\bissue\s+#?(\d+)", text, re.I)
    return int(m.group(1)) if m else None


#: branches merged without an issue number in their name
BRANCHES = {"classify-stops": 25, "docs-site": 26}


def branch_issue(subject):
    m = re.search(r"Merge (?:branch )?'?i(\d+)[a-z]*-", subject)
    if m:
        return int(m.group(1))
    m = re.match(r"Merge (?:branch )?'?([\w-]+)", subject)
    return BRANCHES.get(m.group(1)) if m else None


def main():
    log = git("log", "--format=%H%x09%ad%x09%s", "--date=short")
    commits = [line.split("\t", 2) for line in log.splitlines()]
    issue_of = {h: named_issue(s) for h, _, s in commits}
    # commits brought in by a merge of an issue's branch belong to that issue
    for h, _, s in commits:
        b = branch_issue(s)
        if b is None:
            continue
        for c in git("rev-list", f"{h}^1..{h}^2").split():
            if issue_of.get(c) is None:
                issue_of[c] = b
    by_issue, by_day, days = defaultdict(list), defaultdict(list), defaultdict(set)
    for h, day, s in commits:
        if s.lower().startswith("merge"):
            continue
        k = issue_of.get(h)
        if k is not None:
            by_issue[k].append((day, h[:7], s))
            days[day].add(k)
        else:
            by_day[day].append((h[:7], s))
    out = ["# Changelog", "",
           "symvi 0.1.0 (unreleased). Written from `git log` by `docs/_tools/changelog.py`, "
           "grouped by the issue each commit names (or whose branch it was merged from); "
           "the rest by day. Newest first.", ""]
    for k in sorted(by_issue, reverse=True):
        out += [f"## Issue {k}: {TITLES.get(k, '')}".rstrip(": "), ""]
        out += [f"- {s} ({h}, {d})" for d, h, s in by_issue[k]]
        out.append("")
    out += ["## Other commits, by day", ""]
    for day in sorted(by_day, reverse=True):
        named = ", ".join(str(k) for k in sorted(days[day])) or "none named"
        out += [f"### {day} (issues named that day: {named})", ""]
        out += [f"- {s} ({h})" for h, s in by_day[day]]
        out.append("")
    sys.stdout.write("\n".join(out))


if __name__ == "__main__":
    main()
