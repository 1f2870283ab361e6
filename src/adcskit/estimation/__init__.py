"""adcskit.estimation (see design.md)."""
