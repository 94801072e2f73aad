"""Scenes made in code, whose answers are known: the box room (:mod:`.box`), rooms in a block
(:mod:`.block`), a generated city (:mod:`.city`). Used by the sample projects, the tests and the
benchmarks."""
from en17037cli.samples.box import (
    MULLION_GAP,
    SCALE_UNITS,
    BoxRoom,
    box_room_polygons,
    box_room_project,
    write_obj,
)
from en17037cli.samples.city import city_context, write_ply

__all__ = ["MULLION_GAP", "SCALE_UNITS", "BoxRoom", "box_room_polygons", "box_room_project",
           "write_obj", "city_context", "write_ply"]
