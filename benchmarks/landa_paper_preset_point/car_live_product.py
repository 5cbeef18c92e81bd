"""The paper's loop with the product of the maps, run live on the car as the paper ran it.

The offline re-evaluation of ``landa_paper_preset.py`` replays another combination's stop on
the readings eq. (8)'s search took; step 13 breaks ties by the map, so a live search with
the product reads elsewhere. This runs it live (seeds FIRST to LAST - 1) and appends one
JSON line per run: seed, readings, error (cm), stop.

    python benchmarks/landa_paper_preset_point/car_live_product.py 0 30 --out car_live_product.jsonl
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from landa_paper_preset import D, PAPER_CAR  # noqa: E402

#: The smallest deviation from eq. (8) of the re-evaluation: the product, ε = 0.1, A_ε = 20 cm².
PARAMS = {"preset": "paper", "d": D, "combine": "product", "eps": 0.1, "area_tol": 20.0, "max_steps": 30}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("first", type=int)
    ap.add_argument("last", type=int)
    ap.add_argument("--out", type=Path, default=Path("car_live_product.jsonl"))
    a = ap.parse_args(argv)
    from reciprocity import api
    with a.out.open("a") as out:
        for seed in range(a.first, a.last):
            episode, _, _ = api.execute("paper", "reciprocity", seed=seed, params=dict(PARAMS), platform="car",
                                        platform_options=dict(PAPER_CAR))
            s = episode.summary
            out.write(json.dumps(dict(seed=seed, n=s["n_measurements"], error=s["error"], stop=s["stop_reason"]))
                      + "\n")
            out.flush()


if __name__ == "__main__":
    main()
