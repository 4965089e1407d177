"""rasterkit.runtime."""
