"""Figures and videos of searches.

:mod:`~reciprocity.viz.figures` draws the imaging steps and gradient runs of Landa et al.
(Figs. 4 and 5); :mod:`~reciprocity.viz.episode` draws them from an episode's record;
:mod:`~reciprocity.viz.video` writes the MP4 of a car episode;
:mod:`~reciprocity.viz.lattice`, :mod:`~reciprocity.viz.plume` and
:mod:`~reciprocity.viz.hmm` draw the comparison papers' figures. Import the module you
need: nothing is re-exported here, since some of them pick matplotlib's Agg backend and
import OpenCV on import, and two of them name a function ``search_figure``.
"""
