"""``python -m softcath``: the same as the ``softcath`` command."""

import sys

from softcath.cli import main

sys.exit(main())
