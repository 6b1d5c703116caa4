"""Shipped receiver-model files (TOML), read by :func:`hosedrogue.aircraft.model_file.load_model`."""
