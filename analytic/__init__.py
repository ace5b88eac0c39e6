"""softcath analytic package."""
