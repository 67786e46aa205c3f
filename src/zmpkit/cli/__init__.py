"""The ``zmpkit`` command: ``main(argv)`` runs it (tests call it with ``argv``).

Importing this package registers every subcommand on the root group :data:`cli`.
"""

from zmpkit.cli import balance, demo, identify, robot, sim, walk, zmp  # noqa: F401  (registration)
from zmpkit.cli.app import cli, main

__all__ = ["cli", "main"]
