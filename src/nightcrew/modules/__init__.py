"""nightcrew.modules."""
