"""The scene: geometry, layers, windows and rooms in one local frame (:func:`build_scene`)."""
from en17037cli.scene.build import build_scene
from en17037cli.scene.model import GROUND, INTERIOR, LANDSCAPE, LAYERS, WINDOW, Room, Scene, Window, room_window_group

__all__ = ["build_scene", "Scene", "Room", "Window", "room_window_group", "LAYERS", "WINDOW", "INTERIOR", "GROUND",
           "LANDSCAPE"]
