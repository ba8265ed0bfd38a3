"""Validation cases and the report of `python -m validation`."""
