"""Material laws, as pure functions over arrays (fabric and elastic-shell laws come with the
shell elements)."""

__all__: list[str] = []
