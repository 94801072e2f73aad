from en17037cli.cli import main

main()
