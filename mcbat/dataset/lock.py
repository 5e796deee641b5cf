"""One writer per dataset directory: an OS-level lock held for the whole run.

``run_study`` (every engine, and ``mcbat reproduce``) takes the lock of its output
directory before it changes anything there and keeps it until the last chunk is written.
A second run on the same directory, with or without ``overwrite``, is refused at once with
a message naming the holder (host, pid, start time). The lock is ``fcntl.flock`` on the
file ``LOCK_NAME`` inside the directory: the operating system releases it when its
process ends, however it ends, so the lock of a killed run is never stale. A run that
ends removes the file (a killed run leaves it behind: it is not a lock by itself, and
listings, loads and checks ignore it); a directory the lock created and that is still
empty at the end is removed too, so a refused run leaves nothing behind. Datasets at URLs
(object stores) are not locked: those file systems offer no lock; one writer per URL is
then the user's rule (``docs/errors.md``).
"""

from __future__ import annotations

import contextlib
import datetime
import errno
import fcntl
import os
import socket
from pathlib import Path

from mcbat.dataset import storage
from mcbat.errors import InputError

__all__ = ["LOCK_NAME", "dataset_lock"]

#: The lock file inside a dataset directory (ignored by listings, loads and checks).
LOCK_NAME = "_mcbat.lock"


def _holder(path: Path) -> str:
    try:
        text = path.read_text(encoding="utf-8").strip()
    except OSError:
        text = ""
    return text or "another process"


@contextlib.contextmanager
def dataset_lock(directory):
    """Hold the writer's lock of the dataset ``directory`` (created if missing) if it is
    on this machine, in any spelling (``mcbat.dataset.storage.local_path``).

    Raises
    ------
    InputError
        Naming ``out`` when another run holds the lock, or when the directory cannot be
        created or written.
    """
    # One lock per directory, whatever the spelling (relative, file:, local://): the lock
    # file is found through the directory's absolute local path.
    local = storage.local_path(directory)
    if local is None:  # remote storage: no lock there
        yield
        return
    directory = local
    created = not directory.exists()
    path = directory / LOCK_NAME
    try:
        directory.mkdir(parents=True, exist_ok=True)
        fd = _acquire(path, directory)
    except OSError as err:
        reason = os.strerror(err.errno) if err.errno else str(err)
        raise InputError("out", f"cannot write: {reason}", str(directory)) from None
    try:
        started = datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds")
        os.ftruncate(fd, 0)
        os.pwrite(fd, f"pid {os.getpid()} on {socket.gethostname()}, since {started}\n"
                  .encode(), 0)
        yield
    finally:
        # Unlink while still holding the lock: a waiting opener then holds a lock on a
        # removed file, which _acquire detects (inode check) and retries.
        with contextlib.suppress(OSError):
            path.unlink()
        os.close(fd)  # releases the lock
        if created:
            with contextlib.suppress(OSError):
                directory.rmdir()  # only succeeds when the run left nothing in it


def _acquire(path: Path, directory: Path) -> int:
    """Open ``path`` and take its exclusive lock without waiting; return the descriptor."""
    while True:
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as err:
            os.close(fd)
            if err.errno not in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
                raise
            raise InputError("out", f"another mcbat run is writing this dataset "
                             f"({_holder(path)}); wait for it to finish, or choose another "
                             "directory", str(directory)) from None
        try:
            same_file = os.fstat(fd).st_ino == os.stat(path).st_ino
        except FileNotFoundError:
            same_file = False
        if same_file:
            return fd
        os.close(fd)  # the previous holder removed the file meanwhile: lock the new one
