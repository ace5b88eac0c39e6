"""The ground floor: what every room of softcath may import; it imports no room above it.

One concept per module:

- :mod:`~softcath.core.errors`: the error base types (``SoftcathError``, ``DesignError``,
  ``DataError``);
- :mod:`~softcath.core.atomic`: outputs that appear whole or not at all;
- :mod:`~softcath.core.output_ledger`: which files in an output folder softcath wrote;
- :mod:`~softcath.core.limits`: the one pressure bound and its check;
- :mod:`~softcath.core.interrupts`: a stop request that outlives the extensions that swallow it;
- :mod:`~softcath.core.plotting`: the plotting set-up (matplotlib's file-only backend);
- :mod:`~softcath.core.response`: the one result type of every model tier (``TipResponse``);
- :mod:`~softcath.core.deprecation`: renamed keywords that still work, with a warning.
"""

if __name__ != "softcath.core":  # the bare folder name would load a second copy of every module
    raise ImportError(
        "import softcath.core, not core: the top-level folders are rooms of the softcath package"
    )
