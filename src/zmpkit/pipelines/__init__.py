"""End-to-end pipelines: configuration in, artefacts out; each callable alone."""
