"""nightcrew.events."""
