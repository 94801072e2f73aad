"""Write the CityJSON sample project: the box room of the synthetic street (no generated street
building) placed 20 m north of a block of 15 LoD2 buildings of Rotterdam (cjio's
rotterdam_subset.json, EPSG:7415 coordinates), its south window facing them.

The room's model is local (origin at the window); ``transform`` places it in the city's
coordinates, and the city model's buildings get their layers from the CityJSON types without a
single rule. Usage: python scripts/make_rotterdam_project.py [OUT_DIR]
"""
import sys
from pathlib import Path

import yaml

from en17037cli.samples import BoxRoom, box_room_project

#: Where the window's centre goes [m, EPSG:7415]: 20 m north of the block's north edge (y 435688).
PLACE = (90965.0, 435708.0, 0.0)

DESCRIPTION = ("Fails by design: the box room of synthetic-street, so the sight angle limits its view to "
               "minimum (medium required); the Rotterdam buildings 20 m south leave it 2 h 57 min of sun "
               "on 1 February (minimum).")

if __name__ == "__main__":
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "sample_projects/cityjson-rotterdam")
    path = box_room_project(out, BoxRoom(building_height=0), name="Box room among 15 Rotterdam buildings (CityJSON context)",
                            sunlight={"date": "worst"}, view={"grid_spacing_m": 0.5})
    (out / "model.obj").rename(out / "box.obj")  # not room.obj: 'match: room' would match its file name
    doc = yaml.safe_load(path.read_text())
    room_file = doc["model"]["files"][0]
    room_file.update(path="box.obj", transform={"rotate_deg": 0.0, "translate_m": list(PLACE)})
    doc["model"]["files"].append({"path": "rotterdam_subset.json", "crs": "EPSG:7415"})  # the file names no CRS
    doc["location"] = {"latitude": 51.922, "longitude": 4.481, "timezone": "Europe/Amsterdam"}
    doc["rooms"][0]["floor_z"] = 0.0
    doc = {"version": doc["version"], "name": doc["name"], "description": DESCRIPTION, **doc}
    path.write_text(yaml.safe_dump(doc, sort_keys=False), encoding="utf-8")
    print(f"wrote {path}")
