"""Clearing the toolkit's in-memory caches, as a new process would start."""

import sys


def forget_in_memory_caches() -> None:
    """Clear every module-level ``lru_cache`` of the toolkit, so that the next run reads
    (or computes) its meshes and fields anew, as a new process would."""
    for name, module in list(sys.modules.items()):
        if module is None or name.split(".")[0] not in ("arenas", "reciprocity", "hjplanner"):
            continue
        for obj in list(vars(module).values()):
            if callable(getattr(obj, "cache_clear", None)) and getattr(obj, "__module__", None) == name:
                obj.cache_clear()
