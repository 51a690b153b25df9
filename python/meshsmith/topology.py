"""meshsmith.topology (being written)."""
