"""Where each room and window of a report comes from: the ``source`` of report.json.

A room or a window is named for people (``WD - 004 (2qO3jLTO90MAUdCA8G3HLt)``, ``System
Panel:Glazed:285583 (+2 panes)``); scripts, the BCF topics and the results written back into an
IFC find its elements by ``source`` instead, never by parsing the name:

- ``format``, ``file``: the model file's format (``ifc``, ``gbxml``, ``obj``, ``gltf``, ``dxf``,
  ``cityjson``, ``citygml``...; ``project`` for a room the project file draws) and the file as the
  project file writes it;
- ``ids``: the ids of every element it was made from, in the file's own terms: IFC GlobalIds (the
  IfcSpace; the IfcWindow, IfcDoor or IfcPlate products and every pane joined into one opening),
  gbXML Space and Opening ids, CityJSON / CityGML object ids; OBJ and glTF object names (else group
  names), DXF layer names, which the format has no ids for;
- ``elements``: each of them as the file names it (``id``, ``class``, ``name``; ``object``,
  ``group``, ``material`` where the format has no ids), for a window with the layer rule that made
  it glass (``layer_rule``), and its own ``file`` where it comes from another file than the first;
- ``entry``: the ``rooms[]`` entry of the project file that made the room.

Nothing here traces a ray or reads a file: the window's parts (:attr:`Window.parts`, every part
whose glazing made it) and the room's space (:attr:`Room.space`) carry the identity from the readers.
"""
from __future__ import annotations

import bisect

from en17037cli.scene.layers import by_stem, match_candidates, rule_matches
from en17037cli.scene.model import Room, Scene, Window

#: file name ending (lower case) -> format, longest ending first where several match
FORMATS = {".city.jsonl": "cityjson", ".city.json": "cityjson", ".jsonl": "cityjson", ".json": "cityjson",
           ".ifc": "ifc", ".gbxml": "gbxml", ".xml": "gbxml", ".obj": "obj", ".gltf": "gltf", ".glb": "gltf",
           ".off": "off", ".dxf": "dxf", ".gml": "citygml", ".citygml": "citygml", ".ply": "ply", ".stl": "stl"}
#: part attributes that name an element where the format has no ids (OBJ, glTF, DXF), in the order one stands for its id
NAME_KEYS = ("object", "group", "material")


def format_of(file: str) -> str:
    """The format of a model file by its name's ending (``ifc``, ``gbxml``, ``obj``...)."""
    name = file.lower()
    for ending in sorted(FORMATS, key=len, reverse=True):
        if name.endswith(ending):
            return FORMATS[ending]
    return name.rsplit(".", 1)[-1] if "." in name else ""


class Sources:
    """The ``source`` of each room and window of one run (one per report: the lookups are built once).

    scene : the run's scene; project : its settings (the model files' layer rules and the project file)
    """

    def __init__(self, scene: Scene, project) -> None:
        self.scene, self.project = scene, project
        self._starts = [first for _, _, first, _ in scene.files]
        self._rules: dict[int, list] = {}  # file index in scene.files -> per rule, whether the file's name may place parts
        self._by_id: dict[str, int] | None = None

    def file_of(self, part: int) -> tuple[int, str]:
        """(index in ``model.files``, the file as the project writes it) of a scene part."""
        k = bisect.bisect_right(self._starts, part) - 1
        index, display, _, _ = self.scene.files[k]
        return index, display

    def room(self, room: Room) -> dict:
        """The ``source`` of a room: the space it was made from, else the project file's entry."""
        entry = f"rooms[{room.spec.index}]"
        if room.space is None:
            return {"format": "project", "file": self.project.path.name, "ids": [], "elements": [], "entry": entry}
        file, space = self.scene.spaces[room.space]
        element = {"id": space.id, "class": space.kind.removeprefix("gbXML "), "name": space.name}
        if space.long_name:
            element["long_name"] = space.long_name
        return {"format": format_of(file), "file": file, "ids": [space.id], "elements": [element], "entry": entry}

    def window(self, window: Window) -> dict:
        """The ``source`` of a window: the product it belongs to and every element whose glazing made it."""
        elements: dict[str, dict] = {}
        files: list[str] = []
        if window.key is not None:  # the product (an IfcWindow whose panes are IfcPlates of its own)
            p = self.by_id().get(window.key)
            elements[window.key] = {"id": window.key} | ({} if p is None else self._named(p, with_id=True))
            if p is not None:
                files.append(self.file_of(p)[1])
        for p in window.parts:
            attrs = self.scene.parts[p].attrs
            key = attrs.get("id") or "\0".join(attrs.get(k, "") for k in NAME_KEYS)
            file = self.file_of(p)[1]
            files.append(file)
            element = elements.setdefault(key, self._named(p, with_id=True))
            element.setdefault("layer_rule", self.layer_rule(p))
            if file != files[0]:
                element["file"] = file
        first = files[0] if files else ""
        ids = list(dict.fromkeys(e["id"] for e in elements.values() if e.get("id")))
        return {"format": format_of(first), "file": first, "ids": ids, "elements": list(elements.values())}

    def _named(self, part: int, with_id: bool) -> dict:
        attrs = self.scene.parts[part].attrs
        if "id" in attrs:
            keys = ("id", "class", "name") if with_id else ("class", "name")
            return {k: attrs[k] for k in keys if k in attrs}
        out = {k: attrs[k] for k in (*NAME_KEYS, "class") if k in attrs}
        ident = next((attrs[k] for k in NAME_KEYS if attrs.get(k)), None)
        return ({"id": ident} if ident is not None else {}) | out

    def by_id(self) -> dict[str, int]:
        """Element id -> the first scene part of it."""
        if self._by_id is None:
            self._by_id = {}
            for i, p in enumerate(self.scene.parts):  # once per report, only where a window names a product
                if "id" in p.attrs:
                    self._by_id.setdefault(p.attrs["id"], i)
        return self._by_id

    def layer_rule(self, part: int) -> str:
        """What put a part on the window layer: ``model.files[i].layers[k] (match: 'glass*')``,
        ``model.files[i].layer``, or the format's own default (IFC, gbXML and CityJSON class tables)."""
        index, _ = self.file_of(part)
        spec = self.project.model.files[index]
        if spec.layer is not None:
            return f"model.files[{index}].layer"
        k = bisect.bisect_right(self._starts, part) - 1
        _, _, first, end = self.scene.files[k]
        if k not in self._rules:
            self._rules[k] = by_stem(spec.rules, self.scene.parts[first:end], spec.path.stem)
        p = self.scene.parts[part]
        candidates = (match_candidates(p, spec.path.stem, False), match_candidates(p, spec.path.stem, True))
        for i, rule in enumerate(spec.rules):
            if rule_matches(rule, p, candidates[self._rules[k][i]]):
                return f"model.files[{index}].layers[{i}] ({rule.describe()})"
        return "the format's default"
