"""The processes a command started, read from /proc: to check that none outlives it."""

import os
import signal
import time


def descendants(pid: int) -> set[int]:
    """Every living descendant of `pid`."""
    parents = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit() and state(int(entry)) not in ("Z", "gone"):
            try:
                with open(f"/proc/{entry}/stat") as fh:
                    parents[int(entry)] = int(fh.read().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                continue
    out, frontier = set(), {pid}
    while frontier:
        frontier = {p for p, pp in parents.items() if pp in frontier} - out
        out |= frontier
    return out


def state(pid: int) -> str:
    """The process state letter of `pid` (``Z`` a zombie), or ``"gone"``."""
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().rsplit(")", 1)[1].split()[0]
    except (OSError, IndexError):
        return "gone"


def kill_9_when(proc, ready, polls: int = 6000) -> tuple[set[int], set[int]]:
    """Once ``ready()`` (looked at every 0.05 s, at most `polls` times, while `proc` runs),
    SIGKILL `proc`; return its descendants at that moment and those of them still alive
    afterwards (see :func:`kill_9_and_wait`). AssertionError if `proc` ends first."""
    for _ in range(polls):
        if ready():
            break
        assert proc.poll() is None, "the command ended before it could be killed: give it more work"
        time.sleep(0.05)
    children = descendants(proc.pid)
    return children, kill_9_and_wait(proc, children)


def kill_9_and_wait(proc, children: set[int], polls: int = 600) -> set[int]:
    """SIGKILL `proc` (a Popen), then the `children` still alive after `polls` looks 0.1 s
    apart (a bound on the wait, not the assertion: the kernel ends them at once)."""
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    alive = set(children)
    for _ in range(polls):
        alive = {p for p in alive if state(p) not in ("gone", "Z")}
        if not alive:
            break
        time.sleep(0.1)
    return alive
