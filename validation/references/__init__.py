"""Closed-form reference solutions the tests and the validation report compare against."""
