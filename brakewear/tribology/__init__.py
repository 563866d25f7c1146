"""Tribometer tests (in progress)."""
