"""adcskit.optimal_control (see design.md)."""
