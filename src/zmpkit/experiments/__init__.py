"""zmpkit.experiments."""
