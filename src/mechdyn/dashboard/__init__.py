"""A web dashboard over the results database: runs and studies, a run's page, variants compared side
by side, a study's views with variants picked from a scatter plot (``mechdyn dashboard``)."""

from mechdyn._lazy import attach

__all__ = attach(__name__, {"create_app": "app", "serve": "app", "CacheLimits": "state"})
