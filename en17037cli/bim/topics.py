"""The BCF topics of a run: one per room and criterion that fails or cannot be assessed, with what a
BIM tool shows of it (title, description, camera, selected elements, snapshot). Writes nothing:
:mod:`en17037cli.bim.bcf` turns them into a BCF file.

Each topic's GUID is a UUID version 5 (RFC 4122, 4.3: SHA-1 over a name in a namespace) of the
room's identity and the criterion: ``<IfcSpace GlobalId>/<criterion>`` for a room made from a space
of the model, ``<project file>/<room name>/<criterion>`` for a room the project file draws. The same
room and criterion get the same GUID on every run, so a BCF server updates a topic instead of
adding a copy, and two rooms or two criteria never share one.
"""
from __future__ import annotations

import re
import uuid
from dataclasses import dataclass

import numpy as np

from en17037cli.bim.cameras import Camera, topic_camera
from en17037cli.bim.frames import ModelFiles
from en17037cli.report.verdicts import limit_text

#: The namespace of the topic GUIDs (uuid5 of the tool's URL in the URL namespace): fixed for ever.
NAMESPACE = uuid.uuid5(uuid.NAMESPACE_URL, "https://github.com/en17037cli/en17037cli/bcf-topics")
#: report.json criterion -> how a topic names it, and the clause of EN 17037
CRITERIA = {"daylight": ("daylight provision", "5.1"), "view": ("view out", "5.2"), "sunlight": ("exposure to sunlight", "5.3"),
            "glare": ("protection from glare", "5.4")}
#: statuses that make a topic
OPEN = ("fail", "not_assessable", "not_assessed")
#: an IFC GlobalId: 22 characters of IFC's base-64 alphabet (the BCF schemas' IfcGuid)
IFC_GUID = re.compile(r"^[0-9A-Za-z_$]{22}$")
#: picture names that are plans of a room (report/figures.py, criteria/glare/pictures.py)
PLAN = re.compile(r"-(view-[0-9.]+m-[a-z-]+|daylight-[a-z-]+|glare-positions)\.png$")


@dataclass(frozen=True)
class Topic:
    """One BCF topic.

    guid : the topic's UUID (see the module docstring); index : its place in the file (0, 1, ...)
    title, description : for people; labels : the tool, the criterion, the status
    status : report.json's status of the criterion; file : the model file (as the project writes
    it) the camera and components belong to, or None
    camera : in ``file``'s own coordinates [m] (point, unit direction); components : ids of the
    room's space and windows; ifc : whether they are IFC GlobalIds; snapshot : PNG bytes, or None
    """

    guid: str
    index: int
    title: str
    description: str
    labels: tuple[str, ...]
    status: str
    file: str | None
    camera: Camera
    components: tuple[str, ...]
    space: str | None
    ifc: bool
    snapshot: bytes | None


def topic_guid(room_entry: dict, project_file: str, criterion: str) -> str:
    """The topic's GUID (see the module docstring)."""
    src = room_entry.get("source", {})
    key = f"{src['ids'][0]}/{criterion}" if src.get("ids") else f"{project_file}/{room_entry['name']}/{criterion}"
    return str(uuid.uuid5(NAMESPACE, key))


def title(room: str, criterion: str, section: dict) -> str:
    """``Living room: exposure to sunlight minimum, medium required`` (or ``... not assessable, ...``)."""
    words = CRITERIA[criterion][0]
    reached = section["level"] if section["status"] == "fail" and section.get("level") else section["status"].replace("_", " ")
    return f"{room}: {words} {reached}, {section['required']} required"


def description(criterion: str, section: dict, camera: Camera, windows: list[dict]) -> str:
    """The report's sentence on what limits the room and by how much (or why it was not assessed),
    the clause, and where the viewpoint stands."""
    words, clause = CRITERIA[criterion]
    why = limit_text(criterion, section) if section["status"] == "fail" else section.get("reason", "")
    looking = f", looking at window '{windows[camera.window]['name']}'" \
        if camera.window is not None and "looking" not in camera.how else ""
    status = "fails" if section["status"] == "fail" else f"is {section['status'].replace('_', ' ')}"
    return (f"EN 17037 {clause} {words} {status} ({section['required']} required): {why or 'see the report'}. "
            f"Viewpoint: {camera.how}{looking}.")


def snapshot(figures, room: str, criterion: str, section: dict) -> bytes | None:
    """The room's plan picture for the topic: the criterion's own plan map (view: the map of the
    limiting criterion at the limiting eye height, else the level map), else the room's view level
    map, else any plan of the room, else the criterion's first picture; None without pictures."""
    mine = [f for f in figures if f.room == room]
    plans = [f for f in mine if PLAN.search(f.name)]
    lim = section.get("limiting") or {}
    want = []
    if criterion == "view" and lim.get("criterion") and lim.get("eye_height_m") is not None:
        kind = {"horizontal_sight_angle": "sight-angle", "outside_distance": "distance", "layers": "layers"}[lim["criterion"]]
        want.append(f"-view-{lim['eye_height_m']:g}m-{kind}.png")
    order = [[f for f in plans if f.section == criterion and any(f.name.endswith(w) for w in want)],
             [f for f in plans if f.section == criterion and f.name.endswith("-level.png")],
             [f for f in plans if f.section == criterion],
             [f for f in plans if f.section == "view" and f.name.endswith("-level.png")],
             plans, [f for f in mine if f.section == criterion]]
    return next((group[0].png for group in order if group), None)


def room_topics(result, report: dict, figures, files: ModelFiles) -> list[Topic]:
    """Every topic of a run, room by room in the report's order, criteria in clause order."""
    out: list[Topic] = []
    project_file = report["project"]["file"]
    for entry, r in zip(report["rooms"], result.rooms):
        for criterion in CRITERIA:
            section = entry.get(criterion)
            if not section or section["status"] not in OPEN:
                continue
            cam = topic_camera(result.scene, r.room, criterion, section)
            src = entry["source"]
            ids = list(src["ids"]) + [i for w in entry["windows"] for i in w["source"]["ids"]]
            formats = {src["format"]} | {w["source"]["format"] for w in entry["windows"]}
            home = src["file"] if src["format"] == "ifc" else \
                next((w["source"]["file"] for w in entry["windows"] if w["source"]["format"] == "ifc"), None)
            point, direction = files.to_file(home, cam.point, cam.direction)
            ifc = formats - {"project"} == {"ifc"}
            out.append(Topic(
                guid=topic_guid(entry, project_file, criterion), index=len(out), title=title(entry["name"], criterion, section),
                description=description(criterion, section, cam, entry["windows"]),
                labels=("EN 17037", CRITERIA[criterion][0], section["status"].replace("_", " ")), status=section["status"],
                file=home, camera=Camera(point[0], direction[0], cam.window, cam.how),
                components=tuple(dict.fromkeys(i for i in ids if not ifc or IFC_GUID.match(i))),
                space=src["ids"][0] if src["format"] == "ifc" and src["ids"] else None, ifc=ifc,
                snapshot=snapshot(figures, entry["name"], criterion, section)))
    return out


def up_vector(direction: np.ndarray) -> np.ndarray:
    """The camera's up: +z made perpendicular to ``direction``; +y for a camera looking straight up or down."""
    up = np.array([0.0, 0.0, 1.0]) - direction[2] * direction
    if np.linalg.norm(up) < 1e-6:
        up = np.array([0.0, 1.0, 0.0]) - direction[1] * direction
    return up / np.linalg.norm(up)
