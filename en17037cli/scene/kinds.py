"""What each room is used for (its kinds: :data:`~en17037cli.practice.ROOM_KINDS`), and where that
came from, read in this order; the first source that names a kind decides:

1. the project file's ``room_kinds`` rules, in order: a glob (case-insensitive) on the room's name
   and on every text the model gives its space (:attr:`~en17037cli.io.mesh.Space.usage`);
2. the space's classification references of a room-level table: Uniclass 2015 ``SL_`` codes by
   :data:`UNICLASS_SL`, OmniClass Table 13 (Spaces by Function, ``13-`` codes) by their name;
   other systems (DIN 277 usage groups such as ``2 HNF Büroarbeit``, an authoring tool's
   ``Residence``) class whole buildings, not rooms, and are left out;
3. its IFC ObjectType and IfcSpaceType name, then its LongName, then its Name, then the room's name,
   each by the default name table :data:`NAMES`;
4. the gbXML ``spaceType``, by :data:`GBXML_SPACE_TYPES` (last: it is a load category of the energy
   model; Revit writes ``LivingQuartersHotel`` on living rooms and bedrooms alike);
5. else ``other``.

A text may name several uses (``Living/Kitchen/Dining``, ``Wohnküche``, ``Soggiorno / Cottura``):
the room has them all, and what it is asked is the highest of them (:func:`~en17037cli.project.kinds.room_spec`).
A dining room counts as a living room (a room to sit in; BREEAM's daylight criteria for homes group
living and dining rooms too), a study as an office.
"""
from __future__ import annotations

import fnmatch
import re
import unicodedata

from en17037cli.practice import ROOM_KINDS
from en17037cli.project.kinds import room_spec
from en17037cli.project.settings import Project
from en17037cli.scene.model import Scene

#: The default name table: per kind, regular expressions on a name folded to lower case without
#: accents (``Küche`` -> ``kuche``, ``séjour`` -> ``sejour``; see :func:`fold`). Words of compound
#: languages (German, Dutch) are found inside words (``Elternschlafzimmer``, ``woonkeuken``); short
#: or ambiguous words only whole (``\b``). docs/project-file.md lists them (a test keeps the two alike).
NAMES: dict[str, tuple[str, ...]] = {
    "bedroom": (r"bed ?rooms?", r"\bbeds?\b", r"\bsleeping\b",  # en
                r"schlaf", r"kinderzimmer", r"gastezimmer", r"gaestezimmer",  # de
                r"slaapkamer",  # nl
                r"\bchambres?\b",  # fr
                r"\bcamera\b", r"\bcamere\b", r"\bcamera da letto\b",  # it
                r"\bdormitorio", r"\bquartos?\b"),  # es, it, pt
    "living_room": (r"\bliving\b", r"livingroom", r"\blounge\b", r"\bsitting ?room", r"\bfamily ?room", r"\bdining\b",
                    r"\bdiner\b",  # en (dining: a living room)
                    r"wohn(?!ung)", r"esszimmer", r"essraum", r"essbereich", r"\bessen\b", r"\bstube\b",  # de
                    r"woonkamer", r"woon", r"zitkamer", r"eetkamer",  # nl
                    r"sejour", r"\bsalon\b", r"salle a manger", r"piece a vivre", r"piece de vie",  # fr
                    r"soggiorno", r"salotto", r"tinello", r"sala da pranzo", r"\bpranzo\b",  # it
                    r"sala de estar", r"\bcomedor\b"),  # es, pt
    "kitchen": (r"kitchen",  # en (kitchenette)
                r"kuche", r"kueche", r"kochnische", r"\bkochen\b",  # de
                r"keuken", r"kookhoek",  # nl
                r"cuisine",  # fr
                r"cucina", r"cucinotto", r"\bcottura\b",  # it
                r"cocina", r"cozinha"),  # es, pt
    "office": (r"office", r"\bstudy\b",  # en
               r"buro", r"buero", r"arbeitszimmer",  # de
               r"kantoor", r"werkkamer",  # nl
               r"\bbureaux?\b",  # fr, nl
               r"ufficio", r"\buffici\b",  # it
               r"oficina", r"despacho", r"escritorio"),  # es, pt
}
_NAMES = {kind: re.compile("|".join(f"(?:{p})" for p in pats)) for kind, pats in NAMES.items()}

#: Uniclass 2015 table SL (Spaces/locations), SL_45_10 Living spaces: the codes of a kind of room
#: (uniclass.thenbs.com/taxon/sl_45_10, SL v1.36 as read); a code not here is read by its name.
UNICLASS_SL: dict[str, tuple[str, ...]] = {
    "SL_45_10_09": ("bedroom",),  # Bedrooms
    "SL_45_10_08": ("bedroom", "office"),  # Bedroom-studies
    "SL_45_10_24": ("bedroom",),  # Dormitories
    "SL_45_10_37": ("bedroom",),  # Hotel rooms
    "SL_45_10_57": ("bedroom",),  # Nursing home bedrooms
    "SL_45_10_78": ("bedroom",),  # Single-occupancy bedrooms
    "SL_45_10_14": ("living_room",),  # Communal living rooms
    "SL_45_10_22": ("living_room",),  # Domestic dining rooms
    "SL_45_10_49": ("living_room",),  # Living rooms
    "SL_45_10_23": ("kitchen",),  # Domestic kitchens
    "SL_45_10_44": ("living_room", "kitchen"),  # Kitchen-dining rooms
    "SL_45_10_45": ("living_room", "kitchen"),  # Kitchen-dining-living rooms
    "SL_45_10_16": ("office",),  # Concierge offices
    "SL_45_10_85": ("office",),  # Studies
}

