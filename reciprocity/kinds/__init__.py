"""World kinds: the wiring of each ``world:`` of scenario files to its world (the truth) and
its platforms. The only modules that import both :mod:`reciprocity.worlds` and
:mod:`reciprocity.platforms`; each registers its kind in
:data:`reciprocity.scenarios.WORLD_KINDS` when imported (the registry imports them lazily
by name)."""
