"""Domain errors. The CLI turns an :class:`InputError` into a one-line message and exit code 2."""


class InputError(Exception):
    """Bad input: a project file, a model file or geometry the user must fix.

    The message is one line that names the file, key or object and what to do.
    """


class NotAssessable(Exception):
    """A room (or one window of it) cannot be assessed by a criterion: no window bounds it, its
    utilised area is empty, point P lies above the window head... The run goes on with the other
    rooms; the room is reported ``not_assessable`` with this one-line reason, which fails its
    requirement."""


def internal_message(exc: BaseException) -> str:
    """How an unexpected exception is reported (exit code 3): its type, its message and the last
    line of its traceback, and a request to report it."""
    import traceback

    tb = "".join(traceback.format_exception(exc, limit=-3)).strip().splitlines()
    return f"internal error ({type(exc).__name__}: {exc}); please report it with this project. {tb[-1] if tb else ''}"
