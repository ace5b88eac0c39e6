"""softcath studies package."""
