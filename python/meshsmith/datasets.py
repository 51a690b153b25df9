"""meshsmith.datasets (being written)."""
