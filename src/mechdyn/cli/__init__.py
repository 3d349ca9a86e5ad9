"""The ``mechdyn`` command line."""
