"""Sub-commands of ``vid-eval``: each module has ``add_parser(subparsers)`` and ``run(args)``."""
