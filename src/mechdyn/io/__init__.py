"""Model files: TOML with units, validated, loaded into immutable models; models built in Python saved
as model files (:func:`mechdyn.save`, ``mechdyn.io.save``); commented templates of every file type
(``mechdyn new``, ``mechdyn.io.template``).

The file types are those registered in :mod:`mechdyn.registry` (:class:`mechdyn.registry.ModelType`,
one per ``[model] type``, each by its capability); this package names none of them.
:func:`register_model_type` (name, builder, schema) and :func:`register_writer` are the former,
narrower ways to add a type or a writer, kept working.
"""

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
