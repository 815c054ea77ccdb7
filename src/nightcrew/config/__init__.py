"""nightcrew.config."""
