"""Writes that lose nothing (issue 22): a file is written whole or not at all,
a folder of outputs is committed whole, and an output folder has one writer.

- write_bytes / write_text / replacing: the new content goes to a temporary
  file in the destination's folder, is flushed and fsynced, then renamed over
  the destination (and the folder fsynced). A failure at any point (a full
  disk, an exception of the code writing, a kill) leaves the old file as it
  was; the temporary file is removed (after a kill it stays, as
  `.NAME.tmp-XXXX`, and the old file is intact).
- staged_folder(out): the outputs are written into a staging folder next to
  out (`.NAME.staging-XXXX`) and, when all are written, take out's place in one
  step (an atomic exchange of the two folders where the system has one). A
  MANIFEST (`.libkin-manifest.json`: name, size, SHA-256 of each file) is
  written last; the previous run's outputs (its MANIFEST) are replaced as a
  set, out's other files (the user's) are kept. On a failure out is untouched.
- folder_lock(out): an exclusive lock (flock on `.NAME.lock` next to out) held
  for a run; a second holder fails at once with FolderInUseError. The system
  releases it when the holder exits or dies; the new holder then clears what
  a killed run left (recover()).
"""
from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import errno
import glob
import hashlib
import json
import os
import pathlib
import shutil
import tempfile
from typing import IO, Any, Iterator, Optional, Set, Union

__all__ = ["write_bytes", "write_text", "replacing", "staged_folder", "folder_lock", "recover", "previous_outputs",
           "MANIFEST", "FolderInUseError"]

PathLike = Union[str, "os.PathLike[str]"]
CHUNK = 1 << 16  # bytes per os.write: a full disk may refuse any of them


class FolderInUseError(OSError):
    """Another run holds the output folder's lock."""

    def __str__(self) -> str:
        return f"{self.filename}: {self.strerror}"


def _mode_of(path: pathlib.Path, new: int) -> int:
    """The permission bits of `path`, or of a new file (new=0o666) or
    folder (0o777) under the process's umask: what the replacement keeps."""
    try:
        return path.stat().st_mode & 0o7777
    except OSError:
        um = os.umask(0)
        os.umask(um)
        return new & ~um


def _fsync_folder(folder: PathLike) -> None:
    """Make a rename in folder durable (where the system allows it)."""
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def _target(path: PathLike) -> pathlib.Path:
    """The file to replace: a symbolic link's target, not the link."""
    p = pathlib.Path(path)
    return p.resolve() if p.is_symlink() else p


def _temp_name(p: pathlib.Path, kind: str = "tmp") -> str:
    """A new, empty, unique file next to p, keeping p's suffix (matplotlib
    and PIL choose the format by it)."""
    fd, name = tempfile.mkstemp(prefix=f".{p.name}.{kind}-", suffix=p.suffix, dir=p.parent)
    os.close(fd)
    return name


def _commit_file(tmp: str, p: pathlib.Path) -> None:
    """fsync tmp, give it p's mode (or a new file's), rename it over p, fsync the folder."""
    fd = os.open(tmp, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)
    os.chmod(tmp, _mode_of(p, 0o666))
    os.replace(tmp, p)
    _fsync_folder(p.parent)


@contextlib.contextmanager
def replacing(path: Any) -> Iterator[Any]:
    """Yield a temporary path (str, same folder and suffix as path) to write;
    on a normal exit it replaces path, on an exception it is removed and path
    is untouched. A path that is not a str or os.PathLike (a file object) or
    an existing non-regular file (a device, /dev/stdout) is yielded as it is."""
    if not isinstance(path, (str, os.PathLike)):
        yield path
        return
    p = _target(path)
    if p.exists() and not p.is_file():
        if p.is_dir():
            raise IsADirectoryError(errno.EISDIR, os.strerror(errno.EISDIR), str(path))
        yield str(p)
        return
    tmp = _temp_name(p)
    try:
        yield tmp
        _commit_file(tmp, p)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def _write_all(fd: int, data: bytes) -> None:
    view = memoryview(data)
    while view:
        n = os.write(fd, view[:CHUNK])
        view = view[n:]


def write_bytes(path: PathLike, data: bytes) -> None:
    """Replace the file path by data, whole or not at all."""
    with replacing(path) as tmp:
        fd = os.open(tmp, os.O_WRONLY | os.O_TRUNC)
        try:
            _write_all(fd, bytes(data))
        finally:
            os.close(fd)


def write_text(path: PathLike, text: str, encoding: str = "utf-8") -> None:
    """Replace the file path by text, whole or not at all."""
    write_bytes(path, text.encode(encoding))


def _renameat2_exchange() -> Optional[Any]:
    """libc's renameat2 (Linux, glibc >= 2.28), or None."""
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or None, use_errno=True)
        fn = libc.renameat2
    except (OSError, AttributeError):
        return None
    fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    fn.restype = ctypes.c_int
    return fn


_AT_FDCWD = -100
_RENAME_EXCHANGE = 2


def _exchange(a: pathlib.Path, b: pathlib.Path) -> bool:
    """Swap the folders a and b in one step; False where the system cannot."""
    fn = _renameat2_exchange()
    if fn is None:
        return False
    if fn(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE) == 0:
        return True
    e = ctypes.get_errno()
    if e in (errno.EINVAL, errno.ENOSYS, errno.EOPNOTSUPP):
        return False
    raise OSError(e, os.strerror(e), str(b))


MANIFEST = ".libkin-manifest.json"


