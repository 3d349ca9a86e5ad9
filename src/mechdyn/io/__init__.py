"""Model files: TOML with units, validated, loaded into immutable models."""

from mechdyn.io.modelfile import (
    LoadedModel,
    ModelSource,
    load,
    load_model,
    load_with_source,
    read,
    register_model_type,
)

__all__ = [
    "LoadedModel",
    "ModelSource",
    "load",
    "load_model",
    "load_with_source",
    "read",
    "register_model_type",
]
