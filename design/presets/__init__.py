"""Shipped designs (TOML files next to this module)."""

from __future__ import annotations

from importlib import resources

__all__ = ["names", "text"]


def names() -> list[str]:
    """Names of the shipped presets."""
    return sorted(p.name[:-5] for p in resources.files(__name__).iterdir() if p.name.endswith(".toml"))


def text(name: str) -> str:
    """The TOML text of preset ``name``."""
    return resources.files(__name__).joinpath(f"{name}.toml").read_text(encoding="utf-8")
