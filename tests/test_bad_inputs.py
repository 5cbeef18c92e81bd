"""A corpus of bad inputs: every one is answered cleanly.

Each case runs a command line of ``reciprocity`` or ``hjplanner`` in its own empty folder,
in this process (``main(argv)``), and must

- exit with status 2,
- print exactly one line on stderr, starting ``error:``, and nothing on stdout,
- raise nothing (no traceback),
- write no file (its working folder and its home are compared before and after, the
  caches of meshes and value functions aside; paths outside named in ``absent`` must
  not appear),
- answer within :data:`ANSWER_S` seconds of this process's CPU time (the work it does,
  which other processes' load does not change; no case is judged by the wall clock).

The cases are data, in ``tests/bad_inputs/`` (each file's header says how it expands):
``worlds.yaml`` (scenario files of every world kind, each key mutated), ``arena.yaml``
(plain arena files, for every command that takes one), ``files.yaml`` (unreadable,
binary, malformed and hostile files for every command that reads YAML),
``campaign.yaml`` (campaign specs) and ``flags.yaml`` (command lines of every
subcommand). A few cases that could hang or exhaust memory also run as a subprocess of
the console script, with a timeout and an address-space limit (``subprocess.yaml``).
Arena images go through :func:`arenas.from_image` (no command takes an image); those
cases are in :data:`IMAGE_CASES`.

A case that has used :data:`WATCHDOG_S` CPU seconds is interrupted (SIGPROF) and fails as
a hang; a case blocked without working (waiting on a file or a socket) is interrupted after
:data:`SAFETY_S` seconds of the wall clock, a safety net of minutes that load cannot reach
(a case answers in well under a second of it); an address-space limit :data:`MEMORY_HEADROOM` above the process's own size turns
a runaway allocation into a MemoryError instead of an exhausted machine.

Cases that fail today are listed in :data:`XFAIL` (strict: a fixed case must leave the
table), with the owner of the fix and what happens.
"""

from __future__ import annotations

import contextlib
import functools
import io
import json
import os
import re
import resource
import shutil
import signal
import struct
import subprocess
import sys
import time
import warnings
import zipfile
import zlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest
import yaml

CORPUS = Path(__file__).parent / "bad_inputs"
#: Every case answers within this many CPU seconds (its work, not the wall clock).
ANSWER_S = 5.0
#: A case that has used this many CPU seconds is stopped and fails as a hang.
WATCHDOG_S = 8.0
#: A case blocked for this many wall-clock seconds is stopped: a safety net against a
#: blocking read, far above what any load makes of a case's CPU budget.
SAFETY_S = 300.0
#: Address space a case may add to this process, bytes.
MEMORY_HEADROOM = 3 * 2**30
#: Subprocess cases: CPU-time limit (s, RLIMIT_CPU), wall-clock safety net (s) and
#: address-space limit (bytes).
SUBPROCESS_CPU_S = 20
SUBPROCESS_TIMEOUT_S = 300.0
SUBPROCESS_MEMORY = 4 * 2**30
MISSING = object()


# ---------------------------------------------------------------------------------------
# Cases that fail today: case id -> "owner: what happens". Owners: bounds (world,
# strategy, platform and scenario keys), hj (hjplanner CLI, images, npz), campaign
# (campaign, report, reproduce), cli (reciprocity run/demo flags and output paths),
# yaml (file reading). Remove a line when its fix lands (the marks are strict).
XFAIL: dict[str, str] = {
}


# ---------------------------------------------------------------------------------------
# The corpus


@dataclass(frozen=True)
class Case:
    """One bad input.

    Attributes
    ----------
    id : str
    argv : tuple of str
        The command line, its first item ``reciprocity`` or ``hjplanner``; ``@NAME`` is a
        file of :data:`ARTIFACTS` or of `files`, made in the case's folder.
    subcommand : str
        ``run``, ``demo``, ..., ``hjplanner solve`` (for the corpus' tally).
    world : str or None
        World kind the case exercises.
    kind : str
        ``yaml``, ``flags``, ``image`` or ``npz``: what is bad.
    files : tuple of (name, bytes)
        Files written into the case's folder first.
    absent : tuple of str
        Paths outside the folder that must not exist afterwards.
    """

    id: str
    argv: tuple
    subcommand: str
    world: str | None = None
    kind: str = "flags"
    files: tuple = ()
    absent: tuple = ()


