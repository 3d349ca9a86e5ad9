"""Model files: TOML with units, validated, loaded into immutable models; models built in Python saved
as model files (:func:`mechdyn.save`, ``mechdyn.io.save``); commented templates of every file type
(``mechdyn new``, ``mechdyn.io.template``)."""

from mechdyn.io.modelfile import (
    LoadedModel,
    ModelSource,
    load,
    load_model,
    load_with_source,
    read,
    register_model_type,
)
from mechdyn.io.save import register_writer

__all__ = [
    "LoadedModel",
    "ModelSource",
    "load",
    "load_model",
    "load_with_source",
    "read",
    "register_model_type",
    "register_writer",
]