def _write_manifest(stage: pathlib.Path) -> None:
    """MANIFEST in stage: the name, size and SHA-256 of each file the run wrote."""
    files = {}
    for entry in sorted(os.scandir(stage), key=lambda e: e.name):
        if entry.is_file(follow_symlinks=False) and entry.name != MANIFEST:
            h = hashlib.sha256()
            with open(entry.path, "rb") as f:
                for block in iter(lambda: f.read(1 << 20), b""):
                    h.update(block)
            files[entry.name] = {"size": entry.stat().st_size, "sha256": h.hexdigest()}
    write_text(stage / MANIFEST, json.dumps({"format": "libkin-outputs", "version": 1, "files": files},
                                            indent=1) + "\n")


def previous_outputs(out: PathLike) -> Set[str]:
    """The names of the files the last committed run wrote into out (its
    MANIFEST), or an empty set."""
    try:
        doc = json.loads((pathlib.Path(out) / MANIFEST).read_text())
        return set(doc["files"])
    except (OSError, ValueError, KeyError, TypeError):
        return set()


def _commit_folder(stage: pathlib.Path, out: pathlib.Path) -> None:
    """Put the written folder stage in out's place, keeping out's files that
    are not outputs of the previous run (its MANIFEST)."""
    _write_manifest(stage)
    cwd = pathlib.Path.cwd().resolve()
    if out.exists() and (out == cwd or out in cwd.parents):
        # the folder the caller (or its shell) stands in keeps its identity:
        # the files are renamed in one by one, stale outputs removed, the MANIFEST last
        stale = previous_outputs(out)
        names = sorted(os.listdir(stage), key=lambda n: n == MANIFEST)
        for name in names[:-1]:
            os.replace(stage / name, out / name)
        for name in stale - set(names):
            with contextlib.suppress(OSError):
                (out / name).unlink()
        os.replace(stage / MANIFEST, out / MANIFEST)
        _fsync_folder(out)
        os.rmdir(stage)
        return
    if not out.exists():
        os.rename(stage, out)
        _fsync_folder(out.parent)
        return
    if not out.is_dir():
        raise NotADirectoryError(errno.ENOTDIR, os.strerror(errno.ENOTDIR), str(out))
    moved_later = []
    stale = previous_outputs(out)  # the previous run's outputs go: no old report beside a new summary
    for entry in os.scandir(out):  # other files (the user's) stay in out
        if os.path.lexists(stage / entry.name) or entry.name in stale:
            continue
        if entry.is_file(follow_symlinks=False):
            try:
                os.link(entry.path, stage / entry.name)
            except OSError:
                shutil.copy2(entry.path, stage / entry.name)
        else:
            moved_later.append(entry.name)
    if _exchange(stage, out):
        old = stage  # now holds the previous outputs
    else:  # two renames: a kill between them leaves the old outputs in .NAME.old-XXXX
        old = pathlib.Path(tempfile.mkdtemp(prefix=f".{out.name}.old-", dir=out.parent))
        os.rename(out, old / out.name)
        os.rename(stage, out)
        old = old / out.name
    for name in moved_later:  # folders (and links) of out the run did not write
        os.rename(old / name, out / name)
    _fsync_folder(out.parent)
    shutil.rmtree(old if old.parent == out.parent else old.parent, ignore_errors=True)


@contextlib.contextmanager
def staged_folder(out: PathLike) -> Iterator[pathlib.Path]:
    """Yield a new staging folder next to out to write the outputs into; on a
    normal exit it is committed as out in one step, on an exception it is
    removed and out is untouched."""
    out = pathlib.Path(out).resolve()  # absolute, through links (a link to a folder keeps pointing at it)
    out.parent.mkdir(parents=True, exist_ok=True)
    stage = pathlib.Path(tempfile.mkdtemp(prefix=f".{out.name}.staging-", dir=out.parent))
    os.chmod(stage, _mode_of(out, 0o777))  # mkdtemp's folder is private: give it out's mode
    try:
        yield stage
        _commit_folder(stage, out)
    except BaseException:
        shutil.rmtree(stage, ignore_errors=True)
        raise


def recover(out: PathLike) -> None:
    """After a run that was killed (call it holding out's lock): put back
    the previous outputs if the kill fell between the two renames of a
    commit, and remove the staging folders and temporary files it left."""
    out = pathlib.Path(out).resolve()
    parent, name = out.parent, out.name
    if not parent.is_dir():
        return
    for old in sorted(parent.glob(f".{glob.escape(name)}.old-*")):
        if not os.path.lexists(out) and (old / name).is_dir():
            os.rename(old / name, out)
        shutil.rmtree(old, ignore_errors=True)
    for stale in parent.glob(f".{glob.escape(name)}.staging-*"):
        shutil.rmtree(stale, ignore_errors=True)
    if out.is_dir():
        for stale in out.glob(".*.tmp-*"):
            with contextlib.suppress(OSError):
                stale.unlink()


@contextlib.contextmanager
def folder_lock(out: PathLike) -> Iterator[None]:
    """Hold the exclusive lock of the output folder out (flock on
    `.NAME.lock` next to it) for the block; FolderInUseError at once if
    another process holds it. Where flock is missing (not POSIX) no lock."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - Windows
        yield
        return
    out = pathlib.Path(out).resolve()
    out.parent.mkdir(parents=True, exist_ok=True)
    lock = out.parent / f".{out.name}.lock"
    f: IO[bytes] = open(lock, "a+b")
    try:
        try:
            fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise FolderInUseError(errno.EBUSY, "output folder in use by another run (its lock: "
                                   f"{lock})", str(out)) from None
        recover(out)
        try:
            yield
        finally:
            fcntl.flock(f.fileno(), fcntl.LOCK_UN)
    finally:
        f.close()
