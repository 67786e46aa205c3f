"""zmpkit.compensate."""
