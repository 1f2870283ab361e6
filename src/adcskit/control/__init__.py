"""adcskit.control (see design.md)."""