#: gbXML spaceTypeEnum values of one kind of room (gbXML 6.01 / 7.03; the other values, LivingQuarters*
#: among them, name none).
GBXML_SPACE_TYPES: dict[str, tuple[str, ...]] = {
    "DormitoryBedroom": ("bedroom",), "SleepingQuartersPoliceOrFireStation": ("bedroom",),
    "FoodPreparation": ("kitchen",), "OfficeEnclosed": ("office",), "OfficeOpenPlan": ("office",),
}

#: The order in which the model's texts are read (:attr:`Space.usage`'s ``where``; a classification first).
_ORDER = ("classification", "ObjectType", "IfcSpaceType", "LongName", "Name", "room name", "gbXML spaceType")
_SL = re.compile(r"\bSL[_ ]?(\d\d)(?:[_ ](\d\d))?(?:[_ ](\d\d))?(?:[_ ](\d\d))?\b", re.IGNORECASE)
_OMNICLASS_13 = re.compile(r"^\s*13[- ]\d")


def fold(text: str) -> str:
    """``text`` in lower case without accents, every run of other characters than letters and digits
    one space: ``'Wohn-/Küche'`` -> ``'wohn kuche'``."""
    t = "".join(c for c in unicodedata.normalize("NFKD", text) if not unicodedata.combining(c)).casefold()
    return " ".join(re.sub(r"[\W_]+", " ", t).split())


def by_name(text: str) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """(kinds, the words that name them) of a name by the table :data:`NAMES`, kinds in
    :data:`ROOM_KINDS` order; ((), ()) where it names none."""
    t = fold(text)
    found = [(kind, m.group(0)) for kind in ROOM_KINDS if kind in _NAMES and (m := _NAMES[kind].search(t))]
    return tuple(k for k, _ in found), tuple(w for _, w in found)


def by_classification(text: str) -> tuple[tuple[str, ...], str]:
    """(kinds, how) of a classification reference's text (``'SL_45_10_09 Bedrooms'``): a Uniclass SL
    code by :data:`UNICLASS_SL`, else its name by :data:`NAMES` for a Uniclass SL or OmniClass Table 13
    reference; ((), "") for other systems."""
    m = _SL.search(text)
    if m:
        code = "SL_" + "_".join(g for g in m.groups() if g)
        if code in UNICLASS_SL:
            return UNICLASS_SL[code], f"Uniclass {code}"
    elif not _OMNICLASS_13.match(text):
        return (), ""
    kinds, words = by_name(text)
    return kinds, ("name table " + ", ".join(f"'{w}'" for w in words)) if kinds else ""


def room_kind(name: str, usage, rules) -> tuple[tuple[str, ...], str]:
    """(kinds, where they came from) of the room ``name`` whose space the model describes by
    ``usage`` ((where, text) pairs), by the project's ``rules`` (:class:`~en17037cli.project.kinds.KindRule`)
    and the tables of this module, in the order of the module docstring."""
    texts = [("room name", name), *usage]
    for rule in rules:
        glob = rule.match.casefold()
        for where, text in texts:
            if fnmatch.fnmatchcase(text.casefold(), glob):
                return _sorted(rule.kinds), f"room_kinds[{rule.index}] '{rule.match}' on the {where} '{text}'"
    ranked = sorted(texts, key=lambda wt: next((i for i, w in enumerate(_ORDER) if wt[0].startswith(w)), len(_ORDER)))
    for where, text in ranked:
        if where.startswith("classification"):
            kinds, how = by_classification(text)
        elif where == "gbXML spaceType":
            kinds, how = GBXML_SPACE_TYPES.get(text, ()), ""
        else:
            kinds, words = by_name(text)
            how = "name table " + ", ".join(f"'{w}'" for w in words)
        if kinds:
            return _sorted(kinds), f"{where} '{text}'" + (f": {how}" if how else "")
    return ("other",), "no room_kinds rule, model type or name says what it is used for"


def _sorted(kinds) -> tuple[str, ...]:
    return tuple(k for k in ROOM_KINDS if k in kinds)


def assign_kinds(scene: Scene, project: Project) -> None:
    """Each room's kinds and where they came from (:func:`room_kind`), and what they ask of it: its
    spec's requirements and thresholds (:func:`~en17037cli.project.kinds.room_spec`)."""
    for room in scene.rooms:
        room.kinds, room.kind_source = room_kind(room.name, room.usage, project.kind_rules)
        room.spec, room.by_kind = room_spec(room.spec, room.kinds, project.by_kind)
