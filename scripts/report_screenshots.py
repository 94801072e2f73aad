"""Screenshots of the seed office's report.html on a phone (390 x 844 CSS px) and a desktop
(1280 x 900), the first screen of each, into docs/images/ (report-390.png, report-1280.png), and its
A4 print as PDF page images are left to a browser. Needs Debian's chromium.

Run: python scripts/report_screenshots.py [REPORT.html]  (default: checks the seed office first)
"""
from __future__ import annotations

import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "report"))

from cdp import Browser  # noqa: E402


def main() -> None:
    if len(sys.argv) > 1:
        page = Path(sys.argv[1])
    else:
        out = Path(tempfile.mkdtemp(prefix="en17037-shots-")) / "seed-office"
        subprocess.run([sys.executable, "-m", "en17037cli", "check", str(ROOT / "sample_projects/seed-office/project.yaml"),
                        "--out", str(out), "-q"], check=False)
        page = out / "report.html"
    images = ROOT / "docs" / "images"
    with Browser() as b:
        for width, height in ((390, 844), (1280, 900)):
            b.open(page, width, height)
            shot = images / f"report-{width}.png"
            b.screenshot(shot, full_page=False)
            print(shot)


if __name__ == "__main__":
    main()
