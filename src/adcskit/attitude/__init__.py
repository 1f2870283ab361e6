"""adcskit.attitude (see design.md)."""
