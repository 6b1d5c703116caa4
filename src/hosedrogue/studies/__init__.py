"""Studies: library functions that produce the data of a report section (no files, no figures)."""
