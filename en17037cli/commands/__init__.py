"""The commands of ``en17037``, one module per command or command group; :mod:`en17037cli.cli`
gathers them under the ``en17037`` group.

Conventions every command follows (add new ones the same way):

- A command parses its options, calls the library and prints what it returns; the library does
  the work (:mod:`~en17037cli.commands.check`, :mod:`~en17037cli.commands.validate`,
  :mod:`~en17037cli.commands.study`, :mod:`~en17037cli.commands.batch`,
  :mod:`~en17037cli.commands.compare`, :mod:`~en17037cli.commands.schema`); options several
  commands share are decorators in :mod:`~en17037cli.commands.options`. Each imports the library
  inside the command, so ``en17037 --help`` stays cheap.
- Exit codes: 0 every required level met, 1 a required level missed (or a required check not
  assessed), 2 bad input, 3 internal error, 130 Ctrl-C, 143 SIGTERM.
- **stdout carries results** (the verdict table and status line of ``check``, what ``validate``
  found, the tables of ``compare`` and ``batch``, ``--json`` documents); **stderr carries
  diagnostics** (``error:``, ``warning:`` and ``note:`` lines, progress bars). So
  ``en17037 check p.yaml > log.txt`` keeps the verdict and a script can parse ``--json``.
- Domain errors become one line ``error: ...`` in one place (:mod:`~en17037cli.commands.errors`:
  :func:`~en17037cli.commands.errors.guard`), and so do usage mistakes (naming the command's
  ``--help``), exit 2. Help (``--help``, or a bare ``en17037``) goes to stdout with exit 0.
- Durations for people are written ``5 h 52 min`` (:func:`~en17037cli.report.numbers.fmt_duration`);
  decimal hours appear only in machine fields whose names end in ``_h``.
"""
