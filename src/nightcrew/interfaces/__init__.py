"""nightcrew.interfaces."""
