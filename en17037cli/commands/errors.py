"""Errors into exit codes, in one place: domain errors of a command (:func:`guard`), usage mistakes
and interrupts of the whole CLI (:class:`Group`), SIGTERM (:func:`exit_on_sigterm`).

Exit codes: 0 every required level met, 1 a required level missed (or a required check not
assessed), 2 bad input, 3 internal error, 130 Ctrl-C, 143 SIGTERM.
"""
from __future__ import annotations

import sys

import click

EXIT_PASS, EXIT_FAIL, EXIT_INPUT, EXIT_INTERNAL = 0, 1, 2, 3


def fail(message: str, code: int):
    for line in str(message).splitlines() or [""]:
        click.echo(f"error: {line}", err=True)
    sys.exit(code)


def guard(fn):
    """Run ``fn``; turn InputError into exit 2 and anything unexpected into exit 3."""
    from en17037cli.errors import InputError, internal_message

    try:
        return fn()
    except InputError as exc:
        fail(str(exc), EXIT_INPUT)
    except (SystemExit, KeyboardInterrupt, click.exceptions.Exit):
        raise
    except Exception as exc:  # noqa: BLE001 - the one place internal errors are reported
        fail(internal_message(exc), EXIT_INTERNAL)


class Group(click.Group):
    """click's group: help (and a bare group with no command) on stdout with exit 0; a usage mistake
    as one line ``error: ...`` on stderr naming the command's --help (exit 2), like every other input
    error; Ctrl-C as exit 130."""

    def main(self, args=None, prog_name=None, complete_var=None, standalone_mode=True, **extra):
        if not standalone_mode:
            return super().main(args, prog_name, complete_var, standalone_mode, **extra)
        try:
            code = super().main(args, prog_name, complete_var, False, **extra)
        except click.exceptions.NoArgsIsHelpError as exc:  # a bare `en17037` (or group): its help, not an error
            click.echo(exc.ctx.get_help())
            sys.exit(EXIT_PASS)
        except click.UsageError as exc:  # one line, like every other input error (click lists choices on several)
            where = f" (see {exc.ctx.command_path} --help)" if exc.ctx is not None else ""
            fail(" ".join(exc.format_message().split()) + where, EXIT_INPUT)
        except click.ClickException as exc:
            fail(exc.format_message(), EXIT_INPUT)
        except (click.exceptions.Abort, KeyboardInterrupt):
            click.echo("error: interrupted", err=True)
            sys.exit(130)
        sys.exit(code or 0)


#: Exit codes of a run ended by a signal: Ctrl-C (SIGINT) and SIGTERM (128 + the signal's number).
INTERRUPTED = (130, 143)


def exit_now(code: int):
    """End the process with ``code`` now: its output flushed, its cleanup done (the exception that
    stopped the run has unwound every ``with`` and ``finally``), but no wait for the threads of a
    pool to finish what they are tracing, which ``sys.exit`` would do at the interpreter's end."""
    import os

    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe: nothing left to say
            pass
    os._exit(code)


def exit_on_sigterm():
    """SIGTERM ends the run like Ctrl-C does: cleanup runs, exit code 143 (128 + 15)."""
    import signal

    def handler(signum, frame):
        click.echo("error: terminated", err=True)
        sys.exit(128 + signum)

    signal.signal(signal.SIGTERM, handler)
