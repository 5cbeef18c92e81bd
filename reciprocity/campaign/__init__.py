"""Campaigns: strategies × scenarios × seeds on Dask, results as Parquet, reports.

``reciprocity campaign SPEC.yaml --out DIR`` runs (or resumes) a campaign,
``reciprocity report DIR`` tabulates it, ``reciprocity reproduce TABLE`` re-runs a
published table beside the paper's numbers.

Episodes run on a local Dask cluster, or on a scheduler given by address. A Dask
scheduler runs whatever its clients send: a plain ``tcp://`` scheduler belongs on a
trusted network only; elsewhere use ``tls://`` with certificates of your own CA
(:mod:`reciprocity.campaign.cluster`).
"""

# Imported on first use (PEP 562, via lazy_loader): the campaign commands import the
# spec and cluster modules to declare their flags, not Dask, Parquet or DuckDB.
import lazy_loader as _lazy

__getattr__, __dir__, __all__ = _lazy.attach(__name__, submod_attrs={
    "cluster": ["TLSFiles", "dask_client"],
    "execute": ["CampaignResult", "run_campaign"],
    "report": ["Report", "build_report", "write_report"],
    "reproduce": ["TABLES", "PaperTable", "PaperValue", "register", "reproduce"],
    "spec": ["CampaignSpec", "EpisodeTask", "ScenarioEntry", "StrategyVariant", "episode_seed", "load_spec",
             "parse_spec"],
    "store": ["CONTRACT_SCHEMA", "ResultStore", "connect", "episodes_sql"],
})
