"""Write the synthetic sample project: a 4 x 6 x 3 m box room, a 2 x 1.4 m south window in a
zero-thickness wall, flat ground, and a 10 m high building across a 25 m street.

Known by hand (see tests/test_view_analytic.py): outside distance 25 m from every point,
horizontal sight angle atan((1 - x)/y) + atan((1 + x)/y) at (x, y), layer solid angles from the
rectangle formula. Usage: python scripts/make_synthetic_project.py OUT_DIR
"""
import sys
from pathlib import Path

from en17037cli.samples import BoxRoom, box_room_project

if __name__ == "__main__":
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "sample_projects/synthetic-street")
    path = box_room_project(out, BoxRoom(), name="Synthetic street (box room, 25 m street)",
                            sunlight={"date": "worst"}, view={"grid_spacing_m": 0.5})
    print(f"wrote {path}")
