"""zmpkit.analysis: figures, tables and reports; the numerics they show live in the layers below."""
