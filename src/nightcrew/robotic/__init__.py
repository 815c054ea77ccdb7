"""Robotic operation: what to observe (tasks), when (scheduler), and running it (mastermind)."""