def _load(name: str):
    return yaml.safe_load((CORPUS / name).read_text())


@functools.cache
def _palette() -> dict:
    return _load("worlds.yaml")["palette"]


def _value(token):
    if isinstance(token, str) and token.startswith("$"):
        return MISSING if token == "$missing" else _palette()[token[1:]]
    return token


def _slug(token) -> str:
    if isinstance(token, str) and token.startswith("$"):
        return token[1:]
    text = json.dumps(token, separators=(",", ":"))
    for a, b in (("{", "map."), ("[", "list."), ("}", ""), ("]", ""), (":", "="), (",", "_"), ('"', "")):
        text = text.replace(a, b)
    return re.sub(r"[^A-Za-z0-9.+=-]+", "_", text).strip("_")[:60] or "empty"


def _yaml(mapping) -> bytes:
    return yaml.safe_dump(mapping, sort_keys=False).encode()


def _mutations(spec: dict):
    """(id suffix, mutated mapping) of a spec with `base`, `keys` and `variants`."""
    base = spec["base"]
    for key, tokens in spec.get("keys", {}).items():
        for token in tokens:
            data = dict(base)
            value = _value(token)
            if value is MISSING:
                data.pop(key, None)
            else:
                data[key] = value
            yield f"{key}-{_slug(token)}", data
    for v in spec.get("variants", []):
        data = {k: x for k, x in base.items() if k not in v.get("drop", ())}
        data.update(v.get("set", {}))
        yield v["id"], data


@functools.cache
def _world_bases() -> dict:
    """World kind name -> its valid base scenario (worlds.yaml)."""
    return {name: w["base"] for name, w in _load("worlds.yaml")["worlds"].items()}


def _world_cases() -> list[Case]:
    out = []
    for name, w in _load("worlds.yaml")["worlds"].items():
        world = w.get("world", name)
        argv = ("reciprocity", "run", "--scenario", "@scenario.yaml", "--strategy", w["strategy"],
                *w["flags"], "--quiet")
        for suffix, data in _mutations(w):
            out.append(Case(f"scenario-{name}-{suffix}", argv, "run", world, "yaml",
                            (("scenario.yaml", _yaml(data)),)))
    return out


def _arena_cases() -> list[Case]:
    spec = _load("arena.yaml")
    out = []
    for ep, argv in spec["entry_points"].items():
        sub = "run" if argv[0] == "reciprocity" else f"hjplanner {argv[1]}"
        for suffix, data in _mutations(spec):
            out.append(Case(f"arena-{ep}-{suffix}", tuple(argv), sub, "poisson", "yaml",
                            (("arena.yaml", _yaml(data)),)))
    return out


def _content(c: dict, texts: dict, bomb: str) -> bytes:
    if "text" in c:
        return c["text"].encode()
    if "hex" in c:
        return bytes.fromhex(c["hex"])
    if "parts" in c:
        return "".join(s * n for s, n in c["parts"]).encode()
    text = texts[c["entry"]]
    pad = "# padding padding padding padding padding padding padding\n" * 20_000
    return (text.replace("{BOMB}", bomb).replace("{ALIASES}", ", ".join(["*s"] * 200))
            .replace("{PAD}", pad).encode())


def _file_cases() -> list[Case]:
    spec = _load("files.yaml")
    out = []
    for ep, entry in spec["entry_points"].items():
        argv = entry["argv"]
        sub = {"reciprocity": argv[1]}.get(argv[0], f"hjplanner {argv[1]}")
        for c in spec["contents"]:
            files = ()
            if "artifact" in c:
                where = f"@{c['artifact']}"
            elif "path" in c:
                where = c["path"]
            else:
                where = "@input.yaml"
                files = (("input.yaml", _content(c, entry["texts"], spec["bomb"])),)
            kind = {"floor.png": "image", "value.npz": "npz"}.get(c.get("artifact"), "yaml")
            out.append(Case(f"file-{ep}-{c['id']}", tuple(where if a == "@F" else a for a in argv),
                            sub, None, kind, files))
    return out


def _campaign_cases() -> list[Case]:
    spec = _load("campaign.yaml")
    extra = tuple((name, text.encode()) for name, text in spec.get("files", {}).items())
    bases = tuple((f"{name}.yaml", _yaml(data)) for name, data in _world_bases().items())
    out = []
    for suffix, data in _mutations(spec):
        out.append(Case(f"campaign-spec-{suffix}", tuple(spec["command"]), "campaign", None, "yaml",
                        (("spec.yaml", _yaml(data)), *extra, *bases)))
    return out


