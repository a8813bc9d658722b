"""Reproduce items of this capability (registered on import)."""
