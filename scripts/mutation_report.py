"""Score and surviving mutants of the last `mutmut run` (make mutation; docs/mutation.md).

Reads mutmut's per-file results (mutants/**/*.py.meta) and the equivalent mutants listed in
docs/mutation.md (table rows starting with | `mutant name` |). Score = killed / (all - equivalent),
where killed includes timeouts (the mutant hangs the tests: detected) and every mutant that no
selected test reaches counts as not killed. Prints the survivors that are not listed as
equivalent, with their diffs; exits 1 if there are any.

Usage: python scripts/mutation_report.py [--no-diff]
"""
from __future__ import annotations

import json
import re
import subprocess
import sys
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


def main() -> int:
    metas = sorted((ROOT / "mutants").rglob("*.py.meta"))
    if not metas:
        print("no mutmut results under mutants/: run `make mutation` first")
        return 2
    status: dict[str, str] = {}
    for meta in metas:
        for key, code in json.loads(meta.read_text())["exit_code_by_key"].items():
            status[key] = STATUS.get(code, "suspicious")
    equivalent = equivalent_names(ROOT / "docs" / "mutation.md")
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
