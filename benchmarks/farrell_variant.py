"""One strategy variant on the starts of ``reciprocity reproduce farrell-hmm``, episode by
episode (the same seed index gives the same start and plume as in the table), printing
success, search time, error, distance at the stop and CPU time, and a summary.

    PYTHONPATH=. nice python benchmarks/farrell_variant.py detection-infotaxis '{"wind_window": 60}' 50
"""

import json
import sys
import time

import numpy as np

from reciprocity.campaign.spec import parse_spec
from reciprocity.campaign.worker import execute_task


def main(strategy: str, params: dict, runs: int) -> None:
    spec = parse_spec({"name": "farrell-hmm", "strategies": {strategy: params}, "seeds": runs,
                       "scenarios": [{"name": "farrell", "random_start": True}]})
    rows = []
    for task in spec.tasks():
        t0 = time.process_time()
        s = execute_task(task)[0].summary
        rows.append(dict(seed_index=task.seed_index, success=bool(s["success"]), time=s["sim_time_s"],
                         error=s["error"], distance=s["distance_at_stop"], stop=s["stop"],
                         cpu=time.process_time() - t0))
        print(json.dumps(rows[-1], default=float), flush=True)
    k, n = sum(r["success"] for r in rows), len(rows)
    z = 1.96
    p = k / n
    c, h = (p + z * z / (2 * n)) / (1 + z * z / n), z * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    t = np.array([r["time"] for r in rows])
    print(f"success {k}/{n} (95 % Wilson [{c - h:.0%}, {c + h:.0%}]), wrong stops "
          f"{sum(r['stop'] == 'converged' and not r['success'] for r in rows)}, search time "
          f"{t.mean():.0f} ± {z * t.std(ddof=1) / np.sqrt(n):.0f} s, CPU per episode "
          f"{np.mean([r['cpu'] for r in rows]):.2f} s")


if __name__ == "__main__":
    main(sys.argv[1], json.loads(sys.argv[2]) if len(sys.argv) > 2 else {},
         int(sys.argv[3]) if len(sys.argv) > 3 else 50)
