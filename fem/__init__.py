"""softcath fem package."""
