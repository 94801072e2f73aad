"""A run's open issues as a BCF file (BIM Collaboration Format 2.1, buildingSMART), for the BIM tools
the architect uses (Revit's BCF Manager, Solibri, BIMcollab, ArchiCAD, BlenderBIM import 2.1).

The file is a zip (BCF 2.1 README, "BCF file structure"): ``bcf.version``, and per topic a folder
named by its GUID with ``markup.bcf`` (markup.xsd), ``viewpoint.bcfv`` (visinfo.xsd) and, where
the report has pictures, ``snapshot.png``. Each XML file is written with the standard library in
the elements' schema order and checked against buildingSMART's XSDs in the tests
(tests/data/bcf-2.1). BCF 2.1, not 3.0: 2.1 is what the BIM tools above import (3.0 moved the
header out of the markup into ``documents.xml`` and ``extensions.xml`` and is read by few of them).

Same inputs, same bytes: the dates are the model's (its IFC header's FILE_NAME time stamp, else
1970-01-01), never the clock; every zip entry has the DOS epoch as its time, fixed permissions,
folder entries as the BCF encoding guide asks, and the topics in the report's order.
"""
from __future__ import annotations

import io
import uuid
import xml.etree.ElementTree as ET
import zipfile

import numpy as np

from en17037cli.bim.frames import ModelFiles
from en17037cli.bim.topics import NAMESPACE, Topic, room_topics, up_vector
from en17037cli.version import __version__

#: bcf.version of BCF 2.1, as buildingSMART's Documentation/bcf.version gives it (without its comment)
VERSION_XML = (b'<?xml version="1.0" encoding="UTF-8"?>\n<Version VersionId="2.1" xsi:noNamespaceSchemaLocation="version.xsd" '
               b'xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">\n  <DetailedVersion>2.1</DetailedVersion>\n</Version>\n')
#: The date of a topic whose model gives none (xs:dateTime).
NO_DATE = "1970-01-01T00:00:00+00:00"
#: The author of every topic.
AUTHOR = "en17037cli"
#: Horizontal field of view of every viewpoint [deg] (BCF 2.1 allows 45 to 60).
FIELD_OF_VIEW_DEG = 60.0
#: Colour of the room's space in the viewpoint (RGB hex), by status
COLOURS = {"fail": "E8352B", "not_assessable": "F2A33A", "not_assessed": "F2A33A"}
#: Time of every zip entry (zip's DOS epoch)
ZIP_TIME = (1980, 1, 1, 0, 0, 0)


def _sub(parent: ET.Element, tag: str, text: str | None = None, **attrs) -> ET.Element:
    e = ET.SubElement(parent, tag, {k: v for k, v in attrs.items() if v is not None})
    if text is not None:
        e.text = text
    return e


def _xml(root: ET.Element) -> bytes:
    ET.indent(root, space="  ")
    return b'<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode").encode("utf-8") + b"\n"


def _number(x: float) -> str:
    """A coordinate [m] or a direction's component as xs:double text, to 1e-6, no ``-0``."""
    s = f"{float(x):.6f}"
    return "0.000000" if s == "-0.000000" else s


def _xyz(parent: ET.Element, tag: str, v: np.ndarray) -> None:
    e = _sub(parent, tag)
    for name, x in zip("XYZ", v):
        _sub(e, name, _number(x))


def viewpoint_guid(topic: Topic) -> str:
    """The viewpoint's GUID: uuid5 of the topic's GUID (stable like it)."""
    return str(uuid.uuid5(NAMESPACE, f"{topic.guid}/viewpoint"))


