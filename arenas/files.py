"""Reading user files safely: a size cap, text only, and a strict YAML loader.

Every file a user names (arena, scenario, campaign spec) goes through :func:`read_text`
and, for YAML, :func:`load_yaml`:

- only regular files are read (not folders, devices such as ``/dev/zero``, or pipes),
  and at most :data:`MAX_FILE_BYTES` of them;
- a file with NUL bytes, or that is not UTF-8, is refused as binary;
- YAML is safe-loaded (no Python objects), duplicate keys in one mapping are refused
  (the last one would otherwise silently win), aliases are capped at
  :data:`MAX_ALIASES` (no "billion laughs" expansion) and nesting at :data:`MAX_DEPTH`.

Errors are raised as the caller's exception class with one line that names the file.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

import yaml
from yaml.nodes import MappingNode, ScalarNode

from .errors import ArenaError

__all__ = ["MAX_FILE_BYTES", "MAX_ALIASES", "MAX_DEPTH", "MAX_EXPANDED_NODES", "check_output", "read_text",
           "load_yaml", "parse_yaml", "real_folder", "atomic_output"]

#: Largest user file read, bytes (arena, scenario and campaign files are a few kB).
MAX_FILE_BYTES = 1_000_000
#: Most YAML aliases (``*name``) in one document.
MAX_ALIASES = 100
#: Deepest nesting of YAML collections in one document.
MAX_DEPTH = 32
#: Most scalars and collections in one document once its aliases are expanded.
MAX_EXPANDED_NODES = 200_000

_MERGE_TAG = "tag:yaml.org,2002:merge"


def read_text(src, label: str, *, error: type[Exception] = ArenaError,
              max_bytes: int = MAX_FILE_BYTES) -> str:
    """The text of the user file `src`, checked.

    Parameters
    ----------
    src : str, os.PathLike or importlib.resources.abc.Traversable
        The file.
    label : str
        How messages name the file (e.g. ``"scenario file 'x.yaml'"``).
    error : type
        Exception class raised on any problem (default :class:`ArenaError`).
    max_bytes : int
        Size cap in bytes.

    Returns
    -------
    str
        The file's UTF-8 text.

    Raises
    ------
    error
        Missing, not a regular file, too large, binary, or not UTF-8.
    """
    if isinstance(src, (str, os.PathLike)):
        path = Path(src)
        try:
            # O_NONBLOCK: a FIFO put in the file's place is refused below, never waited on
            fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
        except OSError as exc:
            if isinstance(exc, IsADirectoryError) or path.is_dir():
                raise error(f"{label} is a folder; give a file") from None
            raise error(f"cannot read {label}: {exc.strerror or exc}") from None
        st = os.fstat(fd)
        problem = (f"{label} is a folder; give a file" if stat.S_ISDIR(st.st_mode) else
                   f"{label} is not a regular file (a device, pipe or socket); give a file"
                   if not stat.S_ISREG(st.st_mode) else
                   f"{label} has {st.st_size} bytes; at most {max_bytes} are read" if st.st_size > max_bytes
                   else None)
        if problem is not None:
            os.close(fd)
            raise error(problem)
        with os.fdopen(fd, "rb") as fh:
            try:
                os.set_blocking(fd, True)
                data = fh.read(max_bytes + 1)
            except OSError as exc:
                raise error(f"cannot read {label}: {exc.strerror or exc}") from None
    else:  # a packaged resource
        data = src.read_bytes()
    if len(data) > max_bytes:
        raise error(f"{label} has more than {max_bytes} bytes; at most {max_bytes} are read")
    if b"\0" in data:
        raise error(f"{label} is a binary file, not text")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        raise error(f"{label} is not UTF-8 text") from None


class _StrictLoader(yaml.SafeLoader):
    """SafeLoader that refuses duplicate keys, many aliases and deep nesting."""

    def __init__(self, stream):
        super().__init__(stream)
        self._aliases = 0
        self._depth = 0

    def compose_node(self, parent, index):
        if self.check_event(yaml.AliasEvent):
            self._aliases += 1
            if self._aliases > MAX_ALIASES:
                event = self.peek_event()
                raise yaml.composer.ComposerError(
                    None, None, f"more than {MAX_ALIASES} aliases (*name)", event.start_mark)
        self._depth += 1
        try:
            if self._depth > MAX_DEPTH:
                event = self.peek_event()
                raise yaml.composer.ComposerError(
                    None, None, f"collections nested deeper than {MAX_DEPTH}", event.start_mark)
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1

    def compose_document(self):
        node = super().compose_document()
        sizes: dict[int, int] = {}

        def size(n) -> int:  # nodes of the document with every alias expanded
            if id(n) not in sizes:
                if isinstance(n, ScalarNode):
                    sizes[id(n)] = 1
                else:
                    items = n.value if not isinstance(n, MappingNode) else [x for kv in n.value for x in kv]
                    sizes[id(n)] = 1 + sum(size(c) for c in items)
            return sizes[id(n)]

        if node is not None and size(node) > MAX_EXPANDED_NODES:
            raise yaml.composer.ComposerError(
                None, None, f"more than {MAX_EXPANDED_NODES} values once its aliases are expanded",
                node.start_mark)
        return node

    def construct_mapping(self, node, deep=False):
        if isinstance(node, MappingNode):
            seen = set()
            for key_node, _ in node.value:
                if isinstance(key_node, ScalarNode) and key_node.tag != _MERGE_TAG:
                    key = self.construct_object(key_node, deep=True)
                    if key in seen:
                        raise yaml.constructor.ConstructorError(
                            "while reading a mapping", node.start_mark,
                            f"duplicate key {key!r}", key_node.start_mark)
                    seen.add(key)
        return super().construct_mapping(node, deep=deep)


_StrictLoader.add_constructor("tag:yaml.org,2002:map", _StrictLoader.construct_yaml_map)


def parse_yaml(text: str, label: str, *, error: type[Exception] = ArenaError):
    """Parse YAML `text` strictly (see the module doc); `label` names it in errors."""
    try:
        return yaml.load(text, Loader=_StrictLoader)  # noqa: S506 - a SafeLoader subclass
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" (line {mark.line + 1}, column {mark.column + 1})" if mark is not None else ""
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise error(f"{label} is not valid YAML: {problem}{where}") from None
    except RecursionError:
        raise error(f"{label} is nested too deeply") from None


def load_yaml(src, label: str, *, error: type[Exception] = ArenaError,
              max_bytes: int = MAX_FILE_BYTES):
    """Read and parse the YAML file `src` strictly (see :func:`read_text`, :func:`parse_yaml`)."""
    return parse_yaml(read_text(src, label, error=error, max_bytes=max_bytes), label, error=error)


def check_output(path, label: str, *, folder: bool = False, error: type[Exception] = ArenaError) -> Path:
    """Check, before any work, that an output can be written at `path`.

    Nothing is created: the nearest existing ancestor must be a writable folder (probed
    with a temporary file, so read-only mounts and ``/proc`` are caught), no ancestor may be
    a file, and `path` itself must be a folder if `folder`, else not a folder.

    Parameters
    ----------
    path : str or os.PathLike
        The output file, or folder when `folder` is true.
    label : str
        How messages name the output (e.g. ``"--json"``).
    folder : bool
        Whether `path` is a folder (created later, with its parents) or a file.
    error : type
        Exception class raised on a problem.

    Returns
    -------
    Path
        `path` as a :class:`~pathlib.Path`.
    """
    import tempfile
    p = Path(path)
    if not str(path).strip():
        raise error(f"{label}: an empty path; give a file or folder name")
    if p.exists():
        if folder and not p.is_dir():
            raise error(f"{label} {str(path)!r} is a file; give a folder")
        if not folder and p.is_dir():
            raise error(f"{label} {str(path)!r} is a folder; give a file name")
    probe = p if (folder and p.is_dir()) else p.parent
    while not probe.exists():
        probe = probe.parent
    if not probe.is_dir():
        raise error(f"{label} {str(path)!r}: {str(probe)!r} is a file, so no folder can be made there")
    try:
        with tempfile.TemporaryFile(dir=probe):
            pass
    except OSError as exc:
        raise error(f"{label} {str(path)!r}: cannot write into {str(probe)!r} "
                    f"({exc.strerror or exc})") from None
    return p


def real_folder(root, *parts: str, label: str, error: type[Exception] = ArenaError):
    """The folder ``root/parts...``, made where missing, never through a symbolic link.

    `root` is the user's own output folder (whatever it is); every folder below it that
    the toolkit writes into must be a real folder, so that a link planted inside an output
    folder (``report -> /home/someone``) never sends a write or a clean-up elsewhere.

    Parameters
    ----------
    root : path-like
        The output folder (must exist).
    *parts : str
        Names of the folders below it.
    label : str
        How messages name the output (e.g. ``"campaign folder 'runs/x'"``).
    error : type
        Exception class raised on a problem.

    Returns
    -------
    Path
    """
    path = Path(root)
    for part in parts:
        path = path / part
        try:
            os.mkdir(path, 0o777)
        except FileExistsError:
            pass
        except OSError as exc:
            raise error(f"cannot make {str(path)!r} in {label}: {exc.strerror or exc}") from None
        st = os.lstat(path)
        if stat.S_ISLNK(st.st_mode) or not stat.S_ISDIR(st.st_mode):
            what = "a symbolic link" if stat.S_ISLNK(st.st_mode) else "not a folder"
            raise error(f"{str(path)!r} in {label} is {what}; the folders inside an output folder must be "
                        "real folders (remove it, or choose another output folder)")
    return path


def atomic_output(path, *, error: type[Exception] = ArenaError):
    """A context manager: write to the temporary file it yields, which then replaces `path`.

    The temporary file is made anew (``O_EXCL``) beside `path` and renamed over it, so a
    symbolic link or a file planted at `path` is replaced, never written through, a reader
    never sees half a file, and a failure leaves `path` as it was and no temporary file.

    Examples
    --------
    >>> with atomic_output(out / "figure.png") as tmp:            # doctest: +SKIP
    ...     fig.savefig(tmp, format="png")
    """
    import contextlib
    import tempfile

    @contextlib.contextmanager
    def _write():
        target = Path(path)
        try:
            fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
        except OSError as exc:
            raise error(f"cannot write {str(target)!r}: {exc.strerror or exc}") from None
        os.close(fd)
        try:
            yield Path(tmp)
            os.replace(tmp, target)
        except OSError as exc:
            raise error(f"cannot write {str(target)!r}: {exc.strerror or exc}") from None
        finally:
            with contextlib.suppress(OSError):
                os.unlink(tmp)

    return _write()