def _flag_cases() -> list[Case]:
    spec = _load("flags.yaml")
    out = []
    for group in spec["groups"]:
        for c in group["cases"]:
            argv = list(c["argv"] if "argv" in c else spec["templates"][c["use"]])
            if "strategy" in c:
                argv[argv.index("--strategy") + 1] = c["strategy"]
            argv += c.get("add", [])
            text = " ".join(argv)
            kind = "npz" if "npz-" in text else "image" if ".png" in text and "--plot" not in text else "flags"
            out.append(Case(f"flag-{c['id']}", tuple(argv), group["subcommand"], group.get("world"),
                            kind, absent=tuple(c.get("absent", ()))))
    return out


@functools.cache
def all_cases() -> tuple[Case, ...]:
    """Every in-process case of the corpus."""
    cases = (*_world_cases(), *_arena_cases(), *_file_cases(), *_campaign_cases(), *_flag_cases())
    ids = [c.id for c in cases]
    dup = sorted({i for i in ids if ids.count(i) > 1})
    assert not dup, f"duplicate case ids: {dup}"
    return cases


# ---------------------------------------------------------------------------------------
# Files the cases refer to as @NAME


def _png(path: Path, size=(32, 32)) -> None:
    import cv2
    img = np.full(size, 255, np.uint8)
    img[8:16, 8:16] = 0
    cv2.imwrite(str(path), img)


def _npz_members(src: Path) -> dict:
    with np.load(src, allow_pickle=False) as data:
        return {k: data[k] for k in data.files}


def _with_meta(src: Path, **changes) -> dict:
    arrays = _npz_members(src)
    meta = json.loads(str(arrays["meta"]))
    grid = changes.pop("grid", None)
    if grid:
        meta["grid"].update(grid)
    meta.update(changes)
    arrays["meta"] = np.array(json.dumps(meta))
    return arrays


def _npy_header_only(shape, dtype="|u1") -> bytes:
    """A .npy member whose header claims `shape` but holds a few bytes of data."""
    buf = io.BytesIO()
    np.lib.format.write_array_header_1_0(buf, {"descr": dtype, "fortran_order": False, "shape": shape})
    return buf.getvalue() + b"\0" * 64


