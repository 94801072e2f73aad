"""The project file: load, validate and resolve it into typed settings (:func:`load_project`)."""
from en17037cli.project.load import load_project, read_points_csv
from en17037cli.project.settings import (
                                         LayerRule,
                                         Location,
                                         ModelFile,
                                         ModelSettings,
                                         Project,
                                         Requirements,
                                         RoomSpec,
                                         SunSettings,
                                         ViewSettings,
)

__all__ = ["load_project", "read_points_csv", "LayerRule", "Location", "ModelFile", "ModelSettings", "Project",
           "Requirements", "RoomSpec", "SunSettings", "ViewSettings"]
