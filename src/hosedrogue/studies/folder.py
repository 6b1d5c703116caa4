"""Ownership of a campaign folder by one campaign at a time (:class:`FolderLock`)."""

from __future__ import annotations

import os
import socket
from pathlib import Path

from ..errors import ParameterError

__all__ = ["FolderLock"]


class FolderLock:
    """Ownership of a campaign folder: ``fcntl.flock`` on ``DIR/.lock`` for the campaign's life.

    The kernel releases the lock when its file is closed or its process ends, however it ends (a
    kill, a crash, a lost machine's lease on a network file system), so no stale lock is left to
    clear by hand; a pid file would need a liveness check, which cannot see another host's
    processes and mistakes a reused pid. The file holds the owner's pid and host, for the message
    a second campaign gets. It is never deleted while the folder is in use: deleting a lock file
    lets a waiting process lock the old, unlinked one.

    Parameters
    ----------
    out : Path
        The campaign folder (created if missing).

    Raises
    ------
    ParameterError
        Another process holds the folder, or the folder cannot be made or written.
    """

    def __init__(self, out: Path):
        self.out = out
        self.created = not out.exists()
        self.path = out / ".lock"
        try:
            out.mkdir(parents=True, exist_ok=True)
            self.fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as exc:
            raise ParameterError(f"out = {str(out)!r}: cannot be written ({exc.strerror})") from None
        try:
            import fcntl
        except ImportError:  # pragma: no cover - not POSIX: no protection against two campaigns
            return
        try:
            fcntl.flock(self.fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            owner = os.pread(self.fd, 200, 0).decode("utf-8", "replace").strip() or "unknown"
            os.close(self.fd)
            raise ParameterError(f"out = {str(out)!r}: another campaign ({owner}) is using it; wait for it to end or "
                                 "use another out folder") from None
        os.ftruncate(self.fd, 0)
        os.pwrite(self.fd, f"pid {os.getpid()} on {socket.gethostname()}\n".encode(), 0)

    def release(self, keep: bool = True) -> None:
        """Release the folder; ``keep=False`` (nothing else was written) removes the lock file, and
        the folder if this lock made it and it is empty.

        Parameters
        ----------
        keep : bool
            Whether the campaign wrote anything (then the lock file stays, harmless).
        """
        if not keep:
            self.path.unlink(missing_ok=True)  # still locked: no one else can be between open and lock
            if self.created:
                try:
                    self.out.rmdir()
                except OSError:
                    pass
        os.close(self.fd)

    def __enter__(self) -> "FolderLock":
        return self

    def __exit__(self, *exc) -> None:
        self.release(keep=any(p.name != ".lock" for p in self.out.iterdir()))
