"""Score and surviving mutants of the last `mutmut run` (make mutation; docs/mutation.md).

Reads mutmut's per-file results (mutants/**/*.py.meta) and the equivalent mutants listed in
docs/mutation.md (table rows starting with | `mutant name` |). Score = killed / (all - equivalent),
where killed includes timeouts (the mutant hangs the tests: detected) and every mutant that no
selected test reaches counts as not killed. Prints the survivors that are not listed as
equivalent, with their diffs; exits 1 if there are any.

With ``--modules`` it prints instead a Markdown table per module (mutants, killed, equivalent,
no test, survived, score), the table docs/mutation.md keeps; ``--only PREFIX`` keeps the modules whose
dotted name starts with PREFIX (a group of the Makefile's MUTATE, e.g. ``en17037cli.criteria.daylight``).

With ``--changed`` it prints instead mutmut's name patterns (``'en17037cli.module.*'``, shell-quoted)
of the modules of the selection (pyproject's ``only_mutate``) whose file differs from the commit of
docs/mutation.md's table (its line ``Table commit: `<sha>` ``), working tree included: what
``make mutation CHANGED=1`` re-runs.

Usage: python scripts/mutation_report.py [--no-diff] [--modules] [--only PREFIX ...] [--changed]
"""
from __future__ import annotations

import json
import re
import subprocess
import sys
import tomllib
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
STATUS = {1: "killed", 3: "killed", 0: "survived", 5: "no tests", 33: "no tests", 34: "skipped", 36: "timeout",
          -24: "timeout", 24: "timeout", 152: "timeout", 255: "timeout", None: "not checked"}


def equivalent_names(doc: Path) -> dict[str, str]:
    """Mutant name -> reason, from the rows of docs/mutation.md's equivalent-mutant tables."""
    out = {}
    for line in doc.read_text(encoding="utf-8").splitlines():
        m = re.match(r"^\|\s*`([^`]+__mutmut_\d+)`\s*\|(.*)\|\s*$", line)
        if m:
            out[m.group(1)] = m.group(2).split("|")[-1].strip()
    return out


def module_of(key: str) -> str:
    """The dotted module of a mutant name (``pkg.mod.x_fn__mutmut_3``, ``pkg.mod.xǁClassǁmethod__mutmut_3``)."""
    return key.rsplit("__mutmut_", 1)[0].rsplit(".", 1)[0]


def module_table(status: dict[str, str], equivalent: dict[str, str]) -> list[str]:
    """Markdown rows: per module, mutants, killed (timeouts included), equivalent listed, no test,
    survived (not listed), not checked, and the score killed / (mutants - equivalent - not checked)."""
    rows = ["| module | mutants | killed | equivalent | no test | survived | not checked | score |",
            "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
    by_module: dict[str, Counter] = {}
    for key, s in status.items():
        c = by_module.setdefault(module_of(key), Counter())
        c["mutants"] += 1
        if key in equivalent:
            c["equivalent"] += 1
        elif s in ("killed", "timeout"):
            c["killed"] += 1
        elif s == "no tests":
            c["no test"] += 1
        elif s == "not checked":
            c["not checked"] += 1
        else:
            c["survived"] += 1
    total: Counter = Counter()
    for mod in sorted(by_module):
        c = by_module[mod]
        total.update(c)
        rows.append(_row(f"`{mod}`", c))
    rows.append(_row("**all**", total))
    return rows


def _row(name: str, c: Counter) -> str:
    den = c["mutants"] - c["equivalent"] - c["not checked"]
    score = f"{100.0 * c['killed'] / den:.1f} %" if den else "-"
    return (f"| {name} | {c['mutants']} | {c['killed']} | {c['equivalent']} | {c['no test']} | {c['survived']} | "
            f"{c['not checked']} | {score} |")


def table_commit(doc: Path) -> str:
    """The commit docs/mutation.md's table was measured on (its line ``Table commit: `<sha>` ``)."""
    m = re.search(r"^Table commit: `([0-9a-f]{7,40})`", doc.read_text(encoding="utf-8"), re.M)
    if not m:
        raise SystemExit(f"{doc}: no line 'Table commit: `<sha>`': say which commit the table was measured on")
    return m.group(1)


def changed_patterns(root: Path) -> list[str]:
    """mutmut name patterns of the selected modules whose file changed since the table's commit."""
    files = tomllib.loads((root / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["mutmut"]["only_mutate"]
    commit = table_commit(root / "docs" / "mutation.md")
    out = subprocess.run(["git", "diff", "--name-only", commit, "--", *files], cwd=root,
                         capture_output=True, text=True, check=True).stdout.split()
    return [f"'{f[:-3].replace('/', '.')}.*'" for f in files if f in out]


def main() -> int:
    if "--changed" in sys.argv:
        print(" ".join(changed_patterns(ROOT)))
        return 0
    metas = sorted((ROOT / "mutants").rglob("*.py.meta"))
    if not metas:
        print("no mutmut results under mutants/: run `make mutation` first")
        return 2
    status: dict[str, str] = {}
    for meta in metas:
        for key, code in json.loads(meta.read_text())["exit_code_by_key"].items():
            status[key] = STATUS.get(code, "suspicious")
    equivalent = equivalent_names(ROOT / "docs" / "mutation.md")
    if "--only" in sys.argv:
        prefixes = tuple(a for a in sys.argv[sys.argv.index("--only") + 1:] if not a.startswith("--"))
        status = {k: s for k, s in status.items() if module_of(k).startswith(prefixes)}
    if "--modules" in sys.argv:
        print("\n".join(module_table(status, equivalent)))
        return 0
    counts = Counter(status.values())
    listed = {k for k in equivalent if k in status}
    killed = sum(1 for k, s in status.items() if s in ("killed", "timeout") and k not in listed)
    unchecked = sum(1 for s in status.values() if s == "not checked")  # an interrupted run
    denominator = len(status) - len(listed) - unchecked
    print(f"mutants: {len(status)}  " + "  ".join(f"{k}: {v}" for k, v in sorted(counts.items())))
    print(f"equivalent (docs/mutation.md): {len(listed)}"
          + (f"  (listed but killed: {sorted(k for k in listed if status[k] != 'survived')})"
             if any(status[k] != "survived" for k in listed) else ""))
    print(f"score: {killed} killed / {denominator} non-equivalent checked = {100.0 * killed / max(denominator, 1):.1f} %"
          + (f"  ({unchecked} not checked: the run was interrupted)" if unchecked else ""))
    open_ = sorted(k for k, s in status.items() if s not in ("killed", "timeout", "not checked") and k not in listed)
    print(f"surviving, not listed as equivalent: {len(open_)}")
    for key in open_:
        print(f"  {key}: {status[key]}")
        if "--no-diff" not in sys.argv:
            diff = subprocess.run([str(Path(sys.executable).parent / "mutmut"), "show", key], cwd=ROOT,
                                  capture_output=True, text=True).stdout
            for line in diff.splitlines():
                if line.startswith(("-", "+")) and not line.startswith(("---", "+++")):
                    print(f"      {line}")
    return 1 if open_ else 0


if __name__ == "__main__":
    sys.exit(main())
