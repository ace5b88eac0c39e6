"""The ``softcath`` command line: one module per subcommand, shared options in :mod:`.options`.

The library never imports this package.
"""

from softcath.cli.main import main

__all__ = ["main"]
