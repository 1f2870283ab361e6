"""adcskit.determination (see design.md)."""
