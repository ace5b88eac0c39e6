"""The ``softcath`` command line: one module per subcommand, shared options in :mod:`.options`.

The library never imports this package.
"""

from softcath.cli.main import main

__all__ = ["main"]

if __name__ != "softcath.cli":  # the bare folder name would load a second copy of every module
    raise ImportError("import softcath.cli, not cli: the top-level folders are rooms of the softcath package")
