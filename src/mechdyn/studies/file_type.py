"""The study file type in the registry, so that ``mechdyn fields study``, ``mechdyn new study`` and
the model-file reference find its schema as they find the model types'.

A study file holds no model: it is registered without a builder, so :func:`mechdyn.load` does not
take it (:func:`mechdyn.studies.load_study` reads it). Like the capabilities' ``analyses`` modules,
this one imports nothing numerical.
"""

from __future__ import annotations

from mechdyn.registry import ModelType, register_model_type

__all__: list[str] = []

register_model_type(ModelType("study", builder=None, schema="mechdyn.studies.study_file:StudyFile"))
