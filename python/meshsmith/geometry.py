"""meshsmith.geometry (being written)."""
