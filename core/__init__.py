"""The ground floor: what every room of softcath may import, and nothing above it.

One concept per module, none importing another room:

=============================  ===============================================
``softcath.core.errors``       the error base types (``SoftcathError``, ``DesignError``, ``DataError``)
``softcath.core.atomic``       outputs that appear whole or not at all
``softcath.core.output_ledger``  which files in an output folder softcath wrote
``softcath.core.limits``       the one pressure bound and its check
``softcath.core.interrupts``   a stop request that outlives the extensions that swallow it
``softcath.core.plotting``     the plotting set-up (matplotlib's file-only backend)
=============================  ===============================================
"""

if __name__ != "softcath.core":  # the bare folder name would load a second copy of every module
    raise ImportError(
        "import softcath.core, not core: the top-level folders are rooms of the softcath package"
    )
