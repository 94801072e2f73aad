"""The package's version (``en17037cli.__version__``), in a module of its own so that the reports
and the CLI can name it without importing the package's API (:mod:`en17037cli`), which imports them."""

__version__ = "0.1.0"
