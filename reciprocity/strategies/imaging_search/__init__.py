"""The parts the reciprocity search (:class:`~reciprocity.strategies.reciprocity.ReciprocityStrategy`)
is assembled from, each a small class or a few functions with its own tests:

- :mod:`.likelihood`: eq. (7)'s ``sigma``, the model's error terms, the strength prior
  (how a reading is scored); the maps combine by :mod:`reciprocity.beliefs.combiners`;
- :mod:`.next_point`: step 13, where to read next;
- :mod:`.stop_rule`: step 12 and the stops beside it (step cap, out of reach);
- :mod:`.reachability`: where the observer can read, and which possible sources a reading
  there would see;
- :mod:`.meshing`: the candidate points on the solver's mesh, the source clearance, and
  the re-meshing when the believed walls change (``map: unknown``);
- :mod:`.several`: the search for several sources around
  :class:`~reciprocity.strategies.multi_source.SourceBook`;
- :mod:`.presets`: the named assemblies (``preset="paper"``) and the defaults.
"""