def markup_xml(topic: Topic, files: ModelFiles) -> bytes:
    """``markup.bcf`` (markup.xsd): the model file, the topic, its viewpoint."""
    root = ET.Element("Markup")
    if topic.file is not None and topic.ifc:
        header = _sub(root, "Header")
        f = _sub(header, "File", IfcProject=files.ifc_project(topic.file), isExternal="true")
        _sub(f, "Filename", topic.file.replace("\\", "/").rsplit("/", 1)[-1])
        date = files.ifc_date(topic.file)
        if date is not None:
            _sub(f, "Date", date)
    t = _sub(root, "Topic", Guid=topic.guid, TopicType="Issue", TopicStatus="Open")
    _sub(t, "Title", topic.title)
    _sub(t, "Index", str(topic.index))
    for label in topic.labels:
        _sub(t, "Labels", label)
    _sub(t, "CreationDate", creation_date(topic, files))
    _sub(t, "CreationAuthor", AUTHOR)
    _sub(t, "Description", topic.description)
    vp = _sub(root, "Viewpoints", Guid=viewpoint_guid(topic))
    _sub(vp, "Viewpoint", "viewpoint.bcfv")
    if topic.snapshot is not None:
        _sub(vp, "Snapshot", "snapshot.png")
    _sub(vp, "Index", "0")
    return _xml(root)


def creation_date(topic: Topic, files: ModelFiles) -> str:
    """The model's date (its IFC header's time stamp), else :data:`NO_DATE`: never the clock."""
    date = files.ifc_date(topic.file) if topic.file is not None else None
    return date or NO_DATE


def _component(parent: ET.Element, ident: str, ifc: bool) -> None:
    if ifc:
        _sub(parent, "Component", IfcGuid=ident)
    else:  # a model without IFC GlobalIds: the element's own id, for the tool that wrote the file
        c = _sub(parent, "Component")
        _sub(c, "OriginatingSystem", f"en17037cli {__version__}")
        _sub(c, "AuthoringToolId", ident)


def visinfo_xml(topic: Topic) -> bytes:
    """``viewpoint.bcfv`` (visinfo.xsd): the room's space and windows selected (its space coloured by
    the status), everything else visible, a perspective camera at the topic's point."""
    root = ET.Element("VisualizationInfo", Guid=viewpoint_guid(topic))
    comps = _sub(root, "Components")
    _sub(comps, "ViewSetupHints", SpacesVisible="true", SpaceBoundariesVisible="false", OpeningsVisible="false")
    if topic.components:
        sel = _sub(comps, "Selection")
        for ident in topic.components:
            _component(sel, ident, topic.ifc)
    _sub(comps, "Visibility", DefaultVisibility="true")
    if topic.space is not None:
        colour = _sub(_sub(comps, "Coloring"), "Color", Color=COLOURS[topic.status])
        _component(colour, topic.space, True)
    cam = _sub(root, "PerspectiveCamera")
    _xyz(cam, "CameraViewPoint", topic.camera.point)
    _xyz(cam, "CameraDirection", topic.camera.direction)
    _xyz(cam, "CameraUpVector", up_vector(np.asarray(topic.camera.direction, float)))
    _sub(cam, "FieldOfView", f"{FIELD_OF_VIEW_DEG:g}")
    return _xml(root)


def _entry(name: str, folder: bool = False) -> zipfile.ZipInfo:
    info = zipfile.ZipInfo(name, date_time=ZIP_TIME)
    info.external_attr = ((0o40755 if folder else 0o100644) << 16) | (0x10 if folder else 0)
    info.compress_type = zipfile.ZIP_STORED if folder else zipfile.ZIP_DEFLATED
    info.create_system = 3  # Unix: the permissions above are read as such everywhere
    return info


def bcf_bytes(topics: list[Topic], files: ModelFiles) -> bytes:
    """The BCF 2.1 zip of ``topics`` (see the module docstring)."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        z.writestr(_entry("bcf.version"), VERSION_XML)
        for t in topics:
            z.writestr(_entry(f"{t.guid}/", folder=True), b"")
            z.writestr(_entry(f"{t.guid}/markup.bcf"), markup_xml(t, files))
            z.writestr(_entry(f"{t.guid}/viewpoint.bcfv"), visinfo_xml(t))
            if t.snapshot is not None:
                z.writestr(_entry(f"{t.guid}/snapshot.png"), t.snapshot)
    return buf.getvalue()


def bcf_for(result, report: dict, figures=()) -> tuple[bytes, int]:
    """The BCF file of a run (its bytes) and the number of topics: one per room and criterion that
    fails or cannot be assessed (:func:`~en17037cli.bim.topics.room_topics`)."""
    files = ModelFiles(result.project)
    topics = room_topics(result, report, figures, files)
    return bcf_bytes(topics, files), len(topics)
