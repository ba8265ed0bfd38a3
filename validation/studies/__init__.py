"""Studies: validation cases in the making, with their measured state in their docstrings,
kept out of the report (``validation.cases`` discovers only its own modules) until their
checks pass."""
