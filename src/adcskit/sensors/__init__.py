"""adcskit.sensors (see design.md)."""
