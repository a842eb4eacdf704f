"""The four-step collision pipeline: reduce, quick test, thorough test, respond."""
