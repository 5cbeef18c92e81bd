"""Campaigns: strategies × scenarios × seeds on Dask, results as Parquet, reports.

``reciprocity campaign SPEC.yaml --out DIR`` runs (or resumes) a campaign,
``reciprocity report DIR`` tabulates it, ``reciprocity reproduce TABLE`` re-runs a
published table beside the paper's numbers.

Episodes run on a local Dask cluster, or on a scheduler given by address. A Dask
scheduler runs whatever its clients send: a plain ``tcp://`` scheduler belongs on a
trusted network only; elsewhere use ``tls://`` with certificates of your own CA
(:mod:`reciprocity.campaign.cluster`).
"""

from .cluster import TLSFiles, dask_client
from .execute import CampaignResult, run_campaign
from .report import Report, build_report, write_report
from .reproduce import TABLES, PaperTable, PaperValue, register, reproduce
from .spec import (CampaignSpec, EpisodeTask, ScenarioEntry, StrategyVariant, episode_seed,
                   load_spec, parse_spec)
from .store import CONTRACT_SCHEMA, ResultStore, connect, episodes_sql

__all__ = ["CONTRACT_SCHEMA", "CampaignResult", "CampaignSpec", "EpisodeTask", "PaperTable",
           "PaperValue", "Report", "ResultStore", "ScenarioEntry", "StrategyVariant", "TABLES",
           "TLSFiles", "build_report", "connect", "dask_client", "episode_seed", "episodes_sql", "load_spec",
           "parse_spec", "register", "reproduce", "run_campaign", "write_report"]
