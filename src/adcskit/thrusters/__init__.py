"""adcskit.thrusters (see design.md)."""
