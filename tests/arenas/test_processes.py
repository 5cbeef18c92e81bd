"""Helper processes end with their owner, also when the owner died before they started."""

import os
import subprocess
import sys

#: A safety net against a hung child only, never a performance bound.
HANG_S = 120


def _child(code: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=HANG_S,
                          env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)})


def test_a_worker_whose_owner_is_already_gone_ends_at_once():
    """The bank's kill -9 test left a worker behind when its owner died while the worker was
    still starting: by then ``os.getppid()`` named the adoptive process, which the worker
    took for its parent. Told the owner's id, it sees the owner is gone and exits (code 1)."""
    r = _child("from arenas.processes import die_with_parent\n"
               "die_with_parent(0)\n"                      # no process of ours has id 0
               "import time; time.sleep(60); print('still here')")
    assert r.returncode == 1 and "still here" not in r.stdout


def test_a_worker_whose_owner_lives_carries_on():
    r = _child("import os\nfrom arenas.processes import die_with_parent\n"
               "die_with_parent(os.getppid())\nprint('working')")
    assert r.returncode == 0 and r.stdout.strip() == "working"
