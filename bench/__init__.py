"""Benchmarks: each file runs as a script (.venv/bin/python bench/NAME.py) and prints a table."""
