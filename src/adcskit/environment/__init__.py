"""adcskit.environment (see design.md)."""
