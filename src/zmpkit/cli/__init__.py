"""The ``zmpkit`` command: ``main(argv)`` runs it (tests call it with ``argv``).

The subcommands live in the modules beside this one; the root group :data:`cli` imports each
only when it runs (:data:`zmpkit.cli.app.COMMANDS`).
"""

from zmpkit.cli.app import cli, main

__all__ = ["cli", "main"]
