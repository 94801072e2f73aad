"""Reports: the document built from a run (:mod:`.document`), then one writer per file (:mod:`.write`).

Numbers are formatted by :mod:`.numbers`, which criteria use for their own sections; this package's
``__init__`` imports nothing so that criteria can use it without a cycle.
"""
