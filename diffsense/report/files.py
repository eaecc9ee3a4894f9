"""The files the commands write: inside the folder the user named, never over what the user owns.

Every file a command writes goes through this module, so that

* **nothing the user owns is replaced**: a folder written into (``report --out``, ``trade --out``)
  carries a manifest, ``.diffsense-files.json``, listing the files diffsense wrote there with a
  digest (SHA-256) of what it wrote; a file the command would write that already exists and is
  not listed, or was changed since (a ``report.md`` of the user's own, or one the user edited),
  stops the command before any work, with one line naming it, unless ``force``. A
  single file (``--json``) may be replaced only when it is a JSON file diffsense wrote (its
  ``"written_by"`` key) or with ``force``. The spec a command reads is never written over,
  ``force`` or not;
* **no path comes from a spec string**: names made from spec strings (case and requirement
  names) pass through :func:`safe_name`, and every path is checked to stay inside its folder;
* **writes are atomic**: each file is written to a temporary file in the same folder and renamed
  over the target (:func:`write_atomically`), so an interrupted command leaves the old file or
  the new one, never half of one.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
from pathlib import Path
from typing import Dict, Iterable, Optional

from diffsense.optimize.programs import write_atomically  # the package's one atomic write, re-exported

#: the manifest of a folder diffsense writes into (relative paths of the files it wrote)
MANIFEST = ".diffsense-files.json"
#: the key marking a JSON file written by diffsense (its value: "diffsense")
WRITTEN_BY = "written_by"


class OutputError(Exception):
    """A write refused (an existing file not made by diffsense, the spec itself, a path outside
    the folder): one line saying which file and why."""


def safe_name(text: str, limit: int = 48) -> str:
    """A file-name component made from ``text`` (a spec string): letters, digits and ``+ - _ .``
    kept, every other run of characters (and every run of dots) one ``_``, no leading or trailing
    ``. _ -``, at most ``limit`` characters; when anything was changed, a short digest of
    ``text`` is appended, so that distinct names stay distinct.

    >>> safe_name("search"), safe_name("x/../../escaped"), safe_name("..")
    ('search', 'x_escaped-b32831', 'file-5ec1f7')
    """
    cleaned = re.sub(r"[^A-Za-z0-9_.+-]+|\.{2,}", "_", text)
    cleaned = re.sub(r"_{2,}", "_", cleaned).strip("._-")[:limit]
    if cleaned == text and cleaned:
        return cleaned
    digest = hashlib.sha256(text.encode("utf-8", "surrogatepass")).hexdigest()[:6]
    return f"{cleaned or 'file'}-{digest}"


def _digest(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def _protected(path: Path, protect: Iterable[Path]) -> bool:
    """``path`` is one of the files ``protect`` (the same file, by any name)."""
    for p in protect:
        p = Path(p)
        try:
            if path.resolve() == p.resolve() or (path.exists() and p.exists() and os.path.samefile(path, p)):
                return True
        except OSError:
            continue
    return False


def _is_ours(path: Path) -> bool:
    """True when ``path`` is a JSON object written by diffsense (:data:`WRITTEN_BY`)."""
    try:
        with path.open("rb") as fh:
            data = json.loads(fh.read(1 << 26))
    except (OSError, ValueError):
        return False
    return isinstance(data, dict) and data.get(WRITTEN_BY) == "diffsense"


def check_single_file(path: Path, protect: Iterable[Path] = (), force: bool = False) -> None:
    """Refuse (:class:`OutputError`) to write the single file ``path`` over a protected file
    (the spec read), over a folder, or over an existing file diffsense did not write (without
    ``force``)."""
    path = Path(path)
    if _protected(path, protect):
        raise OutputError(f"{path}: refusing to write over the spec this command reads; choose another file")
    if path.is_dir():
        raise OutputError(f"{path}: is a folder; give a file name")
    if path.exists() and not force and not _is_ours(path):
        raise OutputError(f"{path}: exists and was not written by diffsense; choose another file or pass --force")


def write_json_file(path: Path, record: dict, protect: Iterable[Path] = (), force: bool = False) -> None:
    """Write ``record`` (JSON-ready) to ``path``, marked as written by diffsense, after
    :func:`check_single_file`; atomically."""
    check_single_file(path, protect, force)
    data = {WRITTEN_BY: "diffsense", **record}
    write_atomically(Path(path), json.dumps(data, indent=2, allow_nan=False).encode())


class FileTarget:
    """One file a command will write: ``relative`` in ``folder`` (an :class:`OutputFolder`).
    Figure functions take one in place of a path (:meth:`save_figure`)."""

    def __init__(self, folder: "OutputFolder", relative: str):
        self.folder = folder
        self.relative = relative
        self.path = folder.target(relative)
        self.name = self.path.name
        self.stem = self.path.stem

    def save_figure(self, fig, dpi: Optional[int] = None) -> Path:
        return self.folder.save_figure(self.relative, fig, dpi=dpi)

    def write_text(self, text: str) -> Path:
        return self.folder.write_text(self.relative, text)


class OutputFolder:
    """A folder a command writes into (module docstring): ``protect`` are files never written
    over (the spec read), ``force`` allows replacing files diffsense did not write."""

    def __init__(self, path, protect: Iterable[Path] = (), force: bool = False):
        self.path = Path(path)
        self.protect = [Path(p) for p in protect]
        self.force = force
        self._listed = self._read_manifest()

    def _read_manifest(self) -> Dict[str, str]:
        try:
            data = json.loads((self.path / MANIFEST).read_text())
        except (OSError, ValueError):
            return {}
        files = data.get("files") if isinstance(data, dict) else None
        if not isinstance(files, dict):
            return {}
        return {k: v for k, v in files.items() if isinstance(k, str) and isinstance(v, str)}

    def _ours(self, relative: str, path: Path) -> bool:
        """``path`` holds what diffsense wrote there (listed, and unchanged since)."""
        digest = self._listed.get(relative)
        if digest is None:
            return False
        try:
            return _digest(path.read_bytes()) == digest
        except OSError:
            return False

    def target(self, relative: str) -> Path:
        """The path of ``relative`` (a name made by diffsense, ``/``-separated) in the folder,
        checked: inside the folder, not a protected file, not a file diffsense did not write
        (without ``force``)."""
        parts = relative.split("/")
        if any(p in ("", ".", "..") or p != safe_name(p, limit=200) for p in parts):
            raise OutputError(f"{self.path}: refusing the unsafe file name {relative!r}")
        path = self.path.joinpath(*parts)
        if _protected(path, self.protect):
            raise OutputError(f"{path}: refusing to write over the spec this command reads; choose another --out")
        if path.is_dir():
            raise OutputError(f"{path}: is a folder where diffsense writes a file; choose another --out")
        if path.exists() and not self.force and not self._ours(relative, path):
            raise OutputError(f"{path}: exists and was not written by diffsense (or was changed since); "
                              "choose another --out or pass --force")
        return path

    def check(self, names: Iterable[str] = (), folders: Iterable[str] = ()) -> None:
        """Before any work: refuse now what writing ``names`` would refuse later, and any file in
        the subfolders ``folders`` that diffsense did not write (without ``force``)."""
        if self.path.exists() and not self.path.is_dir():
            raise OutputError(f"{self.path}: is a file, not a folder; choose another --out")
        for name in names:
            self.target(name)
        for folder in folders:
            sub = self.path / folder
            if not sub.is_dir() or self.force:
                continue
            for f in sorted(sub.iterdir()):
                if not self._ours(f"{folder}/{f.name}", f):
                    raise OutputError(f"{f}: exists and was not written by diffsense (or was changed since); "
                                      "choose another --out or pass --force")

    def file(self, relative: str) -> FileTarget:
        """A :class:`FileTarget` for ``relative`` (checked now, written later)."""
        return FileTarget(self, relative)

    def write_bytes(self, relative: str, data: bytes) -> Path:
        """Write ``data`` to ``relative`` in the folder (atomically) and list it in the manifest."""
        path = self.target(relative)
        write_atomically(path, data)
        self._listed[relative] = _digest(data)
        manifest = {"written_by": "diffsense", "files": dict(sorted(self._listed.items()))}
        write_atomically(self.path / MANIFEST, json.dumps(manifest, indent=1).encode())
        return path

    def write_text(self, relative: str, text: str) -> Path:
        return self.write_bytes(relative, text.encode("utf-8"))

    def save_figure(self, relative: str, fig, dpi: Optional[int] = None) -> Path:
        """Save a matplotlib figure as PNG to ``relative`` (atomically)."""
        import io

        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=dpi)
        return self.write_bytes(relative, buf.getvalue())


__all__ = ["OutputFolder", "FileTarget", "OutputError", "safe_name", "write_atomically", "write_json_file", "check_single_file",
           "MANIFEST", "WRITTEN_BY"]
