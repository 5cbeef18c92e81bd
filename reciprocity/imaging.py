"""The imaging map's former home: :mod:`reciprocity.beliefs.imaging` holds it now.

Kept as a re-export because ``reciprocity.viz`` (its figures and the unknown-map replay)
imports ``reciprocity.imaging``; the figures belong to another change under issue 37.
"""

from .beliefs.combiners import COMBINATIONS
from .beliefs.imaging import ImagingMap
from .beliefs.level_sets import superlevel_area

__all__ = ["ImagingMap", "superlevel_area", "COMBINATIONS"]
