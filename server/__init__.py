"""The web shell around the core pipeline (FastAPI). Nothing here computes geometry."""
