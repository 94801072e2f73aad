"""Domain errors. The CLI turns an :class:`InputError` into a one-line message and exit code 2."""


class InputError(Exception):
    """Bad input: a project file, a model file or geometry the user must fix.

    The message is one line that names the file, key or object and what to do.
    """
