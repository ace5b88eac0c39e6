"""softcath hardware package."""