def _npz_variant(name: str, src: Path, path: Path) -> None:
    """The bad value-function file `name` (``npz-...``), made from the valid `src`."""
    good = src.read_bytes()
    if name == "npz-random-bytes.npz":
        path.write_bytes(bytes(range(256)) * 8)
    elif name == "npz-truncated.npz":
        path.write_bytes(good[:len(good) // 2])
    elif name == "npz-text.npz":
        path.write_text("this is not a value function\n")
    elif name == "npz-empty.npz":
        path.write_bytes(b"")
    elif name == "npz-zip-bomb.npz":
        arrays = _npz_members(src)
        with zipfile.ZipFile(path, "w") as z:
            for k, v in arrays.items():
                if k != "phi_high":
                    with z.open(f"{k}.npy", "w") as fh:
                        np.lib.format.write_array(fh, v, allow_pickle=False)
            z.writestr("phi_high.npy", _npy_header_only((10**6, 10**6)))
    else:
        arrays = {
            "npz-no-arrays.npz": lambda: {},
            "npz-pickled.npz": lambda: {**_npz_members(src), "meta": np.array([{"a": 1}], dtype=object)},
            "npz-meta-only.npz": lambda: {"meta": _npz_members(src)["meta"]},
            "npz-meta-not-json.npz": lambda: {**_npz_members(src), "meta": np.array("not json {")},
            "npz-meta-list.npz": lambda: {**_npz_members(src), "meta": np.array("[1, 2]")},
            "npz-wrong-format.npz": lambda: _with_meta(src, format="nope"),
            "npz-missing-phi.npz": lambda: {k: v for k, v in _npz_members(src).items() if k != "phi_high"},
            "npz-phi-wrong-shape.npz": lambda: {**_npz_members(src),
                                                "phi_high": _npz_members(src)["phi_high"][:1]},
            "npz-phi-float.npz": lambda: {**_npz_members(src),
                                          "phi_low": _npz_members(src)["phi_low"].astype(float)},
            "npz-grid-huge.npz": lambda: _with_meta(src, grid={"nx": 10**9, "ny": 10**9}),
            "npz-grid-negative-h.npz": lambda: _with_meta(src, grid={"h": -1.0}),
            "npz-n-obstacles-huge.npz": lambda: {**_npz_members(src), "n_obstacles": np.array(10**12)},
            "npz-quantum-nan.npz": lambda: _with_meta(src, quantum=float("nan")),
            "npz-free-wrong-shape.npz": lambda: {**_npz_members(src), "free": np.ones((2, 2), bool)},
        }[name]()
        with open(path, "wb") as fh:
            np.savez(fh, **arrays)


class Shared:
    """Inputs made once per session: a valid value function, a finished campaign."""

    def __init__(self, root: Path):
        self.root = root

    @functools.cached_property
    def value_npz(self) -> Path:
        from hjplanner import solve
        path = self.root / "value.npz"
        solve(((0.0, 20.0), (0.0, 20.0)), (10.0, 10.0), rho=2.0, h=1.0, ntheta=8).save(path)
        return path

    @functools.cached_property
    def results(self) -> Path:
        """A finished campaign (one random-walk episode on ``empty``), run without Dask."""
        from reciprocity.campaign.spec import parse_spec
        from reciprocity.campaign.store import ResultStore
        from reciprocity.campaign.worker import run_task
        folder = self.root / "results"
        spec = parse_spec({"name": "corpus", "seeds": 1, "strategies": {"random-walk": {"n_steps": 2}},
                           "scenarios": ["empty"]})
        with ResultStore.open(folder, spec) as store:
            store.write([run_task(t) for t in spec.tasks()])
        return folder

    @functools.cached_property
    def foreign_parquet(self) -> Path:
        import pyarrow as pa
        import pyarrow.parquet as pq
        folder = self.root / "foreign-parquet"
        folder.mkdir()
        pq.write_table(pa.table({"x": [1, 2, 3]}), folder / "data.parquet")
        return folder


def _make(name: str, path: Path, shared: Shared) -> None:
    """Make the file or folder `name` of a case at `path`."""
    bases = {f"{k}.yaml": v for k, v in _world_bases().items()}
    if name in bases:
        path.write_bytes(_yaml(bases[name]))
    elif name == "campaign.yaml":
        path.write_bytes(_yaml(_load("campaign.yaml")["base"]))
    elif name == "file.txt":
        path.write_text("just some text\n")
    elif name == "folder":
        path.mkdir()
    elif name == "fifo":
        os.mkfifo(path)
    elif name == "floor.png":
        _png(path)
    elif name == "value.npz":
        shutil.copy(shared.value_npz, path)
    elif name.startswith("npz-"):
        _npz_variant(name, shared.value_npz, path)
    elif name == "results":
        shutil.copytree(shared.results, path)
    elif name == "foreign-parquet":
        shutil.copytree(shared.foreign_parquet, path)
    elif name == "fake-parquet":
        path.mkdir()
        (path / "part-0.parquet").write_text("not parquet\n")
    elif name == "campaign-json-garbage":
        path.mkdir()
        (path / "campaign.json").write_text("garbage {")
    else:
        raise KeyError(f"no artifact {name!r}")


_AT = re.compile(r"@([A-Za-z0-9_.-]+)")


def prepare(case: Case, folder: Path, shared: Shared) -> list[str]:
    """Write the case's files into `folder`; return its argv with every ``@NAME`` resolved
    (program name first)."""
    for name, data in case.files:
        (folder / name).write_bytes(data)
    argv = []
    for arg in case.argv:
        for name in _AT.findall(arg):
            if not (folder / name).exists() and not (folder / name).is_symlink():
                _make(name, folder / name, shared)
        argv.append(_AT.sub(lambda m: str(folder / m.group(1)), arg))
    return argv


def _snapshot(*roots: Path) -> dict:
    out = {}
    for root in roots:
        for dirpath, dirnames, filenames in os.walk(root):
            for n in dirnames + filenames:
                p = Path(dirpath) / n
                with contextlib.suppress(OSError):
                    st = p.lstat()
                    out[str(p)] = (st.st_size, st.st_mtime_ns)
    return out


def _changes(before: dict, after: dict, root: Path) -> list[str]:
    changed = [p for p in after if before.get(p) != after[p]]
    gone = [p for p in before if p not in after]
    return sorted(os.path.relpath(p, root) for p in changed + gone)


# ---------------------------------------------------------------------------------------
# Running a case


class Hang(BaseException):
    """Raised by the watchdog; a BaseException so that ``except Exception`` lets it by."""


@contextlib.contextmanager
def watchdog(seconds: float):
    """Interrupt the block with :class:`Hang` once this process has used `seconds` of CPU
    time (or after :data:`SAFETY_S` of the wall clock, should it block without working),
    and cap the address space at :data:`MEMORY_HEADROOM` above the current size.

    CPU time measures the work a case does: a machine busy with other processes slows the
    wall clock, not this count."""
    def ring(signum, frame):
        raise Hang()

    old = signal.signal(signal.SIGALRM, ring)
    old_prof = signal.signal(signal.SIGPROF, ring)
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    size = _vm_size()
    if size:
        cap = size + MEMORY_HEADROOM
        resource.setrlimit(resource.RLIMIT_AS, (cap if hard == resource.RLIM_INFINITY else min(cap, hard), hard))
    signal.setitimer(signal.ITIMER_PROF, seconds)
    signal.setitimer(signal.ITIMER_REAL, SAFETY_S)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
        signal.signal(signal.SIGPROF, old_prof)
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


def _vm_size() -> int:
    """This process's address space, bytes (0 where /proc is missing)."""
    try:
        status = Path("/proc/self/status").read_text()
    except OSError:
        return 0
    m = re.search(r"VmSize:\s+(\d+) kB", status)
    return int(m.group(1)) * 1024 if m else 0


@contextlib.contextmanager
def _console_warnings():
    """Record the warnings the console script would print on stderr (Python's default
    filters: deprecations and resource warnings hidden), as a list."""
    with warnings.catch_warnings(record=True) as shown:
        warnings.resetwarnings()
        for category in (DeprecationWarning, PendingDeprecationWarning, ImportWarning, ResourceWarning):
            warnings.filterwarnings("ignore", category=category)
        yield shown


def _main(prog: str):
    if prog == "reciprocity":
        from reciprocity.cli import main
    else:
        from hjplanner.cli import main
    return main


@dataclass
class Outcome:
    """What a case did."""

    code: object = None
    out: str = ""
    err: str = ""
    seconds: float = 0.0  # CPU seconds
    raised: str | None = None
    written: list = field(default_factory=list)
    appeared: list = field(default_factory=list)


def problems(o: Outcome) -> list[str]:
    """How an outcome differs from a clean refusal (empty: clean)."""
    found = []
    if o.raised:
        found.append(o.raised)
    elif o.code != 2:
        found.append(f"exit {o.code}" + (" (accepted)" if o.code == 0 else ""))
    # the one warning a refusal may carry: a plain tcp:// scheduler is always warned about
    lines = [ln for ln in o.err.strip().splitlines() if not re.match(r"warning: scheduler '.*' is plain TCP", ln)]
    warned = [m.group(0) for m in map(re.compile(r"\w+Warning: .*").search, lines) if m]
    if "Traceback" in o.err + o.out:
        found.append("traceback printed")
    elif warned:
        found.append(f"{len(warned)} warning(s) printed, the first {warned[0][:80]!r}")
    elif not o.raised and o.code != 0 and (len(lines) != 1 or not lines[0].startswith("error: ")):
        found.append(f"stderr has {len(lines)} lines" + (f", first {lines[0][:100]!r}" if lines else ""))
    if o.out.strip() and not o.raised and o.code != 0:
        found.append(f"stdout not empty ({o.out.strip().splitlines()[0][:60]!r})")
    if o.written:
        found.append(f"wrote {', '.join(o.written[:3])}{' ...' if len(o.written) > 3 else ''}")
    if o.appeared:
        found.append(f"created {', '.join(o.appeared)}")
    if o.seconds > ANSWER_S and not (o.raised or "").startswith("hang"):
        found.append(f"slow ({o.seconds:.1f} CPU s)")
    return found


def run_in_process(case: Case, folder: Path, shared: Shared, capsys, monkeypatch) -> Outcome:
    """Run `case` in this process, in `folder` (with its own home and caches).

    The caches (meshes, value functions) are not watched: what they hold depends on the
    cases run before in this process (their in-memory copies)."""
    work, home = folder / "work", folder / "home"
    work.mkdir()
    home.mkdir()
    argv = prepare(case, work, shared)
    monkeypatch.chdir(work)
    for name, value in _environment(folder, shared).items():
        monkeypatch.setenv(name, value)
    before = _snapshot(work, home)
    capsys.readouterr()
    o, shown = Outcome(), []
    t0 = time.process_time()
    try:
        with watchdog(WATCHDOG_S), _console_warnings() as shown:
            o.code = _main(argv[0])(argv[1:])
    except Hang:
        o.raised = f"hang (stopped after {WATCHDOG_S:g} CPU s)"
    except SystemExit as exc:
        o.code = exc.code
    except BaseException as exc:  # the finding: a traceback
        o.raised = f"{type(exc).__name__}: {str(exc).splitlines()[0][:120] if str(exc) else ''}"
    o.seconds = time.process_time() - t0
    captured = capsys.readouterr()
    o.out, o.err = captured.out, captured.err + "".join(
        f"{w.filename}:{w.lineno}: {w.category.__name__}: {w.message}\n" for w in shown)
    o.written = _changes(before, _snapshot(work, home), folder)
    o.appeared = [p for p in case.absent if os.path.lexists(p)]
    return o


def _environment(folder: Path, shared: Shared) -> dict:
    """A case's home and caches, in `folder`; matplotlib's configuration shared."""
    return {"HOME": str(folder / "home"), "RECIPROCITY_CACHE": str(folder / "cache" / "reciprocity"),
            "HJPLANNER_CACHE": str(folder / "cache" / "hjplanner"),
            "MPLCONFIGDIR": str(shared.root / "matplotlib")}


def _param(case: Case):
    marks = [pytest.mark.xfail(strict=True, reason=XFAIL[case.id])] if case.id in XFAIL else []
    return pytest.param(case, id=case.id, marks=marks)


@pytest.fixture(scope="session")
def shared(tmp_path_factory) -> Shared:
    return Shared(tmp_path_factory.mktemp("shared"))


@pytest.mark.parametrize("case", [_param(c) for c in all_cases()])
def test_bad_input_is_refused_cleanly(case, shared, tmp_path, capsys, monkeypatch):
    o = run_in_process(case, tmp_path, shared, capsys, monkeypatch)
    found = problems(o)
    assert not found, f"{case.id}: {'; '.join(found)}\n  argv: {' '.join(case.argv)}\n  stderr: {o.err[-500:]}"


# ---------------------------------------------------------------------------------------
# Cases that could hang or exhaust memory, also run as a subprocess of the console script


def _subprocess_cases() -> list[Case]:
    spec = _load("subprocess.yaml")
    by_id = {c.id: c for c in all_cases()}
    out = [by_id[i] for i in spec["also_in_process"]]
    for c in spec["only"]:
        files = tuple((name, _yaml({**_world_bases()[v["base"]], **v.get("set", {})}) if isinstance(v, dict)
                       else v.encode()) for name, v in c.get("files", {}).items())
        out.append(Case(c["id"], tuple(c["argv"]), c["subcommand"], c.get("world"), c.get("kind", "flags"),
                        files))
    return out


def _console_script(prog: str) -> list[str]:
    script = Path(sys.executable).with_name(prog)
    if script.exists():
        return [str(script)]
    return [sys.executable, "-m", {"reciprocity": "reciprocity.cli", "hjplanner": "hjplanner.cli"}[prog]]


def _limit_memory():
    resource.setrlimit(resource.RLIMIT_AS, (SUBPROCESS_MEMORY, SUBPROCESS_MEMORY))
    resource.setrlimit(resource.RLIMIT_CPU, (SUBPROCESS_CPU_S, SUBPROCESS_CPU_S + 5))


def _children_cpu() -> float:
    """CPU seconds used by this process's finished children."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_subprocess(case: Case, folder: Path, shared: Shared) -> Outcome:
    """Run `case` as a subprocess of its console script (time and memory limited)."""
    work, home = folder / "work", folder / "home"
    work.mkdir()
    home.mkdir()
    argv = prepare(case, work, shared)
    root = str(Path(__file__).resolve().parents[1])
    env = dict(os.environ, **_environment(folder, shared),
               PYTHONPATH=os.pathsep.join([root, *filter(None, os.environ.get("PYTHONPATH", "").split(os.pathsep))]))
    before = _snapshot(work, home)
    o = Outcome()
    t0 = _children_cpu()
    proc = subprocess.Popen(_console_script(argv[0]) + argv[1:], cwd=work, env=env, stdin=subprocess.DEVNULL,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=_limit_memory, start_new_session=True)
    try:
        o.out, o.err = proc.communicate(timeout=SUBPROCESS_TIMEOUT_S)
        o.code = proc.returncode
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        o.out, o.err = proc.communicate()
        o.raised = f"hang (killed after {SUBPROCESS_TIMEOUT_S:g} s)"
    o.seconds = _children_cpu() - t0
    if o.code == -signal.SIGXCPU:
        o.raised = f"hang (stopped after {SUBPROCESS_CPU_S:g} CPU s)"
    elif o.code is not None and o.code < 0:
        o.raised = f"killed by signal {-o.code}"
    if "MemoryError" in o.err:
        o.raised = "MemoryError"
    o.written = _changes(before, _snapshot(work, home), folder)
    o.appeared = [p for p in case.absent if os.path.lexists(p)]
    return o


def _sub_param(case: Case):
    sid = f"sub-{case.id}"
    marks = [pytest.mark.xfail(strict=True, reason=XFAIL[sid])] if sid in XFAIL else []
    return pytest.param(case, id=sid, marks=marks)


@pytest.mark.parametrize("case", [_sub_param(c) for c in _subprocess_cases()])
def test_hostile_input_fails_fast_in_a_subprocess(case, shared, tmp_path):
    o = run_subprocess(case, tmp_path, shared)
    # a subprocess pays the interpreter's start-up: only its time limit applies
    found = [p for p in problems(o) if not p.startswith("slow")]
    assert not found, f"{case.id}: {'; '.join(found)}\n  argv: {' '.join(case.argv)}\n  stderr: {o.err[-500:]}"


# ---------------------------------------------------------------------------------------
# Arena images: arenas.from_image (no command takes an image)


def _png_claiming(width: int, height: int) -> bytes:
    """A PNG whose header claims width x height pixels, with almost no data."""
    def chunk(tag: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data))
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(b"\0" * 64))
            + chunk(b"IEND", b""))


def _image_file(kind: str, folder: Path) -> Path:
    path = folder / "floor.png"
    if kind == "missing":
        return folder / "nowhere.png"
    if kind == "folder":
        path.mkdir()
    elif kind == "text":
        path.write_text("not an image\n")
    elif kind == "empty":
        path.write_bytes(b"")
    elif kind == "truncated":
        _png(folder / "good.png", (64, 64))
        path.write_bytes((folder / "good.png").read_bytes()[:40])
    elif kind == "huge-header":
        path.write_bytes(_png_claiming(100_000, 100_000))
    elif kind == "tiny":
        _png(path, (2, 2))
    elif kind == "black":
        import cv2
        cv2.imwrite(str(path), np.zeros((32, 32), np.uint8))
    else:
        _png(path)
    return path


#: (id, image: a file kind of _image_file or an array, keyword arguments of from_image)
IMAGE_CASES = [
    ("missing-file", "missing", {}),
    ("a-folder", "folder", {}),
    ("text-file-named-png", "text", {}),
    ("empty-file", "empty", {}),
    ("truncated-png", "truncated", {}),
    ("png-header-claims-1e10-pixels", "huge-header", {}),
    ("two-by-two-pixels", "tiny", {}),
    ("all-black", "black", {}),
    ("cm-per-px-zero", "good", {"cm_per_px": 0}),
    ("cm-per-px-negative", "good", {"cm_per_px": -1}),
    ("cm-per-px-nan", "good", {"cm_per_px": float("nan")}),
    ("cm-per-px-inf", "good", {"cm_per_px": float("inf")}),
    ("cm-per-px-huge", "good", {"cm_per_px": 1e308}),
    ("cm-per-px-text", "good", {"cm_per_px": "big"}),
    ("threshold-negative", "good", {"threshold": -1}),
    ("threshold-300", "good", {"threshold": 300}),
    ("threshold-text", "good", {"threshold": "dark"}),
    ("simplify-negative", "good", {"simplify_cm": -1}),
    ("simplify-nan", "good", {"simplify_cm": float("nan")}),
    ("min-area-nan", "good", {"min_area_cm2": float("nan")}),
    ("source-outside", "good", {"source": [500, 500]}),
    ("source-text", "good", {"source": "corner"}),
    ("start-in-obstacle", "good", {"start": [12, 20]}),  # the dark square: x 8-16, y 16-24 cm
    ("strength-negative", "good", {"strength": -1}),
    ("unknown-keyword", "good", {"colour": 1}),
    ("array-1d", np.zeros(16, np.uint8), {}),
    ("array-empty", np.zeros((0, 0), np.uint8), {}),
    ("array-four-channels", np.zeros((16, 16, 4), np.uint8), {}),
    ("array-two-channels", np.zeros((16, 16, 2), np.uint8), {}),
    ("array-nan", np.full((16, 16), np.nan), {}),
    ("array-of-text", np.full((16, 16), "x"), {}),
    ("array-4d", np.zeros((4, 4, 4, 4), np.uint8), {}),
]


def _image_param(case):
    cid = f"image-{case[0]}"
    marks = [pytest.mark.xfail(strict=True, reason=XFAIL[cid])] if cid in XFAIL else []
    return pytest.param(*case, id=cid, marks=marks)


@pytest.mark.parametrize("name, image, kwargs", [_image_param(c) for c in IMAGE_CASES])
def test_bad_arena_image_raises_arena_error(name, image, kwargs, tmp_path):
    import arenas
    src = _image_file(image, tmp_path) if isinstance(image, str) else image
    kwargs = {"cm_per_px": 1.0, **kwargs}
    t0 = time.process_time()
    with watchdog(WATCHDOG_S):
        try:
            arenas.from_image(src, **kwargs)
        except arenas.ArenaError as exc:
            message = str(exc)
        except Hang:
            pytest.fail(f"hang (stopped after {WATCHDOG_S:g} CPU s)")
        else:
            pytest.fail("accepted")
    assert message and "\n" not in message
    assert time.process_time() - t0 < ANSWER_S


# ---------------------------------------------------------------------------------------
# The corpus itself


def _controls() -> list[Case]:
    """The valid inputs the corpus mutates, as cases that must run (exit 0): a base that
    failed would make every mutation of it pass for the wrong reason. The demo, car,
    campaign and reproduce templates are left out (each takes seconds: a car, or Dask)."""
    out = [Case(f"control-world-{name}", ("reciprocity", "run", "--scenario", f"@{name}.yaml", "--strategy",
                                          w["strategy"], *w["flags"], "--quiet"), "run")
           for name, w in _load("worlds.yaml")["worlds"].items()]
    arena = _load("arena.yaml")
    out += [Case(f"control-arena-{ep}", tuple(argv), "run", files=(("arena.yaml", _yaml(arena["base"])),))
            for ep, argv in arena["entry_points"].items()]
    templates = _load("flags.yaml")["templates"]
    out += [Case(f"control-{name}", tuple(templates[name]), name)
            for name in ("run-poisson", "run-paper", "run-lattice", "run-plume", "run-filament", "report",
                         "hj-solve", "hj-path", "hj-bank")]
    return out


@pytest.mark.parametrize("case", [pytest.param(c, id=c.id) for c in _controls()])
def test_the_inputs_the_corpus_mutates_are_valid(case, shared, tmp_path, capsys, monkeypatch):
    o = run_in_process(case, tmp_path, shared, capsys, monkeypatch)
    assert o.code == 0 and not o.raised, f"{o.raised or o.code}: {o.err[-500:]}"


def test_the_base_campaign_spec_is_valid(tmp_path):
    from reciprocity.campaign.spec import load_spec
    path = tmp_path / "spec.yaml"
    path.write_bytes(_yaml(_load("campaign.yaml")["base"]))
    assert load_spec(path).n_episodes == 1


def test_the_corpus_covers_every_subcommand_and_world_kind():
    cases = all_cases()
    subs = {c.subcommand for c in cases}
    assert {"run", "demo", "campaign", "report", "reproduce", "scenarios", "strategies",
            "hjplanner solve", "hjplanner path", "hjplanner bank"} <= subs
    assert {c.world for c in cases} >= {"poisson", "lattice", "plume", "filament"}
    assert {c.kind for c in cases} >= {"yaml", "flags", "image", "npz"}
    assert len(cases) >= 250
    assert set(XFAIL) <= {c.id for c in cases} | {f"sub-{c.id}" for c in _subprocess_cases()} | {
        f"image-{c[0]}" for c in IMAGE_CASES}, "XFAIL names a case that does not exist"
