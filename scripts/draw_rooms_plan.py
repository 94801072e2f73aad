"""Draw docs/images/rooms-plan.png: the L-shaped flat of en17037cli/samples/flat.py (walls as box
solids, a door, furniture, a stair, a beam) with its two rooms declared by name and level only,
as `en17037 validate --plan` draws what the tool understood.

Run: python scripts/draw_rooms_plan.py
"""
from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import yaml

from en17037cli.samples.box import write_obj
from en17037cli.samples.flat import Flat, flat_polygons

ROOT = Path(__file__).resolve().parents[1]

if __name__ == "__main__":
    tmp = Path(tempfile.mkdtemp(prefix="en17037-rooms-"))
    write_obj(tmp / "flat.obj", flat_polygons(Flat()))
    layers = [{"match": "glass*", "layer": "window"}, {"match": "ground", "layer": "ground"},
              {"match": "neighbour", "layer": "landscape"}, {"match": "*", "layer": "interior"}]
    (tmp / "project.yaml").write_text(yaml.safe_dump({
        "version": 1, "name": "L-shaped flat", "model": {"files": [{"path": "flat.obj", "layers": layers}]},
        "location": {"latitude": 52.0, "longitude": 4.36, "timezone": "Europe/Amsterdam"},
        "rooms": [{"name": "living", "floor_z": 0, "windows": ["glass living*"]},
                  {"name": "bedroom", "floor_z": 0, "windows": ["glass bedroom*"]}],
        "view": {}, "sunlight": {}}, sort_keys=False))
    subprocess.run([sys.executable, "-m", "en17037cli", "validate", str(tmp / "project.yaml"), "--plan", str(tmp / "plan")],
                   check=True, cwd=ROOT)
    shutil.copy(tmp / "plan" / "plan-z0.00.png", ROOT / "docs" / "images" / "rooms-plan.png")
    print(ROOT / "docs" / "images" / "rooms-plan.png")
