"""adcskit.dynamics (see design.md)."""
