"""A reused output folder keeps no file of an earlier run: the one rule of every command that writes
a folder of results (``simulate``, ``sweep``, ``reproduce``, ``study NAME --out``).

Each such command writes, beside its files, :data:`MANIFEST`: the files it wrote, as paths inside
the folder (listed by the command as it writes them; ``reproduce``'s, the files that appeared in the
folder while it built the report). The next command writing
into the folder first removes the files its manifest lists, so none of the earlier run stays beside
the new one; files the package did not write (no manifest lists them) are left. A folder written
before manifests existed: the command's own file names (``known``) are removed instead.

Folders meant to be reused are not cleared: a ``montecarlo`` folder (and a docking or actuator
study's campaigns) resumes its campaign, ``fly`` numbers its flights after the ones there.
"""

from __future__ import annotations

import contextlib
import json
from pathlib import Path
from typing import Iterable, Iterator

from ..jsonio import dumps

__all__ = ["MANIFEST", "Written", "clear_earlier_output", "note_written", "output_folder", "record_output"]

#: The file, in an output folder, that lists what the command that wrote it wrote.
MANIFEST = ".hosedrogue-files.json"


def _listed(out: Path) -> list[str]:
    """The files the folder's manifest lists (none if it has none, or one that is not a manifest)."""
    try:
        data = json.loads((out / MANIFEST).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return []
    files = data.get("files") if isinstance(data, dict) else None
    return [f for f in files if isinstance(f, str)] if isinstance(files, list) else []


def _inside(out: Path, name: str) -> Path | None:
    """``out / name`` when it names a path strictly inside ``out`` (no absolute path, no ``..``)."""
    rel = Path(name)
    if rel.is_absolute() or not rel.parts or ".." in rel.parts:
        return None
    return out / rel


def clear_earlier_output(out: str | Path, known: Iterable[str] = ()) -> list[Path]:
    """Remove the files of an earlier run from an output folder about to be written again: those
    its :data:`MANIFEST` lists (paths inside the folder only), else the ``known`` names, and folders
    they leave empty; anything else in it is left.

    Parameters
    ----------
    out : str or Path
        The output folder (it need not exist).
    known : iterable of str
        The command's own file names, for a folder written before manifests existed.

    Returns
    -------
    list of Path
        The files removed.
    """
    out = Path(out)
    if not out.is_dir():
        return []
    names = _listed(out) or list(known)
    removed = []
    for name in names:
        path = _inside(out, name)
        if path is not None and (path.is_file() or path.is_symlink()):
            path.unlink()
            removed.append(path)
    for path in removed:  # sub-folders the earlier run made, now empty
        for parent in path.parents:
            if parent == out or out not in parent.parents:
                break
            with contextlib.suppress(OSError):
                parent.rmdir()
    with contextlib.suppress(FileNotFoundError):
        (out / MANIFEST).unlink()
    return removed


def record_output(out: str | Path, command: str, files: Iterable[str | Path]) -> Path | None:
    """Write the folder's :data:`MANIFEST`: the files ``command`` wrote into it.

    Parameters
    ----------
    out : str or Path
        The output folder.
    command : str
        The command that wrote it ("simulate").
    files : iterable of str or Path
        The files it wrote (paths as the command wrote them; any outside ``out`` is left out).

    Returns
    -------
    Path or None
        The manifest, or None when the folder does not exist.
    """
    out = Path(out)
    if not out.is_dir():
        return None
    names = set()
    for f in files:
        path = Path(f)
        try:
            rel = path.resolve().relative_to(out.resolve())
        except ValueError:  # not inside the folder
            continue
        if rel.parts and rel.name != MANIFEST and path.is_file():
            names.add(str(rel))
    path = out / MANIFEST
    path.write_text(dumps({"command": command, "files": sorted(names)}, indent=1) + "\n", encoding="utf-8")
    return path


class Written:
    """The files a command writes into its output folder, listed as it writes them (:meth:`add`),
    or, for a command that writes through code that does not say (``reproduce``'s report), found
    after it: the files that were not in the folder when it started (:meth:`new_files`).

    Parameters
    ----------
    out : Path
        The output folder.
    scan : bool
        Note the folder's files now, so that :meth:`new_files` can tell the ones that appear.
    """

    def __init__(self, out: Path, scan: bool):
        self.out, self.files = out, []
        self._before = set(_tree(out)) if scan else None

    def add(self, *paths) -> None:
        """List files written (their paths, as written)."""
        self.files.extend(paths)

    def new_files(self) -> list[Path]:
        """The files in the folder now that were not there at the start (none without ``scan``)."""
        return [] if self._before is None else [p for p in _tree(self.out) if p not in self._before]


def _tree(out: Path) -> list[Path]:
    return [p for p in out.rglob("*") if p.is_file()] if out.is_dir() else []


def note_written(path: str | Path) -> None:
    """Add a file written into another command's output folder (``view --out RUN/view.html``) to
    that folder's :data:`MANIFEST`, so the next run written there removes it too.

    Parameters
    ----------
    path : str or Path
        The file written.
    """
    path = Path(path)
    manifest = path.parent / MANIFEST
    if not manifest.is_file():
        return
    try:
        data = json.loads(manifest.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return
    listed = _listed(path.parent)
    if isinstance(data, dict) and path.name not in listed:
        data["files"] = sorted([*listed, path.name])
        manifest.write_text(dumps(data, indent=1) + "\n", encoding="utf-8")


@contextlib.contextmanager
def output_folder(out: str | Path, command: str, known: Iterable[str] = (), scan: bool = False) -> Iterator[Written]:
    """Write a command's folder of results: the earlier run's files removed first
    (:func:`clear_earlier_output`), the manifest of what was written after (also when the writing
    failed, so a partial output is known to the next run).

    Parameters
    ----------
    out : str or Path
        The output folder, checked already (:func:`hosedrogue.cli.options.prepare_out`).
    command : str
        The command writing it.
    known : iterable of str
        The command's own file names (a folder written before manifests existed).
    scan : bool
        Also list the files that appear in the folder while the command writes (a command whose
        writing code does not list them); a file of the user's that it overwrites is not listed.

    Yields
    ------
    Written
        Where the command lists what it writes (:meth:`Written.add`).
    """
    out = Path(out)
    clear_earlier_output(out, known)
    out.mkdir(parents=True, exist_ok=True)
    record_output(out, command, ())  # listing nothing, should the process be killed while it writes
    written = Written(out, scan)
    try:
        yield written
    finally:
        record_output(out, command, [*written.files, *written.new_files()])
