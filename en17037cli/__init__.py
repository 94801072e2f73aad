"""en17037cli: check EN 17037 View out (clause 5.2) and Exposure to sunlight (clause 5.3)."""

__version__ = "0.1.0"
