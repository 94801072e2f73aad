"""The facades of a city model screened at once (``en17037 screen``, issue 45): see docs/district.md."""
