"""The reciprocity search for several sources, their number unknown: how the search
drives a :class:`~reciprocity.strategies.multi_source.SourceBook`.

With a task that allows more than one source (its ``max_sources``), the search finds the
first as with one source, then one more at a time on the readings the found ones leave
unexplained, until a further source is improbable (its posterior probability, even prior
odds, below ``more_tol``). One more is sought where the search for one source would call
it within reach (``survey_reach="reach"``), or within a given distance along the free
region of the points the observer can reach; while surveying for it, a point's hidden mass
within reach may be discounted by ``exp(-distance / survey_travel)`` from the last reading.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ...beliefs.imaging import ImagingMap
from ...errors import SearchError
from ...outcome import MAX_SOURCES
from ..base import Status
from .stop_rule import UNREACH_MASS

__all__ = ["SeveralSources", "MORE_TOL"]

#: Default ``more_tol``: a search for several sources stops once the posterior
#: probability of one more source is below it (see :mod:`..multi_source`).
MORE_TOL = 0.05


class SeveralSources:
    """The settings of a search for several sources and its book of sources.

    Parameters
    ----------
    max_sources : int, optional
        How many sources there may be; None for the task's ``max_sources``.
    more_tol : float
        Stop once the posterior probability of one more source is below this.
    survey_travel : float, optional
        Discount length (cm) of a point's hidden mass from the last reading; None for none.
    survey_reach : "reach" or float
        Where one more source is sought: within reach, or within this distance (cm,
        along the free region) of the reachable points.

    Attributes
    ----------
    book : SourceBook or None
        The sources found and the maps of one more, when the task allows several.
    bound : int
        How many sources there may be in the episode.
    """

    def __init__(self, max_sources: int | None = None, more_tol: float = MORE_TOL,
                 survey_travel: float | None = None, survey_reach: float | str = "reach"):
        if max_sources is not None and (isinstance(max_sources, bool) or int(max_sources) != max_sources
                                        or not 1 <= int(max_sources) <= MAX_SOURCES):
            raise SearchError(f"max_sources must be a whole number from 1 to {MAX_SOURCES}, or None for "
                              f"the task's; got {max_sources!r}")
        if isinstance(more_tol, bool) or not isinstance(more_tol, (int, float)) or not 0 < more_tol < 1:
            raise SearchError(f"more_tol must be a probability in (0, 1); got {more_tol!r}")
        if survey_travel is not None and (isinstance(survey_travel, bool) or not isinstance(survey_travel, (int, float))
                                          or not 0 < survey_travel < float("inf")):
            raise SearchError(f"survey_travel must be a positive length in cm, or None; got {survey_travel!r}")
        if survey_reach != "reach" and (isinstance(survey_reach, (bool, str)) or not isinstance(survey_reach, (int, float))
                                        or not 0 < survey_reach < float("inf")):
            raise SearchError(f"survey_reach must be a positive length in cm or 'reach'; got {survey_reach!r}")
        self.max_sources = None if max_sources is None else int(max_sources)
        self.more_tol = float(more_tol)
        self.survey_travel = None if survey_travel is None else float(survey_travel)
        self.survey_reach = survey_reach if survey_reach == "reach" else float(survey_reach)
        self.book = None

    def start(self, nominal: dict, imaging: ImagingMap, strength: float, wall_distance: np.ndarray) -> None:
        """A book when the task (`nominal`, or `max_sources`) allows more than one source,
        the map `imaging` its first, `strength` (nominal) each source's."""
        self.bound = int(self.max_sources or nominal.get("max_sources", 1))
        self.book = None
        if self.bound > 1:
            from ..multi_source import SourceBook
            self.book = SourceBook(imaging, float(strength), self.bound, wall_distance)

    def support(self, near_of: Callable[[], np.ndarray], reachability) -> np.ndarray:
        """Mask of the nodes where one more source is sought: within reach (``near_of()``)
        or within `survey_reach` along the free region of the `reachability`'s reachable
        nodes (:meth:`~.reachability.Reachability.within_path`)."""
        return near_of() if self.survey_reach == "reach" else reachability.within_path(self.survey_reach)

    def settle(self, im: ImagingMap, status: Status, converged: bool, converged_of: Callable,
               support_of: Callable[[], np.ndarray], node_area: np.ndarray,
               unseen: np.ndarray | None) -> tuple[ImagingMap, Status, str | None, dict]:
        """After a reading: accept a converged source (`converged`, at ``status.estimate``),
        and decide the number of sources when nothing more can hide.

        Parameters
        ----------
        im : ImagingMap
            The active map (of the source sought).
        status : Status
            The search's status after the reading.
        converged, converged_of
            Whether `im` converged; step 12 for any map (:meth:`.StopRule.converged`).
        support_of : callable
            Returns the mask of the nodes where one more source is sought.
        node_area : ndarray
            Each node's area, cm².
        unseen : ndarray of bool or None
            On an unknown map, the nodes not seen yet.

        Returns
        -------
        im : ImagingMap
            The map to search on now.
        status : Status
            With the sources found (``estimates``) and ``p_more``.
        why : str or None
            The detail of a converged stop (all sources found), else None.
        notes : dict
            For the episode's notes.
        """
        book, why, notes = self.book, None, {}
        if converged and not book.surveying:
            from ..multi_source import spread_of
            book.accept(status.estimate, spread_of(im))
            im = book.active
        found = len(book.found)
        if found:
            status = Status(book.found[0].copy(), status.region_area,
                            extra=dict(status.extra, estimates=[f.tolist() for f in book.found]))
        if book.surveying:
            more = 0.0 if book.full else book.more_probability(support_of(), node_area, unseen)
            status.extra["p_more"] = more
            if more < self.more_tol and book.next_unconfirmed(converged_of) is None:
                why = "as many as the task allows" if book.full else f"probability of one more {more:.3f} < more_tol"
                notes.update(sources_dropped=book.dropped, sources_relocated=book.relocated)
                if not book.full:       # the unreachable rule for the next source
                    out = self.more_out_of_reach(support_of, node_area, unseen)
                    notes["more_out_of_reach"] = round(out, 4)
                    if out >= 1.0 - UNREACH_MASS:
                        why += f"; one more lies out of reach with probability {out:.3f}"
                why = f"{found} source{'s' if found > 1 else ''} found; {why}"
            im = book.active
        return im, status, why, notes

    def more_out_of_reach(self, support_of: Callable[[], np.ndarray], node_area: np.ndarray,
                          unseen: np.ndarray | None) -> float:
        """The posterior probability of one more source out of reach: of one more anywhere
        in the free region, times the share of its mass outside ``support_of()``."""
        book = self.book
        everywhere = np.ones(len(node_area), dtype=bool)
        total = float(book.hidden(everywhere, node_area, unseen).sum())
        if total <= 0:
            return 0.0
        within = float(book.hidden(support_of(), node_area, unseen).sum())
        return book.more_probability(everywhere, node_area, unseen) * max(0.0, 1.0 - within / total)

    @property
    def estimates(self) -> np.ndarray | None:
        """Every source found (k, 2), cm, where the task allows several; else None."""
        return None if self.book is None else np.array(self.book.found, dtype=float).reshape(-1, 2)

    @property
    def estimates_sd(self) -> np.ndarray | None:
        """The standard deviation (cm) of the belief about each of :attr:`estimates`."""
        return None if self.book is None else np.array(self.book.spread, dtype=float)

    def params(self, bound: int | None) -> dict:
        """The settings, as :meth:`ReciprocityStrategy.params` reports them (`bound`: the
        episode's number of sources, once started)."""
        return dict(max_sources=bound if bound is not None else self.max_sources, more_tol=self.more_tol,
                    survey_travel=self.survey_travel, survey_reach=self.survey_reach)
