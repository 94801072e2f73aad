"""The shell of the 6.6 x 5.6 x 2.7 m one-room IFC house the window and space tests build on
(en17037cli.samples.ifc.Builder): a storey, the site at 52.0 N 4.36 E, floor and roof slabs and the
four walls, south (0), east (1), north (2) and west (3), each WALL_M thick inside the footprint."""
from __future__ import annotations

#: The house's footprint [m], anticlockwise from the south-west corner.
FOOT = [(0, 0), (6.6, 0), (6.6, 5.6), (0, 5.6)]


def box_shell(schema: str = "IFC4"):
    """(builder, storey, walls): the shell above, ready for a space and windows."""
    from en17037cli.samples.ifc import Builder

    b = Builder(schema)
    st = b.storey("Ground", 0.0)
    b.locate(52.0, 4.36, 0.0)
    b.slab("Floor", st, FOOT, -0.2, 0.2)
    b.slab("Roof", st, FOOT, 2.7, 0.2)
    walls = [b.wall(f"Wall {k}", st, *p, *q, 0.0, 2.7) for k, (p, q) in enumerate(zip(FOOT, FOOT[1:] + FOOT[:1]))]
    return b, st, walls
