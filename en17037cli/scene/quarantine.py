"""Quarantine: one element the reader cannot place costs that element, never the model.

A window whose glazing lies on another element's opaque face (no opening cut for it:
:func:`~en17037cli.scene.windows.check_glazing_over_opaque`) is taken as opaque: its faces join
the ``interior`` layer, so they block as the wall they lie on does, and it is no window of any room.
Each such element is listed in :attr:`Scene.quarantined` with what was found and what a project
file can do (the layer rule or ``exclude`` the message names), and in every report. A room whose
window it would have been is still assessed without it, but its verdict is withheld
(:attr:`Room.withheld`): a window dropped can only hide light, view and sun, so the room's levels
without it are lower bounds, and the room is never given a pass on them.
"""
from __future__ import annotations

from en17037cli.scene.model import INTERIOR, Quarantined, Scene
from en17037cli.scene.windows import UncutGlazing

#: What is done with a window whose glazing lies on another element.
TAKEN_AS_OPAQUE = "taken as opaque"


def quarantine_windows(scene: Scene, hidden: list[UncutGlazing]) -> None:
    """Take the ``hidden`` windows out of ``scene`` after its rooms are made: their faces become
    ``interior`` (opaque), they leave every room's windows, and each room that loses one is
    withheld (no windows left: it has a problem instead). Adds one warning per element."""
    if not hidden:
        return
    names = {scene.windows[h.position].name: h for h in hidden}
    rooms_of: dict[str, list[str]] = {n: [] for n in names}
    for room in scene.rooms:  # a handful of rooms lose a window
        lost = [w.name for w in room.windows if w.name in names]
        if not lost:
            continue
        for n in lost:
            rooms_of[n].append(room.name)
        room.windows = [w for w in room.windows if w.name not in names]
        room.window_reasons = {k: v for k, v in room.window_reasons.items() if k not in names}
        what = "; ".join(f"{names[n].element}: {names[n].reason}" for n in lost)
        if room.windows:
            room.withheld = (f"{len(lost)} of its windows quarantined ({what}); the room is assessed without "
                             f"{'it' if len(lost) == 1 else 'them'}, and no verdict is given on what remains")
        elif room.problem is None:
            room.problem = f"its only window{'s' if len(lost) > 1 else ''} quarantined ({what})"
    for h in hidden:  # one warning per element
        w = scene.windows[h.position]
        scene.layer[w.face_ids] = INTERIOR
        rooms = tuple(rooms_of[w.name])
        scene.quarantined.append(Quarantined(h.element, TAKEN_AS_OPAQUE, h.reason, h.advice, rooms))
        where = (f"; room{'s' if len(rooms) > 1 else ''} {', '.join(repr(r) for r in rooms)} assessed without it, no verdict"
                 if rooms else "; it is a window of no room")
        scene.warnings.append(f"quarantined: {h.element}: {h.reason}: {TAKEN_AS_OPAQUE}{where}; {h.advice}")
    scene.windows = [w for w in scene.windows if w.name not in names]
    scene.cache.clear()  # lookups over the faces' layers are made again
    scene._boxes = (None,)
