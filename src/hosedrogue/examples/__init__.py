"""Examples of user code that ship with the package, so that scenario files can name them by
entry point and Dask workers can import them (docs/controllers.md):
:mod:`hosedrogue.examples.controllers`."""
