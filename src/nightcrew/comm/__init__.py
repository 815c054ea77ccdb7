"""nightcrew.comm."""
