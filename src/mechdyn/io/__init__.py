"""Model files: TOML with units, validated, loaded into immutable models."""

from mechdyn.io.modelfile import ModelSource, load, load_with_source, read, register_model_type

__all__ = ["ModelSource", "load", "load_with_source", "read", "register_model_type"]
