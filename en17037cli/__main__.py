import sys

try:
    from en17037cli.cli import main
except KeyboardInterrupt:  # Ctrl-C while the command is still being imported
    sys.stderr.write("error: interrupted\n")
    sys.exit(130)

main()
