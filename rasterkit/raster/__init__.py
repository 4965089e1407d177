"""rasterkit.raster."""
