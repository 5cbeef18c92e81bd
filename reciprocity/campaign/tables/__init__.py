"""The published tables that ``reciprocity reproduce`` re-runs, one module per paper.

Importing this package registers every table in
:data:`reciprocity.campaign.paper_table.TABLES` (``reciprocity.campaign.reproduce`` imports
it):

- :mod:`.landa2020` — ``landa2020-testbed`` (reciprocity vs gradient on the car testbed);
- :mod:`.ristic2014` — ``ristic2014-table1``, ``ristic2014-table2`` (RBPF search on a
  random lattice, papers/000);
- :mod:`.song2019` — ``song2019-table1`` (free-energy infotaxis and its peers, papers/002);
- :mod:`.otto` — ``otto-2d`` (grid infotaxis, otto's 2-D protocol);
- :mod:`.hajieghrary` — ``hajieghrary-voi`` (three searchers sharing by value of
  information, papers/001) and ``hajieghrary-misleading`` (the same teams when one
  searcher's sensor is wrong);
- :mod:`.farrell2003` — ``farrell-hmm`` (hidden-Markov plume mapping, papers/003, and
  its Figs. 5–8).
"""

# in the order ``reciprocity reproduce --list`` names them
from . import landa2020  # noqa: F401,I001
from . import ristic2014  # noqa: F401
from . import song2019  # noqa: F401
from . import otto  # noqa: F401
from . import hajieghrary  # noqa: F401
from . import farrell2003  # noqa: F401
