"""Writes that lose nothing (issue 22): a file is written whole or not at all,
a folder of outputs is committed whole, and an output folder has one writer.

- write_bytes / write_text / replacing: the new content goes to a temporary
  file in the destination's folder, is flushed and fsynced, then renamed over
  the destination (and the folder fsynced). A failure at any point (a full
  disk, an exception of the code writing, a kill) leaves the old file as it
  was; the temporary file is removed (after a kill it stays, as
  `.NAME.tmp-XXXX`, and the old file is intact).
- staged_folder(out): the outputs are written aside and committed as a set
  in one step (commit_mode): a staging folder next to out (`.NAME.staging-
  XXXX`) swapped with out (renameat2 RENAME_EXCHANGE); or, where out cannot
  be swapped (the working folder, a mount point, no exchange on the system),
  in place: a run folder `out/.libkin-runs/run-XXXX`, each output a link
  `out/NAME -> .libkin-current/NAME`, and the link `.libkin-current` renamed
  to the new run. A MANIFEST (`.libkin-manifest.json`: name, size, SHA-256 of
  each file) names the set; the previous run's outputs go, out's other files
  and folders (the user's) stay. On a failure out is untouched; a folder
  that can be committed neither way is refused before any work.
- folder_lock(out): an exclusive POSIX lock (`.NAME.lock` next to out) held
  for a run, not inherited by forked workers; a second holder fails at once
  with FolderInUseError. The system releases it when the holder exits or
  dies; the new holder then ends or undoes what a killed run left
  (recover(): never deleting what libkin did not write) and checks out.
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
import re
import tempfile
import threading
from typing import IO, Any, Iterator, Optional, Set, Union

__all__ = ["write_bytes", "write_text", "replacing", "staged_folder", "folder_lock", "recover", "previous_outputs",
           "commit_mode", "MANIFEST", "FolderInUseError", "OutputFolderError"]

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
RUNS, CURRENT = ".libkin-runs", ".libkin-current"  # a folder committed in place (_commit_in_place)
STAGED = ".libkin-staged"  # in out from the exchange to the end of the commit: the staging folder's name


class OutputFolderError(OSError):
    """An output folder the outputs cannot be committed into (read-only,
    not a folder, ...): refused before any work."""

    def __str__(self) -> str:
        return f"{self.filename}: {self.strerror}"


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
        return set(json.loads((pathlib.Path(out) / MANIFEST).read_text())["files"])
    except (OSError, ValueError, KeyError, TypeError):
        return set()


def _mount_points() -> Set[str]:
    """The mount points of the system (Linux's /proc/self/mountinfo), bind mounts too."""
    try:
        with open("/proc/self/mountinfo") as f:
            fields = [line.split()[4] for line in f if len(line.split()) > 4]
    except OSError:
        return set()
    return {re.sub(r"\\([0-7]{3})", lambda m: chr(int(m.group(1), 8)), p) for p in fields}


def _probe(folder: pathlib.Path, out: pathlib.Path, exchange: bool = False, link: bool = True) -> Optional[OSError]:
    """None if a folder can be made in folder (and, exchange: two swapped
    in one step; link: a symbolic link made in it), else the error."""
    made = []
    try:
        for _ in range(2 if exchange else 1):
            made.append(tempfile.mkdtemp(prefix=f".{out.name}.probe-", dir=folder))
        if exchange and not _exchange(pathlib.Path(made[0]), pathlib.Path(made[1])):
            return OSError(errno.EOPNOTSUPP, "no atomic exchange of two folders here")
        if link and not exchange:
            os.symlink(".", os.path.join(made[0], "link"))
        return None
    except OSError as exc:
        return exc
    finally:
        for m in made:
            shutil.rmtree(m, ignore_errors=True)


def commit_mode(out: PathLike) -> str:
    """How out will be committed: "exchange" (a staging folder next to it
    swapped with it in one step) or "in place" (out keeps its identity: the
    folder the caller stands in, a mount point, a folder holding a mount
    point, a parent that cannot be written, a system with no exchange).
    OutputFolderError if it can be neither; cheap, so called before any work."""
    out = pathlib.Path(out).resolve()
    if os.path.lexists(out) and not out.is_dir():
        raise OutputFolderError(errno.ENOTDIR, "the output folder is not a folder", str(out))
    cwd = pathlib.Path.cwd().resolve()
    mounts = _mount_points()
    held = out.is_dir() and any(os.path.join(out, n) in mounts for n in os.listdir(out))
    if out == cwd or out in cwd.parents or os.path.ismount(out) or str(out) in mounts or held:
        in_place = True
    else:
        in_place = _probe(out.parent, out, exchange=True) is not None  # parent writable, exchange there
    if not in_place:
        err = _probe(out, out, link=False) if out.is_dir() else None  # user's folders are moved back into out
    elif not out.is_dir():
        try:
            out.mkdir()
            err = _probe(out, out)
        except OSError as exc:
            err = exc
    else:
        err = _probe(out, out)  # a run folder and links in out
    if err is not None:
        raise OutputFolderError(err.errno or errno.EIO, "the outputs cannot be committed into this folder "
                                f"({err.strerror or err})", str(out))
    return "in place" if in_place else "exchange"


def _move_back(old: pathlib.Path, out: pathlib.Path) -> None:
    """Move into out what old (out's previous folder) holds that libkin did
    not write (the user's folders and links) and out lacks."""
    ours = previous_outputs(old) | {MANIFEST, RUNS, CURRENT, STAGED}
    for entry in list(os.scandir(old)):
        if entry.name in ours or ".tmp-" in entry.name or os.path.lexists(out / entry.name):
            continue
        os.rename(entry.path, out / entry.name)


def _commit_exchange(stage: pathlib.Path, out: pathlib.Path) -> None:
    """Put the written folder stage in out's place, keeping out's files and
    folders that are not outputs of the previous run (its MANIFEST)."""
    _write_manifest(stage)
    if not os.path.lexists(out):
        os.rename(stage, out)
        _fsync_folder(out.parent)
        return
    stale = previous_outputs(out) | {MANIFEST, RUNS, CURRENT, STAGED}  # no old report beside a new summary
    for entry in os.scandir(out):  # the user's files are linked into the new folder
        if entry.is_file(follow_symlinks=False) and not os.path.lexists(stage / entry.name) \
                and entry.name not in stale:
            try:
                os.link(entry.path, stage / entry.name)
            except OSError:
                shutil.copy2(entry.path, stage / entry.name)
    write_text(stage / STAGED, stage.name)  # out's, once exchanged: recover() then ends the moves below
    if not _exchange(stage, out):
        raise OSError(errno.EOPNOTSUPP, "no atomic exchange of two folders here", str(out))
    # stage holds the previous folder now: its folders and links the run did not write go back into out
    _move_back(stage, out)
    os.unlink(out / STAGED)
    _fsync_folder(out)
    _fsync_folder(out.parent)
    shutil.rmtree(stage)


def _link(path: pathlib.Path, target: str) -> None:
    """Make path a symbolic link to target in one step (a new link renamed over it)."""
    if os.path.islink(path) and os.readlink(path) == target:
        return
    tmp = path.parent / f".{path.name}.tmp-{os.urandom(4).hex()}"
    os.symlink(target, tmp)
    os.replace(tmp, path)


def _commit_in_place(stage: pathlib.Path, out: pathlib.Path) -> None:
    """out keeps its identity: the run's files are in out/.libkin-runs/RUN
    (stage), each output NAME in out is a link to .libkin-current/NAME, and
    .libkin-current, a link to the run's folder, is switched to the new
    run in one step (a new link renamed over it)."""
    _write_manifest(stage)
    prev = sorted(previous_outputs(out) | {MANIFEST}, key=lambda n: n == MANIFEST)
    plain = [n for n in prev if os.path.isfile(out / n) and not os.path.islink(out / n)]
    if plain:  # the previous outputs as files (an exchanged commit): into a run folder first, the same content
        conv = pathlib.Path(tempfile.mkdtemp(prefix="run-", dir=out / RUNS))
        os.chmod(conv, stage.stat().st_mode & 0o7777)
        for n in prev:
            src = os.path.realpath(out / n)  # a link's file (os.link's follow_symlinks is ignored on Linux)
            if os.path.isfile(src):
                try:
                    os.link(src, conv / n)
                except OSError:
                    shutil.copy2(src, conv / n)
        _link(out / CURRENT, f"{RUNS}/{conv.name}")
        for n in plain:
            _link(out / n, f"{CURRENT}/{n}")
    for name in sorted(os.listdir(stage)):  # new names dangle until the switch
        _link(out / name, f"{CURRENT}/{name}")
    _fsync_folder(stage)
    _link(out / CURRENT, f"{RUNS}/{stage.name}")  # the switch
    _fsync_folder(out)
    _tidy_in_place(out)


def _tidy_in_place(out: pathlib.Path) -> None:
    """Remove what a folder committed in place no longer uses: the links of
    outputs the current run did not write, the other run folders."""
    current = os.readlink(out / CURRENT) if os.path.islink(out / CURRENT) else None
    names = previous_outputs(out) | {MANIFEST} if current else set()
    for entry in os.scandir(out):
        if entry.is_symlink() and entry.name not in names and os.readlink(entry.path).startswith(CURRENT + "/"):
            with contextlib.suppress(OSError):
                os.unlink(entry.path)
    if (out / RUNS).is_dir():
        for run in os.scandir(out / RUNS):
            if current != f"{RUNS}/{run.name}":
                shutil.rmtree(run.path, ignore_errors=True)


def _discard(stage: pathlib.Path, out: pathlib.Path) -> None:
    """Remove a staging folder a commit did not finish (a failure or, in
    recover(), a kill); when it already holds out's previous folder (the
    exchange happened: out's STAGED names it), what the user kept there
    goes back into out first, and on a failure to move it stays."""
    try:
        swapped = (out / STAGED).read_text() == stage.name
    except OSError:
        swapped = False
    if swapped:
        _move_back(stage, out)
    shutil.rmtree(stage, ignore_errors=True)
    if swapped:
        os.unlink(out / STAGED)


@contextlib.contextmanager
def staged_folder(out: PathLike) -> Iterator[pathlib.Path]:
    """Yield a new folder to write the outputs into; on a normal exit they
    are committed as out's outputs in one step (commit_mode: an exchange of
    folders, or in place the switch of a link), on an exception the folder
    is removed and out is untouched."""
    out = pathlib.Path(out).resolve()  # absolute, through links (a link to a folder keeps pointing at it)
    out.parent.mkdir(parents=True, exist_ok=True)
    mode = commit_mode(out)
    if mode == "in place":
        (out / RUNS).mkdir(exist_ok=True)
        stage = pathlib.Path(tempfile.mkdtemp(prefix="run-", dir=out / RUNS))
    else:
        stage = pathlib.Path(tempfile.mkdtemp(prefix=f".{out.name}.staging-", dir=out.parent))
    os.chmod(stage, _mode_of(out, 0o777))  # mkdtemp's folder is private: give it out's mode
    try:
        yield stage
        (_commit_in_place if mode == "in place" else _commit_exchange)(stage, out)
    except BaseException:
        if mode == "exchange":
            _discard(stage, out)
        elif os.path.islink(out / CURRENT) and os.readlink(out / CURRENT) == f"{RUNS}/{stage.name}":
            _tidy_in_place(out)  # switched: the new outputs stand, what is left is tidied
        else:
            shutil.rmtree(stage, ignore_errors=True)
        raise


def recover(out: PathLike) -> None:
    """After a run that was killed (call it holding out's lock): finish or
    undo its commit and remove what it wrote aside (its staging folder,
    temporary files, old run folders); what it did not write (the user's
    folders in a staging folder that was swapped in) goes back into out."""
    out = pathlib.Path(out).resolve()
    parent, name = out.parent, out.name
    if not parent.is_dir():
        return
    for old in sorted(parent.glob(f".{glob.escape(name)}.old-*")):  # two renames (libkin before issue 39)
        with contextlib.suppress(OSError):
            if not os.path.lexists(out) and (old / name).is_dir():
                os.rename(old / name, out)
            elif (old / name).is_dir():
                _move_back(old / name, out)
            shutil.rmtree(old, ignore_errors=True)
    for stage in parent.glob(f".{glob.escape(name)}.staging-*"):
        with contextlib.suppress(OSError):  # a folder of the user's that cannot be moved: left there
            _discard(stage, out)
    for probe in parent.glob(f".{glob.escape(name)}.probe-*"):
        shutil.rmtree(probe, ignore_errors=True)
    if out.is_dir():
        if not any(parent.glob(f".{glob.escape(name)}.staging-*")):  # else kept: it names the one left
            with contextlib.suppress(OSError):
                os.unlink(out / STAGED)
        for stale in out.glob(".*.tmp-*"):
            with contextlib.suppress(OSError):
                stale.unlink()
        if os.path.lexists(out / RUNS) or os.path.lexists(out / CURRENT):
            _tidy_in_place(out)


_HELD: Set[str] = set()  # the lock files this process holds (a POSIX lock is the process's: see folder_lock)
_HELD_GUARD = threading.Lock()


@contextlib.contextmanager
def folder_lock(out: PathLike) -> Iterator[None]:
    """Hold the exclusive lock of the output folder out (`.NAME.lock` next
    to it; in out where its parent cannot be written) for the block;
    FolderInUseError at once if another run holds it. Then what a killed
    run left is recovered and the folder checked (commit_mode:
    OutputFolderError before any work).

    The lock is a POSIX record lock (fcntl F_SETLK), owned by this process
    alone: a forked child (a pool worker) inherits the file descriptor but
    not the lock, so the lock ends with this process even if its workers
    live on. (flock and Linux's OFD locks belong to the open file, which a
    fork shares: an orphan worker would hold them.) A POSIX lock does not
    exclude the process itself, hence _HELD. Where fcntl is missing (not
    POSIX) no lock."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - Windows
        yield
        return
    out = pathlib.Path(out).resolve()
    out.parent.mkdir(parents=True, exist_ok=True)
    lock = out.parent / f".{out.name}.lock"
    with _HELD_GUARD:  # held here already: not opened again (closing it would end this process's lock)
        if str(out) in _HELD:
            raise FolderInUseError(errno.EBUSY, f"output folder in use by another run (its lock: {lock})", str(out))
        _HELD.add(str(out))
    try:
        try:
            f: IO[bytes] = open(lock, "a+b")
        except OSError as exc:
            if not out.is_dir():
                raise OutputFolderError(exc.errno, f"cannot create the lock {lock} ({exc.strerror})", str(out)) from None
            lock = out / ".libkin.lock"
            f = open(lock, "a+b")
        with f:
            try:
                fcntl.lockf(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError as exc:
                if exc.errno not in (errno.EAGAIN, errno.EACCES):
                    raise
                raise FolderInUseError(errno.EBUSY, "output folder in use by another run (its lock: "
                                       f"{lock})", str(out)) from None
            recover(out)
            commit_mode(out)
            yield
    finally:
        with _HELD_GUARD:
            _HELD.discard(str(out))
