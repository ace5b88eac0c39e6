"""softcath design package: the catheter tip as validated data (skeleton; API lands with issue 2)."""
