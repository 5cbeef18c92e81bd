"""Exceptions raised by :mod:`hjplanner`."""

__all__ = ["HJPlannerError", "PlanningError"]


class HJPlannerError(Exception):
    """Base class of every error raised on purpose by :mod:`hjplanner`."""


class PlanningError(HJPlannerError, ValueError):
    """Invalid planning input (grid, target, start pose, file) or an unreachable goal."""
