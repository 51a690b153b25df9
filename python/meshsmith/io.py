"""meshsmith.io (being written)."""
