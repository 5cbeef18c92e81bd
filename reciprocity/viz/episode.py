"""The figures of one episode, drawn from its record alone (``run(..., figures=True)``):
what the strategy recorded of its belief (:attr:`Episode.belief <reciprocity.episode.Episode.belief>`)
and the environment of the truth (:attr:`Episode.truth <reciprocity.episode.Episode.truth>`)."""

from __future__ import annotations

from arenas import Arena

from ..episode import Episode
from .figures import count_steps_figure, gradient_run_figure, imaging_steps_figure, sources_figure
from .hmm import search_map_figure
from .lattice import lattice_episode_figures
from .mapping import mapping_steps_figure
from .plume import search_figure as plume_search_figure

__all__ = ["episode_figures"]


def _finding_steps(trace) -> list[int]:
    """The steps a search for several sources is drawn at: the first, each step that found
    a source, the last (1-based)."""
    counts = [len(r.get("estimates") or []) for r in trace]
    return sorted({1, len(counts)} | {k + 1 for k in range(1, len(counts)) if counts[k] > counts[k - 1]}
                  | ({1 + counts.index(1)} if 1 in counts else set()))


def episode_figures(episode: Episode, arena: Arena | None):
    """The figures of an episode run with ``figures=True``, drawn from its record alone.

    What is drawn follows what the record holds, never the strategy's name: in a plume
    world (``truth["mean_hits"]``) the search over the true hit rate with the strategy's
    particle clouds; in a filament world (``truth["plume"]``) the track over the plume and
    the strategy's final source map; on a lattice (``truth["lattice"]``) the true lattice
    with the path and the searcher's final clouds or posterior; in an arena, the residual map of one more source (``belief["residual"]``: several sources); the imaging steps
    (``belief["steps"]``, as Fig. 4), the posterior on hit counts step by step
    (``belief["posterior"]``, over the true ``truth["wind"]``) or else the run over the
    true signal (Fig. 5: the painted floor ``truth["floor"]`` or the true ``truth["field"]``, with
    ``belief["gradients"]``); the believed map step by step (``belief["map_steps"]``: an
    unknown map, against ``truth["true_arena"]``).

    Parameters
    ----------
    episode : Episode
        Its :attr:`~Episode.belief` and :attr:`~Episode.truth` (empty: nothing is drawn).
    arena : Arena or None
        For the walls (with the episode's start); None in a world without an arena.

    Yields
    ------
    name : str
        ``"search"`` (plume, filament and lattice worlds), ``"lattice"``, ``"posterior"``,
        ``"sources"``, ``"steps"``, ``"path"``
        or ``"map_steps"``.
    figure : Figure
    """
    belief, truth = episode.belief, episode.truth
    if not belief:
        return
    if "mean_hits" in truth:
        yield "search", plume_search_figure(episode)
        return
    if "plume" in truth:
        yield "search", search_map_figure(episode)
        return
    if "lattice" in truth:
        yield from lattice_episode_figures(episode)
        return
    if "residual" in belief:
        yield "sources", sources_figure(episode, belief["residual"], arena)
    if "steps" in belief:
        steps = _finding_steps(episode.trace) if "residual" in belief else None
        yield "steps", imaging_steps_figure(episode, belief["steps"], arena, eps=belief["eps"], steps=steps,
                                            within_reach=belief.get("within_reach"))
    elif "posterior" in belief:
        yield "steps", count_steps_figure(episode, belief["posterior"], belief["triangulation"], arena,
                                          wind=truth.get("wind"))
    else:
        yield "path", gradient_run_figure(episode, truth.get("field"), arena, belief.get("gradients", ()),
                                          floor=truth.get("floor"))
    if "map_steps" in belief:
        yield "map_steps", mapping_steps_figure(episode, truth["true_arena"])
