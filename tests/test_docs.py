"""The documentation runs: every command, snippet and file the README shows, and every
example of a ``--help`` text.

The README's fenced blocks run in document order, in one empty folder, as a new user
would type them:

- ``yaml`` blocks are parsed by the strict loader, and checked as what they are (arena,
  scenario or campaign spec); one whose first line is ``# NAME.yaml`` is written to NAME,
  for the commands after it;
- ``bash`` blocks run line by line in a shell with the installed console scripts (a
  trailing ``# comment`` is the shell's own); the install and test steps of the set-up
  lines are skipped, as :data:`SKIPPED` says why;
- ``python`` blocks run in one namespace, so a block may use the names of an earlier one.

Budgets are cut only through :data:`BUDGET`: exact substitutions of the README's text,
each of which must still be found in it, so the README cannot drift from what runs.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: Markdown files whose blocks run (the benchmark reports only record results): the README
#: and every page of docs/ and its folders (docs/tutorials/), each in its own empty folder.
DOCS = ("README.md", *sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "docs").rglob("*.md")))
#: Command prefixes not run, and why.
SKIPPED = {
    "python3 -m venv": "the environment exists: .ci/run creates it from scratch the same way",
    ". .venv/bin/activate": "the environment is active",
    "pip install": "the package is installed: .ci/run installs it from scratch the same way",
    "python -m pytest": "it is this test suite",
}
#: Exact substitutions (README text -> what runs) that cut a command's budget.
BUDGET = {
    "reciprocity demo --out demo_out": "reciprocity demo --out demo_out --no-video --quiet",
    "--spacing 12.7 --rho 15 --h 1.5 --ntheta 48": "--spacing 70 --rho 15 --h 1.5 --ntheta 48",
    "seeds: 20 ": "seeds: 1 ",
    "landa2020-testbed --runs 20": "landa2020-testbed --runs 1",
    "farrell-hmm --runs 50": "farrell-hmm --runs 1",
    "reciprocity run --arena paper --strategy reciprocity --seed 3 --out out --json run.json":
        "reciprocity run --arena paper --strategy reciprocity --seed 3 --out out --json run.json --no-video",
    "--arena generate:rooms:3 --strategy reciprocity --quiet":
        "--arena generate:rooms:3 --strategy reciprocity --h 3 --set max_steps=3 --quiet",
    "--arena generate:maze:7:cols=5,rows=5 --strategy reciprocity --quiet":
        "--arena generate:maze:7:cols=5,rows=5 --strategy reciprocity --h 3 --set max_steps=3 --quiet",
    "--scenario rooms.yaml --strategy reciprocity --quiet": "--scenario rooms.yaml --strategy reciprocity --h 3 --quiet",
    "--strategy reciprocity-wind --h 2 --seed 0 --out wind_out":
        "--strategy reciprocity-wind --h 2 --seed 0 --out wind_out --set max_steps=3",
}
#: A command still running after this many seconds is stopped: a safety net against a
#: hang, far above what any command takes on a loaded machine (not a speed check).
COMMAND_TIMEOUT_S = 1200

_FENCE = re.compile(r"^```(\w*)\n(.*?)^```", re.S | re.M)


def blocks(name: str) -> list[tuple[str, str, int]]:
    """``(language, text, line)`` of each fenced block of markdown file `name`."""
    text = (ROOT / name).read_text()
    return [(m.group(1), m.group(2), text.count("\n", 0, m.start()) + 1) for m in _FENCE.finditer(text)]


def commands(text: str) -> list[str]:
    """The shell commands of a bash block: one per line (``\\`` continues a line),
    comments and blank lines dropped, set-up steps of :data:`SKIPPED` removed from ``&&``
    chains."""
    out = []
    for line in text.replace("\\\n", " ").splitlines():
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        steps = [s.strip() for s in line.split("&&")]
        keep = [s for s in steps if not any(s.startswith(p) for p in SKIPPED)]
        if keep:
            out.append(" && ".join(keep))
    return out


def _budgeted(text: str) -> str:
    for old, new in BUDGET.items():
        text = text.replace(old, new)
    return text


def test_every_budget_cut_still_matches_the_readme():
    readme = "\n".join((ROOT / n).read_text() for n in DOCS)
    stale = [old for old in BUDGET if old not in readme]
    assert not stale, f"BUDGET names text the docs no longer have: {stale}"


def test_the_readme_opens_with_the_two_set_up_commands():
    lang, text, _ = blocks("README.md")[0]
    lines = [ln for ln in text.splitlines() if ln.strip()]
    assert lang == "bash" and len(lines) == 2
    assert "pip install -e ." in lines[0] and "reciprocity demo" in lines[0]
    assert 'pip install -e ".[test]"' in lines[1] and "python -m pytest -n 2 -q" in lines[1]
    ci = (ROOT / ".ci" / "run").read_text()
    assert "python -m pytest -n 2 -q" in ci, "the README's test command is not what CI runs"


def _check_yaml(text: str, folder: Path) -> None:
    from arenas import from_dict as arena_from_dict
    from arenas.files import parse_yaml
    from reciprocity.campaign.spec import load_spec
    from reciprocity.scenarios import from_dict as scenario_from_dict
    data = parse_yaml(text, "README block")
    first = text.splitlines()[0]
    name = re.fullmatch(r"#\s*([\w.-]+\.ya?ml)\s*", first)
    if name:
        (folder / name.group(1)).write_text(text)
    if "world" in data:
        scenario_from_dict(data, "readme")
    elif "strategies" in data:
        path = folder / (name.group(1) if name else "spec.yaml")
        path.write_text(text)
        load_spec(path)
    else:
        arena_from_dict(data, where="README arena")


def _run_shell(cmd: str, folder: Path) -> None:
    env = dict(os.environ, MPLBACKEND="Agg", PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")
    done = subprocess.run(["bash", "-c", cmd], cwd=folder, env=env, capture_output=True, text=True,
                          timeout=COMMAND_TIMEOUT_S)
    assert done.returncode == 0, f"exit {done.returncode}\n{done.stdout[-1500:]}\n{done.stderr[-1500:]}"


#: Pages whose blocks take tens of seconds (whole campaigns, demos and sessions): they run in
#: the slower tier (``-m slow``), which CI runs after the README's suite.
SLOW_DOCS = ("README.md", "docs/beyond-the-papers.md", "docs/campaigns.md", "docs/generated-arenas.md",
             "docs/getting-started.md", "docs/papers.md", "docs/tutorials/flow.md", "docs/tutorials/poisson.md")


def test_every_slow_page_exists():
    assert set(SLOW_DOCS) <= set(DOCS)


@pytest.mark.parametrize("doc", [pytest.param(d, marks=pytest.mark.slow) if d in SLOW_DOCS else d for d in DOCS])
def test_every_block_of_the_docs_runs_in_order(doc, tmp_path, monkeypatch):
    import matplotlib
    matplotlib.use("Agg")
    monkeypatch.chdir(tmp_path)
    # the examples register world kinds and strategies in this process: drop them after,
    # so that later tests (tests/test_contract.py) see the built-in ones only
    from reciprocity.scenarios import WORLD_KINDS
    from reciprocity.strategies import STRATEGIES
    kinds_before, strategies_before = set(WORLD_KINDS), set(STRATEGIES)
    namespace: dict = {"__name__": "__readme__"}
    ran = 0
    for lang, text, line in blocks(doc):
        where = f"{doc}:{line} ({lang})"
        text = _budgeted(text)
        try:
            if lang == "yaml":
                _check_yaml(text, tmp_path)
            elif lang == "bash":
                for cmd in commands(text):
                    _run_shell(cmd, tmp_path)
            elif lang == "python":
                exec(compile(text, where, "exec"), namespace)
            else:
                continue                      # a diagram or a listing: nothing to run
        except BaseException as exc:
            pytest.fail(f"{where} fails: {type(exc).__name__}: {str(exc)[:3000]}")
        ran += 1
    runnable = sum(lang in ("yaml", "bash", "python") for lang, _, _ in blocks(doc))
    for name in set(WORLD_KINDS) - kinds_before:
        del WORLD_KINDS[name]
    for name in set(STRATEGIES) - strategies_before:
        del STRATEGIES[name]
    assert ran == runnable


def test_the_docs_show_commands_and_code():
    """The README and the docs together show at least ten runnable blocks (all run above)."""
    assert sum(lang in ("yaml", "bash", "python") for doc in DOCS for lang, _, _ in blocks(doc)) >= 10
    assert {"README.md", "docs/framework.md", "docs/campaigns.md"} <= set(DOCS)


def test_the_site_renders_offline():
    """No page needs the network to render: no diagram drawn by a script from a CDN
    (```mermaid), no script or style sheet fetched from elsewhere, and every image a
    file of the repository."""
    config = (ROOT / "mkdocs.yml").read_text()
    assert "mermaid" not in config and "extra_javascript" not in config and "extra_css" not in config
    for doc in DOCS:
        text = (ROOT / doc).read_text()
        assert [lang for lang, _, _ in blocks(doc) if lang == "mermaid"] == [], doc
        for image in re.findall(r"!\[[^\]]*\]\(([^)\s]+)", text):
            assert not image.startswith(("http:", "https:", "//")), f"{doc}: {image}"
            assert ((ROOT / doc).parent / image).is_file(), f"{doc}: {image} is not a file"


# ---------------------------------------------------------------------------------------
# Examples in --help texts


def _help_texts() -> list[tuple[str, str]]:
    """``(command, help string)`` of every argument of every subcommand of both CLIs."""
    from hjplanner.cli import build_parser as hj_parser
    from reciprocity.cli import build_parser
    out = []
    for prog, parser in (("reciprocity", build_parser()), ("hjplanner", hj_parser())):
        subs = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
        for name, sub in subs.choices.items():
            sub.format_help()       # declares the arguments of a command declared on use (campaign)
            out += [(f"{prog} {name}", a.help) for a in sub._actions if a.help]
    return out


def help_examples() -> list[tuple[str, str, str]]:
    """``(command, flag, value)`` of every ``e.g. --flag value`` of a help text."""
    out = []
    for command, text in _help_texts():
        for m in re.finditer(r"e\.g\. ((?:--[\w-]+ [^\s,()]+(?:,[^\s,()]+)*(?:, )?)+)", text):
            for ex in m.group(1).split(", "):
                flag, value = ex.split(" ", 1)
                out.append((command, flag, value))
    return sorted(set(out))


#: How each example runs: the command line it is added to. Car options are checked by the
#: full pre-run validation (reciprocity.cli's plan), not driven: a car episode takes minutes.
_BASE = {
    "reciprocity run": ["run", "--arena", "paper", "--strategy", "reciprocity", "--h", "5", "--set",
                        "max_steps=2", "--quiet"],
    "reciprocity demo": ["run", "--arena", "paper", "--strategy", "reciprocity", "--h", "5", "--set",
                         "max_steps=2", "--quiet"],
}


def test_the_help_texts_have_examples():
    found = {(c, f) for c, f, _ in help_examples()}
    assert {("reciprocity run", "--set"), ("reciprocity run", "--mismatch"), ("reciprocity run", "--car")} <= found


@pytest.mark.parametrize("command, flag, value", help_examples(), ids=lambda x: str(x))
def test_every_help_example_is_accepted(command, flag, value, capsys):
    from reciprocity import cli
    argv = _BASE[command] + [flag, value]
    if flag == "--car":
        argv += ["--platform", "car"]
        args = cli.build_parser().parse_args(argv)
        cli._plan(args, args.arena, args.strategy, cli._params(args.set))
        return
    assert cli.main(argv) == 0, capsys.readouterr().err


def test_the_hjplanner_module_examples_run(tmp_path, monkeypatch):
    import hjplanner.cli
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("HJPLANNER_CACHE", str(tmp_path / "cache"))
    lines = [ln.strip() for ln in hjplanner.cli.__doc__.splitlines() if ln.strip().startswith("hjplanner ")]
    assert len(lines) >= 4
    for line in lines:
        argv = shlex.split(_budgeted(line.split("#")[0]))[1:]
        if argv[0] == "bank":
            argv = [a if a != "12.7" else "70" for a in argv]
        assert hjplanner.cli.main(argv) == 0, line
