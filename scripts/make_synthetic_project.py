"""Write the synthetic sample project: a 4 x 6 x 3 m box room, a 2 x 1.4 m south window in a
zero-thickness wall, flat ground, and a 10 m high building across a 25 m street.

Known by hand (see tests/test_view_analytic.py): outside distance 25 m from every point,
horizontal sight angle atan((1 - x)/y) + atan((1 + x)/y) at (x, y), layer solid angles from the
rectangle formula. Usage: python scripts/make_synthetic_project.py OUT_DIR
"""
import sys
from pathlib import Path

from en17037cli.samples import BoxRoom, box_room_project

DESCRIPTION = ("Fails by design: the view needs medium, and a 2 m wide window in a 4 m wide room gives "
               "medium's 28 deg sight angle at 67 % of the points (75 % needed): view minimum. Sunlight "
               "medium (3 h 20 min on 1 February). Every figure is known by hand "
               "(en17037cli/samples/box.py).")

if __name__ == "__main__":
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "sample_projects/synthetic-street")
    path = box_room_project(out, BoxRoom(), name="Synthetic street (box room, 25 m street)",
                            sunlight={"date": "worst"}, view={"grid_spacing_m": 0.5},
                            description=DESCRIPTION)
    print(f"wrote {path}")
