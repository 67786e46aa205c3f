"""zmpkit.robots."""
