"""Which files in an output folder softcath wrote (:mod:`softcath.core.output_ledger`)."""

from softcath.core.output_ledger import (
    LEDGER,
    check_inputs_outside,
    check_replace,
    forget_inputs,
    protect_inputs,
    record,
    stale_files,
)

__all__ = [
    "LEDGER",
    "protect_inputs",
    "forget_inputs",
    "check_replace",
    "check_inputs_outside",
    "record",
    "stale_files",
]
