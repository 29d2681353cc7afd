"""Figures, the HTML report and the study's text outputs (the only layer importing matplotlib)."""
