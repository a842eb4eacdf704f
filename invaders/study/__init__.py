"""Measuring the pipeline: an exact oracle, shadow scoring, and (to come) the method matrix."""
