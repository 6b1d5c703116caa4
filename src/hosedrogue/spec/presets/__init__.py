"""Named model presets: TOML files of parameter sections overriding the paper's case (see
:mod:`hosedrogue.spec.config`)."""
