"""Matplotlib figures; every function returns a Figure and never calls show()."""
